"""Murooka et al.'s multi-contact motions (Fig. 4) as contact sequences (`bench.motions`),
and episodes of `preview_control` + `centroidal_feedback` on them in both simulators."""

import math

import numpy as np
import pytest

from bench.controllers import CONTROLLERS, refusal
from bench.scenarios import make_scenario
from robots.humanoid import humanoid
from robots.model import RobotModel
from robots.multi_contact_scenes import MOTION_PERIOD_S, WALL_INNER_FACE_Y, WALL_WALK_FACE_Y
from robots.scene import contact_normal
from tests.bench.episodes import run_controller

DT = 0.002
GRAVITY = 9.81


def _grasp_contact(scenario, grasp):
    """The contact that a scene `Grasp` realises: its limb's, in the phase it starts with."""
    return next(
        c
        for p in scenario.phases
        if p.start == pytest.approx(grasp.start)
        for c in p.contacts
        if c.limb == grasp.limb
    )


def _check_phases_cover(scenario):
    assert scenario.phases[0].start == 0.0
    for a, b in zip(scenario.phases, scenario.phases[1:], strict=False):
        assert a.end == pytest.approx(b.start, abs=1e-12)
    assert scenario.phases[-1].end == pytest.approx(scenario.duration, abs=1e-12)


@pytest.mark.parametrize("scale", [1.0, 1.2])
def test_moving_contacts_puts_each_palm_on_its_wall_facing_it(scale):
    """(E): the palms' contacts lie on the walls' faces (y = +-0.45 m x scale) with their
    normals (z axes) out of the wall, towards the robot; each hand leaves from its standing
    pose (a waypoint); the walls and floors move only once both hands are on."""
    model = RobotModel(humanoid(scale))
    scenario = make_scenario("moving_contacts", model)
    _check_phases_cover(scenario)
    last = scenario.phases[-1]
    assert sorted(last.limbs) == ["left_foot", "left_hand", "right_foot", "right_hand"]
    for contact in last.contacts:
        if contact.limb.endswith("hand"):
            side = 1.0 if contact.limb == "left_hand" else -1.0
            assert contact.position_world[1] == pytest.approx(side * WALL_INNER_FACE_Y * scale)
            np.testing.assert_allclose(
                contact_normal(contact.orientation_world), (0, -side, 0), atol=1e-12
            )
    standing = model.standing_state()
    for waypoint in scenario.limb_waypoints:
        frame = model.robot.limb(waypoint.limb).contact_frame
        np.testing.assert_allclose(
            waypoint.position_world, model.frame_pose(standing, frame)[0], atol=1e-12
        )
    on_walls = min(p.start for p in scenario.phases if len(p.contacts) == 4)
    for box in scenario.scene.moving_boxes:
        assert box.start_time == pytest.approx(on_walls + 0.8 * math.sqrt(scale))
        assert box.period == pytest.approx(MOTION_PERIOD_S * math.sqrt(scale))
    assert scenario.duration - on_walls >= 2 * MOTION_PERIOD_S * math.sqrt(scale)


def test_flat_ground_controllers_are_refused_the_motions():
    reason = refusal(CONTROLLERS["preview_zmp+dcm"], "moving_contacts")
    assert reason is not None
    assert "multi_contact" in reason
    assert refusal(CONTROLLERS["preview_control+centroidal_feedback"], "moving_contacts") is None


@pytest.fixture(scope="module", params=["mujoco", "pybullet"])
def moving_contacts_episode(request):
    return request.param, run_controller(
        "preview_control+centroidal_feedback", request.param, "moving_contacts"
    )


def test_moving_contacts_balances_without_a_fall(moving_contacts_episode):
    _, result = moving_contacts_episode
    assert result.summary["status"] == "ok", result.summary["error"]
    assert not result.summary["fell"]


def test_moving_contacts_feet_and_walls_carry_the_weight(moving_contacts_episode):
    """While floors and walls move (after both hands are on), the measured contact forces'
    vertical components (the feet's normal forces, about level to 2 deg, and the palms'
    friction along their frames' y axes, which are world z for the left palm and -z for the
    right) average to m g, to 0.5 % (measured 0.24 % under in both simulators, 2026-12-03):
    the robot neither sinks nor rises over the motion."""
    _, result = moving_contacts_episode
    trace = result.trace
    model = RobotModel(humanoid())
    start = max(
        box.start_time for box in make_scenario("moving_contacts", model).scene.moving_boxes
    )
    moving = trace[trace["time"] >= start]
    vertical = (
        moving["wrench_measured_left_foot_fz"]
        + moving["wrench_measured_right_foot_fz"]
        + moving["wrench_measured_left_hand_fy"]
        - moving["wrench_measured_right_hand_fy"]
    )
    weight = model.robot.total_mass * GRAVITY
    assert vertical.mean() == pytest.approx(weight, rel=0.005)


