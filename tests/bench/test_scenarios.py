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
