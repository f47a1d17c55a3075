"""Multi-contact scenario data: free-limb waypoints, the swing clearance along the contacts'
normals, delayed moving boxes (Murooka Fig. 4 motions, `bench.motions`)."""

import math
from dataclasses import replace

import numpy as np
import pytest

from robots.scene import (
    Contact,
    ContactPhase,
    LimbWaypoint,
    MovingBox,
    Scenario,
    Scene,
    contact_normal,
)

FEET = (Contact("left_foot", (0.0, 0.1, 0.0)), Contact("right_foot", (0.0, -0.1, 0.0)))
ON_LEFT_WALL = (math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0)  # z axis -y: palm on a +y wall
HANGING = ((0.02, 0.28, 0.79), (1.0, 0.0, 0.0, 0.0))
PALM_A = Contact("left_hand", (0.05, 0.45, 1.0), ON_LEFT_WALL)
PALM_B = Contact("left_hand", (0.35, 0.45, 1.1), ON_LEFT_WALL)


def _scenario(phases, waypoints=(), swing_height=0.05) -> Scenario:
    return Scenario(
        "test",
        phases[-1].end,
        Scene(),
        tuple(phases),
        (),
        swing_height=swing_height,
        limb_waypoints=waypoints,
    )


def _hand_on_wall_twice() -> Scenario:
    """Stand 1 s; the left hand leaves its hanging pose (a waypoint) at 1 s, presses the wall
    at A from 2 to 3 s, moves to B on the wall by 4 s and stays there to 5 s."""
    return _scenario(
        [
            ContactPhase(0.0, 1.0, FEET),
            ContactPhase(1.0, 2.0, FEET),
            ContactPhase(2.0, 3.0, (*FEET, PALM_A)),
            ContactPhase(3.0, 4.0, FEET),
            ContactPhase(4.0, 5.0, (*FEET, PALM_B)),
        ],
        (LimbWaypoint("left_hand", 1.0, *HANGING),),
    )


def test_contact_normal_is_the_frames_z_axis():
    np.testing.assert_allclose(contact_normal((1.0, 0.0, 0.0, 0.0)), (0, 0, 1), atol=1e-15)
    np.testing.assert_allclose(contact_normal(ON_LEFT_WALL), (0, -1, 0), atol=1e-15)


def test_a_hand_swings_from_its_waypoint_to_the_wall_and_arrives_at_rest():
    scenario = _hand_on_wall_twice()
    position, orientation = scenario.limb_pose("left_hand", 1.0)
    np.testing.assert_allclose(position, HANGING[0], atol=1e-15)
    np.testing.assert_allclose(orientation, HANGING[1], atol=1e-15)
    position, orientation = scenario.limb_pose("left_hand", 0.5)  # before: held there
    np.testing.assert_allclose(position, HANGING[0], atol=1e-15)
    position, orientation = scenario.limb_pose("left_hand", 2.0)
    np.testing.assert_allclose(position, PALM_A.position_world, atol=1e-15)
    np.testing.assert_allclose(orientation, ON_LEFT_WALL, atol=1e-15)
    # zero velocity at both ends of the swing (finite differences)
    h = 1e-5
    for t in (1.0 + h, 2.0 - h):
        before, after = (scenario.limb_pose("left_hand", t + d)[0] for d in (-h, h))
        assert np.linalg.norm(after - before) / (2 * h) < 1e-3
    # half way, the orientation has turned half of the 90 deg about x
    _, middle = scenario.limb_pose("left_hand", 1.5)
    angle = 2 * math.atan2(np.linalg.norm(middle[1:]), middle[0])
    assert angle == pytest.approx(math.pi / 4, abs=1e-9)


def test_a_hand_moving_along_the_wall_lifts_off_it_not_up():
    """Between two palm contacts on the same wall (normal -y) the clearance is along the
    normal: at mid-swing the palm is swing_height off the wall, at the heights' midpoint."""
    scenario = _hand_on_wall_twice()
    position, _ = scenario.limb_pose("left_hand", 3.5)
    middle = (np.array(PALM_A.position_world) + PALM_B.position_world) / 2
    np.testing.assert_allclose(position, np.add(middle, (0.0, -0.05, 0.0)), atol=1e-12)


