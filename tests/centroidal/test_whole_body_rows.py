"""`centroidal.whole_body_rows`: Jacobians and drifts against finite differences of the
kinematics along a motion with constant generalized acceleration (the pink / mink rule: every
Jacobian checked by finite differences), and H, h against pinocchio's RNEA."""

import numpy as np
import pinocchio as pin
import pytest

from centroidal.whole_body_rows import whole_body_terms
from robots.humanoid import humanoid
from robots.model import cached_model


@pytest.fixture(scope="module")
def model():
    return cached_model(humanoid())


def _frames_and_com(pin_model, data, q, frames):
    pin.framesForwardKinematics(pin_model, data, q)
    positions = {f: data.oMf[f].translation.copy() for f in frames}
    rotations = {f: data.oMf[f].rotation.copy() for f in frames}
    return positions, rotations, pin.centerOfMass(pin_model, data, q).copy()


@pytest.mark.parametrize("seed", [0, 1])
def test_task_accelerations_equal_second_differences_of_the_motion(model, seed):
    """Along q(t) with q'(0) = v, q''= a (base twist integrated on the group), each frame's
    position and the CoM have second differences J a + J' v (and first differences J v), and
    each frame's angular velocity changes at the angular rows' rate, to the differences'
    accuracy (h = 1e-4 s)."""
    rng = np.random.default_rng(seed)
    pin_model, data = model.model, model.model.createData()
    robot = model.robot
    joints = rng.uniform(robot.array("lower"), robot.array("upper"))
    q = np.concatenate(
        [
            [0.1, -0.2, 0.8],
            pin.Quaternion(pin.AngleAxis(0.3, np.array([0.6, 0.8, 0]))).coeffs(),
            joints,
        ]
    )
    v = rng.normal(size=pin_model.nv)
    a = rng.normal(size=pin_model.nv)
    frames = [model.frame_id[limb.contact_frame] for limb in robot.limbs] + [
        model.frame_id[robot.base_link]
    ]
    terms = whole_body_terms(pin_model, data, q, v, frames)
    # central differences at h: truncation O(h^2), rounding about 1e-16 / h^2, both near 1e-8
    # (measured at most 1.6e-7); 1e-5 allows the third derivatives of a random motion
    h = 1e-4
    states = {
        s: pin.integrate(pin_model, q, s * v * h + 0.5 * s * s * a * h * h) for s in (-1, 0, 1)
    }
    kinematics = {s: _frames_and_com(pin_model, data, states[s], frames) for s in states}
    for f in frames:
        p = {s: kinematics[s][0][f] for s in states}
        velocity = (p[1] - p[-1]) / (2 * h)
        acceleration = (p[1] - 2 * p[0] + p[-1]) / (h * h)
        np.testing.assert_allclose(terms.jacobian[f][:3] @ v, velocity, rtol=0, atol=1e-6)
        expected = terms.jacobian[f][:3] @ a + terms.drift[f][:3]
        np.testing.assert_allclose(expected, acceleration, rtol=0, atol=1e-5)
        # angular: world angular velocity from the rotations, then its rate
        rotation = {s: kinematics[s][1][f] for s in states}
        omega_plus = pin.log3(rotation[1] @ rotation[0].T) / h
        omega_minus = pin.log3(rotation[0] @ rotation[-1].T) / h
        np.testing.assert_allclose(
            terms.jacobian[f][3:] @ v, (omega_plus + omega_minus) / 2, rtol=0, atol=1e-5
        )
        np.testing.assert_allclose(
            terms.jacobian[f][3:] @ a + terms.drift[f][3:],
            (omega_plus - omega_minus) / h,
            rtol=0,
            atol=1e-5,
        )
    c = {s: kinematics[s][2] for s in states}
    np.testing.assert_allclose(terms.com_jacobian @ v, (c[1] - c[-1]) / (2 * h), atol=1e-6)
    np.testing.assert_allclose(
        terms.com_jacobian @ a + terms.com_drift, (c[1] - 2 * c[0] + c[-1]) / (h * h), atol=1e-5
    )


def test_mass_matrix_and_bias_are_the_dynamics(model):
    """H a + h equals RNEA(q, v, a) for a random state (H symmetric, full)."""
    rng = np.random.default_rng(3)
    pin_model, data = model.model, model.model.createData()
    q = pin.randomConfiguration(pin_model, -np.ones(pin_model.nq), np.ones(pin_model.nq))
    q[3:7] /= np.linalg.norm(q[3:7])
    v, a = rng.normal(size=pin_model.nv), rng.normal(size=pin_model.nv)
    terms = whole_body_terms(pin_model, data, q, v, [])
    np.testing.assert_allclose(terms.mass_matrix, terms.mass_matrix.T, atol=0)
    expected = pin.rnea(pin_model, pin_model.createData(), q, v, a)
    np.testing.assert_allclose(terms.mass_matrix @ a + terms.bias, expected, rtol=0, atol=1e-9)
