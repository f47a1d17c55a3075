"""Projected angles (Ficht & Behnke Sec. 3.4) and eq. 13's flywheel angle."""

import math

import numpy as np
import pytest

from centroidal.tilt import angles_of_axis, axis_from_angles, flywheel_angles


@pytest.mark.parametrize("angles", [(0.0, 0.0), (0.3, 0.0), (0.0, -0.2), (0.25, -0.4)])
def test_projected_angles_round_trip(angles):
    assert angles_of_axis(axis_from_angles(*angles)) == pytest.approx(angles, abs=1e-12)


def test_projected_angles_are_the_projections_angles_from_the_vertical():
    """theta_x is the angle of the axis's projection onto the xz plane, whatever its y part."""
    axis = np.array([1.0, 2.0, 1.0])
    assert angles_of_axis(axis) == pytest.approx([math.pi / 4, math.atan(2.0)], abs=1e-12)


def test_the_flywheel_is_at_zero_along_the_pendulum_however_long_either_vector():
    pendulum = np.array([0.03, -0.02, 0.8])  # feet's midpoint to CoM [m]
    assert flywheel_angles(5.0 * pendulum, pendulum) == pytest.approx([0.0, 0.0], abs=1e-12)


def test_the_flywheel_angle_is_the_axis_tilt_from_the_pendulum_in_each_plane():
    pendulum = axis_from_angles(0.2, -0.1) * 0.75
    axis = axis_from_angles(0.2 + 0.05, -0.1 - 0.03)
    assert flywheel_angles(axis, pendulum) == pytest.approx([0.05, -0.03], abs=1e-12)


@pytest.mark.parametrize("angles", [(0.0, 0.0), (0.2, 0.0), (-0.1, 0.3), (0.6, -0.5)])
def test_tilt_rotation_is_the_least_rotation_taking_z_onto_the_axis(angles):
    """Eq. 5's and eq. 12's tilt (Rodrigues): a proper rotation that takes the world z axis
    onto the axis, about an axis in the horizontal plane (no yaw: the least angle)."""
    import pinocchio as pin

    from centroidal.tilt import tilt_rotation

    axis = axis_from_angles(*angles)
    rotation = tilt_rotation(axis)
    np.testing.assert_allclose(rotation @ [0.0, 0.0, 1.0], axis, atol=1e-12)
    np.testing.assert_allclose(rotation.T @ rotation, np.eye(3), atol=1e-12)
    assert np.linalg.det(rotation) == pytest.approx(1.0, abs=1e-12)
    rotation_vector = pin.log3(rotation)
    assert rotation_vector[2] == pytest.approx(0.0, abs=1e-12)
    assert np.linalg.norm(rotation_vector) == pytest.approx(math.acos(axis[2]), abs=1e-12)