def test_moving_contacts_hands_stay_mostly_on_the_moving_walls(moving_contacts_episode):
    """The damping control (eq. 15) keeps each palm on its wall for most of the motion: a
    wall receding faster than F_d / K_d (the desired force over Table II's 10000 N s/m) leaves
    the palm for a while (the left one for about 2.5 s of each 8 s period), but it is back in
    every period of the motion."""
    _, result = moving_contacts_episode
    trace = result.trace
    scenario = make_scenario("moving_contacts", RobotModel(humanoid()))
    boxes = scenario.scene.moving_boxes
    start, period = max(b.start_time for b in boxes), boxes[0].period
    moving = trace[trace["time"] >= start]
    for hand in ("left_hand", "right_hand"):
        assert moving[f"contact_{hand}"].mean() > 0.5
        for k in range(2):
            window = moving[(moving["time"] >= start + k * period)]
            window = window[window["time"] < start + (k + 1) * period]
            assert window[f"contact_{hand}"].mean() > 0.25, (hand, k)


def test_table_iv_rows_are_reported_per_number_of_contacts(moving_contacts_episode):
    """`latency_by_contacts_us`: Table IV's rows for each number of planned contacts (2 feet,
    + one hand, + both hands), over as many periods as the phases with that many last."""
    _, result = moving_contacts_episode
    by_contacts = result.summary["latency_by_contacts_us"]
    scenario = make_scenario("moving_contacts", RobotModel(humanoid()))
    expected: dict[str, float] = {}
    for phase in scenario.phases:
        key = str(len(phase.contacts))
        expected[key] = expected.get(key, 0.0) + (phase.end - phase.start) / DT
    assert sorted(by_contacts) == ["2", "3", "4"]
    for key, periods in expected.items():
        rows = by_contacts[key]
        assert set(rows) == {
            "centroidal_control",
            "reference",
            "preview",
            "projection",
            "distribution",
        }
        assert rows["projection"]["periods"] == pytest.approx(periods, abs=2)
        # each period's total holds every stage of it, so its median is no less than any
        # stage's (a median below its own p99, asserted here before, holds for any numbers)
        stages = [rows[name]["median"] for name in rows if name != "centroidal_control"]
        assert min(stages) > 0.0
        assert rows["centroidal_control"]["median"] >= max(stages)


# --- grasps, lifted swings and the handrail stairs (Fig. 4 B) ------------------------------


def test_a_grasp_contact_holds_a_pull_that_a_pressed_palm_cannot():
    """`Contact.grasp` gives the phase's cone the facing pyramids (Murooka Sec. III-B1): a
    hand whose palm faces forward along a rail (`bench.motions` RAIL orientation) can hold
    a pull forward and up on the hand (the rail holding a body that hangs behind and below
    it), which the same palm pressed (a unilateral contact) cannot: its normal force only
    pushes (towards -x), and its friction needs a normal force."""
    from centroidal.projection import WrenchProjector
    from robots.limbs import PhaseContacts, limb_surfaces
    from robots.scene import Contact, ContactPhase

    surfaces = limb_surfaces(humanoid(), 0.6)
    position = (0.5, 0.38, 1.3)
    pressed = Contact("left_hand", position, (math.sqrt(0.5), 0.0, -math.sqrt(0.5), 0.0))
    grasped = Contact("left_hand", position, pressed.orientation_world, grasp=True)
    pull = np.array([80.0, 0.0, 100.0])  # on the hand: forward (against its normal) and up
    wrench = np.concatenate([pull, np.cross(position, pull)])  # about the world origin
    projector = WrenchProjector()
    errors = {}
    for contact in (pressed, grasped):
        phase = ContactPhase(0.0, 1.0, (contact,))
        contacts, _ = PhaseContacts(surfaces)(phase)
        realised, _ = projector.project(contacts.matrix, wrench)
        errors[contact.grasp] = np.linalg.norm(realised[:3] - pull)
        assert PhaseContacts(surfaces).grasps(phase) == (("left_hand",) if contact.grasp else ())
    assert errors[True] < 1e-3
    assert errors[False] == pytest.approx(np.linalg.norm(pull), rel=1e-3)


def test_a_sequence_records_each_grasp_from_touchdown_to_lift_off():
    from bench.motions import ContactSequence
    from robots.scene import Contact

    feet = (Contact("left_foot", (0.0, 0.09, 0.0)), Contact("right_foot", (0.0, -0.09, 0.0)))
    sequence = ContactSequence(feet)
    hang = {"left_hand": (np.array([0.0, 0.28, 0.8]), np.array([1.0, 0.0, 0.0, 0.0]))}
    first = Contact("left_hand", (0.2, 0.38, 1.1), grasp=True)
    second = Contact("left_hand", (0.5, 0.38, 1.25), grasp=True)
    sequence.hold(1.0)
    sequence.move((first,), 2.0, hang, boxes={"left_hand": "rail_a"}, lift=0.05, settle=0.5)
    sequence.hold(1.0)
    sequence.move((second,), 2.0, boxes={"left_hand": "rail_b"}, lift=0.05, lift_over=False)
    sequence.hold(1.0)
    grasps = sequence.all_grasps()
    assert [(g.box, g.start, g.end) for g in grasps] == [
        ("rail_a", 3.0, 4.0),
        ("rail_b", 6.0, math.inf),
    ]
    with pytest.raises(ValueError, match="name its box"):
        sequence.move((first,), 1.0)
    # the waypoints: leaving the hanging pose at 1 s, lifted to 0.05 m above the higher end
    # (1.15 m) at 0.3 and 0.7 of the 1.5 s swing, waiting at the target from 2.5 s; the move
    # along the rail lifted 0.05 m above each end
    hand = [(w.time, w.position_world) for w in sequence.waypoints]
    assert hand[0] == (1.0, (0.0, 0.28, 0.8))
    times = sorted(t for t, _ in hand)
    assert times == pytest.approx([1.0, 1.45, 2.05, 2.5, 4.6, 5.4])
    heights = {round(t, 2): p[2] for t, p in hand}
    assert heights[1.45] == pytest.approx(1.15)
    assert heights[2.05] == pytest.approx(1.15)
    assert heights[4.6] == pytest.approx(1.15)
    assert heights[5.4] == pytest.approx(1.30)


