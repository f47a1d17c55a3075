"""Issue 16's compiled kernels against the numpy formulas they replaced (kept here as the
references): the damping control of eqs. 15-16, the IK's QP terms and pose errors, the
estimator's one-pass kinematics, the scenario lookups by bisection, the linear MPC's face
rows. Bounds are rounding."""

import numpy as np
import pinocchio as pin
import pytest
from scipy.spatial.transform import Rotation

from bench.scenarios import make_scenario
from centroidal.cone_faces import cone_faces
from centroidal.kernels import damping_control, face_rows_hold, pose_errors, unit_face_rows
from estimators.kinematic_inertial import KinematicInertialEstimator
from robots.humanoid import humanoid
from robots.limbs import PhaseContacts, limb_surfaces
from robots.model import RobotModel
from robots.scene import Scene
from sims.base import make_simulator
from wholebody.ik import qp_terms


@pytest.fixture(scope="module")
def model():
    return RobotModel(humanoid())


def quaternions(rng, k):
    return Rotation.random(k, random_state=rng).as_quat(scalar_first=True)


def _damping_world_axes(positions, targets, measured, desired, kd, ks, kf, dt, linear, angular):
    """The world-axes form that the kernel had until issue 19 (numpy): errors R (w_a - w_d),
    Euler on the linear compliance, the rotation by dt times the rate composed on SO(3), the
    compliance applied before the target (exp(p) R). Updates linear and angular in place."""
    rotation = Rotation.from_quat(
        targets / np.linalg.norm(targets, axis=1, keepdims=True), scalar_first=True
    )
    difference = (measured - desired).reshape(len(targets), 2, 3)
    error = np.concatenate([rotation.apply(difference[:, 0]), rotation.apply(difference[:, 1])], 1)
    linear += dt * (kf[:, :3] * error[:, :3] - ks[:, :3] * linear) / kd[:, :3]
    rate = (kf[:, 3:] * error[:, 3:] - ks[:, 3:] * angular) / kd[:, 3:]
    angular[:] = (Rotation.from_rotvec(dt * rate) * Rotation.from_rotvec(angular)).as_rotvec()
    orientation = (Rotation.from_rotvec(angular) * rotation).as_quat(scalar_first=True)
    return positions + linear, orientation


def _same_quaternions(a, b, atol):
    np.testing.assert_allclose(a, np.sign(a[:, :1] * b[:, :1]) * b, rtol=0, atol=atol)


