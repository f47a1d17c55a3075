"""The `Estimator` protocol, what every estimator shares, and the estimator registry.

Every estimator gives a `RobotState` with the CoM and its velocity (pinocchio) and the
measured ZMP on z = 0 from the force sensors of the limbs in contact (`EstimatorBase`); they
differ in where the base pose and twist come from (`estimators.ground_truth`,
`estimators.proprioceptive`).
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
import pinocchio as pin

from centroidal.wrench import resultant_about_origin, zmp_on_plane
from estimators import DEFAULT_ESTIMATOR  # noqa: F401 - re-exported
from robots.model import RobotModel
from robots.registry import ComponentSpec, Registry
from robots.types import CentroidalPlan, RobotState, Sensors


class Estimator(Protocol):
    name: str

    def reset(self, initial: RobotState, sensors: Sensors) -> None: ...
    def estimate(self, sensors: Sensors) -> RobotState: ...
    def follow(self, plan: CentroidalPlan) -> None: ...


class EstimatorBase:
    name = "base"

    def __init__(self, model: RobotModel) -> None:
        self.robot_model = model
        self.model = model.model
        self.data = self.model.createData()
        robot = model.robot
        self.limb_frames = [model.frame_id[limb.contact_frame] for limb in robot.limbs]
        self.foot_index = [k for k, limb in enumerate(robot.limbs) if limb.name.endswith("foot")]

    def reset(self, initial: RobotState, sensors: Sensors) -> None:
        """Start from the known initial state (the scenario's)."""

    def follow(self, plan: CentroidalPlan) -> None:
        """The plan of this period (called after the planner): for estimators that place the
        robot relative to the planned contacts (`estimators.kinematic_inertial`); others
        ignore it."""

    def _complete(self, state: RobotState, sensors: Sensors) -> RobotState:
        """Add CoM, CoM velocity, measured wrenches, contact flags and ZMP to `state`."""
        q = self.robot_model.configuration(state)
        v = self.robot_model.velocity(state, q)
        pin.forwardKinematics(self.model, self.data, q, v)
        pin.updateFramePlacements(self.model, self.data)
        return self._complete_from_kinematics(state, sensors, None)

    def _complete_from_kinematics(
        self, state: RobotState, sensors: Sensors, shift: tuple[np.ndarray, np.ndarray] | None
    ) -> RobotState:
        """`_complete` with the forward kinematics (positions, velocities, frame placements)
        already in `self.data`: of `state` itself (`shift` None), or of `state` with its base
        moved by -shift[0] [m] and its base linear velocity reduced by shift[1] [m/s] (world),
        which moves every point, the CoM included, by the same -shift[0] and changes every
        velocity by the same -shift[1] (so one kinematics pass serves an estimator that places
        the base relative to its stance, `estimators.proprioceptive`)."""
        model, data = self.model, self.data
        com = pin.centerOfMass(model, data, pin.KinematicLevel.VELOCITY, False).copy()
        com_velocity = data.vcom[0].copy()
        flags = sensors.contact_flag_limb
        touching = [k for k, flag in enumerate(flags.tolist()) if flag]
        placements = [data.oMf[self.limb_frames[k]] for k in touching]
        positions = np.array([p.translation for p in placements]).reshape(-1, 3)
        if shift is not None:
            com += shift[0]
            com_velocity += shift[1]
            positions += shift[0]
        resultant = resultant_about_origin(
            positions,
            np.array([p.rotation for p in placements]).reshape(-1, 3, 3),
            sensors.contact_wrench_limb[touching],
        )
        return RobotState(
            state.base_position_world,
            state.base_orientation_world,
            state.base_linear_velocity_world,
            state.base_angular_velocity_world,
            state.joint_position,
            state.joint_velocity,
            time=sensors.time,
            com_position_world=com,
            com_velocity_world=com_velocity,
            contact_wrench_limb=sensors.contact_wrench_limb,
            contact_flag_limb=flags,
            zmp_world=zmp_on_plane(resultant),
        )


# `ComponentSpec.factory(model, dt)` builds an estimator for a `RobotModel` and control period
# dt [s] (the period at which `estimate` is called: `Scene.control_dt`)
ESTIMATORS = Registry(
    "estimator",
    modules=(
        "estimators.ground_truth",
        "estimators.proprioceptive",
        "estimators.kinematic_inertial",
        "estimators.five_mass_kalman",
    ),
)
register = ESTIMATORS.register


def make_estimator(name: str, model: RobotModel, dt: float) -> Estimator:
    """An estimator by name, for control period dt [s]; unknown names raise KeyError listing
    the known ones."""
    return ESTIMATORS.get(name).factory(model, dt)


__all__ = ["ESTIMATORS", "ComponentSpec", "Estimator", "EstimatorBase", "make_estimator"]
