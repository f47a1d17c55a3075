"""The `inverse_dynamics` layer: the torques it computes from (q'', f) reproduce q'' through
pinocchio's forward dynamics (ABA) with those contact forces (Sherikov et al. eq. 1)."""

import numpy as np
import pinocchio as pin
import pytest

from robots.humanoid import humanoid
from robots.model import cached_model
from robots.types import WholeBodyTargets
from wholebody.base import make_whole_body
from wholebody.inverse_dynamics import joint_torques


@pytest.fixture(scope="module")
def model():
    return cached_model(humanoid())


def _random_state(model, rng):
    pin_model = model.model
    robot = model.robot
    joints = rng.uniform(robot.array("lower"), robot.array("upper"))
    axis = rng.normal(size=3)
    quaternion = pin.Quaternion(pin.AngleAxis(rng.uniform(0, 0.5), axis / np.linalg.norm(axis)))
    q = np.concatenate([rng.normal(size=3), quaternion.coeffs(), joints])
    v = rng.normal(size=pin_model.nv)
    return q, v


def _targets(n_limbs: int, in_contact, wrenches, acceleration) -> WholeBodyTargets:
    """Targets with only what the layer reads: the contacts, their desired wrenches (limb
    frames) and q'' (None: not given)."""
    return WholeBodyTargets(
        com_position_world=np.zeros(3),
        base_orientation_world=np.array([1.0, 0, 0, 0]),
        limb_position_world=np.zeros((n_limbs, 3)),
        limb_orientation_world=np.tile([1.0, 0, 0, 0], (n_limbs, 1)),
        limb_in_contact=in_contact,
        com_desired_world=np.zeros(3),
        zmp_desired_world=np.zeros(3),
        contact_wrench_desired_limb=wrenches,
        generalized_acceleration=acceleration,
    )


def _consistent_motion(model, seed: int):
    """Random posture q, velocity v, joint accelerations and foot wrenches (limb frames); the
    base's accelerations from the base rows (eq. 2, M_bb a_b = sum J_c,b^T f - h_b - M_bj a_j,
    so that (q'', f) is consistent): (q, v, a, wrenches, in_contact, frames)."""
    rng = np.random.default_rng(seed)
    pin_model, data = model.model, model.model.createData()
    q, v = _random_state(model, rng)
    limbs = model.robot.limbs
    frames = [model.frame_id[limb.contact_frame] for limb in limbs]
    in_contact = np.array([limb.name.endswith("foot") for limb in limbs])
    wrenches = np.zeros((len(limbs), 6))
    wrenches[in_contact] = rng.normal(scale=[50, 50, 300, 10, 10, 5], size=(in_contact.sum(), 6))
    acceleration = np.zeros(pin_model.nv)
    acceleration[6:] = rng.normal(size=pin_model.nv - 6)
    mass_matrix = pin.crba(pin_model, data, q)
    mass_matrix = np.triu(mass_matrix) + np.triu(mass_matrix, 1).T
    bias = pin.rnea(pin_model, data, q, v, np.zeros(pin_model.nv))
    pin.computeJointJacobians(pin_model, data, q)
    pin.updateFramePlacements(pin_model, data)
    generalized_force = np.zeros(pin_model.nv)
    for k in np.flatnonzero(in_contact):
        generalized_force += (
            pin.getFrameJacobian(pin_model, data, frames[k], pin.LOCAL).T @ (wrenches[k])
        )
    rhs = generalized_force[:6] - bias[:6] - mass_matrix[:6, 6:] @ acceleration[6:]
    acceleration[:6] = np.linalg.solve(mass_matrix[:6, :6], rhs)
    return q, v, acceleration, wrenches, in_contact, frames


def _forward_dynamics(model, q, v, torque, wrenches, in_contact, frames) -> np.ndarray:
    """q'' of pinocchio's ABA with the joint torques and the limbs' wrenches as external
    forces (the base unactuated)."""
    pin_model = model.model
    external = [pin.Force.Zero() for _ in range(pin_model.njoints)]
    for k in np.flatnonzero(in_contact):
        frame = pin_model.frames[frames[k]]
        external[frame.parentJoint] += frame.placement.act(pin.Force(wrenches[k]))
    tau = np.concatenate([np.zeros(6), torque])
    return pin.aba(pin_model, pin_model.createData(), q, v, tau, external)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_torques_reproduce_the_accelerations_through_forward_dynamics(model, seed):
    """Random posture, velocity, joint accelerations and consistent foot wrenches: ABA with
    the computed torques and the wrenches as external forces gives q'' back to 1e-8."""
    q, v, acceleration, wrenches, in_contact, frames = _consistent_motion(model, seed)
    data = model.model.createData()
    torque = joint_torques(model, data, q, v, acceleration, wrenches, in_contact, frames)
    reproduced = _forward_dynamics(model, q, v, torque, wrenches, in_contact, frames)
    np.testing.assert_allclose(reproduced, acceleration, rtol=0, atol=1e-8)


