"""Grasps (issue 19, Murooka et al. Sec. V, Fig. 7: about 200 N of pull on the hands on a
ladder): a hand welded to a scene box (`robots.scene.Grasp`, `Simulator.grasp` / `release`)
holds a pull that a palm pressed on the box cannot, and the hand's measured wrench is the weld's
force (plus the pad's contact, if it touches), in both simulators.

The set-up (as `test_agreement.test_palm_contact_is_sensed`, on the right hand, with the robot
and the bar turned by `YAW` so that the palm's axes are not the world's): the robot stands with
its right forearm vertical and its hand pad level, over a bar whose top is 3 mm below the pad;
the knees bend so that the body goes down about 4 mm and the pad presses on the bar (about
40 N through the wrist servos; 80 N before the robot had wrists). A constant load `LOAD`
(110 N; `Simulator.push`) pulls the hand up, away from the bar, forward and outward: on the
grasped hand link (`GRASPED_LINK`) where a grasp must hold it alone (0.4 N m about the palm
centre), on the forearm where it drags a released hand away. The weld and the arm hold the hand
in parallel, and the weld's share of the load is its stiffness over the sum: measured (before
the wrists, the load on the forearm: 4.7 N m about the palm), the grasped hand's wrench changed
by the load's to 0.08 N and 0.02 N m
in both engines (MuJoCo's weld nearly rigid, `sims.mujoco_sim.GRASP_SOLIMP`, PyBullet's rigid;
with MuJoCo's default impedance the arm's servos took a third of the moment about x); with the
wrists and the load on the hand link, 0.15 N and 0.011 N m in MuJoCo, 2e-5 N and 1.7e-4 N m in
PyBullet (2026-12-03). The tolerances are 0.5 N and 0.05 N m. The load's effect is isolated
from the slow settling of the pressed stance by subtracting the same episode without the load,
period by period.
"""

import numpy as np
import pytest

from robots.scene import Box, Grasp, MovingBox, Scene
from robots.types import JointCommand, RobotState
from sims import mujoco_sim
from sims.base import make_simulator, quaternion_to_matrix
from sims.pybullet_sim import pb
from tests.sims.helpers import knees_bent

SIMS = ["mujoco", "pybullet"]
YAW = 0.5  # [rad] the robot and the bar turn left about the vertical: palm axes are not world's
TURNED = (np.cos(YAW / 2), 0.0, 0.0, np.sin(YAW / 2))  # (w, x, y, z)
GRASPED_LINK = "right_hand_link"
"""The link the grasp welds, which `test_a_grasp_holds_a_pull_that_a_pressed_palm_cannot` loads:
on the forearm, the wrist servos' compliance would share the load with the arm."""
LOAD = quaternion_to_matrix(TURNED) @ [40.0, -20.0, 100.0]  # [N] on the right forearm, world:
# up, forward and outward in the robot's frame
LOAD_START, LOAD_END = 0.6, 1.4  # [s]
GRASP_START = 0.5  # [s], once the pad presses on the bar
HAND = "right_hand"


@pytest.fixture(scope="module")
def initial(robot, model):
    """Standing turned by YAW, the right forearm vertical and its pad level."""
    standing = model.standing_state()
    q = np.array(standing.joint_position)
    for joint, angle in (("shoulder_pitch", 0.2), ("shoulder_roll", 0.0), ("elbow", -0.2)):
        q[robot.joint_names.index(f"right_{joint}")] = angle
    return RobotState.at_rest(standing.base_position_world, np.array(TURNED), q)


@pytest.fixture(scope="module")
def palm(model, initial):
    return model.frame_positions_world(initial, ["right_palm"])[0]


def bar_under(palm: np.ndarray, gap: float) -> Box:
    """A bar 120 x 60 x 40 mm under the pad (turned as the robot), its top `gap` [m] below the
    palm centre."""
    top = palm[2] - gap
    return Box("bar", (palm[0], palm[1], top - 0.02), (0.06, 0.03, 0.02), TURNED)


def pressing(robot, model, initial) -> JointCommand:
    """Hold the posture with the knees bent 0.033 rad more: the pad presses on the bar."""
    return knees_bent(robot, model.hold_command(initial))


