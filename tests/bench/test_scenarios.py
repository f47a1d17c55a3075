"""Scenarios as data: contact phases, pushes, and errors for bad parameters."""

import numpy as np
import pytest

from bench.scenarios import make_scenario
from robots.humanoid import humanoid
from robots.model import RobotModel


@pytest.fixture(scope="module")
def model():
    return RobotModel(humanoid())


def test_stand_is_ten_seconds_of_double_support_at_the_soles(model):
    scenario = make_scenario("stand", model)
    assert scenario.duration == 10.0
    assert scenario.pushes == ()
    phase = scenario.phase_at(5.0)
    assert set(phase.limbs) == {"left_foot", "right_foot"}
    state = model.standing_state()
    for contact in phase.contacts:
        limb = model.robot.limb(contact.limb)
        position, _ = model.frame_pose(state, limb.contact_frame)
        np.testing.assert_allclose(contact.position_world, position, atol=1e-12)
        assert contact.position_world[2] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize(
    ("direction", "expected"), [(0.0, (1, 0)), (90.0, (0, 1)), (225.0, (-(0.5**0.5), -(0.5**0.5)))]
)
def test_stand_push_direction_and_impulse(model, direction, expected):
    scenario = make_scenario("stand_push", model, push_impulse=30.0, push_direction_deg=direction)
    (push,) = scenario.pushes
    assert push.time == 2.0
    assert push.duration == 0.1
    assert push.link == model.robot.base_link
    np.testing.assert_allclose(
        push.impulse_world, [30 * expected[0], 30 * expected[1], 0], atol=1e-12
    )


@pytest.mark.parametrize(
    ("name", "kwargs", "message"),
    [
        ("walk_on_moon", {}, "choose one of: stand, stand_push"),
        ("stand_push", {"push_impulse": -1.0}, ">= 0"),
        ("stand", {"push_impulse": 5.0}, "takes no push"),
        ("stand", {"duration": 0.0}, "positive"),
    ],
)
def test_bad_scenario_requests_are_rejected(model, name, kwargs, message):
    with pytest.raises((KeyError, ValueError), match=message):
        make_scenario(name, model, **kwargs)


def test_walk_push_is_lateral_and_mid_single_support(model):
    scenario = make_scenario("walk_push", model)
    (push,) = scenario.pushes
    assert push.link == model.robot.base_link
    np.testing.assert_allclose(push.impulse_world, [0.0, 10.0, 0.0], atol=1e-12)  # defaults
    middle = push.time + push.duration / 2
    phase = scenario.phase_at(middle)
    assert len(phase.contacts) == 1  # single support, the 5th of the walk
    assert middle == pytest.approx((phase.start + phase.end) / 2)
    singles = [p for p in scenario.phases if len(p.contacts) == 1]
    assert singles.index(phase) == 4
    walk = make_scenario("walk", model)
    assert scenario.phases == walk.phases
    assert scenario.duration == walk.duration


def test_swing_foot_lands_without_vertical_speed(model):
    """The clearance profile 64 s^3 (1 - s)^3: peak 0.05 m mid-swing, zero vertical velocity at
    lift-off and touchdown (finite differences over 1 ms)."""
    scenario = make_scenario("walk", model)
    single = next(p for p in scenario.phases if len(p.contacts) == 1)
    (support,) = single.limbs
    swing = "right_foot" if support == "left_foot" else "left_foot"

    def height(t):
        return scenario.limb_pose(swing, t)[0][2]

    start, end, h = single.start, single.end, 1e-3
    assert height((start + end) / 2) == pytest.approx(0.05, abs=1e-12)
    assert abs(height(start + h) - height(start)) / h < 1e-4
    assert abs(height(end) - height(end - h)) / h < 1e-4


def _footprints(scenario) -> dict[str, list[np.ndarray]]:
    """Each foot's successive contact positions [m], in phase order, without repeats."""
    prints: dict[str, list[np.ndarray]] = {"left_foot": [], "right_foot": []}
    for phase in scenario.phases:
        for contact in phase.contacts:
            position = np.array(contact.position_world)
            if not prints[contact.limb] or not np.array_equal(prints[contact.limb][-1], position):
                prints[contact.limb].append(position)
    return prints


