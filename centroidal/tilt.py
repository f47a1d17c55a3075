"""Tilts in projected angles (Ficht & Behnke Sec. 3.4, their [11]): a tilt of the z axis is
two angles, theta_x toward +x and theta_y toward +y, the angles of the axis's projections onto
the xz and yz planes from the vertical, so that each can be held independently and no gimbal
lock occurs below 90 deg. z(theta) = normalise(tan theta_x, tan theta_y, 1)."""

from __future__ import annotations

import math

import numpy as np


def axis_from_angles(theta_x: float, theta_y: float) -> np.ndarray:
    """The unit axis with projected angles (theta_x, theta_y) [rad] from the vertical."""
    axis = np.array([math.tan(theta_x), math.tan(theta_y), 1.0])
    return axis / math.sqrt(axis @ axis)


def angles_of_axis(axis: np.ndarray) -> np.ndarray:
    """(theta_x, theta_y) [rad] of an axis with a positive z component."""
    return np.array([math.atan2(axis[0], axis[2]), math.atan2(axis[1], axis[2])])


def flywheel_angles(inertia_axis_world: np.ndarray, pendulum_world: np.ndarray) -> np.ndarray:
    """Eq. 13's flywheel angle theta_f [rad] (theta_x, theta_y): the projected angles of the
    principal z axis of inertia less those of the pendulum, the line from the feet's midpoint
    to the CoM (eq. 5's neutral tilt, where "the torque of a flywheel attached to a pendulum is
    zero"). Both vectors in the world frame, with positive z components; neither need be unit.
    """
    return angles_of_axis(inertia_axis_world) - angles_of_axis(pendulum_world)


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b of two 3-vectors (numpy's `cross` costs about 20 us per call on 3-vectors)."""
    a0, a1, a2 = a.tolist()
    b0, b1, b2 = b.tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def tilt_rotation(axis: np.ndarray) -> np.ndarray:
    """The rotation of least angle that turns the world z axis onto the unit `axis` (Rodrigues'
    formula about z x axis: R = I + [k] sin + [k]^2 (1 - cos), written out)."""
    x, y, z = axis.tolist()
    sine_squared = x * x + y * y  # |z_world x axis|^2
    if sine_squared < 1e-24:
        return np.eye(3)
    # k = (-y, x, 0) / sine; (1 - cos) / sine^2 = 1 / (1 + cos)
    c = 1.0 / (1.0 + z)
    return np.array(
        [
            [1.0 - x * x * c, -x * y * c, x],
            [-x * y * c, 1.0 - y * y * c, y],
            [-x, -y, z],
        ]
    )


def yaw_rotation(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def tilt_and_yaw(axis: np.ndarray, yaw: float) -> np.ndarray:
    """Rodrigues' axis-angle composition of eq. 5: the frame whose z axis is `axis` and whose
    rotation about it is `yaw` [rad] (the tilt applied after the yaw)."""
    return tilt_rotation(axis) @ yaw_rotation(yaw)


__all__ = [
    "angles_of_axis",
    "axis_from_angles",
    "cross",
    "tilt_and_yaw",
    "tilt_rotation",
    "yaw_rotation",
]