def _boxes_containing(scene, point, margin=0.0):
    """Names of the scene's static boxes that contain `point` (grown by `margin`)."""
    from centroidal.rotations import to_matrix

    inside = []
    for box in scene.boxes:
        local = to_matrix(np.array(box.orientation_world)).T @ (np.array(point) - box.center_world)
        if np.all(np.abs(local) <= np.array(box.half_extents) + margin):
            inside.append(box.name)
    return inside


@pytest.mark.parametrize("scale", [1.0, 1.2])
def test_handrail_stairs_steps_on_the_treads_and_grasps_the_rails(scale):
    """(B): the feet end on the landing, every foot contact lies on a tread's top face and
    inside it by the sole's half length (0.11 m x scale) and a margin; every grasp names the
    rail piece under the hand, whose centre line the palm is above by the bar's half section
    and the pad's half length; the single supports carry Sec. V-C's 50 mm inward offset; and
    the swinging soles' centres (sampled every 10 ms) never go 1 mm into a step."""
    from robots.multi_contact_scenes import (
        HANDRAIL_HALF_SECTION,
        PAPER_STEP_COUNT,
        PAPER_STEP_RISE_M,
    )

    model = RobotModel(humanoid(scale))
    scenario = make_scenario("handrail_stairs", model)
    _check_phases_cover(scenario)
    boxes = {b.name: b for b in scenario.scene.boxes}
    last = scenario.phases[-1]
    for contact in last.contacts:
        if contact.limb.endswith("foot"):
            assert contact.position_world[2] == pytest.approx(
                PAPER_STEP_COUNT * PAPER_STEP_RISE_M * scale
            )
    for phase in scenario.phases:
        for contact in phase.contacts:
            if contact.limb.endswith("foot") and contact.position_world[2] > 1e-6:
                k = round(contact.position_world[2] / (PAPER_STEP_RISE_M * scale))
                step = boxes[f"step_{k}"]
                front = step.center_world[0] - step.half_extents[0]
                back = step.center_world[0] + step.half_extents[0]
                assert front + 0.11 * scale < contact.position_world[0] < back - 0.11 * scale
        feet = [c for c in phase.contacts if c.limb.endswith("foot")]
        if len(feet) == 1:
            assert abs(phase.com_offset_world[1]) == pytest.approx(0.05 * scale)
            assert np.sign(phase.com_offset_world[1]) == -np.sign(feet[0].position_world[1])
    assert scenario.scene.grasps
    for grasp in scenario.scene.grasps:
        contact = _grasp_contact(scenario, grasp)
        assert contact.grasp
        rail = boxes[grasp.box]
        assert grasp.box.startswith(f"rail_{grasp.limb.split('_')[0]}")
        below = np.array(contact.position_world) - [0.0, 0.0, 0.05 * scale]
        assert _boxes_containing(
            scenario.scene, below, margin=HANDRAIL_HALF_SECTION * scale * 0.5 + 1e-9
        )
        assert rail.name in _boxes_containing(scenario.scene, below, margin=0.012 * scale)
    for t in np.arange(0.0, scenario.duration, 0.01):
        for foot in ("left_foot", "right_foot"):
            position, _ = scenario.limb_pose(foot, t)
            inside = _boxes_containing(scenario.scene, position, margin=-0.001)
            steps = [n for n in inside if n.startswith("step")]
            assert not steps, (t, foot, position)


def _rail_box_frame(scenario, box_name):
    from centroidal.rotations import to_matrix

    box = next(b for b in scenario.scene.boxes if b.name == box_name)
    return box, to_matrix(np.array(box.orientation_world))


