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
        match="choose one of: five_mass_pose, five_mass_pose_bent, "
        "five_mass_pose_bent_feedforward, five_mass_pose_feedforward, ik, ik_angular_momentum, "
        "ik_feedforward",
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


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
@pytest.mark.parametrize("layer", ["ik", "ik_feedforward"])
def test_both_layers_hold_a_standing_robot(sim, layer):
    """1 s standing with hold + posture through each layer: no fall, and the feet carry the
    weight (the measured vertical forces sum to m g within 2 %)."""
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
