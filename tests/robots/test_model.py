"""The pinocchio model's centroidal quantities against independent computations from the
description, and the static torques against the equilibrium they claim."""

import numpy as np
import pinocchio as pin
import pytest

from centroidal.rotations import to_matrix
from robots.humanoid import humanoid
from robots.model import RobotModel
from robots.types import RobotState


@pytest.fixture(scope="module")
def model():
    return RobotModel(humanoid())


def _link_poses(model, state):
    """World pose of every link from pinocchio's joint placements (link frame = joint frame)."""
    q = model.configuration(state)
    data = model.model.createData()
    pin.forwardKinematics(model.model, data, q)
    child = {j.name: j.child for j in model.robot.joints}
    poses = {model.robot.base_link: data.oMi[1]}
    for i in range(2, model.model.njoints):
        poses[child[model.model.names[i]]] = data.oMi[i]
    return poses


def _random_joints(robot, rng, spread: float) -> np.ndarray:
    """The nominal posture moved by up to +-spread [rad] per joint, inside the limits."""
    return np.clip(
        np.array(robot.nominal_posture) + rng.uniform(-spread, spread, robot.n_joints),
        robot.array("lower"),
        robot.array("upper"),
    )


def test_rigid_rotation_momentum_equals_sum_over_links(model):
    """Joints still, the whole robot spinning at omega about its base: the angular momentum
    about the CoM is sum_i (R_i I_i R_i^T omega + m_i r_i x (omega x r_i)), r_i from the CoM to
    link i's CoM, computed here from the description's link inertias."""
    robot = model.robot
    rng = np.random.default_rng(2)
    joints = _random_joints(robot, rng, 0.4)
    quaternion = rng.normal(size=4)
    quaternion /= np.linalg.norm(quaternion)
    omega = np.array([0.3, -0.5, 0.8])
    base = np.array([0.1, 0.2, 0.9])
    com = model.com_position_world(RobotState.at_rest(base, quaternion, joints))
    # the base origin moves with omega about the CoM, so the CoM itself is still
    state = RobotState(
        base, quaternion, np.cross(omega, base - com), omega, joints, np.zeros(robot.n_joints)
    )
    expected = np.zeros(3)
    for link in robot.links:
        pose = _link_poses(model, state)[link.name]
        rotation = pose.rotation
        link_com = pose.translation + rotation @ np.array(link.inertial.com_in_link)
        r = link_com - com
        inertia = rotation @ link.inertial.inertia_matrix @ rotation.T
        expected += inertia @ omega + link.inertial.mass * np.cross(r, np.cross(omega, r))
    linear, angular = model.centroidal_momentum(state)
    np.testing.assert_allclose(linear, 0.0, atol=1e-9)
    np.testing.assert_allclose(angular, expected, rtol=1e-9, atol=1e-9)
    # Murooka eq. 6: with joints still, L = I_all qdot = I_base omega
    np.testing.assert_allclose(model.inertia_base(state) @ omega, expected, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(
        model.inertia_all(state) @ model.velocity(state), expected, rtol=1e-9, atol=1e-9
    )


def test_constant_inertia_is_diagonal_and_physical(model):
    inertia = model.constant_inertia()
    np.testing.assert_array_equal(inertia, np.diag(np.diag(inertia)))
    ixx, iyy, izz = np.diag(inertia)
    assert min(ixx, iyy, izz) > 0
    assert ixx + iyy >= izz  # triangle inequality of a real body
    # a 58 kg, 0.8 m-tall-above-ground body: pitch/roll inertia about its CoM ~ m h^2 / 12..4
    mass = model.robot.total_mass
    assert mass * 0.5**2 / 12 < iyy < mass * 1.6**2 / 4


def test_static_torques_balance_gravity(model):
    """tau = g_j - J_j^T w with g_b = J_b^T w: the whole generalised force balance holds and
    the feet carry m g vertically."""
    state = model.standing_state()
    feet = ["left_sole", "right_sole"]
    torque = model.static_torques(state, feet)
    q = model.configuration(state)
    gravity = pin.computeGeneralizedGravity(model.model, model.model.createData(), q)
    jacobian = np.vstack([model.frame_jacobian(state, f) for f in feet])
    wrenches = np.linalg.lstsq(jacobian[:, :6].T, gravity[:6], rcond=None)[0]
    np.testing.assert_allclose(jacobian[:, :6].T @ wrenches, gravity[:6], atol=1e-8)
    np.testing.assert_allclose(gravity[6:] - jacobian[:, 6:].T @ wrenches, torque, atol=1e-8)
    vertical = wrenches[2] + wrenches[8]
    assert vertical == pytest.approx(model.robot.total_mass * 9.81, rel=1e-9)


def test_frame_pose_orientation_matches_base_in_zero_posture(model):
    robot = model.robot
    quaternion = np.array([np.cos(0.2), 0.0, np.sin(0.2), 0.0])
    state = RobotState.at_rest(np.zeros(3), quaternion, np.zeros(robot.n_joints))
    _, rotation = model.frame_pose(state, "left_palm")
    np.testing.assert_allclose(rotation, to_matrix(quaternion), atol=1e-12)


def test_com_state_and_frame_position_match_their_own_passes(model):
    """The runner's one-pass ground truth (centre of mass, its velocity, a palm) equals the
    separate passes, in a random posture and motion, even after the scratch data was left by
    another state (the frame must be placed from this state's joints, not a stale pass)."""
    robot = model.robot
    rng = np.random.default_rng(5)
    joints = _random_joints(robot, rng, 0.5)
    quaternion = rng.normal(size=4)
    state = RobotState(
        rng.normal(size=3),
        quaternion / np.linalg.norm(quaternion),
        rng.normal(size=3),
        rng.normal(size=3),
        joints,
        rng.normal(size=robot.n_joints),
    )
    model.frame_positions_world(model.standing_state(), ["right_palm"])  # stale scratch data
    com, com_velocity, palm = model.com_state_and_frame_position_world(state, "right_palm")
    expected_com, expected_velocity = model.com_state_world(state)
    np.testing.assert_allclose(com, expected_com, rtol=0, atol=1e-12)
    np.testing.assert_allclose(com_velocity, expected_velocity, rtol=0, atol=1e-12)
    standing_palm = model.frame_positions_world(model.standing_state(), ["right_palm"])[0]
    np.testing.assert_allclose(
        palm, model.frame_positions_world(state, ["right_palm"])[0], rtol=0, atol=1e-12
    )
    assert np.linalg.norm(palm - standing_palm) > 0.1  # a different place: not stale
