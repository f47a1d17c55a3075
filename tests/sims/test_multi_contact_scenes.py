"""Murooka et al.'s multi-contact scenes (Fig. 4 A-E, `robots.multi_contact_scenes`) and moving
boxes (`robots.scene.MovingBox`) in both simulators.

- Each scene is built the same in MuJoCo and PyBullet: every box's pose and size, read back
  from each engine (`scene_boxes_world`), equals the spec to 1e-9 (both engines store double
  precision: the read-back is exact to rounding, ~1e-16).
- The paper's dimensions hold, scaled with the robot: (A) 25 deg boards, (B) four 150 mm rises,
  (C) rungs 200 mm apart and 75 mm deep (less than half the sole), (D) supports at 500 mm,
  (E) 20 mm and 2 deg.
- A moving box's velocity is its pose's derivative; both engines hold its prescribed pose at
  the simulator's time to 1e-9 after every physics step, and carry a robot standing on it
  (friction sees the box's velocity: a MuJoCo mocap body would not, see `sims.mujoco_sim`).
- A scene without moving boxes never runs the moving-box update.
"""

import math

import numpy as np
import pytest

from robots.humanoid import humanoid
from robots.multi_contact_scenes import (
    HANDRAIL_HEIGHT,
    MULTI_CONTACT_SCENES,
    PAPER_BOARD_INCLINE_RAD,
    PAPER_MOTION_ROTATION_RAD,
    PAPER_MOTION_TRANSLATION_M,
    PAPER_RUNG_DEPTH_M,
    PAPER_RUNG_SPACING_M,
    PAPER_STEP_RISE_M,
    PAPER_SUPPORT_HEIGHT_M,
    STEP_RUN,
    hand_supports,
    hand_wall,
    handrail_stairs,
    ladder,
    moving_contacts,
)
from robots.scene import Box, MovingBox, Scene
from sims.base import make_simulator, quaternion_product, quaternion_to_matrix

SIMS = ["mujoco", "pybullet"]
SCALES = [1.0, 0.8]


def quaternion_distance(a, b) -> float:
    """Largest component difference of two unit quaternions, up to sign (q and -q are one
    rotation)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return min(np.abs(a - b).max(), np.abs(a + b).max())


def top(box: Box) -> float:
    """[m] height of an axis-aligned box's top face."""
    return box.center_world[2] + box.half_extents[2]


def named(scene: Scene, prefix: str) -> list[Box]:
    return [box for box in scene.boxes if box.name.startswith(prefix)]


# ------------------------------------------------------------------ built identically
@pytest.mark.parametrize("sim_name", SIMS)
@pytest.mark.parametrize("scene_name", list(MULTI_CONTACT_SCENES))
def test_every_box_reads_back_as_specified(robot, model, sim_name, scene_name):
    """The engine holds every box of the scene, static and moving (at t = 0), with the spec's
    centre, orientation and half extents to 1e-9; no box is missing or extra."""
    scene = MULTI_CONTACT_SCENES[scene_name](robot)
    sim = make_simulator(sim_name)
    try:
        sim.reset(robot, scene, model.standing_state())
        read = sim.scene_boxes_world()
    finally:
        sim.close()
    expected = {box.name: (box.center_world, box.orientation_world) for box in scene.boxes}
    expected |= {box.name: box.pose_at(0.0) for box in scene.moving_boxes}
    assert set(read) == set(expected)
    for box in (*scene.boxes, *scene.moving_boxes):
        center, quaternion, half_extents = read[box.name]
        np.testing.assert_allclose(half_extents, box.half_extents, rtol=0, atol=1e-9)
        np.testing.assert_allclose(center, expected[box.name][0], rtol=0, atol=1e-9)
        assert quaternion_distance(quaternion, expected[box.name][1]) <= 1e-9, box.name


