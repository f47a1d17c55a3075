"""Wrench bookkeeping: limb wrenches to a resultant, and the ZMP of a resultant.

A wrench is (force [N], moment [N m]) as a 6-vector; "about the origin" and "about the CoM"
say which point the moment is taken about. Limb wrenches are expressed in the limb's contact
frame about its origin (the `Sensors` convention).
"""

from __future__ import annotations

import numpy as np
from numba import njit

_NEXT, _LAST = np.array([1, 2, 0]), np.array([2, 0, 1])  # component i of a x b: a_next b_last - ...


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b for 3-vectors or (k, 3) stacks (numpy's `cross` costs 14-40 us a call)."""
    if a.ndim == 1 and b.ndim == 1:
        a0, a1, a2 = a.tolist()
        b0, b1, b2 = b.tolist()
        return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
    # take() keeps the result C-ordered, like numpy's cross (fancy indexing would give an
    # F-ordered stack, and BLAS products with it round differently)
    return a.take(_NEXT, axis=-1) * b.take(_LAST, axis=-1) - a.take(_LAST, axis=-1) * b.take(
        _NEXT, axis=-1
    )


@njit(cache=True)
def _resultant(positions: np.ndarray, rotations: np.ndarray, wrenches: np.ndarray) -> np.ndarray:
    total = np.zeros(6)
    for k in range(len(positions)):
        r, w, p = rotations[k], wrenches[k], positions[k]
        f = r[:, 0] * w[0] + r[:, 1] * w[1] + r[:, 2] * w[2]  # R f_frame
        n = r[:, 0] * w[3] + r[:, 1] * w[4] + r[:, 2] * w[5]  # R n_frame
        total[0] += f[0]
        total[1] += f[1]
        total[2] += f[2]
        total[3] += n[0] + (p[1] * f[2] - p[2] * f[1])
        total[4] += n[1] + (p[2] * f[0] - p[0] * f[2])
        total[5] += n[2] + (p[0] * f[1] - p[1] * f[0])
    return total


def resultant_about_origin(
    frame_positions_world: np.ndarray,
    frame_rotations_world: np.ndarray,
    wrenches_in_frame: np.ndarray,
) -> np.ndarray:
    """Sum of limb wrenches (k, 6) given in their frames (positions (k, 3) [m], rotations
    (k, 3, 3)) as one world wrench about the world origin (compiled: one call)."""
    return _resultant(
        np.ascontiguousarray(frame_positions_world, dtype=float),
        np.ascontiguousarray(frame_rotations_world, dtype=float),
        np.ascontiguousarray(wrenches_in_frame, dtype=float),
    )


def shift_moment(wrench: np.ndarray, from_point: np.ndarray, to_point: np.ndarray) -> np.ndarray:
    """The same wrench with its moment taken about `to_point` instead of `from_point` [m]:
    n_to = n_from + (from - to) x f."""
    force, moment = wrench[:3], wrench[3:]
    return np.concatenate([force, moment + cross(from_point - to_point, force)])


def zmp_on_plane(wrench_about_origin: np.ndarray, height: float = 0.0) -> np.ndarray:
    """The zero-moment point of a world wrench about the origin on the horizontal plane
    z = `height` [m]: the point where the horizontal moment vanishes. NaN when the vertical
    force is not positive."""
    fx, fy, fz, nx, ny, _ = wrench_about_origin.tolist()
    if fz <= 1e-9:
        return np.full(3, np.nan)
    return np.array([(height * fx - ny) / fz, (nx + height * fy) / fz, height])
