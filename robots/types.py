"""The plain data objects that pass between stages (DESIGN.md, "The loop"). SI units; world
frame Z up; quaternions (w, x, y, z). Arrays are float64 numpy arrays; joint arrays follow
`RobotDescription.joints`, limb arrays follow `RobotDescription.limbs`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class RobotState:
    """Floating-base state. The base is the root link's frame (not its centre of mass).

    base_position_world [m]; base_orientation_world (w, x, y, z); base_linear_velocity_world
    [m/s] of the base frame origin; base_angular_velocity_world [rad/s]; joint_position [rad];
    joint_velocity [rad/s]."""

    base_position_world: np.ndarray
    base_orientation_world: np.ndarray
    base_linear_velocity_world: np.ndarray
    base_angular_velocity_world: np.ndarray
    joint_position: np.ndarray
    joint_velocity: np.ndarray

    @staticmethod
    def at_rest(base_position_world, base_orientation_world, joint_position) -> RobotState:
        q = np.asarray(joint_position, dtype=float)
        return RobotState(
            base_position_world=np.asarray(base_position_world, dtype=float),
            base_orientation_world=np.asarray(base_orientation_world, dtype=float),
            base_linear_velocity_world=np.zeros(3),
            base_angular_velocity_world=np.zeros(3),
            joint_position=q,
            joint_velocity=np.zeros_like(q),
        )


@dataclass(frozen=True)
class Sensors:
    """What the simulator reports after each control period.

    time [s]; joint_position [rad], joint_velocity [rad/s], joint_torque [N m] (applied by the
    servo during the last physics step, after clipping); ground-truth base pose and twist as in
    `RobotState`; IMU: imu_orientation_world (w, x, y, z), imu_angular_velocity_imu [rad/s],
    imu_linear_acceleration_imu [m/s^2] (specific force: reads +9.81 along the world's up
    direction at rest); contact_wrench_limb (n_limbs, 6): force [N] then moment [N m] of the
    environment on the limb, expressed in the limb's contact frame (sole / palm centre) about
    its origin; contact_flag_limb (n_limbs,) bool."""

    time: float
    joint_position: np.ndarray
    joint_velocity: np.ndarray
    joint_torque: np.ndarray
    base_position_world: np.ndarray
    base_orientation_world: np.ndarray
    base_linear_velocity_world: np.ndarray
    base_angular_velocity_world: np.ndarray
    imu_orientation_world: np.ndarray
    imu_angular_velocity_imu: np.ndarray
    imu_linear_acceleration_imu: np.ndarray
    contact_wrench_limb: np.ndarray
    contact_flag_limb: np.ndarray

    def ground_truth(self) -> RobotState:
        return RobotState(
            self.base_position_world,
            self.base_orientation_world,
            self.base_linear_velocity_world,
            self.base_angular_velocity_world,
            self.joint_position,
            self.joint_velocity,
        )


@dataclass(frozen=True)
class JointCommand:
    """Targets for the joint servo law tau = kp (q_d - q) + kd (dq_d - dq) + tau_ff, clipped to
    the torque limit. position [rad], velocity [rad/s], torque_feedforward [N m], kp [N m/rad],
    kd [N m s/rad]; all in joint order."""

    position: np.ndarray
    velocity: np.ndarray
    torque_feedforward: np.ndarray
    kp: np.ndarray
    kd: np.ndarray


@dataclass(frozen=True)
class MassProperties:
    """Mass properties as one library reports them, per massive body, in the body's link frame
    (the URDF link frame): mass [kg], centre of mass [m], inertia about the centre of mass
    [kg m^2]; plus the joint names and position limits [rad] in the library's own order."""

    source: str
    body_names: tuple[str, ...]
    mass: np.ndarray
    com_in_body: np.ndarray
    inertia_at_com_in_body: np.ndarray
    joint_names: tuple[str, ...]
    joint_lower: np.ndarray
    joint_upper: np.ndarray

    @property
    def total_mass(self) -> float:
        return float(self.mass.sum())