def test_damping_kernel_is_eqs_15_16_in_the_contact_frame():
    """Eq. 15 per axis of each limb's contact frame (the target's): Kd dp/dt = Kf (w_a - w_d)
    - Ks p with the errors as measured (limb frames), Euler on the linear compliance, the
    rotation by dt times the rate composed on SO(3); the compliant pose is the target moved by
    R p and turned by exp(p) about its own axes."""
    rng = np.random.default_rng(15)
    k, dt = 4, 0.002
    targets = quaternions(rng, k) * 1.7  # not unit: the kernel normalises
    positions = rng.normal(size=(k, 3))
    measured, desired = rng.normal(scale=50, size=(2, k, 6))
    kd, ks, kf = rng.uniform(1, 1e4, (3, k, 6))
    linear, angular = rng.normal(scale=0.01, size=(2, k, 3))
    linear_kernel, angular_kernel = linear.copy(), angular.copy()
    position, orientation = damping_control(
        positions, targets, measured, desired, kd, ks, kf, dt, linear_kernel, angular_kernel
    )

    unit = targets / np.linalg.norm(targets, axis=1, keepdims=True)
    rotation = Rotation.from_quat(unit, scalar_first=True)
    error = measured - desired
    linear_expected = linear + dt * (kf[:, :3] * error[:, :3] - ks[:, :3] * linear) / kd[:, :3]
    rate = (kf[:, 3:] * error[:, 3:] - ks[:, 3:] * angular) / kd[:, 3:]
    turned = Rotation.from_rotvec(dt * rate) * Rotation.from_rotvec(angular)
    angular_expected = turned.as_rotvec()
    orientation_expected = (rotation * Rotation.from_rotvec(angular_expected)).as_quat(
        scalar_first=True
    )
    np.testing.assert_allclose(linear_kernel, linear_expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(angular_kernel, angular_expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(
        position, positions + rotation.apply(linear_expected), rtol=0, atol=1e-12
    )
    _same_quaternions(orientation, orientation_expected, 1e-12)
    assert np.abs(linear_kernel - linear).max() > 1e-6  # the update did something


def _table_ii_contact(k):
    from stabilizers.centroidal_feedback import TABLE_II

    return [
        np.tile(np.array(TABLE_II["contact"][x], dtype=float), (k, 1)) for x in ("kd", "ks", "kf")
    ]


def test_contact_frame_damping_is_the_world_axes_one_for_a_horizontal_contact():
    """Soles on flat ground turned by any yaw, Table II's contact gains (equal for x and y):
    200 periods of random wrench errors give the same compliant poses as the world-axes form
    it replaced, to rounding."""
    rng = np.random.default_rng(19)
    k, dt = 2, 0.002
    yaw = rng.uniform(-np.pi, np.pi, k)
    targets = Rotation.from_euler("z", yaw[:, None]).as_quat(scalar_first=True)
    positions = rng.normal(size=(k, 3))
    kd, ks, kf = _table_ii_contact(k)
    contact = [np.zeros((k, 3)) for _ in range(2)]
    world = [np.zeros((k, 3)) for _ in range(2)]
    for _ in range(200):
        measured, desired = rng.normal(scale=50, size=(2, k, 6))
        position, orientation = damping_control(
            positions, targets, measured, desired, kd, ks, kf, dt, *contact
        )
        expected = _damping_world_axes(
            positions, targets, measured, desired, kd, ks, kf, dt, *world
        )
        np.testing.assert_allclose(position, expected[0], rtol=0, atol=1e-12)
        _same_quaternions(orientation, expected[1], 1e-12)
    assert np.abs(position - positions).max() > 1e-4  # it moved


def test_contact_frame_damping_on_a_wall_acts_about_the_wall_normal_as_table_ii_says():
    """A palm on a wall beside the robot: its contact normal (sole-frame z) along world -y.
    Table II for a contact: the moment about the normal has Kf = 0 and Ks = 2000, the
    tangential ones Kf = 1, Kd = 100 (eq. 15). A 5 N m moment error about the normal leaves
    the palm unturned in the contact frame; the world-axes form turned it about the normal at
    Kf m / Kd = 0.05 rad/s (world y carries the tangential gains). A 5 N m moment about the
    world z (a tangent of the wall) turns the palm at 0.05 rad/s about it; the world-axes form
    applied the normal's Kf = 0 to it and did not."""
    dt = 0.002
    wall = Rotation.from_euler("x", 90.0, degrees=True)  # sole z -> world -y
    np.testing.assert_allclose(wall.apply([0.0, 0.0, 1.0]), [0.0, -1.0, 0.0], atol=1e-15)
    targets = wall.as_quat(scalar_first=True)[None, :]
    positions = np.zeros((1, 3))
    kd, ks, kf = _table_ii_contact(1)
    for axis_world in ([0.0, -1.0, 0.0], [0.0, 0.0, 1.0]):  # the normal, then a tangent
        moment_limb = wall.inv().apply(5.0 * np.array(axis_world))
        measured = np.concatenate([np.zeros(3), moment_limb])[None, :]
        contact = [np.zeros((1, 3)) for _ in range(2)]
        world = [np.zeros((1, 3)) for _ in range(2)]
        _, orientation = damping_control(
            positions, targets, measured, np.zeros((1, 6)), kd, ks, kf, dt, *contact
        )
        _, old = _damping_world_axes(
            positions, targets, measured, np.zeros((1, 6)), kd, ks, kf, dt, *world
        )
        turn = (Rotation.from_quat(orientation, scalar_first=True) * wall.inv()).as_rotvec()[0]
        turn_old = (Rotation.from_quat(old, scalar_first=True) * wall.inv()).as_rotvec()[0]
        expected = dt * 5.0 / 100.0 * np.array(axis_world)
        if axis_world[1]:  # about the normal
            np.testing.assert_allclose(turn, 0.0, atol=1e-15)
            np.testing.assert_allclose(turn_old, expected, rtol=1e-9, atol=1e-15)
        else:  # about a tangent
            np.testing.assert_allclose(turn, expected, rtol=1e-9, atol=1e-15)
            np.testing.assert_allclose(turn_old, 0.0, atol=1e-15)


def test_ik_qp_terms_are_the_weighted_least_squares_in_numpy():
    rng = np.random.default_rng(16)
    n_rows, nv, joints = 30, 26, 20
    jacobian, weight, error = (
        rng.normal(size=(n_rows, nv)),
        rng.uniform(0, 1e3, n_rows),
        rng.normal(size=n_rows),
    )
    gain, posture, damping = 0.7, 1e-2, 1e-6
    nominal, q = rng.normal(size=(2, joints))
    lower_limit, upper_limit = q - rng.uniform(0, 0.1, joints), q + rng.uniform(0, 0.1, joints)
    max_step = rng.uniform(0, 0.05, joints)
    damping_and_posture = damping * np.eye(nv)
    damping_and_posture[6:, 6:] += posture * np.eye(joints)
    lower, upper = np.full(nv, -1.0), np.full(nv, 1.0)
    hessian, gradient = qp_terms(
        jacobian,
        weight,
        error,
        gain,
        damping_and_posture,
        posture,
        nominal,
        q,
        lower_limit,
        upper_limit,
        max_step,
        lower,
        upper,
    )
    # the stacked form the kernel replaced: the posture task as rows [0 I]
    rows = np.vstack([jacobian, np.hstack([np.zeros((joints, 6)), np.eye(joints)])])
    weights = np.concatenate([weight, np.full(joints, posture)])
    errors = np.concatenate([error, nominal - q]) * gain
    np.testing.assert_allclose(
        hessian, rows.T @ (weights[:, None] * rows) + damping * np.eye(nv), rtol=1e-12
    )
    np.testing.assert_allclose(
        gradient, -(weights[:, None] * rows).T @ errors, rtol=1e-12, atol=1e-12
    )
    np.testing.assert_array_equal(lower[6:], np.minimum(np.maximum(lower_limit - q, -max_step), 0))
    np.testing.assert_array_equal(upper[6:], np.maximum(np.minimum(upper_limit - q, max_step), 0))
    np.testing.assert_array_equal(lower[:6], -1.0)  # the base's bounds are left alone


def test_pose_errors_are_positions_and_pinocchio_log3():
    rng = np.random.default_rng(17)
    targets, actual = quaternions(rng, 3), Rotation.random(3, random_state=rng).as_matrix()
    target_positions, positions = rng.normal(size=(2, 2, 3))
    errors = pose_errors(target_positions, targets, positions, actual)
    for i in range(3):
        target = Rotation.from_quat(targets[i], scalar_first=True).as_matrix()
        np.testing.assert_allclose(errors[i, 3:], pin.log3(target @ actual[i].T), atol=1e-12)
    np.testing.assert_allclose(errors[:2, :3], target_positions - positions, atol=0)
    np.testing.assert_array_equal(errors[2, :3], 0.0)


def test_estimator_one_pass_equals_kinematics_at_the_estimated_base(model):
    """The CoM, its velocity and the measured ZMP of the shifted single pass equal a second
    full pass at the estimated state (the way `_complete` computes them)."""
    initial = model.standing_state()
    command = model.hold_command(initial)
    estimator, reference = KinematicInertialEstimator(model), KinematicInertialEstimator(model)
    sim = make_simulator("mujoco")
    try:
        sensors = sim.reset(model.robot, Scene(), initial)
        estimator.reset(initial, sensors)
        for k in range(300):
            if k == 100:
                sim.push(model.robot.base_link, np.array([8.0, -5.0, 0.0]), 0.1)
            sensors = sim.step(command)
            state = estimator.estimate(sensors)
        full = reference._complete(state, sensors)  # a full pass at the estimated state
    finally:
        sim.close()
    np.testing.assert_allclose(state.com_position_world, full.com_position_world, atol=1e-12)
    np.testing.assert_allclose(state.com_velocity_world, full.com_velocity_world, atol=1e-12)
    np.testing.assert_allclose(state.zmp_world, full.zmp_world, atol=1e-9)
    assert np.linalg.norm(state.com_velocity_world) > 1e-3  # the push moved it


@pytest.mark.parametrize("name", ["walk", "walk_side", "walk_turn", "stand_push"])
def test_scenario_lookups_by_bisection_equal_the_scan(model, name):
    """`phase_at` and `limb_pose` (bisection over the phases) against the linear scan they
    replaced (the code path for phases out of time order), bit for bit, every 1 ms."""
    scenario = make_scenario(name, model)
    times = np.arange(-0.1, scenario.duration + 0.3, 0.001)
    limbs = model.robot.limb_names

    def lookups():
        return [
            (scenario.phase_at(t), [scenario.limb_pose(limb, t) for limb in limbs]) for t in times
        ]

    fast = lookups()
    assert scenario._timeline is not None  # the bisection was used
    scenario.__dict__["_timeline"] = None  # force the scan
    slow = lookups()
    for (phase_fast, poses_fast), (phase_slow, poses_slow) in zip(fast, slow, strict=True):
        assert phase_fast is phase_slow
        for a, b in zip(poses_fast, poses_slow, strict=True):
            assert (a is None) == (b is None)
            if a is not None:
                np.testing.assert_array_equal(a[0], b[0])
                np.testing.assert_array_equal(a[1], b[1])


def test_mpc_face_rows_are_the_numpy_expression_to_the_bit(model):
    """The face form's unit rows F_k T_k^-1 / norm (`unit_face_rows`) and its check C'U >=
    -slack (`face_rows_hold`) against the numpy expressions `FaceForm.solve` had before them:
    equal to the bit (the same products and sums in the same order), so that the MPC's
    answers did not change. Faces of `walk`'s double and single supports, 20 samples."""
    scenario = make_scenario("walk", model)
    contacts = PhaseContacts(limb_surfaces(model.robot, scenario.scene.friction))
    phases = [scenario.phase_at(t) for t in (0.5, 1.0)]
    cones = [cone_faces(contacts(phase)[0].matrix) for phase in phases]
    assert phases[0].limbs != phases[1].limbs  # two feet, then one
    rng = np.random.default_rng(5)
    faces = [cones[k % 3 == 0] for k in range(20)]
    sizes = [len(f) for f in faces]
    stacked, sample = np.vstack(faces), np.repeat(np.arange(20), sizes)
    points = rng.normal(scale=0.3, size=(20, 3)) + np.array([0.0, 0.0, 0.8])
    about = np.repeat(points, sizes, axis=0)
    rows = stacked.copy()
    rows[:, :3] += np.cross(stacked[:, 3:], about)
    rows /= np.sqrt(np.einsum("ij,ij->i", rows, rows))[:, None]
    kernel = unit_face_rows(stacked, sample, points)
    assert np.array_equal(kernel, rows)
    inputs = rng.normal(scale=50.0, size=(20, 6)) + np.array([0.0, 0.0, 570.0, 0.0, 0.0, 0.0])
    slack = np.full(len(rows), 1e-9)
    expected = np.einsum("ij,ij->i", -rows, inputs[sample]) >= -slack
    assert 0 < expected.sum() < len(rows)  # some rows hold, some do not
    assert np.array_equal(face_rows_hold(kernel, sample, inputs, slack), expected)
    # at the threshold itself, where only the same sum in the same order decides: every row
    # holds with its own value as the slack, none with the next float below it
    value = np.einsum("ij,ij->i", rows, inputs[sample])
    assert face_rows_hold(kernel, sample, inputs, value).all()
    assert not face_rows_hold(kernel, sample, inputs, np.nextafter(value, -np.inf)).any()