def test_handrail_stairs_resting_is_the_same_climb_with_hands_on_the_rails_tops():
    """`handrail_stairs_resting`: the phases, limbs, hand poses and held boxes of (B), but each
    hand contact is unilateral (not a grasp), held by the scene as a grasp is, and touches the
    top face of the rail piece that holds it: its surface's origin on that face, within the bar,
    its normal the face's (the box's z axis)."""
    from centroidal.rotations import to_matrix

    model = RobotModel(humanoid())
    grasped = make_scenario("handrail_stairs", model)
    resting = make_scenario("handrail_stairs_resting", model)
    assert [(p.start, p.end, p.limbs) for p in resting.phases] == [
        (p.start, p.end, p.limbs) for p in grasped.phases
    ]
    assert [(g.limb, g.box, g.start, g.end) for g in resting.scene.grasps] == [
        (g.limb, g.box, g.start, g.end) for g in grasped.scene.grasps
    ]
    hands = 0
    for grasp in resting.scene.grasps:
        contact = _grasp_contact(resting, grasp)
        twin = _grasp_contact(grasped, grasp)
        assert (contact.position_world, contact.orientation_world) == (
            twin.position_world,
            twin.orientation_world,
        )
        assert not contact.grasp
        assert contact.held
        box, rotation = _rail_box_frame(resting, grasp.box)
        origin, orientation = contact.surface_pose_world
        local = rotation.T @ (np.array(origin) - box.center_world)
        assert local[2] == pytest.approx(box.half_extents[2], abs=1e-9)  # on the top face
        assert abs(local[1]) < box.half_extents[1]
        assert abs(local[0]) < box.half_extents[0]
        np.testing.assert_allclose(
            to_matrix(np.array(orientation))[:, 2], rotation[:, 2], atol=1e-9
        )
        hands += 1
    assert hands == 12


def test_a_resting_hand_pushes_on_the_rail_and_cannot_pull():
    """A hand resting on the sloped rail (`Contact.surface_pose_world`): the rail's push along
    its top face's normal is realised exactly, with friction along the rail up to mu (0.6);
    beyond mu, or pulling the hand off the rail, it is not. The same hand grasping the rail
    realises the pull (the facing pyramids)."""
    from bench.motions import _rail_grasp
    from centroidal.projection import WrenchProjector
    from centroidal.rotations import to_matrix
    from robots.limbs import PhaseContacts, limb_surfaces
    from robots.multi_contact_scenes import PAPER_STEP_RISE_M, STEP_RUN, WALKWAY_START_X
    from robots.scene import ContactPhase

    x = WALKWAY_START_X + 0.5 * STEP_RUN  # on the sloped piece
    resting, box = _rail_grasp(1.0, "left", x, 0.05, resting=True)  # the humanoid's palm pad
    grasping, _ = _rail_grasp(1.0, "left", x, 0.05)
    assert box == "rail_left_slope"
    origin, orientation = resting.surface_pose_world
    frame = to_matrix(np.array(orientation))
    normal, along = frame[:, 2], frame[:, 0]
    slope = math.atan(PAPER_STEP_RISE_M / STEP_RUN)  # the rail's pitch, 26.6 deg
    np.testing.assert_allclose(normal, [-math.sin(slope), 0.0, math.cos(slope)], atol=1e-12)
    surfaces = limb_surfaces(humanoid(), 0.6)
    projector = WrenchProjector()

    def error(contact, force):
        contacts, _ = PhaseContacts(surfaces)(ContactPhase(0.0, 1.0, (contact,)))
        wrench = np.concatenate([force, np.cross(origin, force)])  # at the surface's centre
        realised, _ = projector.project(contacts.matrix, wrench)
        return np.linalg.norm(realised - wrench) / np.linalg.norm(force)

    push = 100.0 * normal
    assert error(resting, push) < 1e-6
    assert error(resting, push + 50.0 * along) < 1e-6  # tangential 0.5 < mu
    assert error(resting, push + 80.0 * along) > 0.05  # 0.8 > mu
    assert error(resting, -push) > 0.99  # a pull: nothing of it
    assert error(grasping, -push) < 1e-6


def test_a_surface_pose_needs_its_polygon():
    from robots.scene import Contact

    with pytest.raises(ValueError, match="needs its support_in_frame"):
        Contact("left_hand", (0.0, 0.0, 1.0), surface_pose_world=((0.0, 0.0, 0.95), (1, 0, 0, 0)))


@pytest.fixture(scope="module", params=["mujoco", "pybullet"])
def stairs_episode(request):
    return request.param, run_controller(
        "preview_control+centroidal_feedback", request.param, "handrail_stairs"
    )


@pytest.mark.slow
def test_handrail_stairs_climbs_without_a_fall(stairs_episode):
    """Fig. 4 (B) with `preview_control` + `centroidal_feedback`: the whole 49 s sequence (4
    steps of 150 mm, 12 grasps) without a fall by the runner's criteria."""
    _, result = stairs_episode
    assert result.summary["status"] == "ok", result.summary["error"]
    assert not result.summary["fell"]


