"""Murooka et al. Sec. V-F, measured on the simulated robot (ground truth): how far the
centroidal angular momentum is from the approximations of eqs. 6-7 that its preview control
plans with,

    L = I_all q' (exact)  ~  I_base omega  ~  I omega  ~  I alpha'

with I_all the angular rows of the centroidal momentum matrix, I_base its block of the base's
angular velocity omega (world axes), I the constant diagonal approximation of I_base
(`RobotModel.constant_inertia`) and alpha' the rates of the base's ZYX Euler angles
alpha = (roll, pitch, yaw), omega = K_Euler(alpha) alpha' (eq. 7 drops K_Euler). The paper
reports the means of ||I_base omega - I omega|| (0.044 kg m^2/s), ||I_all q' - I omega|| (3.1;
0.011 with the IK's angular-momentum task) and ||I omega - I alpha'|| (0.0051) for walking and
the handrail stairs.

A pinocchio pass per sample (the centroidal map): sampled every `EVERY` control periods
(50 Hz at 500 Hz) so that every episode pays about a tenth of it; the means are over the
samples.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from robots.model import RobotModel
from robots.types import RobotState

EVERY = 10  # control periods between samples
KEYS = ("base_vs_constant", "all_vs_constant", "constant_vs_euler")
"""Summary keys [kg m^2/s]: means of ||I_base omega - I omega||, ||I_all q' - I omega||,
||I omega - I alpha'||."""


def euler_rates_zyx(rotation: np.ndarray, omega_world: np.ndarray) -> np.ndarray:
    """alpha' = K_Euler(alpha)^-1 omega for R = Rz(yaw) Ry(pitch) Rx(roll) and a world-axes
    angular velocity: omega = [[cy cp, -sy, 0], [sy cp, cy, 0], [-sp, 0, 1]] (roll', pitch',
    yaw'). Singular at pitch = +-90 deg (a fallen robot): NaN there."""
    pitch = -math.asin(max(-1.0, min(1.0, rotation[2, 0])))
    yaw = math.atan2(rotation[1, 0], rotation[0, 0])
    cy, sy, cp, sp = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch)
    k_euler = np.array([[cy * cp, -sy, 0.0], [sy * cp, cy, 0.0], [-sp, 0.0, 1.0]])
    if abs(cp) < 1e-6:
        return np.full(3, np.nan)
    return np.linalg.solve(k_euler, omega_world)


class AngularMomentumErrors:
    """Accumulates the three errors of Sec. V-F from ground-truth states."""

    def __init__(self, model: RobotModel) -> None:
        self.model = model
        self.data = model.model.createData()
        self.inertia = model.constant_inertia()
        self.sums = np.zeros(len(KEYS))
        self.count = 0

    def observe(self, state: RobotState) -> None:
        model = self.model
        q = model.configuration(state)
        v = model.velocity(state, q)
        rotation = pin.Quaternion(q[6], q[3], q[4], q[5]).toRotationMatrix()
        angular_rows = pin.computeCentroidalMap(model.model, self.data, q)[3:]
        omega = np.asarray(state.base_angular_velocity_world, dtype=float)
        exact = angular_rows @ v
        base = angular_rows[:, 3:6] @ (rotation.T @ omega)
        constant = self.inertia @ omega
        euler = self.inertia @ euler_rates_zyx(rotation, omega)
        errors = (
            np.linalg.norm(base - constant),
            np.linalg.norm(exact - constant),
            np.linalg.norm(constant - euler),
        )
        if all(map(math.isfinite, errors)):
            self.sums += errors
            self.count += 1

    def summary(self) -> dict[str, float] | None:
        """Means [kg m^2/s] under `KEYS`, None before any sample."""
        if not self.count:
            return None
        return {key: float(value / self.count) for key, value in zip(KEYS, self.sums, strict=True)}