def test_level_swings_are_unchanged_by_the_normal_rule():
    """Feet on level ground (any yaw): the clearance is added to z alone, bit for bit."""
    yawed = (math.cos(0.2), 0.0, 0.0, math.sin(0.2))
    start = Contact("right_foot", (0.0, -0.1, 0.0), yawed)
    end = Contact("right_foot", (0.25, -0.1, 0.0))
    scenario = _scenario(
        [
            ContactPhase(0.0, 1.0, (FEET[0], start)),
            ContactPhase(1.0, 2.0, FEET[:1]),
            ContactPhase(2.0, 3.0, (FEET[0], end)),
        ]
    )
    s = 0.25  # exact in binary: the same s as limb_pose computes
    position, _ = scenario.limb_pose("right_foot", 1.0 + s)
    blend = s**3 * (10 - 15 * s + 6 * s * s)
    expected = np.array(start.position_world) + blend * (
        np.subtract(end.position_world, start.position_world)
    )
    expected[2] += 0.05 * 64.0 * (s * (1.0 - s)) ** 3
    assert position.tolist() == expected.tolist()


def test_out_of_order_phases_give_the_same_poses_with_waypoints():
    """`limb_pose` scans the phases when they are not in time order: the same waypoint rule."""
    ordered = _hand_on_wall_twice()
    shuffled = replace(ordered, phases=tuple(reversed(ordered.phases)))
    assert shuffled._timeline is None
    for t in np.linspace(0.0, 5.0, 41):
        a, b = ordered.limb_pose("left_hand", t), shuffled.limb_pose("left_hand", t)
        np.testing.assert_allclose(a[0], b[0], atol=1e-12)
        np.testing.assert_allclose(a[1], b[1], atol=1e-12)


def test_a_delayed_moving_box_rests_then_moves_as_the_undelayed_one():
    box = MovingBox(
        "floor",
        (0.0, 0.0, -0.05),
        (0.4, 0.2, 0.05),
        translation_amplitude_world=(0.0, 0.0, 0.02),
        rotation_axis_world=(0.0, 1.0, 0.0),
        rotation_amplitude=math.radians(2.0),
        period=8.0,
        ramp_time=4.0,
    )
    delayed = replace(box, start_time=5.0)
    for t in (0.0, 2.0, 4.999):
        center, quaternion = delayed.pose_at(t)
        np.testing.assert_array_equal(center, box.center_world)
        np.testing.assert_allclose(quaternion, (1, 0, 0, 0), atol=1e-15)
        assert not np.any(delayed.velocity_at(t)[0])
    for t in (0.5, 3.0, 7.0):
        np.testing.assert_array_equal(delayed.pose_at(5.0 + t)[0], box.pose_at(t)[0])
        np.testing.assert_array_equal(delayed.velocity_at(5.0 + t)[1], box.velocity_at(t)[1])
    with pytest.raises(ValueError, match="start_time"):
        replace(box, start_time=-1.0).validate()


def test_a_released_limb_has_no_target_after_its_last_waypoint():
    """`LimbWaypoint(release=True)`: the hand leaves the wall, swings to the waypoint and has
    no target after it (the posture task takes it), instead of holding the pose for ever."""
    scenario = _scenario(
        [
            ContactPhase(0.0, 1.0, (*FEET, PALM_A)),
            ContactPhase(1.0, 3.0, FEET),
        ],
        (LimbWaypoint("left_hand", 2.0, *HANGING, release=True),),
    )
    assert scenario.limb_pose("left_hand", 0.5)[0].tolist() == list(PALM_A.position_world)
    np.testing.assert_allclose(
        scenario.limb_pose("left_hand", 2.0 - 1e-9)[0], HANGING[0], atol=1e-6
    )
    assert scenario.limb_pose("left_hand", 2.0) is None
    assert scenario.limb_pose("left_hand", 2.9) is None
    held = replace(scenario, limb_waypoints=(LimbWaypoint("left_hand", 2.0, *HANGING),))
    np.testing.assert_allclose(held.limb_pose("left_hand", 2.9)[0], HANGING[0], atol=1e-15)
