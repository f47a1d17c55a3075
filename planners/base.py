"""The `Planner` protocol and the planner registry (DESIGN.md, interfaces and registries)."""

from __future__ import annotations

from typing import Protocol

from robots.model import RobotModel
from robots.registry import ComponentSpec, Registry
from robots.scene import Scenario
from robots.types import CentroidalPlan, RobotState


class Planner(Protocol):
    name: str

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
