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


def tilt_rotation(axis: np.ndarray) -> np.ndarray:
    """The rotation of least angle that turns the world z axis onto the unit `axis` (Rodrigues'
    formula about z x axis)."""
    z = np.array([0.0, 0.0, 1.0])
    cross = np.cross(z, axis)
    sine = math.sqrt(cross @ cross)
    cosine = float(axis[2])
    if sine < 1e-12:
        return np.eye(3)
    k = cross / sine
    skew = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + sine * skew + (1.0 - cosine) * skew @ skew


def yaw_rotation(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def tilt_and_yaw(axis: np.ndarray, yaw: float) -> np.ndarray:
    """Rodrigues' axis-angle composition of eq. 5: the frame whose z axis is `axis` and whose
    rotation about it is `yaw` [rad] (the tilt applied after the yaw)."""
    return tilt_rotation(axis) @ yaw_rotation(yaw)


__all__ = ["angles_of_axis", "axis_from_angles", "tilt_and_yaw", "tilt_rotation", "yaw_rotation"]
