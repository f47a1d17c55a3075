"""Rotations with quaternions in (w, x, y, z) order, in plain numpy (scipy's `Rotation` costs
tens of microseconds per call, too much for a 2 ms control period; tests check these against
scipy)."""

from __future__ import annotations

import math

import numpy as np

IDENTITY_WXYZ = np.array([1.0, 0.0, 0.0, 0.0])
_EPS = float(np.finfo(float).eps)


def to_matrix(quaternion_wxyz: np.ndarray) -> np.ndarray:
    """Rotation matrix of a quaternion (w, x, y, z), normalised first."""
    w, x, y, z = np.asarray(quaternion_wxyz, dtype=float) / np.linalg.norm(quaternion_wxyz)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def from_matrix(rotation: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) with w >= 0 of a rotation matrix (Shepperd's method)."""
    # Python floats (the same IEEE arithmetic as numpy scalars, several times faster)
    (m00, m01, m02), (m10, m11, m12), (m20, m21, m22) = np.asarray(rotation).tolist()
    trace = m00 + m11 + m22
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = np.array([0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s])
    elif m00 > m11 and m00 > m22:
        s = 2.0 * math.sqrt(1.0 + m00 - m11 - m22)
        q = np.array([(m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s])
    elif m11 > m22:
        s = 2.0 * math.sqrt(1.0 + m11 - m00 - m22)
        q = np.array([(m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s])
    else:
        s = 2.0 * math.sqrt(1.0 + m22 - m00 - m11)
        q = np.array([(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s])
    q /= np.linalg.norm(q)
    return -q if q[0] < 0 else q


def log(rotation: np.ndarray) -> np.ndarray:
    """Rotation vector [rad] of a rotation matrix (angle in [0, pi])."""
    cos_angle = np.clip((np.trace(rotation) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(cos_angle)
    axis_times_sin = 0.5 * np.array(
        [
            rotation[2, 1] - rotation[1, 2],
            rotation[0, 2] - rotation[2, 0],
            rotation[1, 0] - rotation[0, 1],
        ]
    )
    if angle < 1e-6:
        return axis_times_sin  # sin(angle) ~ angle
    if np.pi - angle < 1e-6:  # near pi: axis from the symmetric part
        symmetric = (rotation + np.eye(3)) / 2.0
        axis = np.sqrt(np.clip(np.diag(symmetric), 0.0, None))
        k = int(np.argmax(axis))
        axis = symmetric[k] / axis[k]
        return angle * axis / np.linalg.norm(axis)
    return angle / np.sin(angle) * axis_times_sin


def skew(v: np.ndarray) -> np.ndarray:
    """[v]x (3, 3), so that [v]x u = v x u."""
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def exp(rotation_vector: np.ndarray) -> np.ndarray:
    """Rotation matrix of a rotation vector [rad] (Rodrigues' formula)."""
    angle = float(np.linalg.norm(rotation_vector))
    k = skew(rotation_vector)
    if angle < 1e-9:
        return np.eye(3) + k
    return np.eye(3) + np.sin(angle) / angle * k + (1 - np.cos(angle)) / angle**2 * k @ k


def rotation_error(target: np.ndarray, actual: np.ndarray) -> np.ndarray:
    """Rotation vector [rad], world axes, that turns `actual` into `target`: log(T A^T)."""
    return log(target @ actual.T)


def rotate_by_vector(rotation_vector: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """exp(rotation_vector) rotation: `rotation` turned by a world-axes rotation vector."""
    return exp(rotation_vector) @ rotation


# Batched versions on stacks of quaternions (..., 4) and rotation vectors (..., 3), for the
# per-limb loops of the stabilizers (one call for every limb instead of one per limb). The
# product and the rotation matrix are bilinear / quadratic in the quaternion components, so each
# is one `einsum` with a constant tensor, built below from the scalar formulas.


def _hamilton(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return np.array(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ]
    )


def _unnormalised_matrix(q):
    w, x, y, z = q
    return np.array(
        [
            [w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z],
        ]
    )


_BASIS = np.eye(4)
_PRODUCT = np.stack(
    [np.stack([_hamilton(a, b) for b in _BASIS], axis=-1) for a in _BASIS], axis=1
)  # (4, 4, 4): c_i = sum_jk P_ijk a_j b_k
_QUADRATIC = np.stack(
    [
        np.stack(
            [0.25 * (_unnormalised_matrix(a + b) - _unnormalised_matrix(a - b)) for b in _BASIS],
            axis=-1,
        )
        for a in _BASIS
    ],
    axis=2,
)  # (3, 3, 4, 4): R_ij = sum_kl S_ijkl q_k q_l (polarisation of the quadratic form)


def quaternion_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products a b of quaternions (..., 4) in (w, x, y, z) order."""
    return np.einsum("ijk,...j,...k->...i", _PRODUCT, a, b)


def quaternions_from_vectors(rotation_vectors: np.ndarray) -> np.ndarray:
    """Unit quaternions (..., 4) of rotation vectors (..., 3) [rad]."""
    angle = np.sqrt((rotation_vectors * rotation_vectors).sum(axis=-1, keepdims=True))
    # sin(angle / 2) / angle = sinc(angle / 2pi) / 2, exact at zero: numpy's sinc written out
    # (its dtype lookups cost more than the arithmetic on a few limbs)
    x = np.pi * (angle / (2.0 * np.pi))
    y = np.where(x, x, _EPS)
    scale = 0.5 * (np.sin(y) / y)
    return np.concatenate([np.cos(0.5 * angle), scale * rotation_vectors], axis=-1)


def vectors_from_quaternions(quaternions_wxyz: np.ndarray) -> np.ndarray:
    """Rotation vectors (..., 3) [rad], angle in [0, pi], of unit quaternions (..., 4)."""
    w = quaternions_wxyz[..., :1]
    vector = np.where(w < 0, -quaternions_wxyz[..., 1:], quaternions_wxyz[..., 1:])
    w = np.abs(w)
    sin_half = np.sqrt((vector * vector).sum(axis=-1, keepdims=True))
    angle = 2.0 * np.arctan2(sin_half, w)
    # angle / sin(angle / 2), with its limit 2 / w for a vanishing vector part
    scale = np.divide(angle, sin_half, out=2.0 / np.maximum(w, 1e-300), where=sin_half > 1e-9)
    return scale * vector


def to_matrices(quaternions_wxyz: np.ndarray) -> np.ndarray:
    """Rotation matrices (k, 3, 3) of quaternions (k, 4), each normalised first."""
    q = quaternions_wxyz
    q = q / np.sqrt((q * q).sum(axis=-1, keepdims=True))
    return np.einsum("ijkl,nk,nl->nij", _QUADRATIC, q, q)


def yaw_of(quaternion_wxyz) -> float:
    """The heading [rad] of an orientation (w, x, y, z): the angle of its x axis about world Z."""
    w, x, y, z = (float(v) for v in quaternion_wxyz)
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def heading_quaternion(yaw: float) -> np.ndarray:
    """The level orientation (w, x, y, z) with heading `yaw` [rad]."""
    return np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])


def circular_mean(angles: np.ndarray) -> float:
    """The mean direction [rad] of angles [rad] (atan2 of the summed sines and cosines)."""
    return float(np.arctan2(np.sin(angles).sum(), np.cos(angles).sum()))