# ------------------------------------------------------------------ the paper's geometry
@pytest.mark.parametrize("scale", SCALES)
def test_hand_wall_boards_are_inclined_25_degrees(scale):
    """(A): the ascending and descending boards are inclined 25 deg (their normal from the
    vertical), the top board is flat, the top faces meet edge to edge from the ground up and
    back; a wall on each side."""
    scene = hand_wall(humanoid(scale))
    boards = {box.name: box for box in named(scene, "board_")}
    assert set(boards) == {"board_up", "board_top", "board_down"}

    def incline(box: Box) -> float:
        return math.acos(quaternion_to_matrix(box.orientation_world)[2, 2])

    def top_face_ends(box: Box) -> np.ndarray:
        """(x, z) of the top face's centre line at the box's -x and +x ends."""
        rotation = quaternion_to_matrix(box.orientation_world)
        hx, _, hz = box.half_extents
        ends = [np.array(box.center_world) + rotation @ [sx * hx, 0.0, hz] for sx in (-1, 1)]
        return np.array([[end[0], end[2]] for end in ends])

    assert incline(boards["board_up"]) == pytest.approx(PAPER_BOARD_INCLINE_RAD, abs=1e-12)
    assert incline(boards["board_down"]) == pytest.approx(PAPER_BOARD_INCLINE_RAD, abs=1e-12)
    assert math.radians(25.0) == PAPER_BOARD_INCLINE_RAD
    assert incline(boards["board_top"]) == pytest.approx(0.0, abs=1e-12)
    up, flat, down = (top_face_ends(boards[n]) for n in ("board_up", "board_top", "board_down"))
    assert up[0, 1] == pytest.approx(0.0, abs=1e-12)  # starts at the ground
    assert up[1, 1] > up[0, 1]  # rises along +x
    np.testing.assert_allclose(up[1], flat[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(flat[1], down[0], rtol=0, atol=1e-12)
    assert down[1, 1] == pytest.approx(0.0, abs=1e-12)  # and back to the ground
    walls = named(scene, "wall_")
    assert sorted(np.sign(wall.center_world[1]) for wall in walls) == [-1.0, 1.0]


@pytest.mark.parametrize("scale", SCALES)
def test_handrail_stairs_have_four_rises_of_150_mm(scale):
    """(B): four steps, each 0.150 m x scale above the last (the first above the ground),
    treads deeper than the sole; each side's sloped rail runs parallel to the pitch line
    (through the nosings) at the rail height above it."""
    robot = humanoid(scale)
    scene = handrail_stairs(robot)
    steps = sorted(named(scene, "step_"), key=top)
    assert len(steps) == 4
    rises = np.diff([0.0, *(top(step) for step in steps)])
    np.testing.assert_allclose(rises, PAPER_STEP_RISE_M * scale, rtol=0, atol=1e-12)
    assert PAPER_STEP_RISE_M == 0.150
    foot = next(limb for limb in robot.limbs if limb.name == "left_foot")
    nosings = [(step.center_world[0] - step.half_extents[0], top(step)) for step in steps]
    assert all(2 * step.half_extents[0] > 2 * foot.half_extents[0] for step in steps)
    for side in ("left", "right"):
        rail = next(box for box in scene.boxes if box.name == f"rail_{side}_slope")
        axis = quaternion_to_matrix(rail.orientation_world)[:, 0]
        assert axis[2] / axis[0] == pytest.approx(PAPER_STEP_RISE_M / STEP_RUN, abs=1e-12)
        for x, z in nosings:  # the rail's centre line above each nosing
            height = rail.center_world[2] + (x - rail.center_world[0]) * axis[2] / axis[0]
            assert height - z == pytest.approx(HANDRAIL_HEIGHT * scale, abs=1e-12)


@pytest.mark.parametrize("scale", SCALES)
def test_ladder_rungs_are_200_mm_apart_and_75_mm_deep(scale):
    """(C): rungs 0.200 m x scale apart (top faces), 0.075 m x scale deep, which is less than
    half the sole's length (so the feet stand on the toes)."""
    robot = humanoid(scale)
    rungs = sorted(named(ladder(robot), "rung_"), key=top)
    assert len(rungs) >= 5
    spacing = np.diff([top(rung) for rung in rungs])
    np.testing.assert_allclose(spacing, PAPER_RUNG_SPACING_M * scale, rtol=0, atol=1e-12)
    depths = [2 * rung.half_extents[0] for rung in rungs]
    np.testing.assert_allclose(depths, PAPER_RUNG_DEPTH_M * scale, rtol=0, atol=1e-12)
    assert (PAPER_RUNG_SPACING_M, PAPER_RUNG_DEPTH_M) == (0.200, 0.075)
    sole_length = (
        2 * next(limb for limb in robot.limbs if limb.name.endswith("foot")).half_extents[0]
    )
    assert sole_length == pytest.approx(0.22 * scale, abs=1e-12)
    assert max(depths) < 0.5 * sole_length


@pytest.mark.parametrize("scale", SCALES)
def test_hand_supports_are_at_500_mm(scale):
    """(D): two supports, one either side of the soles, their tops at 0.500 m x scale."""
    scene = hand_supports(humanoid(scale))
    supports = named(scene, "support_")
    assert len(supports) == 2
    np.testing.assert_allclose(
        [top(support) for support in supports], PAPER_SUPPORT_HEIGHT_M * scale, rtol=0, atol=1e-12
    )
    assert PAPER_SUPPORT_HEIGHT_M == 0.500
    assert sorted(np.sign(support.center_world[1]) for support in supports) == [-1.0, 1.0]
    assert min(abs(s.center_world[1]) - s.half_extents[1] for s in supports) > 0.15 * scale


@pytest.mark.parametrize("scale", SCALES)
def test_moving_contacts_move_20_mm_and_2_degrees(scale):
    """(E): two floors and two walls, each translating 0.020 m x scale and turning 2 deg at
    their peak (sampled over a period after the ramp), periodic with 8 s x sqrt(scale); the
    floors' tops are at z = 0 at t = 0, where the robot is placed, and there is no ground."""
    scene = moving_contacts(humanoid(scale))
    assert not scene.ground
    assert not scene.boxes
    assert sorted(box.name for box in scene.moving_boxes) == [
        "floor_left",
        "floor_right",
        "wall_left",
        "wall_right",
    ]
    for box in scene.moving_boxes:
        assert box.period == pytest.approx(8.0 * math.sqrt(scale), abs=1e-12)
        times = box.ramp_time + np.linspace(0.0, box.period, 401)
        shifts, angles = [], []
        for t in times:
            center, quaternion = box.pose_at(t)
            shifts.append(np.linalg.norm(center - box.center_world))
            turn = quaternion_product(quaternion, np.array(box.orientation_world) * [1, -1, -1, -1])
            angles.append(2 * math.atan2(np.linalg.norm(turn[1:]), abs(turn[0])))
        assert max(shifts) == pytest.approx(PAPER_MOTION_TRANSLATION_M * scale, rel=1e-4)
        assert max(angles) == pytest.approx(PAPER_MOTION_ROTATION_RAD, rel=1e-4)
        t = box.ramp_time + 0.3
        np.testing.assert_allclose(box.pose_at(t)[0], box.pose_at(t + box.period)[0], atol=1e-12)
        center, quaternion = box.pose_at(0.0)
        np.testing.assert_array_equal(center, box.center_world)
        if box.name.startswith("floor"):
            assert center[2] + box.half_extents[2] == pytest.approx(0.0, abs=1e-15)
    assert PAPER_MOTION_TRANSLATION_M == 0.020
    assert math.radians(2.0) == PAPER_MOTION_ROTATION_RAD


def test_robot_starts_standing_on_the_moving_floors(robot, model):
    """(E): placed as on flat ground, the robot stands on the two floors at the start: after
    0.1 s (the floors still at rest within the ramp) each sole carries a share of the weight
    and both together m g within 5 %, in both simulators."""
    weight = model.total_mass * 9.81
    scene = moving_contacts(robot)
    initial = model.standing_state()
    for sim_name in SIMS:
        sim = make_simulator(sim_name)
        try:
            sim.reset(robot, scene, initial)
            for _ in range(50):
                sensors = sim.step(model.hold_command(initial))
        finally:
            sim.close()
        feet = [i for i, limb in enumerate(robot.limbs) if limb.name.endswith("foot")]
        normal = sensors.contact_wrench_limb[feet, 2]
        assert all(normal > 0.25 * weight), (sim_name, normal)
        assert normal.sum() == pytest.approx(weight, rel=0.05), sim_name


# ------------------------------------------------------------------------- moving boxes
SKEW_BOX = MovingBox(
    "skew",
    (1.5, -0.5, 0.4),
    (0.2, 0.1, 0.05),
    orientation_world=(math.cos(0.2), 0.0, 0.0, math.sin(0.2)),
    translation_amplitude_world=(0.02, -0.01, 0.015),
    rotation_axis_world=(1.0, 2.0, 2.0),
    rotation_amplitude=math.radians(10.0),
    period=0.25,
    phase=0.4,
    ramp_time=0.1,
)
"""A box off to the side of the robot, moving along all three axes and turning about a skew
axis, fast (period 0.25 s), with a ramp."""


@pytest.mark.parametrize("time", [0.01, 0.03, 0.07, 0.16, 0.9])
def test_moving_box_velocity_is_the_derivative_of_its_pose(time):
    """velocity_at's linear velocity is d(centre)/dt and its angular velocity (world) is
    2 dq/dt q* (central differences, h = 1e-6 s, truncation ~1e-10), in the ramp and after
    it (away from t = 0 and the ramp's end, where the second derivative jumps)."""
    h = 1e-6
    before, after = SKEW_BOX.pose_at(time - h), SKEW_BOX.pose_at(time + h)
    linear, angular = SKEW_BOX.velocity_at(time)
    np.testing.assert_allclose(linear, (after[0] - before[0]) / (2 * h), rtol=0, atol=1e-8)
    _, quaternion = SKEW_BOX.pose_at(time)
    derivative = (after[1] - before[1]) / (2 * h)
    spin = 2 * quaternion_product(derivative, quaternion * [1, -1, -1, -1])
    np.testing.assert_allclose(angular, spin[1:], rtol=0, atol=1e-8)
    assert np.abs(linear).max() > 0.01  # the test is not vacuous


def test_a_ramped_box_starts_at_rest_in_its_mean_pose():
    """With a ramp, t = 0 is the mean pose with zero velocity; the motion is continuous in
    position and velocity through the ramp's end."""
    center, quaternion = SKEW_BOX.pose_at(0.0)
    np.testing.assert_array_equal(center, SKEW_BOX.center_world)
    assert quaternion_distance(quaternion, SKEW_BOX.orientation_world) < 1e-15
    linear, angular = SKEW_BOX.velocity_at(0.0)
    assert not linear.any()
    assert not angular.any()
    end, h = SKEW_BOX.ramp_time, 1e-9
    for a, b in zip(SKEW_BOX.velocity_at(end - h), SKEW_BOX.velocity_at(end + h), strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-6)
    np.testing.assert_allclose(
        SKEW_BOX.pose_at(end - h)[0], SKEW_BOX.pose_at(end + h)[0], atol=1e-9
    )


@pytest.mark.parametrize("sim_name", SIMS)
def test_moving_box_follows_its_motion_every_physics_step(robot, model, sim_name):
    """Over 300 physics steps (150 control periods of two), the engine's pose of the box
    equals `pose_at(sim.time)` to 1e-9 m (centre) and 1e-9 (quaternion) after every period;
    the update runs after every physics step, at its time (one call per step, at t = k dt),
    and the box does move (centre over 25 mm, 8 deg)."""
    scene = Scene(moving_boxes=(SKEW_BOX,))
    sim = make_simulator(sim_name)
    calls: list[float] = []
    move = sim._move_boxes

    def recorded(time: float) -> None:
        calls.append(time)
        move(time)

    sim._move_boxes = recorded
    initial = model.standing_state()
    errors, centers = [], []
    try:
        sim.reset(robot, scene, initial)
        command = model.hold_command(initial)
        for _ in range(150):
            sim.step(command)
            center, quaternion, half_extents = sim.scene_boxes_world()["skew"]
            expected_center, expected_quaternion = SKEW_BOX.pose_at(sim.time)
            errors.append(
                (
                    np.abs(center - expected_center).max(),
                    quaternion_distance(quaternion, expected_quaternion),
                    np.abs(half_extents - SKEW_BOX.half_extents).max(),
                )
            )
            centers.append(center)
    finally:
        sim.close()
    # every one of centre, orientation and half extents (a list comparison checked the first)
    assert (np.max(errors, axis=0) <= 1e-9).all()
    dt = scene.physics_dt
    np.testing.assert_allclose(calls, dt * np.arange(301), rtol=0, atol=1e-12)
    assert np.ptp(np.array(centers), axis=0).max() > 0.025
    angles = [
        2 * math.acos(min(1.0, abs(SKEW_BOX.pose_at(t)[1] @ SKEW_BOX.orientation_world)))
        for t in calls
    ]
    assert max(angles) > math.radians(8.0)


@pytest.mark.parametrize("sim_name", SIMS)
def test_robot_on_a_moving_floor_is_carried_by_friction(robot, model, sim_name):
    """The robot holding its posture on a floor plate that slides 20 mm along x (period 1 s,
    no ramp: it starts at 0.126 m/s) moves with it: over 1 s the soles' displacement equals
    the plate's to 1.5 mm (the plate sweeps 40 mm). Friction must see the plate's velocity;
    on a MuJoCo mocap plate the soles would stay put (20 mm off)."""
    plate = MovingBox(
        "plate",
        (0.0, 0.0, -0.05),
        (0.5, 0.5, 0.05),
        translation_amplitude_world=(0.02, 0.0, 0.0),
        period=1.0,
    )
    scene = Scene(ground=False, moving_boxes=(plate,))
    initial = model.standing_state()
    soles = ["left_sole", "right_sole"]
    sim = make_simulator(sim_name)
    errors = []
    try:
        sim.reset(robot, scene, initial)
        start = sim.frame_positions_world(soles).copy()
        command = model.hold_command(initial)
        for _ in range(500):
            sim.step(command)
            moved = plate.pose_at(sim.time)[0] - plate.center_world
            errors.append(np.abs(sim.frame_positions_world(soles) - start - moved).max())
        fall = sim.fall_reason()
    finally:
        sim.close()
    assert fall is None
    assert max(errors) < 1.5e-3


@pytest.mark.parametrize("sim_name", SIMS)
def test_a_scene_without_moving_boxes_never_moves_boxes(robot, model, sim_name):
    """Flat ground and static boxes: the moving-box update is never called (the physics step
    is the one from before moving boxes existed), and the static boxes read back exactly."""
    box = Box("block", (0.6, 0.0, 0.05), (0.1, 0.3, 0.05))
    scene = Scene(boxes=(box,))
    sim = make_simulator(sim_name)

    def forbidden(time: float) -> None:
        raise AssertionError("moving-box update on a static scene")

    sim._move_boxes = forbidden
    initial = model.standing_state()
    try:
        sim.reset(robot, scene, initial)
        for _ in range(5):
            sim.step(model.hold_command(initial))
        center, quaternion, half_extents = sim.scene_boxes_world()["block"]
    finally:
        sim.close()
    np.testing.assert_array_equal(center, box.center_world)
    np.testing.assert_array_equal(half_extents, box.half_extents)
    assert quaternion_distance(quaternion, box.orientation_world) == 0.0


def test_moving_boxes_leave_the_robots_mass_properties_alone(robot, model):
    """MuJoCo's moving boxes are free bodies: the robot's mass properties (bodies, joints,
    limits) read the same with them as without."""
    initial = model.standing_state()
    properties = []
    for scene in (Scene(), moving_contacts(robot)):
        sim = make_simulator("mujoco")
        try:
            sim.reset(robot, scene, initial)
            properties.append(sim.mass_properties())
        finally:
            sim.close()
    flat, moving = properties
    assert moving.body_names == flat.body_names
    assert moving.joint_names == flat.joint_names
    np.testing.assert_array_equal(moving.mass, flat.mass)
    np.testing.assert_array_equal(moving.joint_lower, flat.joint_lower)


def test_scene_validation_rejects_repeated_names_and_bad_motions():
    static = Box("a", (0.0, 0.0, 0.0), (0.1, 0.1, 0.1))
    with pytest.raises(ValueError, match="unique, repeated: a"):
        Scene(
            boxes=(static,), moving_boxes=(MovingBox("a", (1, 0, 0), (0.1, 0.1, 0.1)),)
        ).validate()
    with pytest.raises(ValueError, match="period"):
        Scene(moving_boxes=(MovingBox("b", (0, 0, 0), (0.1, 0.1, 0.1), period=0.0),)).validate()
    with pytest.raises(ValueError, match="axis"):
        Scene(
            moving_boxes=(MovingBox("c", (0, 0, 0), (1, 1, 1), rotation_axis_world=(0, 0, 0)),)
        ).validate()
