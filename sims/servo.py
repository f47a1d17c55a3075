"""The joint servo law shared by every simulator backend (so both run the same controller).

tau = Kp (q_d - q) + Kd (dq_d - dq) + tau_ff, clipped to +-torque_limit, evaluated at every
physics step with the state at the start of that step.
"""

from __future__ import annotations

import numpy as np

from robots.types import JointCommand


def servo_torque(
    command: JointCommand, q: np.ndarray, dq: np.ndarray, torque_limit: np.ndarray
) -> np.ndarray:
    """Joint torques [N m] of the servo law for joint positions `q` [rad], velocities `dq`
    [rad/s]."""
    tau = (
        command.kp * (command.position - q)
        + command.kd * (command.velocity - dq)
        + command.torque_feedforward
    )
    return np.minimum(np.maximum(tau, -torque_limit), torque_limit)  # np.clip, 3x cheaper
