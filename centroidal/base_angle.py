"""The base angle alpha of Murooka et al.'s centroidal state (RA-L 2022, Sec. III-A4, eqs. 2, 6).

The paper's angular part of the centroidal state is the base link's orientation alpha, taken as
ZYX Euler angles, with the angular velocity omega = K_Euler alpha' whose K_Euler it neglects
(omega ~ alpha'), and the constant diagonal inertia of eq. 6. Our planners (`preview_control`,
`linear_mpc`) take alpha as the rotation vector of the base orientation instead (an adaptation,
README "Adaptations"): the same as the Euler angles to first order about the identity, and with
it omega = alpha' holds to first order as well. `zyx_euler_angles` gives the paper's alpha for
comparison (`tests/centroidal/test_base_angle.py` measures the two apart).
"""

from __future__ import annotations

import numpy as np

from centroidal.rotations import exp, from_matrix, log, to_matrix


def base_angle(orientation_wxyz: np.ndarray) -> np.ndarray:
    """alpha [rad] (3,) of a base orientation, world axes: the rotation vector log(R).

    Adaptation of Murooka et al. Sec. III-A4, where alpha is the ZYX Euler angles (roll, pitch,
    yaw) = `zyx_euler_angles`; both agree to first order about the identity."""
    return log(to_matrix(orientation_wxyz))


def base_orientation(angle: np.ndarray) -> np.ndarray:
    """The base orientation (w, x, y, z) of alpha [rad] (3,): exp(alpha), the inverse of
    `base_angle`."""
    return from_matrix(exp(angle))


def zyx_euler_angles(orientation_wxyz: np.ndarray) -> np.ndarray:
    """The paper's alpha: (roll, pitch, yaw) [rad] with R = R_z(yaw) R_y(pitch) R_x(roll)
    (Murooka et al. Sec. III-A4), pitch in [-pi/2, pi/2]."""
    r = to_matrix(orientation_wxyz)
    pitch = -np.arcsin(np.clip(r[2, 0], -1.0, 1.0))
    roll = np.arctan2(r[2, 1], r[2, 2])
    yaw = np.arctan2(r[1, 0], r[0, 0])
    return np.array([roll, pitch, yaw])


def zyx_euler_orientation(angles: np.ndarray) -> np.ndarray:
    """The base orientation (w, x, y, z) of the paper's alpha = (roll, pitch, yaw) [rad]:
    R = R_z(yaw) R_y(pitch) R_x(roll), the inverse of `zyx_euler_angles`."""
    roll, pitch, yaw = (float(a) for a in angles)
    return from_matrix(
        exp(np.array([0.0, 0.0, yaw]))
        @ exp(np.array([0.0, pitch, 0.0]))
        @ exp(np.array([roll, 0.0, 0.0]))
    )