@pytest.mark.parametrize("speed", [0.1, 0.2, -0.1])
def test_gait_speed_sets_the_step_length(model, speed):
    """Forward speed v with step period T: the path advances v T per step, and the feet end
    side by side (steps - 1) v T from where they started."""
    from bench.scenarios import GaitCommand

    scenario = make_scenario("walk", model, speed=speed)
    start, end = scenario.phases[0], scenario.phases[-1]
    gait = GaitCommand(speed=speed)
    assert gait.step_length_for(1.0) == pytest.approx((speed * 0.9, 0.0))
    for first, last in zip(start.contacts, end.contacts, strict=True):
        assert first.limb == last.limb
        travel = np.array(last.position_world) - np.array(first.position_world)
        np.testing.assert_allclose(travel, [9 * speed * 0.9, 0.0, 0.0], atol=1e-12)
    landings = [  # the swing foot's x where it lands, step by step
        next(c for c in after.contacts if c.limb != during.limbs[0]).position_world[0]
        for during, after in zip(scenario.phases[1::2], scenario.phases[2::2], strict=True)
    ]
    assert len(landings) == 10
    np.testing.assert_allclose(np.diff(landings)[:-1], speed * 0.9, atol=1e-12)
    assert landings[-1] == pytest.approx(landings[-2], abs=1e-12)  # side by side at the end


def test_default_gait_is_the_walk_of_earlier_releases(model):
    """`walk` as it was built before gait commands: right foot first, stride 0.25 m (the
    first and last steps half), 0.9 s steps with 15 % double support, 1.0 s before, 1.5 s
    after."""
    scenario = make_scenario("walk", model)
    single = [p for p in scenario.phases if len(p.contacts) == 1]
    assert len(single) == 10
    assert [p.limbs[0] for p in single[:2]] == ["left_foot", "right_foot"]  # right swings first
    assert single[0].start == 1.0
    assert single[0].end - single[0].start == pytest.approx(0.9 * 0.85)
    assert scenario.duration == pytest.approx(1.0 + 10 * 0.9 * 0.85 + 9 * 0.9 * 0.15 + 1.5)
    prints = _footprints(scenario)
    right = [p[0] for p in prints["right_foot"]]  # swings on steps 1, 3, ..., 9
    left = [p[0] for p in prints["left_foot"]]  # on steps 2, 4, ..., 10
    assert np.diff(right).tolist() == [0.125, 0.25, 0.25, 0.25, 0.25]
    assert np.diff(left).tolist() == [0.25, 0.25, 0.25, 0.25, 0.125]


def test_walk_side_leads_with_the_left_foot_and_never_crosses(model):
    scenario = make_scenario("walk_side", model)
    single = [p for p in scenario.phases if len(p.contacts) == 1]
    assert single[0].limbs == ("right_foot",)  # the left foot swings first
    sole_width = 2 * model.robot.limb("left_foot").half_extents[1]
    for phase in scenario.phases:
        if len(phase.contacts) == 2:
            feet = {c.limb: np.array(c.position_world) for c in phase.contacts}
            assert feet["left_foot"][1] - feet["right_foot"][1] > sole_width  # a gap between
            assert feet["left_foot"][0] == pytest.approx(feet["right_foot"][0], abs=1e-12)
    end = {c.limb: c.position_world[1] for c in scenario.phases[-1].contacts}
    start = {c.limb: c.position_world[1] for c in scenario.phases[0].contacts}
    for limb in end:
        assert end[limb] - start[limb] == pytest.approx(9 * 0.05, abs=1e-12)


def test_speed_is_for_the_walks_only(model):
    with pytest.raises(ValueError, match="speed applies to walk, walk_push"):
        make_scenario("stand", model, speed=0.1)


def _standing_palm(model) -> np.ndarray:
    """The right palm [m] in the standing posture, by `frame_pose` (the scenarios use
    `frame_positions_world`)."""
    frame = model.robot.limb("right_hand").contact_frame
    return model.frame_pose(model.standing_state(), frame)[0]


# (time [s], the right palm's target offset [m] from the standing palm, world axes)
REACH_EXPECTED = [
    (0.0, (0.5, -0.1, 0.05)),  # 0.5 m ahead, 0.1 m right, 0.05 m up
    (3.999, (0.5, -0.1, 0.05)),
    (4.0, (0.8, -0.1, 0.05)),  # 0.3 m further forward
    (7.999, (0.8, -0.1, 0.05)),
    (8.0, (0.8, -0.4, 0.05)),  # 0.3 m further right
    (12.0, (0.8, -0.4, 0.05)),
]


