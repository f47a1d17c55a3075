"""Rotations with quaternions in (w, x, y, z) order, in plain numpy (scipy's `Rotation` costs
tens of microseconds per call, too much for a 2 ms control period; tests check these against
scipy)."""

from __future__ import annotations

import math

import numpy as np

from centroidal.kernels import (
    exp_of_vector,
    log_of_matrix,
    matrix_of_quaternion,
    matrix_rows_of_quaternions,
    multiply_quaternion_rows,
    quaternion_of_matrix,
    quaternion_rows_of_vectors,
    vector_rows_of_quaternions,
)

IDENTITY_WXYZ = np.array([1.0, 0.0, 0.0, 0.0])
_EPS = float(np.finfo(float).eps)


def to_matrix(quaternion_wxyz: np.ndarray) -> np.ndarray:
    """Rotation matrix of a quaternion (w, x, y, z), normalised first."""
    return matrix_of_quaternion(np.asarray(quaternion_wxyz, dtype=float))


def from_matrix(rotation: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) with w >= 0 of a rotation matrix (Shepperd's method)."""
    return quaternion_of_matrix(np.asarray(rotation, dtype=float))


def log(rotation: np.ndarray) -> np.ndarray:
    """Rotation vector [rad] of a rotation matrix (angle in [0, pi])."""
    return log_of_matrix(np.asarray(rotation, dtype=float))


def skew(v: np.ndarray) -> np.ndarray:
    """[v]x (3, 3), so that [v]x u = v x u."""
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def exp(rotation_vector: np.ndarray) -> np.ndarray:
    """Rotation matrix of a rotation vector [rad] (Rodrigues' formula)."""
    return exp_of_vector(np.asarray(rotation_vector, dtype=float))


def rotation_error(target: np.ndarray, actual: np.ndarray) -> np.ndarray:
    """Rotation vector [rad], world axes, that turns `actual` into `target`: log(T A^T)."""
    return log(target @ actual.T)


def rotate_by_vector(rotation_vector: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """exp(rotation_vector) rotation: `rotation` turned by a world-axes rotation vector."""
    return exp(rotation_vector) @ rotation


# Batched versions on stacks of quaternions (..., 4) and rotation vectors (..., 3), for the
# per-limb loops of the stabilizers (one call for every limb instead of one per limb), compiled
# (numba, cached on disk): one call where numpy needs four to eight (tests check them against
# scipy).
def _rows(function, *arrays: np.ndarray) -> np.ndarray:
    """`function` of stacks (k, n) applied to arrays (..., n) of floats."""
    first = arrays[0]
    if type(first) is np.ndarray and first.ndim == 2 and first.dtype == np.float64:
        return function(*arrays)  # stacks already (the per-period callers)
    shape = np.shape(first)
    rows = [np.ascontiguousarray(a, dtype=float).reshape(-1, shape[-1]) for a in arrays]
    result = function(*rows)
    return result.reshape(*shape[:-1], *result.shape[1:])


def quaternion_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products a b of quaternions (..., 4) in (w, x, y, z) order."""
    if np.shape(a) != np.shape(b):
        a, b = np.broadcast_arrays(a, b)
    return _rows(multiply_quaternion_rows, a, b)


def quaternions_from_vectors(rotation_vectors: np.ndarray) -> np.ndarray:
    """Unit quaternions (..., 4) of rotation vectors (..., 3) [rad]."""
    return _rows(quaternion_rows_of_vectors, rotation_vectors)


def vectors_from_quaternions(quaternions_wxyz: np.ndarray) -> np.ndarray:
    """Rotation vectors (..., 3) [rad], angle in [0, pi], of unit quaternions (..., 4)."""
    return _rows(vector_rows_of_quaternions, quaternions_wxyz)


def to_matrices(quaternions_wxyz: np.ndarray) -> np.ndarray:
    """Rotation matrices (k, 3, 3) of quaternions (k, 4), each normalised first."""
    return _rows(matrix_rows_of_quaternions, quaternions_wxyz)


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