def run(
    robot, sim_name, scene, initial, command, duration, load=None, check=None, link="right_forearm"
) -> dict:
    """`duration` [s] of `command`, with `load` [N] on `link` (default the right forearm) from
    LOAD_START to LOAD_END; after each period check(sim, sensors). Returns per period the
    time [s], the right hand's wrench and contact flag, the palm's position [m], and the fall
    reason."""
    hand = robot.limb_names.index(HAND)
    sim = make_simulator(sim_name)
    times, wrenches, flags, palms, states = [], [], [], [], []
    try:
        sim.reset(robot, scene, initial)
        for _ in range(round(duration / scene.control_dt)):
            if load is not None and abs(sim.time - LOAD_START) < 1e-9:
                length = LOAD_END - LOAD_START
                sim.push(link, load * length, length)
            sensors = sim.step(command)
            times.append(sensors.time)
            wrenches.append(sensors.contact_wrench_limb[hand].copy())
            flags.append(bool(sensors.contact_flag_limb[hand]))
            palms.append(sim.frame_positions_world(["right_palm"])[0])
            states.append(sensors.ground_truth())
            if check is not None:
                check(sim, sensors)
        fall = sim.fall_reason()
    finally:
        sim.close()
    return {
        "time": np.array(times),
        "wrench": np.array(wrenches),
        "flag": np.array(flags),
        "palm": np.array(palms),
        "state": states,
        "fall": fall,
    }


def period(trace: dict, time: float) -> int:
    """Index of the period that ends at `time` [s]."""
    return int(np.argmin(np.abs(trace["time"] - time)))


def expected_wrench(model, state: RobotState, load: np.ndarray) -> np.ndarray:
    """The wrench a rigid grasp applies to hold `load` [N] at the grasped link's centre of mass
    (`GRASPED_LINK`): -load, and minus its moment about the palm centre, in the palm frame."""
    link, link_rotation = model.frame_pose(state, GRASPED_LINK)
    com = link + link_rotation @ np.array(model.robot.link(GRASPED_LINK).inertial.com_in_link)
    palm, palm_rotation = model.frame_pose(state, "right_palm")
    return np.concatenate([palm_rotation.T @ -load, palm_rotation.T @ -np.cross(com - palm, load)])


@pytest.mark.parametrize("sim_name", SIMS)
def test_a_grasp_holds_a_pull_that_a_pressed_palm_cannot(robot, model, initial, palm, sim_name):
    """The same pull on the same pressed hand: with the palm contact alone the hand leaves the
    bar; grasped, it stays, and its measured wrench changes by exactly the load's (-LOAD and its
    moment about the palm, in the palm frame)."""
    bar = bar_under(palm, 0.003)
    command = pressing(robot, model, initial)
    duration = LOAD_END
    contact_only = run(
        robot, sim_name, Scene(boxes=(bar,)), initial, command, duration, LOAD, link=GRASPED_LINK
    )
    grasp = Scene(boxes=(bar,), grasps=(Grasp(HAND, "bar", GRASP_START),))
    loaded = run(robot, sim_name, grasp, initial, command, duration, LOAD, link=GRASPED_LINK)
    unloaded = run(robot, sim_name, grasp, initial, command, duration)
    for trace in (contact_only, loaded, unloaded):
        assert trace["fall"] is None
    start, end = period(loaded, LOAD_START), len(loaded["time"]) - 1

    # palm contact only: pressing before the pull (41-44 N); the pull unloads it and drags
    # the hand away (along the bar and off its edge: 0.12-0.14 m)
    assert contact_only["flag"][start]
    assert contact_only["wrench"][start, 2] > 20.0
    assert not contact_only["flag"][end]
    np.testing.assert_array_equal(contact_only["wrench"][end], 0.0)
    assert np.linalg.norm(contact_only["palm"][end] - contact_only["palm"][start]) > 0.02  # [m]

    # grasped: the hand stays where it was grasped and counts as in contact
    grasped = period(loaded, GRASP_START) + 1  # the first period with the grasp
    assert loaded["flag"][grasped:].all()
    moved = np.linalg.norm(loaded["palm"][start:] - loaded["palm"][start], axis=1)
    assert moved.max() < 5e-5  # [m]
    # its wrench changes by the load's, once the step response has settled (0.2 s)
    settled = slice(period(loaded, LOAD_START + 0.2), end + 1)
    change = (loaded["wrench"] - unloaded["wrench"])[settled].mean(axis=0)
    expected = expected_wrench(model, loaded["state"][end], LOAD)
    np.testing.assert_allclose(change[:3], expected[:3], rtol=0, atol=0.5)  # [N]
    np.testing.assert_allclose(change[3:], expected[3:], rtol=0, atol=0.05)  # [N m]
    # the moment is not negligible next to the 0.05 N m tolerance (0.4 N m: the hand link's
    # centre of mass is 1 cm from the palm; a sign or frame error would be off by 0.8 N m)
    assert abs(expected[4]) > 0.3