@pytest.mark.slow
def test_handrail_stairs_climbs_upright_on_its_plan(stairs_episode):
    """(B) with the CoM 0.74 m above the feet and the rails lowered with it (2026-11-27;
    before, at the standing height, the base tilted up to 12.6 / 16.4 deg and the CoM strayed
    up to 0.33 / 0.35 m from its reference): the base stays within 6 deg of upright, the
    controller's CoM (its estimate, what it feeds back) within 35 mm RMS of its plan over the
    whole climb, and both feet stand on the landing at the end."""
    _, result = stairs_episode
    trace = result.trace
    x, y = (trace[f"base_quat_{a}"].to_numpy() for a in "xy")
    tilt = np.degrees(np.arccos(np.clip(1.0 - 2.0 * (x**2 + y**2), -1.0, 1.0)))
    assert tilt.max() < 6.0
    error = np.linalg.norm(
        trace[["com_actual_x", "com_actual_y", "com_actual_z"]].to_numpy()
        - trace[["com_planned_x", "com_planned_y", "com_planned_z"]].to_numpy(),
        axis=1,
    )
    assert np.sqrt(np.mean(error**2)) < 0.035
    last = trace[trace["time"] > trace["time"].max() - 1.0]
    assert last["contact_left_foot"].all()
    assert last["contact_right_foot"].all()


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason="(B) does not track its plan at the steps up (2026-11-27, CoM 0.74 m above the "
    "feet): in the double support after each step up the feet leave the treads while the "
    "robot hangs on its grasps (no foot in contact for 1.03 / 1.37 s in all, MuJoCo / "
    "PyBullet), and the CoM is then up to 0.127 / 0.166 m from its reference (re-measured "
    "2026-12-03, with Coulomb's circle; 0.33 / 0.35 m at the standing height, 2026-11-24)",
)
def test_handrail_stairs_tracks_its_plan(stairs_episode):
    _, result = stairs_episode
    trace = result.trace
    error = np.linalg.norm(
        trace[["com_actual_x", "com_actual_y", "com_actual_z"]].to_numpy()
        - trace[["com_ref_x", "com_ref_y", "com_ref_z"]].to_numpy(),
        axis=1,
    )
    assert error.max() < 0.10
    last = trace[trace["time"] > trace["time"].max() - 1.0]
    assert last["contact_left_foot"].all()
    assert last["contact_right_foot"].all()


@pytest.fixture(scope="module", params=["mujoco", "pybullet"])
def resting_stairs(request):
    return request.param, {
        planner: run_controller(f"{planner}+centroidal_feedback", request.param, name)
        for planner, name in (
            ("preview_control", "handrail_stairs_resting"),
            ("linear_mpc", "handrail_stairs_resting"),
        )
    }


@pytest.mark.slow
def test_the_mpc_plans_no_wrench_to_project_on_the_resting_stairs(resting_stairs):
    """Sec. V-G on (B) with the hands resting (unilateral): the linear MPC's planned wrench
    needs no projection (zero within solver tolerance) over the climb, in both simulators; the
    feedback then leaves a desired wrench to project (not zero). Whether it climbs to the end
    is decided by round-off in MuJoCo (2026-11-27: a fall at 28.9 s, none in a version that
    differed from it by round-off; docs/multi-contact.md; 2026-12-03: no fall, 49.2 s), so
    the errors are judged over what
    it climbed: more than half the motion. "Not zero" is 1e-2 N, four orders of magnitude above the
    planned error (the desired one was 1.3-7.1 N at the standing CoM height, 0.08-0.27 N since
    the climb tracks its plan better, 2026-11-27: less feedback to project; 0.66 N in MuJoCo
    on 2026-12-03, preview control's 0.29 N)."""
    _, episodes = resting_stairs
    summary = episodes["linear_mpc"].summary
    assert summary["status"] in ("ok", "fell"), summary["error"]
    assert summary["duration"] > 24.0
    errors = summary["projection_error"]
    assert errors["planned_force_N"] < 1e-5
    assert errors["planned_moment_Nm"] < 1e-5
    assert errors["desired_force_N"] > 1e-2


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason="Sec. V-G's preview control plans wrenches to project on (B) (2.2 N, 4.4 N m in the "
    "paper); ours never leaves the cones, also with the hands resting (2026-11-27: 5e-7 N, "
    "5e-7 N m in both simulators, as the MPC's): its planned CoM acceleration is 0.07 m/s^2 "
    "on average (4 N), which four contacts or three hold",
)
def test_preview_control_plans_wrenches_to_project_on_the_resting_stairs(resting_stairs):
    _, episodes = resting_stairs
    assert episodes["preview_control"].summary["projection_error"]["planned_force_N"] > 0.1


# --- walking on the scaffold boards with a hand on the wall (Fig. 4 A) ---------------------


