"""One flat float64 buffer per control period that a simulator's compiled sensor kernel fills
(`sims.kernels`), and the `Sensors` whose arrays are views of it.

Building `Sensors` from eleven separately computed numpy arrays costs a dozen numpy calls per
period; a kernel that writes one buffer and eleven slices of it costs two. The layout, in
order: joint positions, velocities and torques (n each), base position (3), base orientation
(4, w x y z), base linear and angular velocity (3 + 3, world), IMU orientation (4), gyro (3),
accelerometer (3), limb wrenches (6 per limb, row by row).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from robots.types import Sensors

_FIELDS = (
    ("joint_position", "n"),
    ("joint_velocity", "n"),
    ("joint_torque", "n"),
    ("base_position_world", 3),
    ("base_orientation_world", 4),
    ("base_linear_velocity_world", 3),
    ("base_angular_velocity_world", 3),
    ("imu_orientation_world", 4),
    ("imu_angular_velocity_imu", 3),
    ("imu_linear_acceleration_imu", 3),
    ("contact_wrench_limb", "6k"),
)


@dataclass(frozen=True)
class SensorLayout:
    """Where each `Sensors` field lives in the buffer of a robot with `n_joints` joints and
    `n_limbs` limbs; `offset[name]` is the field's first entry."""

    n_joints: int
    n_limbs: int
    offset: dict[str, int] = field(init=False)
    size: int = field(init=False)

    def __post_init__(self) -> None:
        sizes = {"n": self.n_joints, "6k": 6 * self.n_limbs}
        offset, start = {}, 0
        for name, size in _FIELDS:
            offset[name] = start
            start += sizes.get(size, size) if isinstance(size, str) else size
        object.__setattr__(self, "offset", offset)
        object.__setattr__(self, "size", start)

    def buffer(self) -> np.ndarray:
        return np.empty(self.size)

    def sensors(self, time: float, buffer: np.ndarray, contact_flag_limb: np.ndarray) -> Sensors:
        """`Sensors` at `time` [s] whose arrays are views of `buffer` (one buffer per period:
        the caller gives each period a new one)."""
        n, o = self.n_joints, self.offset["base_position_world"]
        wrench = o + 23
        return Sensors(
            time=time,
            joint_position=buffer[:n],
            joint_velocity=buffer[n : 2 * n],
            joint_torque=buffer[2 * n : o],
            base_position_world=buffer[o : o + 3],
            base_orientation_world=buffer[o + 3 : o + 7],
            base_linear_velocity_world=buffer[o + 7 : o + 10],
            base_angular_velocity_world=buffer[o + 10 : o + 13],
            imu_orientation_world=buffer[o + 13 : o + 17],
            imu_angular_velocity_imu=buffer[o + 17 : o + 20],
            imu_linear_acceleration_imu=buffer[o + 20 : wrench],
            contact_wrench_limb=buffer[wrench:].reshape(self.n_limbs, 6),
            contact_flag_limb=contact_flag_limb,
        )
