"""Scenario data: hand targets and the one active at a time."""

import numpy as np
import pytest

from robots.scene import Contact, ContactPhase, HandTarget, Scenario, Scene


def _scenario(targets: tuple[HandTarget, ...]) -> Scenario:
    feet = (Contact("left_foot", (0.0, 0.1, 0.0)), Contact("right_foot", (0.0, -0.1, 0.0)))
    return Scenario(
        "test", 10.0, Scene(), (ContactPhase(0.0, 10.0, feet),), (), hand_targets=targets
    )


# listed out of time order on purpose: the lookup must not depend on the order given
TARGETS = (
    HandTarget("right_hand", 4.0, (0.8, -0.3, 0.9)),
    HandTarget("right_hand", 1.0, (0.5, -0.3, 0.9)),
    HandTarget("left_hand", 2.0, (0.3, 0.4, 1.0)),
)


@pytest.mark.parametrize(
    ("limb", "time", "expected"),
    [
        ("right_hand", 0.0, None),  # before its first target
        ("right_hand", 0.999, None),
        ("right_hand", 1.0, (0.5, -0.3, 0.9)),  # from the target's time on, inclusive
        ("right_hand", 3.999, (0.5, -0.3, 0.9)),
        ("right_hand", 4.0, (0.8, -0.3, 0.9)),
        ("right_hand", 100.0, (0.8, -0.3, 0.9)),  # the last one holds after the end
        ("left_hand", 1.5, None),
        ("left_hand", 2.0, (0.3, 0.4, 1.0)),  # each limb its own targets
        ("left_foot", 5.0, None),  # a limb without targets
    ],
)
def test_hand_target_at_is_the_last_target_at_or_before_the_time(limb, time, expected):
    target = _scenario(TARGETS).hand_target_at(limb, time)
    if expected is None:
        assert target is None
    else:
        np.testing.assert_array_equal(target, expected)


def test_hand_target_at_returns_a_copy_and_none_without_targets():
    scenario = _scenario(TARGETS)
    scenario.hand_target_at("right_hand", 5.0)[:] = 0.0  # the caller's to modify
    np.testing.assert_array_equal(scenario.hand_target_at("right_hand", 5.0), (0.8, -0.3, 0.9))
    plain = _scenario(())
    assert plain.hand_targets == ()
    assert plain.hand_target_at("right_hand", 5.0) is None
    assert plain.phase_at(5.0).limbs == ("left_foot", "right_foot")  # the rest unchanged