@pytest.mark.parametrize("scale", [1.0, 1.2])
def test_hand_wall_steps_on_the_boards_and_switches_hands(scale):
    """(A): every sole lies on one board's top face (or the ground), heel and toe (0.11 m x
    scale either side along its own x axis) on it, its normal the board's; the palms are on
    the walls' faces, the left one first, the right one after the switch, the left let go
    (a release waypoint); Table II's wall K_d (1000) and the lowered CoM offset are set."""
    from centroidal.rotations import to_matrix
    from robots.multi_contact_scenes import BOARD_THICKNESS

    model = RobotModel(humanoid(scale))
    scenario = make_scenario("hand_wall", model)
    _check_phases_cover(scenario)
    assert scenario.hand_contact_kd_linear == 1000.0
    assert scenario.com_height_offset == pytest.approx(0.78 * scale)
    assert (scenario.swing_profile, scenario.swing_scale) == ("cubic_spline_simple", scale)
    boards = [b for b in scenario.scene.boxes if b.name.startswith("board")]
    for phase in scenario.phases:
        for contact in phase.contacts:
            rotation = to_matrix(np.array(contact.orientation_world))
            if contact.limb.endswith("hand"):
                side = 1.0 if contact.limb == "left_hand" else -1.0
                assert contact.position_world[1] == pytest.approx(side * WALL_WALK_FACE_Y * scale)
                continue
            ends = [np.array(contact.position_world) + d * rotation[:, 0] for d in (-0.11, 0.11)]
            if contact.position_world[2] < 1e-9:
                assert all(abs(e[2]) < 1e-9 for e in ends)
                assert not _boxes_containing(scenario.scene, contact.position_world, -1e-3)
                continue
            on = []
            for board in boards:
                frame = to_matrix(np.array(board.orientation_world))
                local = [frame.T @ (e - board.center_world) for e in ends]
                if all(
                    abs(p[2] - 0.5 * BOARD_THICKNESS * scale) < 1e-9
                    and abs(p[0]) <= board.half_extents[0]
                    for p in local
                ):
                    on.append(board.name)
                    np.testing.assert_allclose(rotation[:, 2], frame[:, 2], atol=1e-9)
            assert len(on) == 1, (contact, on)
    first = {
        limb: min(p.start for p in scenario.phases if limb in p.limbs)
        for limb in ("left_hand", "right_hand")
    }
    assert first["left_hand"] < first["right_hand"]
    assert "left_hand" not in scenario.phases[-1].limbs
    assert "right_hand" in scenario.phases[-1].limbs
    releases = [w for w in scenario.limb_waypoints if w.release]
    assert [w.limb for w in releases] == ["left_hand"]
    assert scenario.limb_pose("left_hand", scenario.duration - 0.01) is None


@pytest.mark.slow
@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
def test_hand_wall_completes_with_feedforward_torques(sim):
    """(A) with Murooka's pair and the `ik_feedforward` layer walks the whole scaffold, the
    palm on the wall: no fall, the base never tilted by more than 4 deg (measured 1.97 / 1.88
    deg, MuJoCo / PyBullet, 2026-12-03), both feet ending on
    the ground within 5 cm of the last foothold (x = 2.05 m). In MuJoCo since (A)'s swings are
    the authors' (`robots.swing`; with our lifted swing it fell at 42.4 s, the stance feet
    yawing up to 0.18 rad). With the paper's `ik` layer it falls (`_FALLS` below)."""
    from bench.motions import WALL_WALK_FOOTHOLDS

    result = run_controller("preview_control+centroidal_feedback+ik_feedforward", sim, "hand_wall")
    assert result.summary["status"] == "ok", result.summary["error"]
    trace = result.trace
    q = trace[["base_quat_x", "base_quat_y"]].to_numpy()
    assert np.degrees(2 * np.arcsin(np.hypot(q[:, 0], q[:, 1]))).max() < 4.0
    steps = result.footsteps
    for foot in ("left_foot", "right_foot"):
        last = steps[steps["limb"] == foot].iloc[-1]
        assert abs(last["x_m"] - WALL_WALK_FOOTHOLDS[-1]) < 0.05, last
        assert abs(last["z_m"]) < 0.01, last


# --- climbing the vertical ladder (Fig. 4 C) -------------------------------------------------


def test_a_contact_on_part_of_the_sole_bears_its_load_only_there():
    """A foot on its toes (`Contact.support_in_frame`): the projected wrench of a load whose
    line of action passes through the sole's centre (outside the toe polygon) cannot be
    realised, and the best one has its CoP on the polygon's back edge; on the whole sole the
    same load is realised exactly."""
    from centroidal.projection import WrenchProjector
    from robots.limbs import PhaseContacts, limb_surfaces
    from robots.scene import Contact, ContactPhase

    surfaces = limb_surfaces(humanoid(), 0.6)
    toes = ((0.10, 0.05), (0.03, 0.05), (0.03, -0.05), (0.10, -0.05))
    position = np.array([0.2, 0.0, 0.4])
    load = np.array([0.0, 0.0, 300.0])  # on the foot, through the sole's centre
    wrench = np.concatenate([load, np.cross(position, load)])
    projector = WrenchProjector()
    cop_x = {}
    for support in (None, toes):
        phase = ContactPhase(
            0.0, 1.0, (Contact("left_foot", tuple(position), support_in_frame=support),)
        )
        contacts, _ = PhaseContacts(surfaces)(phase)
        realised, _ = projector.project(contacts.matrix, wrench)
        # CoP x on the sole's plane: moment about the world y axis, my = z fx - x fz
        force, moment = realised[:3], realised[3:]
        cop_x[support is None] = (position[2] * force[0] - moment[1]) / force[2] - position[0]
        if support is None:
            np.testing.assert_allclose(realised, wrench, atol=1e-6)
    assert cop_x[True] == pytest.approx(0.0, abs=1e-6)
    assert cop_x[False] == pytest.approx(0.03, abs=1e-3)