@pytest.mark.parametrize("name", ["reach", "reach_push"])
def test_reach_targets_move_the_right_palm_as_sherikov_test_1(model, name):
    """Sherikov et al. 2014 Tests 1 and 2: 12 s standing in double support (the controller
    must choose its own steps), the right palm's target moved forward at 4 s and right at 8 s,
    relative to where the palm is when standing."""
    from bench.scenarios import SCENARIOS

    scenario = make_scenario(name, model)
    assert scenario.duration == 12.0
    assert {t.limb for t in scenario.hand_targets} == {"right_hand"}
    assert [t.time for t in scenario.hand_targets] == [0.0, 4.0, 8.0]
    stand = make_scenario("stand", model, duration=12.0)
    assert scenario.phases == stand.phases  # flat ground, both feet where they stand
    assert scenario.scene == stand.scene
    palm = _standing_palm(model)
    for time, offset in REACH_EXPECTED:
        target = scenario.hand_target_at("right_hand", time)
        np.testing.assert_allclose(target - palm, offset, rtol=0, atol=1e-12)
    assert scenario.hand_target_at("left_hand", 5.0) is None
    spec = SCENARIOS[name]
    assert spec.requires == frozenset({"flat_ground"})
    assert ("Test 1" if name == "reach" else "Test 2") in spec.description


def test_reach_target_is_out_of_the_arms_reach_at_first(model):
    """Sherikov et al.: "The desired position of the hand is set to a point which is initially
    unreachable": from the standing shoulder the first target is farther than the arm's
    segments laid end to end (shoulder to elbow to palm), so the robot must step towards it."""
    shoulder, elbow, palm = model.frame_positions_world(
        model.standing_state(), ["right_shoulder_pitch", "right_elbow", "right_palm"]
    )
    arm = np.linalg.norm(elbow - shoulder) + np.linalg.norm(palm - elbow)
    target = make_scenario("reach", model).hand_target_at("right_hand", 0.0)
    assert np.linalg.norm(target - shoulder) > arm + 0.1


def test_reach_push_pushes_from_the_right_then_from_the_front(model):
    """Test 2: 15 N s to the torso at 2.5 s from the right (towards +y: a step to the left)
    and at 7 s from the front (towards -x: a step back), each over 0.1 s; otherwise `reach`."""
    scenario = make_scenario("reach_push", model)
    reach = make_scenario("reach", model)
    assert reach.pushes == ()
    assert scenario.hand_targets == reach.hand_targets
    first, second = scenario.pushes
    for push, time, direction in ((first, 2.5, (0, 1, 0)), (second, 7.0, (-1, 0, 0))):
        assert push.time == time
        assert push.duration == 0.1
        assert push.link == model.robot.base_link
        assert np.linalg.norm(push.impulse_world) == pytest.approx(15.0, abs=1e-12)
        np.testing.assert_allclose(push.impulse_world, 15.0 * np.array(direction), atol=1e-12)
    # the same convention as `stand_push`'s direction in degrees
    for push, degrees in ((first, 90.0), (second, 180.0)):
        (same,) = make_scenario(
            "stand_push", model, push_impulse=15.0, push_direction_deg=degrees
        ).pushes
        assert push.impulse_world == same.impulse_world


def test_reach_offsets_scale_with_the_robot():
    """At scale 0.5 the palm's target offsets are half the paper's (the times and the 15 N s
    impulses as printed)."""
    small = RobotModel(humanoid(0.5))
    scenario = make_scenario("reach_push", small)
    palm = _standing_palm(small)
    for time, offset in REACH_EXPECTED:
        target = scenario.hand_target_at("right_hand", time)
        np.testing.assert_allclose(target - palm, 0.5 * np.array(offset), rtol=0, atol=1e-12)
    assert [np.linalg.norm(p.impulse_world) for p in scenario.pushes] == pytest.approx([15, 15])


@pytest.mark.parametrize("robot", ["centrobench_humanoid", "jvrc1"])
def test_every_push_acts_on_the_torso_above_the_centre_of_mass(robot):
    """Sherikov et al. Sec. VII-A: "All disturbances are applied to the torso of the robot".
    Every pushing scenario pushes the link both arms branch from, on both robots: the
    humanoid's base, and JVRC-1's chest above its waist joints (not its pelvis, whose centre of
    mass is at the robot's own height), whose centre of mass is well above the robot's."""
    from robots.robot_registry import make_robot

    description = make_robot(robot)
    standing = RobotModel(description)
    state = standing.standing_state()
    torso = description.torso_link
    position, rotation = standing.frame_pose(state, torso)
    torso_com = position + rotation @ np.array(description.link(torso).inertial.com_in_link)
    assert torso_com[2] > standing.com_position_world(state)[2] + 0.2
    hands = {limb.link for limb in description.limbs if limb.name.endswith("hand")}
    assert torso not in hands
    for name in ("stand_push", "walk_push", "reach_push"):
        pushed = {push.link for push in make_scenario(name, standing).pushes}
        assert pushed == {torso}, name