def test_the_layer_takes_the_robot_s_own_velocity(model):
    """Through the layer, from a moving robot's `RobotState` (world-frame base twist, joint
    rates): its torques reproduce q'' through ABA at the state's velocity, so the Coriolis and
    centrifugal terms are those of the state (with the velocity dropped they differ by more
    than 1 N m and q'' is not reproduced)."""
    from robots.types import RobotState

    q, v, acceleration, wrenches, in_contact, frames = _consistent_motion(model, 3)
    rotation = pin.Quaternion(q[6], q[3], q[4], q[5]).toRotationMatrix()
    state = RobotState(
        q[:3], np.array([q[6], q[3], q[4], q[5]]), rotation @ v[:3], rotation @ v[3:6],
        q[7:], v[6:],
    )  # fmt: skip
    limbs = model.robot.limbs
    targets = _targets(len(limbs), in_contact, wrenches, acceleration)
    layer = make_whole_body("inverse_dynamics", model, 0.002)
    layer.reset(model, state)
    torque = layer.command(targets, state).torque_feedforward
    reproduced = _forward_dynamics(model, q, v, torque, wrenches, in_contact, frames)
    np.testing.assert_allclose(reproduced, acceleration, rtol=0, atol=1e-8)
    at_rest = joint_torques(
        model, model.model.createData(), q, np.zeros_like(v), acceleration, wrenches,
        in_contact, frames,
    )  # fmt: skip
    assert np.abs(torque - at_rest).max() > 1.0  # [N m] the velocity terms matter here


def test_the_layer_commands_pure_torque(model):
    """Zero servo gains: the command is the feed-forward torque alone; a standing robot at rest
    with its weight on the feet gets the static torques of `RobotModel.static_torques`."""
    state = model.standing_state()
    layer = make_whole_body("inverse_dynamics", model, 0.002)
    layer.reset(model, state)
    limbs = model.robot.limbs
    feet = [limb.contact_frame for limb in limbs if limb.name.endswith("foot")]
    # the static wrenches (least norm, world-aligned) expressed in each foot's frame
    q = model.configuration(state)
    data = model.model.createData()
    gravity = pin.computeGeneralizedGravity(model.model, data, q)
    pin.computeJointJacobians(model.model, data, q)
    pin.updateFramePlacements(model.model, data)
    jacobians = [
        pin.getFrameJacobian(model.model, data, model.frame_id[f], pin.LOCAL_WORLD_ALIGNED)
        for f in feet
    ]
    base = np.vstack(jacobians)[:, :6]
    world = base @ np.linalg.solve(base.T @ base, gravity[:6])
    wrenches = np.zeros((len(limbs), 6))
    in_contact = np.array([limb.name.endswith("foot") for limb in limbs])
    for i, k in enumerate(np.flatnonzero(in_contact)):
        rotation = data.oMf[model.frame_id[feet[i]]].rotation
        wrenches[k] = np.concatenate(
            [rotation.T @ world[6 * i : 6 * i + 3], rotation.T @ world[6 * i + 3 : 6 * i + 6]]
        )
    targets = _targets(len(limbs), in_contact, wrenches, np.zeros(model.model.nv))
    command = layer.command(targets, state)
    assert not command.kp.any()
    assert not command.kd.any()
    np.testing.assert_allclose(
        command.torque_feedforward, model.static_torques(state, feet), rtol=0, atol=1e-9
    )
    assert np.abs(command.torque_feedforward).max() > 1.0  # the legs carry the weight


def test_a_stabilizer_without_accelerations_is_refused(model):
    layer = make_whole_body("inverse_dynamics", model, 0.002)
    state = model.standing_state()
    limbs = model.robot.limbs
    targets = _targets(len(limbs), np.ones(len(limbs), dtype=bool), None, None)
    with pytest.raises(ValueError, match="generalized_acceleration"):
        layer.command(targets, state)
