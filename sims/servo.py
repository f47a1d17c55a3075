"""The joint servo law shared by every simulator backend (so both run the same controller).

tau = Kp (q_d - q) + Kd (dq_d - dq) + tau_ff, clipped to +-torque_limit, evaluated at every
physics step with the state at the start of that step.
"""

from __future__ import annotations

import numpy as np

from robots.types import JointCommand
from sims.kernels import servo_torque_kernel


def servo_torque(
    command: JointCommand, q: np.ndarray, dq: np.ndarray, torque_limit: np.ndarray
) -> np.ndarray:
    """Joint torques [N m] of the servo law for joint positions `q` [rad], velocities `dq`
    [rad/s]."""
    return servo_torque_kernel(
        command.position,
        command.velocity,
        command.torque_feedforward,
        command.kp,
        command.kd,
        q,
        dq,
        torque_limit,
    )
