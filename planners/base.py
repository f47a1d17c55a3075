"""The `Planner` protocol and the planner registry (DESIGN.md, interfaces and registries)."""

from __future__ import annotations

from typing import Protocol

from robots.model import RobotModel
from robots.registry import ComponentSpec, Registry
from robots.scene import Scenario
from robots.types import CentroidalPlan, RobotState


class Planner(Protocol):
    name: str
    projects_wrench: bool
    """Whether the plan's wrench_projected_world is a projection of its wrench_planned_world
    onto the contacts' wrench cones (Murooka eqs. 9-10); otherwise the two are the same wrench
    and the runner records no planned projection error (Sec. V-G) for the episode."""
    tracks_hand_targets: bool
    """Whether the planner drives a hand to the scenario's hand targets (Sherikov et al. 2014,
    eq. 17); otherwise the runner records `hand_task` False in a scenario with targets, and a
    reach's hand error says where the hand stayed, not how well it was driven."""
    plans_com_trajectory: bool
    """Whether the plan's CoM position and velocity are a trajectory planned ahead of the
    state; otherwise (Sherikov et al.'s hierarchy: its plan's CoM is the state it was computed
    from) the CoM tracking error and eq. 18's e_c and e_v would compare the state with itself,
    and the runner records them as None (`bench.metrics.walking_quality`)."""

    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None: ...
    def plan(self, t: float, state: RobotState) -> CentroidalPlan: ...


PLANNERS = Registry(
    "planner",
    modules=(
        "planners.hold",
        "planners.preview_control",
        "planners.preview_zmp",
        "planners.linear_mpc",
        "planners.five_mass_gait",
        "planners.capturability_hierarchy",
    ),
)
PlannerSpec = ComponentSpec
register = PLANNERS.register
planner_spec = PLANNERS.get
