"""The kinematic check (`bench.kinematic_check`): the IK alone on a scenario's targets."""

import json

import numpy as np
import pytest

from bench.cli import main
from bench.kinematic_check import check_scenario, smoothed
from bench.scenarios import make_scenario
from robots.humanoid import humanoid
from robots.model import RobotModel


@pytest.fixture(scope="module")
def model():
    return RobotModel(humanoid())


def test_smoothing_turns_a_step_into_a_ramp_across_the_window():
    """A unit step at sample 10, averaged over the 4 samples i - 2 ... i + 1: 0 up to sample
    8, then 1/4, 2/4, 3/4 and 1 from sample 12 on; the ends held (a constant stays)."""
    step = np.zeros((20, 1))
    step[10:] = 1.0
    out = smoothed(step, 4)[:, 0]
    np.testing.assert_allclose(out[:9], 0.0)
    np.testing.assert_allclose(out[9:12], [0.25, 0.5, 0.75])
    np.testing.assert_allclose(out[12:], 1.0)
    np.testing.assert_allclose(smoothed(np.full((5, 3), 2.0), 4), 2.0)


def test_the_walk_is_followed_within_a_centimetre_without_touching(model):
    """The flat-ground walk, which every controller walks in both simulators: the IK alone
    keeps the CoM and every tracked limb within 1 cm of their targets, no link but the feet
    touches the ground, and no joint reaches a limit."""
    check = check_scenario(model, make_scenario("walk", model))
    assert check.feasible
    for phase in check.phases:
        assert phase.com_error_max_m < 0.01, phase
        assert phase.limb_error_max_m < 0.01, phase
        assert not phase.at_limit, phase


def test_the_ladder_touches_a_rung_with_the_stepping_leg(model):
    """Fig. 4 (C) with Sec. V-C's CoM 0.3 m behind the ladder: the first touch happens while
    the right foot swings up to the first rung (hands on the rung, left foot on the ground)
    and is a link of the right leg."""
    scenario = make_scenario("ladder", model)
    check = check_scenario(model, scenario)
    assert not check.feasible
    time, links = check.first_touch
    phase = scenario.phase_at(time)
    assert set(phase.limbs) == {"left_foot", "left_hand", "right_hand"}
    assert set(links) <= {"right_thigh", "right_shank"}


def test_the_stairs_keep_the_knees_bent_and_the_com_on_its_reference(model):
    """Fig. 4 (B) with its CoM 0.74 m above the feet and the rails 0.85 m above the pitch
    line (`STAIRS_COM_HEIGHT`, `HANDRAIL_HEIGHT`): no link touches, no knee reaches its limit
    (at the standing height the trailing leg straightened in the double support after each
    step up, the CoM 91 mm from its reference there), and once both hands hold their rails
    the IK alone keeps the CoM within 15 mm of its reference in every phase."""
    scenario = make_scenario("handrail_stairs", model)
    check = check_scenario(model, scenario)
    assert check.feasible
    both_grasped = min(
        phase.start
        for phase in scenario.phases
        if {"left_hand", "right_hand"} <= {c.limb for c in phase.contacts}
    )
    for phase in check.phases:
        assert not [j for j in phase.at_limit if j.endswith("knee")], phase
        if phase.start >= both_grasped:
            assert phase.com_error_max_m < 0.015, phase


def test_the_scaffold_walk_keeps_ankles_wrists_and_the_com_within_reach(model):
    """Fig. 4 (A) with the ankle pitch to -1.48 rad and the wrists to +-1.92 rad (JVRC-1's
    ranges), the walls 0.40 m out and the palm moved at every foothold, midway to the next
    (`WALL_WALK_FACE_Y`, `hand_wall_palm_place`, a fourth foothold down), the authors' swing
    (`robots.swing`; with it the walls at 0.41 m left an elbow at its limit): no link touches,
    no ankle, wrist, knee or elbow reaches a limit, and after the first phase (the reference
    starting 4.6 cm below the standing CoM) the IK alone keeps the CoM within 15 mm of its
    reference and every tracked limb within 10 mm of its target (11.7 and 7.2 mm measured). As
    first built (ankles to -1.0, wrists to +-1.2, walls at 0.45 m, the palm 0.10 m ahead of
    the feet, moved every other foothold) an ankle was at its limit in 17 of 62 phases and
    the CoM up to 81 mm off."""
    check = check_scenario(model, make_scenario("hand_wall", model))
    assert check.feasible
    for phase in check.phases:
        kinds = ("ankle", "wrist", "knee", "elbow")
        assert not [j for j in phase.at_limit if any(k in j for k in kinds)], phase
        if phase.start > 0.0:
            assert phase.com_error_max_m < 0.015, phase
            assert phase.limb_error_max_m < 0.010, phase


def test_check_command_prints_json(capsys):
    assert main(["check", "--scenario", "stand", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["scenario"] == "stand"
    assert report["feasible"] is True
    assert report["first_touch"] is None
    assert main(["check", "--scenario", "no_such_scenario"]) == 2
    assert "unknown scenario" in capsys.readouterr().err