@pytest.mark.parametrize("sim_name", SIMS)
def test_a_released_grasp_lets_the_hand_go(robot, model, initial, palm, sim_name):
    """Grasped from 0.5 s to 1.0 s, pulled from 0.6 s to 1.4 s: the hand holds until the
    release, then the engine holds no constraint, the hand is dragged away (along the bar and
    off its edge: 56-59 mm in 0.4 s) and its wrench is zero."""
    release = 1.0
    scene = Scene(boxes=(bar_under(palm, 0.003),), grasps=(Grasp(HAND, "bar", 0.5, release),))
    seen = {}

    def check(sim, sensors):
        active = (
            int(sim.data.eq_active.sum())
            if sim_name == "mujoco"
            else pb.getNumConstraints(physicsClientId=sim.client)
        )
        seen.setdefault("active", []).append(active)
        seen.setdefault("grasping", []).append(sim.grasping())

    trace = run(robot, sim_name, scene, initial, pressing(robot, model, initial), 1.4, LOAD, check)
    assert trace["fall"] is None
    # the grasp holds from the period after the one that ends at 0.5 s to the one that ends at
    # the release
    made, after = period(trace, 0.5) + 1, period(trace, release) + 1
    start, before = period(trace, LOAD_START), after - 1
    active = np.array(seen["active"])
    assert (active[:made] == 0).all()
    assert (active[made:after] == 1).all()
    assert (active[after:] == 0).all()
    assert seen["grasping"][before] == {HAND: "bar"}
    assert seen["grasping"][after] == {}
    held = np.linalg.norm(trace["palm"][start : before + 1] - trace["palm"][start], axis=1)
    assert held.max() < 5e-5  # [m]
    assert trace["wrench"][before, 2] < -10.0  # pulling the hand down onto the bar
    assert np.linalg.norm(trace["palm"][-1] - trace["palm"][before]) > 0.02  # [m]
    assert not trace["flag"][-1]
    np.testing.assert_array_equal(trace["wrench"][-1], 0.0)


@pytest.mark.parametrize("sim_name", SIMS)
def test_a_moving_box_carries_a_grasping_hand(robot, model, initial, palm, sim_name):
    """A bar 1 mm under the palm moving 20 mm forward and back and 5 mm up and down (period
    1 s, after a 0.25 s ramp; more would push the nearly straight arm harder: 320 N at
    the peaks already): the grasping hand follows it, down as well as up, to 0.1 mm; without
    the grasp, the hand stays where it was when the bar goes back and down."""
    top = palm[2] - 0.001
    bar = MovingBox(
        "bar",
        (palm[0], palm[1], top - 0.02),
        (0.06, 0.03, 0.02),
        TURNED,
        translation_amplitude_world=tuple(quaternion_to_matrix(TURNED) @ [0.02, 0.0, 0.005]),
        period=1.0,
        phase=np.pi,  # back and down first
        ramp_time=0.25,
    )
    hold = model.hold_command(initial)
    errors, gaps = {}, {}
    for grasped, duration in ((True, 1.25), (False, 0.25)):
        scene = Scene(moving_boxes=(bar,), grasps=(Grasp(HAND, "bar"),) if grasped else ())
        rows = []

        def check(sim, sensors, rows=rows):
            moved = bar.pose_at(sim.time)[0] - np.array(bar.center_world)
            rows.append(moved)

        trace = run(robot, sim_name, scene, initial, hold, duration, check=check)
        assert trace["fall"] is None
        moved = np.array(rows)
        errors[grasped] = np.linalg.norm(trace["palm"] - palm - moved, axis=1)
        gaps[grasped] = trace["palm"][:, 2] - (top + moved[:, 2])
        assert np.ptp(moved[:, 2]) > 0.0049  # the bar went 5 mm down (and up)
    assert errors[True].max() < 1e-4  # [m]
    assert np.abs(gaps[True] - 0.001).max() < 1e-4
    # left behind: 20 mm from where the bar took the palm, 6 mm above it
    assert errors[False][-1] > 0.015
    assert gaps[False][-1] > 0.004


