"""Whole-body layers: the registry, `ik` (no feed-forward torque) against `ik_feedforward`
(static torques that carry the weight), and both holding a standing robot in the loop."""

import numpy as np
import pytest

from bench.controllers import controller_spec
from bench.runner import EpisodeSpec, run_episode
from robots.humanoid import humanoid
from robots.model import RobotModel
from tests.wholebody.test_ik import _targets_of
from wholebody.base import DEFAULT_WHOLE_BODY, WHOLE_BODY_LAYERS, make_whole_body

DT = 0.002


@pytest.fixture(scope="module")
def model():
    return RobotModel(humanoid())


def test_unknown_layer_lists_the_known_ones(model):
    with pytest.raises(
        KeyError,
        match=r"choose one of: five_mass_pose, five_mass_pose_bent, "
        r"five_mass_pose_bent_feedforward, five_mass_pose_feedforward, ik, ik_angular_momentum, "
        r"ik_feedforward, inverse_dynamics\W*$",  # every one, the last included
    ):
        make_whole_body("inverse_dynamics_someday", model, DT)
    assert DEFAULT_WHOLE_BODY in WHOLE_BODY_LAYERS.names()


def test_ik_layer_sends_no_feedforward_torque(model):
    state = model.standing_state()
    layer = make_whole_body("ik", model, DT)
    layer.reset(model, state)
    command = layer.command(_targets_of(model, state), state)
    assert command.torque_feedforward.shape == (model.robot.n_joints,)
    assert not command.torque_feedforward.any()
    np.testing.assert_allclose(command.position, state.joint_position, atol=1e-6)  # at rest


def test_ik_feedforward_layer_sends_the_static_torques(model):
    """Standing with the weight on the feet and no desired wrenches, the feed-forward is the
    least-norm static torque tau = g_j(q) - J_c,j^T lambda (`RobotModel.static_torques`)."""
    state = model.standing_state()
    layer = make_whole_body("ik_feedforward", model, DT)
    layer.reset(model, state)
    command = layer.command(_targets_of(model, state), state)
    feet = [limb.contact_frame for limb in model.robot.limbs if limb.name.endswith("foot")]
    np.testing.assert_allclose(
        command.torque_feedforward, model.static_torques(state, feet), atol=1e-6
    )
    assert np.abs(command.torque_feedforward).max() > 1.0  # the knees carry the weight


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_ik_feedforward_realises_desired_wrenches_in_the_limbs_frames(model, seed):
    """Desired foot wrenches (limb frames, about the contact-frame origin) on a tilted and
    bent configuration: the feed-forward is the static torque g_j(q) - sum J_c,j^T f_c, the
    `inverse_dynamics` layer's at rest (eq. 1 with v = a = 0, its Jacobians in the LOCAL frame,
    this layer's world-aligned with the wrenches rotated), to 1e-9 N m. On a level robot the
    soles' axes are the world's, and a wrench left unrotated passed."""
    from dataclasses import replace

    import pinocchio as pin

    from wholebody.inverse_dynamics import joint_torques

    rng = np.random.default_rng(seed)
    state = model.standing_state()
    layer = make_whole_body("ik_feedforward", model, DT)
    layer.reset(model, state)
    q = layer.ik.q.copy()
    q[7:] += rng.uniform(-0.3, 0.3, model.robot.n_joints)
    q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(*rng.uniform(-0.4, 0.4, 3))).coeffs()
    layer.ik.q = q
    limbs = model.robot.limbs
    wrenches = np.zeros((len(limbs), 6))
    wrenches[:2] = rng.normal(scale=[50, 50, 300, 10, 10, 5], size=(2, 6))
    targets = replace(_targets_of(model, state), contact_wrench_desired_limb=wrenches)
    frames = [model.frame_id[limb.contact_frame] for limb in limbs]
    nv = model.model.nv
    expected = joint_torques(
        model, model.model.createData(), q, np.zeros(nv), np.zeros(nv), wrenches,
        targets.limb_in_contact, frames,
    )  # fmt: skip
    np.testing.assert_allclose(layer._feedforward(targets), expected, rtol=0, atol=1e-9)
    assert np.abs(expected).max() > 10.0  # [N m]


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
@pytest.mark.parametrize("layer", ["ik", "ik_feedforward"])
def test_both_layers_hold_a_standing_robot(sim, layer):
    """1 s standing with hold + posture through each layer: no fall, and the feet carry the
    weight (the measured vertical forces sum to m g within 2 %). The servos alone (`ik`) let the
    CoM sag under the load by more than 1 mm; with the static torques (`ik_feedforward`) it
    stays within 0.5 mm of its target (measured in MuJoCo -1.86 and -0.07 mm; with the
    feed-forward's sign flipped -4.0 mm, and the weight still on the feet)."""
    result = run_episode(
        EpisodeSpec(
            planner="hold",
            stabilizer="posture",
            sim=sim,
            scenario="stand",
            duration=1.0,
            whole_body=layer,
        )
    )
    assert result.summary["status"] == "ok", result.summary["error"]
    assert result.summary["whole_body"] == layer
    trace = result.trace.iloc[-100:]
    vertical = trace["wrench_measured_left_foot_fz"] + trace["wrench_measured_right_foot_fz"]
    weight = result.summary["mass_kg"] * 9.81
    assert vertical.mean() == pytest.approx(weight, rel=0.02)
    sag = (trace["com_true_z"] - trace["com_desired_z"]).mean()  # [m]
    if layer == "ik":
        assert sag < -1e-3
    else:
        assert abs(sag) < 0.5e-3


def test_controllers_name_their_whole_body_layer():
    assert controller_spec("hold+posture").whole_body == DEFAULT_WHOLE_BODY
    paper = controller_spec("preview_control+centroidal_feedback")
    assert paper.whole_body == "ik"  # Murooka Sec. V-A1: IK joint angles to the servos
    triple = controller_spec("preview_control+centroidal_feedback+ik_feedforward")
    assert (triple.planner, triple.stabilizer, triple.whole_body) == (
        "preview_control",
        "centroidal_feedback",
        "ik_feedforward",
    )
    assert triple.name == "preview_control+centroidal_feedback+ik_feedforward"
    assert controller_spec("preview_control+centroidal_feedback+ik") == paper
    with pytest.raises(
        KeyError,
        match="whole-body layers five_mass_pose, five_mass_pose_bent, "
        "five_mass_pose_bent_feedforward, five_mass_pose_feedforward, ik, ik_angular_momentum, "
        "ik_feedforward",
    ):
        controller_spec("hold+posture+torque_magic")
