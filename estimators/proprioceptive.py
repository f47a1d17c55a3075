"""`proprioceptive`: what a real robot knows. Base orientation from the IMU, base angular
velocity from the gyro, base position and linear velocity from stance-foot kinematics: a foot
whose force sensor carries more than `contact_threshold` of the weight is taken as not moving;
its world position is remembered when it lands (its anchor) and the base is placed so that the
foot is at its anchor (several stance feet: weighted by their vertical forces); the base
velocity makes the stance feet's velocity zero.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from numba import njit

from centroidal.gravity import GRAVITY
from centroidal.kernels import relative_configuration
from estimators.base import ComponentSpec, EstimatorBase, register
from robots.model import RobotModel
from robots.types import RobotState, Sensors


@njit(cache=True)
def place_on_stance(
    vertical_force: np.ndarray,
    stance: np.ndarray,
    anchors_world: np.ndarray,
    offsets: np.ndarray,
    velocities: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The base position [m] that puts the stance limbs (`stance` (k,) bool) at their anchors
    (k, 3) [m] given their offsets from the base (m, 3) [m] (world axes), and the base velocity
    [m/s] that stops their velocities relative to it (m, 3) [m/s], each the average over the
    stance limbs weighted by their vertical forces (k,) [N]."""
    total = 0.0
    for k in range(len(stance)):
        if stance[k]:
            total += vertical_force[k]
    position, velocity = np.zeros(3), np.zeros(3)
    i = 0
    for k in range(len(stance)):
        if stance[k]:
            weight = vertical_force[k] / total
            for j in range(3):
                position[j] += weight * (anchors_world[k, j] - offsets[i, j])
                velocity[j] -= weight * velocities[i, j]
            i += 1
    return position, velocity


class ProprioceptiveEstimator(EstimatorBase):
    name = "proprioceptive"

    def __init__(self, model: RobotModel, contact_threshold: float = 0.05) -> None:
        super().__init__(model)
        self.contact_force = contact_threshold * model.robot.total_mass * GRAVITY
        self.anchors = np.zeros((len(self.limb_frames), 3))
        self.in_contact = np.zeros(len(self.limb_frames), dtype=bool)
        self.base_position = np.zeros(3)
        self.base_velocity = np.zeros(3)
        self.last_time = 0.0
        self._q = np.zeros(self.model.nq)  # the kinematics pass's configuration, velocity
        self._v = np.zeros(self.model.nv)
        self._rotation = np.eye(3)  # and base rotation

    def reset(self, initial: RobotState, sensors: Sensors) -> None:
        q = self.robot_model.configuration(initial)
        pin.framesForwardKinematics(self.model, self.data, q)
        self.anchors = np.array([self.data.oMf[f].translation for f in self.limb_frames])
        self.in_contact = np.zeros(len(self.limb_frames), dtype=bool)
        self.in_contact[self.foot_index] = True
        self.base_position = np.array(initial.base_position_world, dtype=float)
        self.base_velocity = np.array(initial.base_linear_velocity_world, dtype=float)
        self.last_time = sensors.time

    def estimate(self, sensors: Sensors) -> RobotState:
        orientation = sensors.imu_orientation_world  # the IMU frame has the base's axes
        # One kinematics pass with the base at the origin, the IMU's orientation and no base
        # linear velocity (positions, velocities, frames) serves the stance below and the CoM
        # and ZMP (`_complete_from_kinematics`, which shifts them by the base's estimate).
        q, v, rotation = self._q, self._v, self._rotation
        relative_configuration(
            orientation,
            sensors.imu_angular_velocity_imu,  # the base's angular velocity in its own axes
            sensors.joint_position,
            sensors.joint_velocity,
            q,
            v,
            rotation,
        )
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q, v)
        pin.updateFramePlacements(model, data)
        vertical = sensors.contact_wrench_limb[:, 2]
        stance = self._stance(vertical)
        dt = max(sensors.time - self.last_time, 0.0)
        self.last_time = sensors.time
        if stance.any():
            frames = [self.limb_frames[k] for k in np.flatnonzero(stance).tolist()]
            offsets = np.array([data.oMf[f].translation for f in frames])
            # Stance feet do not move: J(foot) v = 0 for the base linear velocity v_b. The
            # columns of v_b (base axes) in a LOCAL_WORLD_ALIGNED Jacobian are the base rotation
            # R, so R v_b = -(the foot's velocity from every other joint), which is the foot's
            # velocity in this pass (it has v_b = 0).
            moving = np.array(
                [
                    pin.getFrameVelocity(model, data, f, pin.LOCAL_WORLD_ALIGNED).linear
                    for f in frames
                ]
            )
            self._anchor(stance, stance & ~self.in_contact)
            self.base_position, self.base_velocity = place_on_stance(
                vertical, stance, self.anchors, offsets, moving
            )
        else:  # flight: carry on with the last velocity
            self._flight(dt)
        self.in_contact = stance
        state = RobotState(
            self.base_position.copy(),
            orientation.copy(),
            self.base_velocity.copy(),
            rotation @ sensors.imu_angular_velocity_imu,
            sensors.joint_position,
            sensors.joint_velocity,
        )
        return self._complete_from_kinematics(
            state, sensors, (self.base_position, self.base_velocity)
        )

    def _flight(self, dt: float) -> None:
        """No limb carries weight: the base moves on with its last velocity over dt [s]."""
        self.base_position = self.base_position + self.base_velocity * dt

    def _stance(self, vertical_force: np.ndarray) -> np.ndarray:
        """(n_limbs,) bool: the limbs taken as not moving, from their vertical forces [N]."""
        stance = np.zeros_like(self.in_contact)
        stance[self.foot_index] = vertical_force[self.foot_index] > self.contact_force
        return stance

    def _anchor(self, stance: np.ndarray, landed: np.ndarray) -> None:
        """Set the anchors of the stance limbs (n_limbs,) bool: each newly `landed` one where
        the kinematics put it now (its world position from the last base position and the
        current relative kinematics in `self.data`); the others keep theirs."""
        for k in np.flatnonzero(landed):
            self.anchors[k] = self.base_position + self.data.oMf[self.limb_frames[k]].translation


register(
    ComponentSpec(
        "proprioceptive",
        lambda model, dt: ProprioceptiveEstimator(model),  # dt unused: it uses the sensors' time
        "IMU orientation and rate, stance-foot kinematics, force sensors",
    )
)
