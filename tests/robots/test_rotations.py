"""The numpy rotation helpers against scipy."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from centroidal import rotations


@pytest.mark.parametrize("seed", range(50))
def test_rotations_agree_with_scipy(seed):
    reference = Rotation.random(random_state=seed)
    matrix = reference.as_matrix()
    x, y, z, w = reference.as_quat()
    np.testing.assert_allclose(rotations.to_matrix(np.array([w, x, y, z])), matrix, atol=1e-12)
    back = rotations.from_matrix(matrix)
    assert back[0] >= 0
    np.testing.assert_allclose(np.abs(back @ [w, x, y, z]), 1.0, atol=1e-12)
    np.testing.assert_allclose(rotations.log(matrix), reference.as_rotvec(), atol=1e-9)
    np.testing.assert_allclose(rotations.exp(reference.as_rotvec()), matrix, atol=1e-12)


@pytest.mark.parametrize("angle", [0.0, 1e-8, np.pi - 1e-7, np.pi])
def test_log_near_zero_and_pi(angle):
    axis = np.array([1.0, -2.0, 0.5]) / np.linalg.norm([1.0, -2.0, 0.5])
    matrix = Rotation.from_rotvec(angle * axis).as_matrix()
    result = rotations.exp(rotations.log(matrix))
    np.testing.assert_allclose(result, matrix, atol=1e-6)


def _wxyz(rotation: Rotation) -> np.ndarray:
    return np.roll(rotation.as_quat(), 1, axis=-1)


def test_batched_rotations_agree_with_scipy():
    a, b = Rotation.random(64, random_state=1), Rotation.random(64, random_state=2)
    product = rotations.quaternion_multiply(_wxyz(a), _wxyz(b))
    np.testing.assert_allclose(np.abs(np.sum(product * _wxyz(a * b), axis=1)), 1.0, atol=1e-12)
    vectors = a.as_rotvec()
    quaternions = rotations.quaternions_from_vectors(vectors)
    np.testing.assert_allclose(np.abs(np.sum(quaternions * _wxyz(a), axis=1)), 1.0, atol=1e-12)
    np.testing.assert_allclose(rotations.vectors_from_quaternions(quaternions), vectors, atol=1e-9)
    np.testing.assert_allclose(rotations.to_matrices(_wxyz(a)), a.as_matrix(), atol=1e-12)


@pytest.mark.parametrize("angle", [0.0, 1e-12, 1e-7, 1e-3, np.pi - 1e-7])
def test_batched_rotation_vectors_near_zero_and_pi(angle):
    axis = np.array([1.0, -2.0, 0.5]) / np.linalg.norm([1.0, -2.0, 0.5])
    vector = np.array([angle * axis, -angle * axis])
    quaternions = rotations.quaternions_from_vectors(vector)
    np.testing.assert_allclose(np.linalg.norm(quaternions, axis=1), 1.0, atol=1e-15)
    np.testing.assert_allclose(rotations.vectors_from_quaternions(quaternions), vector, atol=1e-9)
    np.testing.assert_allclose(
        rotations.to_matrices(quaternions), Rotation.from_rotvec(vector).as_matrix(), atol=1e-12
    )
