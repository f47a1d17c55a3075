"""Murooka et al.'s swing (`robots.swing`, MultiContactController's CubicSplineSimple) and its
use by `Scenario.limb_pose` for a motion that asks for it."""

import math
from dataclasses import replace

import numpy as np
import pytest

from robots.scene import Contact, ContactPhase, LimbWaypoint, Scenario, Scene, contact_normal
from robots.swing import (
    APPROACH_OFFSET_M,
    SWING_OFFSET_M,
    WITHDRAW_OFFSET_M,
    CubicSplineSimpleSwing,
)

HALF = 0.5 * math.radians(25.0)
ON_BOARD = (math.cos(-HALF), 0.0, math.sin(-HALF), 0.0)  # toes up 25 deg, as (A)'s board
LEVEL = (1.0, 0.0, 0.0, 0.0)
START = ((0.18, -0.09, 0.0), LEVEL)
END = ((0.42, -0.09, 0.056), ON_BOARD)
T0, T1 = 2.0, 3.0


def _velocity(swing: CubicSplineSimpleSwing, t: float, h: float = 1e-6) -> np.ndarray:
    return (swing.position(t + h) - swing.position(t - h)) / (2 * h)


def test_the_swing_withdraws_and_approaches_along_the_contact_normals():
    swing = CubicSplineSimpleSwing(T0, T1, START, END)
    p0, p1 = np.array(START[0]), np.array(END[0])
    np.testing.assert_allclose(swing.position(T0), p0, atol=1e-12)
    np.testing.assert_allclose(swing.position(T1), p1, atol=1e-12)
    withdrawn = swing.position(T0 + 0.2)
    approached = swing.position(T1 - 0.2)
    np.testing.assert_allclose(withdrawn - p0, WITHDRAW_OFFSET_M * np.array((0, 0, 1)), atol=1e-12)
    np.testing.assert_allclose(
        approached - p1, APPROACH_OFFSET_M * np.array(contact_normal(ON_BOARD)), atol=1e-12
    )
    # on the way out and in the limb moves along the normal only
    for t in (T0 + 0.05, T0 + 0.15):
        assert np.linalg.norm(swing.position(t)[:2] - p0[:2]) < 1e-12
    for t in (T1 - 0.15, T1 - 0.05):
        offset = swing.position(t) - p1
        assert np.linalg.norm(np.cross(offset, contact_normal(ON_BOARD))) < 1e-12


def test_the_swing_peaks_above_the_midpoint_and_never_stops_between_contacts():
    swing = CubicSplineSimpleSwing(T0, T1, START, END)
    middle = swing.position(0.5 * (T0 + T1))
    mean = 0.5 * (np.array(START[0]) + np.array(END[0]))
    assert np.linalg.norm(middle - mean) == pytest.approx(SWING_OFFSET_M, abs=1e-12)
    np.testing.assert_allclose(_velocity(swing, T0 + 1e-6), 0.0, atol=1e-4)
    np.testing.assert_allclose(_velocity(swing, T1 - 1e-6), 0.0, atol=1e-4)
    speeds = [np.linalg.norm(_velocity(swing, t)) for t in np.linspace(T0 + 0.01, T1 - 0.01, 99)]
    assert min(speeds) > 0.01  # the quintic-with-waypoints swing stops at each waypoint
    # velocity is continuous where the pieces join (withdraw | spline | approach)
    for join in (T0 + 0.2, T1 - 0.2):
        before, after = _velocity(swing, join - 1e-4), _velocity(swing, join + 1e-4)
        np.testing.assert_allclose(before, after, atol=1e-2)


def test_the_orientation_is_held_while_withdrawing_and_approaching():
    swing = CubicSplineSimpleSwing(T0, T1, START, END)
    np.testing.assert_allclose(swing.orientation(T0 + 0.1), LEVEL, atol=1e-12)
    q = swing.orientation(T1 - 0.1)
    assert abs(float(np.dot(q, ON_BOARD))) == pytest.approx(1.0, abs=1e-12)


def test_limb_pose_uses_it_between_two_contacts_but_not_from_a_waypoint():
    left = Contact("left_foot", (0.0, 0.09, 0.0))
    right_before, right_after = Contact("right_foot", *START), Contact("right_foot", *END)
    palm = Contact("left_hand", (0.3, 0.41, 1.0), (math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0))
    phases = (
        ContactPhase(0.0, T0, (left, right_before)),
        ContactPhase(T0, T1, (left,)),  # the right foot swings
        ContactPhase(T1, 4.5, (left, right_after)),  # the left hand leaves its waypoint at 4 s
        ContactPhase(4.5, 5.0, (left, right_after, palm)),
    )
    hand = LimbWaypoint("left_hand", 4.0, (0.0, 0.3, 0.8))
    scenario = Scenario("t", 5.0, Scene(), phases, (), limb_waypoints=(hand,))
    ours = replace(scenario, swing_profile="cubic_spline_simple")
    swing = CubicSplineSimpleSwing(T0, T1, START, END)
    for t in (2.1, 2.5, 2.9):
        np.testing.assert_allclose(ours.limb_pose("right_foot", t)[0], swing.position(t))
        assert np.linalg.norm(scenario.limb_pose("right_foot", t)[0] - swing.position(t)) > 1e-3
    for t in (4.1, 4.3):  # from the hand's waypoint: the quintic in both
        np.testing.assert_array_equal(
            ours.limb_pose("left_hand", t)[0], scenario.limb_pose("left_hand", t)[0]
        )


def test_an_unknown_swing_profile_is_refused_in_one_line():
    with pytest.raises(ValueError, match="swing_profile"):
        Scenario("t", 1.0, Scene(), (ContactPhase(0.0, 1.0, ()),), (), swing_profile="spline")


def test_the_offsets_scale_with_the_robot():
    big = CubicSplineSimpleSwing(T0, T1, START, END, scale=2.0)
    np.testing.assert_allclose(
        big.position(T0 + 0.2) - np.array(START[0]), (0.0, 0.0, 2.0 * WITHDRAW_OFFSET_M)
    )
    mean = 0.5 * (np.array(START[0]) + np.array(END[0]))
    middle = big.position(0.5 * (T0 + T1))
    assert np.linalg.norm(middle - mean) == pytest.approx(2.0 * SWING_OFFSET_M, abs=1e-12)
