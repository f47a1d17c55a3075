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

from estimators.base import ComponentSpec, EstimatorBase, register
from robots.model import RobotModel
from robots.types import RobotState, Sensors


class ProprioceptiveEstimator(EstimatorBase):
    name = "proprioceptive"

    def __init__(self, model: RobotModel, contact_threshold: float = 0.05) -> None:
        super().__init__(model)
        self.contact_force = contact_threshold * model.robot.total_mass * 9.81
        self.anchors = np.zeros((len(self.limb_frames), 3))
        self.in_contact = np.zeros(len(self.limb_frames), dtype=bool)
        self.base_position = np.zeros(3)
        self.base_velocity = np.zeros(3)
        self.last_time = 0.0

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
        rotation = pin.Quaternion(*orientation).normalized().toRotationMatrix()
        omega_world = rotation @ sensors.imu_angular_velocity_imu
        # Kinematics with the base at the origin and the estimated orientation.
        relative = RobotState(
            np.zeros(3),
            orientation,
            np.zeros(3),
            omega_world,
            sensors.joint_position,
            sensors.joint_velocity,
        )
        q = self.robot_model.configuration(relative)
        v = self.robot_model.velocity(relative, q)
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        vertical = sensors.contact_wrench_limb[:, 2]
        stance = self._stance(vertical)
        dt = max(sensors.time - self.last_time, 0.0)
        self.last_time = sensors.time
        if stance.any():
            offsets = np.array(
                [self.data.oMf[self.limb_frames[k]].translation for k in np.flatnonzero(stance)]
            )
            self._anchor(stance, stance & ~self.in_contact)
            weights = vertical[stance] / vertical[stance].sum()
            self.base_position = weights @ (self.anchors[stance] - offsets)
            # Stance feet do not move: J_lin(foot) v = 0 solved for the base linear velocity.
            velocities = []
            for k in np.flatnonzero(stance):
                jacobian = pin.getFrameJacobian(
                    self.model, self.data, self.limb_frames[k], pin.LOCAL_WORLD_ALIGNED
                )[:3]
                rest = jacobian[:, 3:] @ v[3:]
                velocities.append(-np.linalg.solve(jacobian[:, :3], rest))
            base_velocity_local = weights @ np.array(velocities)
            self.base_velocity = rotation @ base_velocity_local
        else:  # flight: carry on with the last velocity
            self._flight(dt)
        self.in_contact = stance
        state = RobotState(
            self.base_position.copy(),
            orientation.copy(),
            self.base_velocity.copy(),
            omega_world,
            sensors.joint_position,
            sensors.joint_velocity,
        )
        return self._complete(state, sensors)

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
        ProprioceptiveEstimator,
        "IMU orientation and rate, stance-foot kinematics, force sensors",
    )
)
