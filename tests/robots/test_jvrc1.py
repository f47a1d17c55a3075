"""JVRC-1 through its adapter (`robots.jvrc1`): the package's numbers kept, what the adapter adds
where its sources put it, and a robot that stands."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from bench.scenarios import make_scenario
from robots.jvrc1 import (
    HALF_SITTING,
    LOCKED_JOINTS,
    SOLE_HALF_EXTENTS,
    SOLE_IN_ANKLE,
    jvrc1,
    urdf_path,
)
from robots.jvrc1_shapes import BOXES
from robots.mesh_fit import urdf_collision_boxes
from robots.model import RobotModel
from robots.robot_registry import ROBOTS, make_robot, robot_entry
from tests.bench.episodes import run_controller

GRAVITY = 9.81


@pytest.fixture(scope="module")
def robot():
    return jvrc1()


@pytest.fixture(scope="module")
def model(robot):
    return RobotModel(robot)


def test_mass_and_joints_are_the_packages_less_the_locked_ones(robot):
    """62.4 kg (every URDF link's mass, the massless root dropped), 29 actuated joints: the
    package's 44 revolute joints less the neck's 3 and the fingers' 12, each with the URDF's
    own limits."""
    root = ET.parse(urdf_path()).getroot()
    masses = [float(m.get("value")) for m in root.iter("mass")]
    revolute = {j.get("name"): j for j in root.findall("joint") if j.get("type") == "revolute"}
    assert robot.total_mass == pytest.approx(sum(masses), rel=1e-12)
    assert robot.total_mass == pytest.approx(62.4, rel=1e-12)
    assert len(revolute) == 44
    assert robot.n_joints == 29
    assert set(robot.joint_names) == set(revolute) - LOCKED_JOINTS
    assert robot.base_link == "PELVIS_S"
    for joint in robot.joints:
        limit = revolute[joint.name].find("limit")
        assert joint.lower == float(limit.get("lower"))
        assert joint.upper == float(limit.get("upper"))
        assert joint.velocity_limit == float(limit.get("velocity"))
    ankles = {"L_ANKLE_P", "L_ANKLE_R", "R_ANKLE_P", "R_ANKLE_R"}  # `level_soles` turns them
    for name, q in zip(robot.joint_names, robot.nominal_posture, strict=True):
        if name in ankles:
            assert q == pytest.approx(HALF_SITTING[name], abs=0.021)
        else:
            assert q == HALF_SITTING[name]


def test_sole_frames_are_at_the_sole_centres(robot, model):
    """Each sole frame is mc_rtc's foot surface centre on the ankle link, and is the centre of
    the bottom face of the foot's collision box, which is the 0.20 x 0.08 m sole."""
    state = model.standing_state()
    for side in ("left", "right"):
        limb = robot.limb(f"{side}_foot")
        frame = robot.frame(limb.contact_frame)
        assert frame.link == limb.link
        assert frame.position_in_link == SOLE_IN_ANKLE
        assert limb.half_extents == SOLE_HALF_EXTENTS == (0.10, 0.04)
        (box,) = robot.link(limb.link).geometries
        bottom = np.array(box.position_in_link) - np.array([0.0, 0.0, box.size[2]])
        np.testing.assert_allclose(bottom, frame.position_in_link, rtol=0, atol=1e-12)
        assert box.size[:2] == SOLE_HALF_EXTENTS
    soles = model.frame_positions_world(state, ["left_sole", "right_sole"])
    assert np.abs(soles[:, 2]).max() < 1e-4  # standing: both soles on the ground


def test_the_half_sitting_com_is_inside_the_support_polygon(robot, model):
    state = model.standing_state()
    com = model.com_position_world(state)[:2]
    corners = []
    for side in ("left", "right"):
        position = model.frame_positions_world(state, [f"{side}_sole"])[0, :2]
        for dx in (-1, 1):
            for dy in (-1, 1):
                corners.append(position + np.array(SOLE_HALF_EXTENTS) * (dx, dy))
    hull = ConvexHull(np.array(corners))
    inside = hull.equations[:, :2] @ com + hull.equations[:, 2]
    assert inside.max() < -0.05  # more than 5 cm inside every edge


def test_static_torques_of_the_half_sitting_are_below_the_limits(robot, model):
    """The torques that hold the half-sitting posture on both soles: under a tenth of every
    limit (the limits by similarity from the humanoid's, `robots.jvrc1.torque_limits`)."""
    torques = model.static_torques(model.standing_state(), ["left_sole", "right_sole"])
    assert np.all(np.abs(torques) < 0.1 * robot.array("torque_limit"))
    assert np.abs(torques).max() > 5.0  # the knees and the waist do carry the body


def test_committed_collision_boxes_are_the_installed_meshes_bounding_boxes():
    assert urdf_collision_boxes(urdf_path()) == BOXES


def test_the_registry_answers_unknown_names_and_keeps_jvrc1_at_one_size():
    assert set(ROBOTS) == {"centrobench_humanoid", "jvrc1"}
    with pytest.raises(KeyError, match="centrobench_humanoid, jvrc1"):
        robot_entry("atlas")
    with pytest.raises(ValueError, match="one size"):
        make_robot("jvrc1", 1.2)
    assert make_robot("jvrc1") is jvrc1()
    assert make_robot("centrobench_humanoid", 1.2).scale == 1.2


@pytest.mark.parametrize("name", list(ROBOTS))
def test_the_standing_state_has_level_soles_and_nothing_inside_the_ground(name):
    """Every robot starts with its soles level (their z axes vertical: the scenarios' footholds
    are level) and no collision shape below the ground. mc_rtc's half-sitting with an upright
    pelvis had JVRC-1's soles pitched 0.010 rad and the right one rolled 0.019 rad, a corner
    1.75 mm inside the ground (`robots.jvrc1.level_soles`)."""
    import pinocchio as pin

    robot = make_robot(name)
    model = RobotModel(robot)
    state = model.standing_state()
    pin.framesForwardKinematics(model.model, model.data, model.configuration(state))
    lowest = np.inf
    for link in robot.links:
        placement = model.data.oMf[model.frame_id[link.name]]
        for shape in link.geometries:
            if not shape.collides:
                continue
            rotation = placement.rotation @ pin.rpy.rpyToMatrix(*shape.rpy_in_link)
            centre = placement.act(np.array(shape.position_in_link))
            if shape.kind == "box":  # half its vertical extent
                depth = np.abs(rotation[2]) @ np.array(shape.size)
            elif shape.kind == "capsule":
                depth = abs(rotation[2, 2]) * shape.size[1] + shape.size[0]
            else:
                depth = shape.size[0]
            lowest = min(lowest, centre[2] - depth)
    assert lowest > -1e-9
    for limb in robot.limbs:
        if limb.name.endswith("foot"):
            _, rotation = model.frame_pose(state, limb.contact_frame)
            assert np.abs(rotation[:2, 2]).max() < 1e-9
            assert model.frame_pose(state, limb.contact_frame)[0][2] < 2e-4  # on the ground


@pytest.mark.parametrize("name", list(ROBOTS))
@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
def test_a_robot_set_down_standing_takes_its_weight_without_a_blow(name, sim):
    """Murooka's pair holding the standing robot: over the first 0.3 s the feet carry at most
    1.5 m g and never less than 0.5 m g after the first 10 ms (measured 1.09 / 1.09 m g on the
    humanoid, 1.21 / 1.11 on JVRC-1, MuJoCo / PyBullet; JVRC-1 took 2.39 / 1.18 m g while the
    controllers' level footholds turned its tilted soles flat in the first periods)."""
    result = run_controller(
        "preview_control+centroidal_feedback", sim, "stand", duration=0.3, robot=name
    )
    weight = make_robot(name).total_mass * GRAVITY
    trace = result.trace
    feet = (
        trace["wrench_measured_left_foot_fz"] + trace["wrench_measured_right_foot_fz"]
    ).to_numpy()
    assert feet.max() < 1.5 * weight
    assert feet[5:].min() > 0.5 * weight


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
def test_jvrc1_stands_with_its_weight_on_the_feet(robot, sim):
    """5 s of `stand` with Murooka's pair: no fall, and over the last second the feet's
    measured vertical forces sum to m g within 1 %."""
    result = run_controller(
        "preview_control+centroidal_feedback", sim, "stand", duration=5.0, robot="jvrc1"
    )
    assert result.summary["status"] == "ok", result.summary["error"]
    assert not result.summary["fell"]
    assert result.summary["robot"] == "jvrc1"
    trace = result.trace
    last = trace[trace["time"] > trace["time"].max() - 1.0]
    feet = last["wrench_measured_left_foot_fz"] + last["wrench_measured_right_foot_fz"]
    assert feet.mean() == pytest.approx(robot.total_mass * GRAVITY, rel=0.01)


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
def test_hold_and_posture_stand_on_jvrc1_and_bring_the_com_over_the_feet(sim):
    """`hold` + `posture` stands 5 s on JVRC-1, whose half-sitting CoM starts 19.8 mm behind
    its feet's midpoint, and ends with the true CoM within 2 mm of that midpoint (measured
    0.7 mm in both simulators; with a reference at the midpoint from t = 0 it fell at 1.29 s /
    3.56 s, MuJoCo / PyBullet)."""
    result = run_controller("hold+posture", sim, "stand", duration=5.0, robot="jvrc1")
    assert result.summary["status"] == "ok", result.summary["error"]
    last = result.trace.iloc[-1]
    model = RobotModel(make_robot("jvrc1"))
    scenario = make_scenario("stand", model)
    middle = np.mean([c.position_world for c in scenario.phases[0].contacts], axis=0)
    offset = np.array([last["com_true_x"], last["com_true_y"]]) - middle[:2]
    assert np.linalg.norm(offset) < 2e-3


def test_locking_a_joint_between_actuated_ones_keeps_the_kinematics(monkeypatch):
    """Locking the waist too (an experiment the adapter allows) re-parents the shoulders onto
    the pelvis: 26 joints, the same mass, and in the zero posture every frame where the
    29-joint model puts it."""
    import robots.jvrc1 as module
    from robots.types import RobotState

    full = module.jvrc1()
    monkeypatch.setattr(
        module, "LOCKED_JOINTS", module.LOCKED_JOINTS | {"WAIST_Y", "WAIST_P", "WAIST_R"}
    )
    monkeypatch.setattr(module, "HALF_SITTING", {**module.HALF_SITTING, "WAIST_P": 0.0})
    module.jvrc1.cache_clear()
    try:
        locked = module.jvrc1()
    finally:
        module.jvrc1.cache_clear()
    assert locked.n_joints == 26
    assert locked.total_mass == pytest.approx(full.total_mass, rel=1e-12)
    assert locked.joints[locked.joint_names.index("L_SHOULDER_P")].parent == "PELVIS_S"
    names = [frame.name for frame in full.frames]
    positions = []
    for robot in (full, locked):
        zero = RobotState.at_rest(np.zeros(3), np.array([1.0, 0, 0, 0]), np.zeros(robot.n_joints))
        positions.append(RobotModel(robot).frame_positions_world(zero, names))
    np.testing.assert_allclose(positions[1], positions[0], rtol=0, atol=1e-12)


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
def test_the_zmp_preview_walks_jvrc1_whose_soles_stand_at_two_heights(sim):
    """`preview_zmp + dcm` walks `walk` on JVRC-1 (its soles 0.1 mm apart in height: the
    cart-table's height reference steps between supports; before `follow_height` the step
    planned a negative vertical force and the episode ended in an error at 1.0 s). In PyBullet
    it fell at 8.72 s until its ZMP reference moved 2 cm inward of the soles' centres, as the
    authors' implementation (`zmp_reference`). Measured: 10 steps, CoM 8.3 / 8.1 mm RMS from
    the plan (MuJoCo / PyBullet, 2026-12-03; 7.8 / 8.1 mm at 4268572, and 10.1 mm in MuJoCo
    before the inward reference): within 9.5 mm, below the 10.1 of before."""
    result = run_controller("preview_zmp+dcm", sim, "walk", robot="jvrc1")
    assert result.summary["status"] == "ok", result.summary["error"]
    assert result.summary["steps_taken"] >= 10
    assert result.summary["com_error_rms_m"] < 0.0095
