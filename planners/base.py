"""The `Planner` protocol and the planner registry (DESIGN.md, interfaces and registries)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

from robots.model import RobotModel
from robots.scene import Scenario
from robots.types import CentroidalPlan, RobotState


class Planner(Protocol):
    name: str

    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None: ...
    def plan(self, t: float, state: RobotState) -> CentroidalPlan: ...


@dataclass(frozen=True)
class PlannerSpec:
    """A registered planner: `factory(dt)` builds one for control period dt [s];
    `pairs_with` names the only stabilizers it makes sense with (empty: any)."""

    name: str
    factory: Callable[[float], Planner]
    description: str
    pairs_with: tuple[str, ...] = ()


PLANNERS: dict[str, PlannerSpec] = {}


def register(spec: PlannerSpec) -> PlannerSpec:
    if spec.name in PLANNERS:
        raise ValueError(f"planner {spec.name!r} registered twice")
    PLANNERS[spec.name] = spec
    return spec


def planner_spec(name: str) -> PlannerSpec:
    """The registered planner `name`; unknown names raise KeyError listing the known ones."""
    _load_all()
    if name not in PLANNERS:
        raise KeyError(f"unknown planner {name!r}; choose one of: {', '.join(sorted(PLANNERS))}")
    return PLANNERS[name]


def _load_all() -> None:
    import planners.hold  # noqa: F401  (registers on import)
