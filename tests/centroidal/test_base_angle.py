"""The base angle alpha (Murooka et al. Sec. III-A4): our rotation vector against the paper's
ZYX Euler angles."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from centroidal.base_angle import (
    base_angle,
    base_orientation,
    zyx_euler_angles,
    zyx_euler_orientation,
)


def _wxyz(rotation: Rotation) -> np.ndarray:
    x, y, z, w = rotation.as_quat()
    return np.array([w, x, y, z])


def test_zyx_euler_angles_are_scipys_intrinsic_zyx():
    rng = np.random.default_rng(0)
    for rotation in Rotation.random(50, random_state=rng):
        yaw, pitch, roll = rotation.as_euler("ZYX")
        np.testing.assert_allclose(
            zyx_euler_angles(_wxyz(rotation)), [roll, pitch, yaw], atol=1e-12
        )


def test_base_orientation_inverts_base_angle():
    """Up to 3 rad: nearer pi the log map loses digits, about as eps / (pi - angle)^2 (up to
    4e-10 at pi - 1.6e-3, 1e-11 at pi - 0.01, 5e-14 at pi - 0.14)."""
    rng = np.random.default_rng(1)
    for rotation in Rotation.random(200, random_state=rng):
        if rotation.magnitude() > 3.0:
            continue
        q = _wxyz(rotation)
        back = base_orientation(base_angle(q))
        assert min(np.abs(back - q).max(), np.abs(back + q).max()) < 1e-12


@pytest.mark.parametrize("axis", range(3))
def test_one_axis_rotations_give_the_same_alpha(axis):
    angle = np.zeros(3)
    angle[axis] = 0.7
    q = _wxyz(Rotation.from_rotvec(angle))
    np.testing.assert_allclose(base_angle(q), angle, atol=1e-12)
    np.testing.assert_allclose(zyx_euler_angles(q), angle, atol=1e-12)


def test_the_two_alphas_differ_at_second_order():
    """The adaptation is first-order exact: for tilts and turns of size e the two alphas differ
    by O(e^2) (here e = 0.01 -> 0.1 rad: the difference grows 100x), never O(e)."""
    direction = np.array([0.6, -0.3, 0.74])
    direction /= np.linalg.norm(direction)
    gaps = []
    for size in (0.01, 0.1):
        q = _wxyz(Rotation.from_euler("ZYX", size * direction[::-1]))
        gaps.append(np.abs(base_angle(q) - zyx_euler_angles(q)).max())
    assert 0 < gaps[0] < 0.01**2
    assert 50 < gaps[1] / gaps[0] < 200


def test_zyx_euler_orientation_inverts_zyx_euler_angles():
    rng = np.random.default_rng(2)
    for rotation in Rotation.random(50, random_state=rng):
        q = _wxyz(rotation)
        back = zyx_euler_orientation(zyx_euler_angles(q))
        assert min(np.abs(back - q).max(), np.abs(back + q).max()) < 1e-12