@pytest.mark.parametrize("scale", [1.0, 1.2])
def test_ladder_stands_on_the_rungs_on_its_toes_and_grasps_the_rungs(scale):
    """(C): every foot contact above the ground is on a rung's top face, its support polygon
    (world vertices) over the rung (within its depth and length) and narrower than the sole
    (the rung is 75 mm deep); the feet end three rungs up; every hand contact grasps the rung
    its grasp names, on the rung's near face; Sec. V-C's CoM rule holds whenever both hands
    grasp (the reference 0.3 m behind the ladder's centre, on its centre line); Table III's
    ladder gains and Table II's ladder K_d (50000) are set; and the swinging feet's sole
    centres and toe tips (sampled every 10 ms) never go 1 mm into a rung."""
    from centroidal.rotations import to_matrix
    from planners.reference import support_centre
    from robots.multi_contact_scenes import LADDER_X, PAPER_RUNG_DEPTH_M, PAPER_RUNG_SPACING_M

    model = RobotModel(humanoid(scale))
    scenario = make_scenario("ladder", model)
    _check_phases_cover(scenario)
    assert scenario.ladder_gains
    assert scenario.hand_contact_kd_linear == 50000.0
    boxes = {b.name: b for b in scenario.scene.boxes}
    spacing, depth = PAPER_RUNG_SPACING_M * scale, PAPER_RUNG_DEPTH_M * scale
    for phase in scenario.phases:
        for contact in phase.contacts:
            if not contact.limb.endswith("foot") or contact.position_world[2] < 1e-9:
                continue
            rung = boxes[f"rung_{round(contact.position_world[2] / spacing):02d}"]
            top = rung.center_world[2] + rung.half_extents[2]
            assert contact.position_world[2] == pytest.approx(top, abs=1e-12)
            assert contact.support_in_frame is not None
            rotation = to_matrix(np.array(contact.orientation_world))
            for vertex in contact.support_in_frame:
                point = np.array(contact.position_world) + rotation @ np.array([*vertex, 0.0])
                local = point - rung.center_world
                assert abs(local[0]) < rung.half_extents[0]
                assert abs(local[1]) < rung.half_extents[1]
            xs = [v[0] for v in contact.support_in_frame]
            assert max(xs) - min(xs) < depth < 0.5 * 0.22 * scale
        if {"left_hand", "right_hand"} <= set(phase.limbs):
            centre, _ = support_centre(scenario, phase.start)
            np.testing.assert_allclose(centre, [LADDER_X * scale - 0.3 * scale, 0.0], atol=1e-12)
    for foot in scenario.phases[-1].contacts:
        if foot.limb.endswith("foot"):
            assert foot.position_world[2] == pytest.approx(3 * spacing)
    assert len(scenario.scene.grasps) == 8  # the first grasps and three moves of each hand
    for grasp in scenario.scene.grasps:
        contact = _grasp_contact(scenario, grasp)
        assert contact.grasp
        rung = boxes[grasp.box]
        assert contact.position_world[0] == pytest.approx(
            rung.center_world[0] - rung.half_extents[0], abs=1e-12
        )
        assert abs(contact.position_world[2] - rung.center_world[2]) <= rung.half_extents[2]
        np.testing.assert_allclose(
            contact_normal(contact.orientation_world), (-1, 0, 0), atol=1e-12
        )
    toe = np.array([0.11 * scale, 0.0, 0.0])
    for t in np.arange(0.0, scenario.duration, 0.01):
        for foot in ("left_foot", "right_foot"):
            position, orientation = scenario.limb_pose(foot, t)
            for point in (position, position + to_matrix(orientation) @ toe):
                inside = _boxes_containing(scenario.scene, point, margin=-0.001)
                assert not [n for n in inside if n.startswith("rung")], (t, foot, point)


# --- moving with both hands on the supports (Fig. 4 D) --------------------------------------


@pytest.mark.parametrize("scale", [1.0, 1.2])
def test_hand_supports_swings_both_feet_while_the_palms_carry_the_body(scale):
    """(D): the palms lie flat on the supports' tops (normal up, on their footprints); in
    every phase without a foot both palms are in contact, and both feet leave and land in the
    same phases (they swing together); each landing is the same distance ahead of the last,
    ahead of the hands, and the CoM reference on the hands alone is above their centre; no
    swinging limb passes through a support; the crouch's CoM offset and the scene's own fall
    height are set below the standing ones."""
    from planners.reference import support_centre

    model = RobotModel(humanoid(scale))
    scenario = make_scenario("hand_supports", model)
    _check_phases_cover(scenario)
    supports = [b for b in scenario.scene.boxes if b.name.startswith("support")]
    assert len(supports) == 2
    flights = 0
    landings = []
    for before, phase in zip(scenario.phases, scenario.phases[1:], strict=False):
        feet = {c.limb for c in phase.contacts if c.limb.endswith("foot")}
        assert feet in (set(), {"left_foot", "right_foot"}), phase
        if not feet:
            flights += 1
            assert {c.limb for c in phase.contacts} == {"left_hand", "right_hand"}
            hands = np.mean([c.position_world[:2] for c in phase.contacts], axis=0)
            centre, _ = support_centre(scenario, 0.5 * (phase.start + phase.end))
            np.testing.assert_allclose(centre, hands, rtol=0, atol=1e-12)
        elif not any(c.limb.endswith("foot") for c in before.contacts):
            xs = {c.position_world[0] for c in phase.contacts if c.limb.endswith("foot")}
            assert len(xs) == 1
            hands = [c.position_world[0] for c in before.contacts]
            assert xs.pop() > max(hands)
            landings.append(next(c for c in phase.contacts if c.limb == "left_foot"))
        for contact in phase.contacts:
            if contact.limb.endswith("hand"):
                np.testing.assert_allclose(contact_normal(contact.orientation_world), (0, 0, 1))
                on = [
                    b
                    for b in supports
                    if abs(contact.position_world[2] - (b.center_world[2] + b.half_extents[2]))
                    < 1e-12
                    and all(
                        abs(contact.position_world[k] - b.center_world[k]) <= b.half_extents[k]
                        for k in (0, 1)
                    )
                ]
                assert len(on) == 1, contact
    assert flights == 3
    steps = np.diff([0.0] + [c.position_world[0] for c in landings])
    np.testing.assert_allclose(steps, steps[0], rtol=0, atol=1e-12)
    assert steps[0] > 0.05 * scale
    for t in np.arange(0.0, scenario.duration, 0.01):
        for limb in ("left_foot", "right_foot", "left_hand", "right_hand"):
            pose = scenario.limb_pose(limb, t)
            if pose is not None:
                assert not _boxes_containing(scenario.scene, pose[0], margin=-0.001), (t, limb)
    standing = model.standing_state()
    assert scenario.com_height_offset < model.com_position_world(standing)[2] - 0.15 * scale
    assert scenario.scene.fall_height < model.robot.fall_height


