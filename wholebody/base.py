"""The `WholeBodyLayer` protocol and the whole-body layer registry (DESIGN.md, interfaces).

A layer turns the stabilizer's targets into the joint command that the simulators' servo law
executes (position and velocity targets, feed-forward torques, gains). It is given the
estimated state too, so that a layer that needs it (inverse dynamics) fits the same loop.
"""

from __future__ import annotations

from typing import Protocol

from robots.model import RobotModel
from robots.registry import ComponentSpec, Registry
from robots.types import JointCommand, RobotState, WholeBodyTargets


class WholeBodyLayer(Protocol):
    name: str

    def reset(self, model: RobotModel, state: RobotState) -> None: ...
    def command(self, targets: WholeBodyTargets, state: RobotState) -> JointCommand: ...


# `ComponentSpec.factory(model, dt)` builds a layer for a `RobotModel` and control period dt [s]
WHOLE_BODY_LAYERS = Registry(
    "whole-body layer",
    modules=(
        "wholebody.ik_feedforward",
        "wholebody.ik_only",
        "wholebody.five_mass_pose",
        "wholebody.inverse_dynamics",
    ),
)
register = WHOLE_BODY_LAYERS.register
DEFAULT_WHOLE_BODY = "ik"
"""The layer of a controller that names none: the IK to joint position servos, as Murooka et
al.'s robot (Sec. V-A1) and every position-controlled humanoid of the papers here."""


def make_whole_body(name: str, model: RobotModel, dt: float) -> WholeBodyLayer:
    """A whole-body layer by name; unknown names raise KeyError listing the known ones."""
    return WHOLE_BODY_LAYERS.get(name).factory(model, dt)


__all__ = [
    "DEFAULT_WHOLE_BODY",
    "WHOLE_BODY_LAYERS",
    "ComponentSpec",
    "WholeBodyLayer",
    "make_whole_body",
]
