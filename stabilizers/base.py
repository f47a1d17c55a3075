"""The `Stabilizer` protocol and the stabilizer registry (DESIGN.md, interfaces)."""

from __future__ import annotations

from typing import Protocol

from robots.model import RobotModel
from robots.registry import ComponentSpec, Registry
from robots.scene import Scenario
from robots.types import CentroidalPlan, RobotState, WholeBodyTargets


class Stabilizer(Protocol):
    name: str

    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None: ...
    def stabilize(self, t: float, plan: CentroidalPlan, state: RobotState) -> WholeBodyTargets: ...


STABILIZERS = Registry(
    "stabilizer",
    modules=(
        "stabilizers.posture",
        "stabilizers.centroidal_feedback",
        "stabilizers.dcm",
        "stabilizers.direct_centroidal",
        "stabilizers.passthrough",
    ),
)
StabilizerSpec = ComponentSpec
register = STABILIZERS.register
stabilizer_spec = STABILIZERS.get
