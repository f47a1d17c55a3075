"""The `Stabilizer` protocol and the stabilizer registry (DESIGN.md, interfaces)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

from robots.model import RobotModel
from robots.scene import Scenario
from robots.types import CentroidalPlan, RobotState, WholeBodyTargets


class Stabilizer(Protocol):
    name: str

    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None: ...
    def stabilize(self, t: float, plan: CentroidalPlan, state: RobotState) -> WholeBodyTargets: ...


@dataclass(frozen=True)
class StabilizerSpec:
    """A registered stabilizer: `factory(dt)` builds one for control period dt [s];
    `pairs_with` names the only planners it makes sense with (empty: any)."""

    name: str
    factory: Callable[[float], Stabilizer]
    description: str
    pairs_with: tuple[str, ...] = ()


STABILIZERS: dict[str, StabilizerSpec] = {}


def register(spec: StabilizerSpec) -> StabilizerSpec:
    if spec.name in STABILIZERS:
        raise ValueError(f"stabilizer {spec.name!r} registered twice")
    STABILIZERS[spec.name] = spec
    return spec


def stabilizer_spec(name: str) -> StabilizerSpec:
    """The registered stabilizer `name`; unknown names raise KeyError listing the known ones."""
    _load_all()
    if name not in STABILIZERS:
        known = ", ".join(sorted(STABILIZERS))
        raise KeyError(f"unknown stabilizer {name!r}; choose one of: {known}")
    return STABILIZERS[name]


def _load_all() -> None:
    import stabilizers.posture  # noqa: F401  (registers on import)