_FALLS = {
    "hand_wall": "(A) falls (2026-11-27, with the authors' swing, `robots.swing`, walls 0.40 m "
    "out): at 42.8 / 56.8 s (MuJoCo / PyBullet) on the descent, the soles landing 0.10-0.17 s "
    "early and 1-4 cm beyond their footholds on the ascent, 4-8 cm on the top board, up to 21 cm "
    "on the descent (the estimate anchored on the plan's; with our lifted swing 54.8 / 54.9 s, "
    "before the redesign 14.0 / 15.2 s)",
    "ladder": "(C) falls (2026-11-24) at 7.82 s in both simulators: the right thigh touches a "
    "rung on the first step up, as the kinematics predict for Sec. V-C's CoM 0.3 m behind "
    "the ladder (docs/multi-contact.md, (C) the ladder)",
}


@pytest.mark.slow
@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
@pytest.mark.parametrize(
    "motion",
    [pytest.param(m, marks=pytest.mark.xfail(strict=True, reason=r)) for m, r in _FALLS.items()]
    + ["hand_supports"],
)
def test_motion_completes_without_a_fall(motion, sim):
    """(A), (C) and (D) with `preview_control` + `centroidal_feedback`, the whole sequence."""
    result = run_controller("preview_control+centroidal_feedback", sim, motion)
    assert result.summary["status"] == "ok", result.summary["error"]
    assert not result.summary["fell"]


@pytest.mark.parametrize("robot", ["centrobench_humanoid", "jvrc1"])
def test_rung_and_rail_contacts_fit_the_robot_s_own_sole_and_palm(robot):
    """The ladder's toe polygons lie on the robot's own sole, inside its inner margin, and a
    rail grasp holds the palm centre half the robot's own palm pad above the bar. The
    humanoid's sole (0.11 x 0.06 m) and palm pad (0.05 m) were fixed in the code until
    2026-12-03: on JVRC-1 (a 0.10 x 0.04 m sole) the polygon reached 13 mm past the sole's
    side edge, and the palm sat 15 mm high."""
    from centroidal.rotations import to_matrix
    from robots.limbs import CONTACT_MARGIN
    from robots.multi_contact_scenes import HANDRAIL_HALF_SECTION
    from robots.robot_registry import make_robot

    model = RobotModel(make_robot(robot))
    margin = CONTACT_MARGIN * model.robot.scale
    ladder = make_scenario("ladder", model)
    checked = 0
    for phase in ladder.phases:
        for contact in phase.contacts:
            if not contact.limb.endswith("foot") or contact.support_in_frame is None:
                continue
            half_length, half_width = model.robot.limb(contact.limb).half_extents
            for x, y in contact.support_in_frame:
                assert abs(x) <= half_length - margin + 1e-12
                assert abs(y) <= half_width - margin + 1e-12
            checked += 1
    assert checked > 0
    stairs = make_scenario("handrail_stairs", model)
    boxes = {b.name: b for b in stairs.scene.boxes}
    grasps = [c for p in stairs.phases for c in p.contacts if c.limb.endswith("hand")]
    assert grasps
    level = 0
    for contact in grasps:
        pad = model.robot.limb(contact.limb).half_extents[0]
        position = np.array(contact.position_world)
        for rail in (b for name, b in boxes.items() if name.startswith("rail_")):
            rotation = to_matrix(np.array(rail.orientation_world))
            local = rotation.T @ (position - np.array(rail.center_world))
            level_piece = abs(rotation[2, 2] - 1.0) < 1e-12  # the rails' level ends
            if level_piece and abs(local[0]) <= rail.half_extents[0] and abs(local[1]) < 0.05:
                assert local[2] - HANDRAIL_HALF_SECTION * model.robot.scale == pytest.approx(
                    pad, abs=1e-9
                )
                level += 1
    assert level > 0
