"""The fixed step timing of the capturability hierarchy (Sherikov et al. Sec. III): phases
and the support of each preview sample, worked out by hand for 0.7 s + 0.1 s steps."""

import math

import numpy as np
import pytest

from planners.step_schedule import StepSchedule


def test_standing_is_double_support_without_end():
    schedule = StepSchedule()
    phase = schedule.phase(3.0)
    assert phase.swing is None
    assert phase.stance is None
    assert phase.remaining_s == math.inf
    assert not schedule.sample_supports(3.0, 0.1, 16).any()


def test_phases_of_a_walk():
    schedule = StepSchedule(0.7, 0.1)
    schedule.start(1.0, "right_foot")
    single = schedule.phase(1.35)  # step 0's single support: the right foot swings
    assert (single.swing, single.stance, single.step) == ("right_foot", "left_foot", 0)
    assert single.touchdown_s == pytest.approx(1.7)
    assert single.remaining_s == pytest.approx(0.35)
    double = schedule.phase(1.75)  # after its touchdown: the right foot is the next stance
    assert (double.swing, double.stance, double.step) == (None, "right_foot", 0)
    assert double.remaining_s == pytest.approx(0.05)
    assert schedule.phase(1.85).swing == "left_foot"  # step 1


def test_preview_samples_belong_to_the_foothold_that_carries_the_robot():
    """From t = 1.35 (step 0's single support), samples on the walk's grid, 1.40 ... 2.90
    (the first interval 0.05 s): up to the touchdown at 1.7 (included) the stance foot (0),
    from the double support's end at 1.8 the landed foot through step 1's single support and
    its touchdown at 2.5 (1), then the next footstep (2): the CoP, linear between samples,
    changes feet only while both are down."""
    schedule = StepSchedule(0.7, 0.1)
    schedule.start(1.0, "right_foot")
    assert schedule.first_interval(1.35, 0.1) == pytest.approx(0.05)
    supports = schedule.sample_supports(1.35, 0.1, 16)
    expected = np.array([0] * 4 + [1] * 8 + [2] * 4)
    np.testing.assert_array_equal(supports, expected)
    # in the double support after a touchdown the landed foot is the current foothold
    supports = schedule.sample_supports(1.75, 0.1, 16)
    np.testing.assert_array_equal(supports, [0] * 8 + [1] * 8)
    # on the grid itself the first interval is whole; at the touchdown the landed foot is
    # the current foothold
    assert schedule.first_interval(1.7, 0.1) == pytest.approx(0.1)
    np.testing.assert_array_equal(schedule.sample_supports(1.7, 0.1, 9), [0] * 8 + [1])


def test_no_sample_leaves_the_stance_foot_while_the_other_is_in_the_air():
    """At every control period of a walk (2 ms), two successive samples (the CoP is linear
    between them) on different footholds are both within a double support."""
    schedule = StepSchedule(0.7, 0.1)
    schedule.start(1.03, "left_foot")
    for t in np.arange(1.03, 3.0, 0.002):
        first = schedule.first_interval(t, 0.1)
        times = t + first + 0.1 * np.arange(16)
        supports = schedule.sample_supports(t, 0.1, 16)
        for k in range(1, 16):
            if supports[k] != supports[k - 1]:
                for sample in (times[k - 1], times[k]):
                    into = (sample - 1.03) % 0.8
                    # at or after a touchdown (0.7 into a step) and no later than the next
                    # step's lift-off (0.8, i.e. 0.0 of the next)
                    assert into > 0.7 - 1e-6 or into < 1e-6, (t, k, into)


def test_a_walk_of_two_steps_ends_standing():
    schedule = StepSchedule(0.7, 0.1)
    schedule.start(1.0, "left_foot", steps=2)
    assert schedule.phase(2.35).swing == "right_foot"  # step 1 swings the other foot
    assert schedule.phase(2.65).step == -1  # standing after 2 x 0.8 s
    assert schedule.sample_supports(2.65, 0.1, 4).tolist() == [0, 0, 0, 0]


def test_bad_timing_is_refused():
    with pytest.raises(ValueError, match="positive"):
        StepSchedule(0.0, 0.1)
    with pytest.raises(ValueError, match="first swing"):
        StepSchedule().start(0.0, "left_hand")


def test_before_a_walk_starts_the_preview_sees_its_steps():
    """Standing at 0.95 with a walk from 1.0: samples from 1.0 (the walk's grid) on the first
    step's stance foot (0) until its touchdown at 1.7, then footstep 1 from 1.8 to step 1's
    touchdown at 2.5."""
    schedule = StepSchedule(0.7, 0.1)
    schedule.start(1.0, "left_foot", steps=11)  # a finite walk too (a gait command's)
    assert schedule.starting(0.95)
    assert schedule.phase(0.95).step == -1
    supports = schedule.sample_supports(0.95, 0.1, 16)
    np.testing.assert_array_equal(supports, [0] * 8 + [1] * 8)


def test_the_samples_after_a_walk_of_given_length_are_marked():
    """A walk of 2 steps from 1.0 ends at 2.6 (2 x 0.8 s). At 1.95 (step 1's single support)
    the samples fall at 2.0, 2.1, ...: those from 2.6 on (the seventh on) are after it; a
    walk without end, standing, or a time after the end mark none."""
    schedule = StepSchedule(0.7, 0.1)
    schedule.start(1.0, "left_foot", steps=2)
    after = schedule.samples_after_walk(1.95, 0.1, 10)
    np.testing.assert_array_equal(after, [False] * 6 + [True] * 4)
    # before the walk: the samples at 1.0 ... 2.5, before its end at 2.6
    np.testing.assert_array_equal(schedule.samples_after_walk(0.95, 0.1, 16), [False] * 16)
    assert schedule.samples_after_walk(1.05, 0.1, 16).sum() == 1  # 2.6 is the 16th sample
    assert not schedule.samples_after_walk(2.7, 0.1, 16).any()
    endless = StepSchedule(0.7, 0.1)
    endless.start(1.0, "left_foot")
    assert not endless.samples_after_walk(1.95, 0.1, 16).any()
    assert not StepSchedule().samples_after_walk(0.0, 0.1, 16).any()