@pytest.mark.parametrize("sim_name", SIMS)
def test_without_grasps_nothing_changes(robot, model, initial, palm, sim_name, monkeypatch):
    """A scene whose grasp comes after the episode runs bit for bit as the scene without it,
    and, in MuJoCo, as the same scene compiled without the inactive welds it declares for its
    boxes (an inactive equality makes no constraint row); a flat scene has no weld at all."""
    bar = bar_under(palm, 0.003)
    command = pressing(robot, model, initial)

    def episode(grasps):
        scene = Scene(boxes=(bar,), grasps=grasps)
        return run(robot, sim_name, scene, initial, command, 0.3, LOAD)

    traces = [episode(()), episode((Grasp(HAND, "bar", 10.0),))]
    if sim_name == "mujoco":
        mujoco_sim.clear_cache()
        monkeypatch.setattr(mujoco_sim, "_add_grasp_weld", lambda *args: None)
        try:
            traces.append(episode(()))
        finally:
            mujoco_sim.clear_cache()  # forget the model without welds
    for trace in traces[1:]:
        for key in ("wrench", "flag", "palm"):
            np.testing.assert_array_equal(trace[key], traces[0][key])
    sim = make_simulator(sim_name)
    try:
        sim.reset(robot, Scene(), initial)
        if sim_name == "mujoco":
            assert sim.model.neq == 0
        else:
            assert pb.getNumConstraints(physicsClientId=sim.client) == 0
    finally:
        sim.close()


@pytest.mark.parametrize("sim_name", SIMS)
def test_grasp_arguments_are_checked(robot, model, initial, palm, sim_name):
    sim = make_simulator(sim_name)
    try:
        sim.reset(robot, Scene(boxes=(bar_under(palm, 0.003),)), initial)
        with pytest.raises(KeyError, match="no limb"):
            sim.grasp("tail", "bar")
        with pytest.raises(KeyError, match="no box"):
            sim.grasp(HAND, "rung")
        sim.grasp(HAND, "bar")
        with pytest.raises(ValueError, match="already grasps"):
            sim.grasp(HAND, "bar")
        sim.release(HAND)
        sim.release(HAND)  # holds nothing: nothing to do
        assert sim.grasping() == {}
        unknown_limb = Scene(boxes=(bar_under(palm, 0.003),), grasps=(Grasp("tail", "bar"),))
        with pytest.raises(KeyError, match="no limb"):
            sim.reset(robot, unknown_limb, initial)
    finally:
        sim.close()


def test_scene_validation_rejects_bad_grasps():
    bar = Box("bar", (0.0, 0.0, 0.5), (0.1, 0.1, 0.1))
    with pytest.raises(ValueError, match="no box named 'rung'"):
        Scene(boxes=(bar,), grasps=(Grasp(HAND, "rung"),)).validate()
    with pytest.raises(ValueError, match="finite start before its end"):
        Scene(boxes=(bar,), grasps=(Grasp(HAND, "bar", 1.0, 0.5),)).validate()
    with pytest.raises(ValueError, match="at once"):
        Scene(
            boxes=(bar,), grasps=(Grasp(HAND, "bar", 0.0, 1.0), Grasp(HAND, "bar", 0.5, 2.0))
        ).validate()
    Scene(  # one after the other, and two hands at once
        boxes=(bar,),
        grasps=(
            Grasp(HAND, "bar", 0.0, 1.0),
            Grasp(HAND, "bar", 1.0),
            Grasp("left_hand", "bar", 0.5, 2.0),
        ),
    ).validate()
