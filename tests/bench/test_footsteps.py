"""Footsteps taken, measured: debouncing of contact chatter, the sole pose at touchdown, the
summary fields, and a walk's steps in both simulators."""

from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from bench.footsteps import (
    COLUMNS,
    PLANNED_COLUMNS,
    FootstepRecorder,
    PlannedFootstepRecorder,
    compare_with_plan,
    footstep_summary,
)
from bench.runner import EpisodeSpec, run_episode
from centroidal.rotations import IDENTITY_WXYZ
from robots.types import Footstep

LIMBS = ("left_foot", "right_foot", "left_hand", "right_hand")


def _recorder(positions: dict[str, list[tuple[float, float]]]):
    """A recorder whose `pose_of` returns each limb's next listed (x, y) and yaw x / 10."""
    queues = {limb: list(values) for limb, values in positions.items()}

    def pose_of(limb: str):
        x, y = queues[limb].pop(0)
        return np.array([x, y, 0.0]), x / 10

    return FootstepRecorder(LIMBS, (0, 1), pose_of)


def _flags(left: bool, right: bool) -> list[bool]:
    return [left, right, False, False]


def test_chatter_is_one_touchdown_and_the_first_contact_counts():
    recorder = _recorder(
        {
            "left_foot": [(0.0, 0.1), (0.25, 0.1)],
            "right_foot": [(0.0, -0.1), (0.125, -0.1), (0.126, -0.1), (0.127, -0.1)],
        }
    )
    sequence = [
        (0.0, _flags(True, True)),
        (1.0, _flags(True, False)),  # right lifts off
        (1.770, _flags(True, True)),  # right lands ...
        (1.772, _flags(True, False)),  # ... chatters for 2 ms ...
        (1.774, _flags(True, True)),
        (1.780, _flags(True, False)),  # ... and 6 ms
        (1.786, _flags(True, True)),
        (1.9, _flags(False, True)),  # left lifts off
        (2.66, _flags(True, True)),  # and lands
        (3.0, _flags(True, False)),  # right lifts off and is still in the air at the end
    ]
    for t, flags in sequence:
        recorder.observe(t, flags)
        recorder.observe(t + 0.001, flags)  # unchanged flags: nothing recorded
    steps = recorder.table()
    assert steps["limb"].tolist() == ["right_foot", "left_foot"]
    assert steps["liftoff_time_s"].tolist() == [1.0, 1.9]
    assert steps["touchdown_time_s"].tolist() == [1.770, 2.66]
    assert steps["x_m"].tolist() == [0.125, 0.25]  # the pose at the first contact
    assert steps["yaw_rad"].tolist() == pytest.approx([0.0125, 0.025])
    assert steps["swing_length_m"].tolist() == pytest.approx([0.125, 0.25])


def test_a_bounce_after_a_touchdown_is_no_step_but_a_step_in_place_is():
    """An early touchdown that bounces (off for 0.06 s, landing 5 mm from where it landed: the
    bent-knee five-mass walks' sagging swing foot) is one step whose touchdown is the first; a
    lift of 0.06 s that lands 3.5 cm from the last touchdown, and a step in place of 0.3 s,
    are steps."""
    recorder = _recorder(
        {
            "left_foot": [(0.0, 0.1)],
            "right_foot": [(0.0, -0.1), (0.2, -0.1), (0.205, -0.1), (0.235, -0.1), (0.235, -0.1)],
        }
    )
    sequence = [
        (0.0, _flags(True, True)),
        (1.0, _flags(True, False)),  # right lifts off
        (1.40, _flags(True, True)),  # lands at x = 0.2 ...
        (1.45, _flags(True, False)),  # ... bounces for 0.06 s ...
        (1.51, _flags(True, True)),  # ... and lands 5 mm on: no step
        (2.0, _flags(True, False)),
        (2.06, _flags(True, True)),  # 0.06 s off, 3 cm on: a step
        (3.0, _flags(True, False)),
        (3.3, _flags(True, True)),  # 0.3 s off, in place: a step
    ]
    for t, flags in sequence:
        recorder.observe(t, flags)
    steps = recorder.table()
    assert steps["touchdown_time_s"].tolist() == [1.40, 2.06, 3.3]
    assert steps["liftoff_time_s"].tolist() == [1.0, 2.0, 3.0]
    assert steps["swing_length_m"].tolist() == pytest.approx([0.2, 0.035, 0.0])


def test_a_bounce_of_a_standing_foot_or_inside_chatter_is_no_step():
    """A standing foot that lifts for 0.05 s and lands 2 mm from where it stood takes no step;
    a swing that lands, chatters for 4 ms, bounces for 0.07 s and lands 4 mm on is one step
    (touchdown the first contact); a loss of exactly `BOUNCE_MAX_S` in place is a step."""
    recorder = _recorder(
        {
            "left_foot": [(0.0, 0.1), (0.002, 0.1), (0.3, 0.1), (0.301, 0.1), (0.304, 0.1)],
            "right_foot": [(0.0, -0.1), (0.0, -0.1)],
        }
    )
    sequence = [
        (0.0, _flags(True, True)),
        (0.5, _flags(False, True)),  # the standing left foot lifts ...
        (0.55, _flags(True, True)),  # ... and lands 2 mm on: no step
        (1.0, _flags(False, True)),  # a swing of the left foot
        (1.5, _flags(True, True)),  # lands at x = 0.3, chatters ...
        (1.502, _flags(False, True)),
        (1.506, _flags(True, True)),
        (1.55, _flags(False, True)),  # ... bounces 0.07 s, lands 4 mm on
        (1.62, _flags(True, True)),
        (2.0, _flags(True, False)),  # the right foot off for exactly 0.1 s, in place
        (2.1, _flags(True, True)),
    ]
    for t, flags in sequence:
        recorder.observe(t, flags)
    steps = recorder.table()
    assert steps["limb"].tolist() == ["left_foot", "right_foot"]
    assert steps["touchdown_time_s"].tolist() == [1.5, 2.1]
    assert steps["x_m"].tolist() == [0.3, 0.0]
    assert steps["swing_length_m"].tolist() == pytest.approx([0.3, 0.0])


def test_a_foot_that_lands_after_the_first_period_stands_where_it_landed():
    recorder = _recorder({"left_foot": [(0.0, 0.1), (0.3, 0.1)], "right_foot": []})
    recorder.observe(0.0, _flags(False, False))
    recorder.observe(0.002, _flags(True, False))  # settles onto the ground
    recorder.observe(1.0, _flags(False, False))
    recorder.observe(1.8, _flags(True, False))
    steps = recorder.table()
    assert steps["swing_length_m"].tolist() == pytest.approx([0.3])


def test_summary_of_steps_and_goal():
    recorder = _recorder({"left_foot": [(0.0, 0.1), (0.25, 0.1)], "right_foot": [(0.0, -0.1)]})
    for t, flags in [
        (0.0, _flags(True, True)),
        (1.0, _flags(False, True)),
        (1.9, _flags(True, True)),
    ]:
        recorder.observe(t, flags)
    summary = footstep_summary(
        recorder.table(), np.array([0.0, 0.0]), np.array([0.3, 0.4]), (0.3, 0.0)
    )
    assert summary["steps_taken"] == 1
    assert summary["mean_step_length_m"] == pytest.approx(0.25)
    assert summary["mean_step_duration_s"] is None  # one touchdown: no interval
    assert summary["distance_walked_m"] == pytest.approx(0.5)
    assert summary["final_position_error_m"] == pytest.approx(0.4)


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
def test_a_walk_takes_its_ten_steps_and_ends_at_its_goal(sim):
    """preview_control + centroidal_feedback on `walk`: the ten steps alternate from the right
    foot, and the CoM ends within 5 cm of the gait command's goal (1.125 m ahead)."""
    result = run_episode(
        EpisodeSpec(
            planner="preview_control", stabilizer="centroidal_feedback", sim=sim, scenario="walk"
        )
    )
    summary, steps = result.summary, result.footsteps
    assert summary["status"] == "ok", summary["error"]
    assert summary["steps_taken"] == 10
    assert steps["limb"].tolist() == ["right_foot", "left_foot"] * 5
    assert (steps["touchdown_time_s"] > steps["liftoff_time_s"]).all()
    assert summary["final_position_error_m"] < 0.05
    assert summary["distance_walked_m"] == pytest.approx(1.125, abs=0.05)


def test_standing_takes_no_step_and_has_no_goal():
    result = run_episode(
        EpisodeSpec(
            planner="hold", stabilizer="posture", sim="mujoco", scenario="stand", duration=0.5
        )
    )
    assert result.summary["steps_taken"] == 0
    assert result.summary["final_position_error_m"] is None
    assert result.summary["distance_walked_m"] < 0.001


def _step(limb, x, liftoff, touchdown):
    return Footstep(limb, np.array([x, 0.0, 0.0]), 0.0, liftoff, touchdown, IDENTITY_WXYZ)


def test_the_planned_steps_are_the_last_versions_before_their_touchdown():
    """An adaptive plan moves the right foot's step twice before it lands at t = 0.5 s: the
    record keeps the last version; a step the plan drops is not kept; a step not yet due at the
    end is not kept either."""
    recorder = PlannedFootstepRecorder()
    first, moved, moved_again = (_step("right_foot", x, 0.1, 0.5) for x in (0.2, 0.25, 0.3))
    left, dropped = _step("left_foot", 0.4, 0.6, 1.0), _step("left_foot", 0.9, 1.1, 1.4)
    plans = [(0.0, (first, left)), (0.2, (moved, left)), (0.4, (moved_again, left))]
    plans += [(0.5, (left, dropped)), (0.8, (left,)), (1.0, ()), (1.2, ())]
    for t, footsteps in plans:
        recorder.observe(t, footsteps)
    table = recorder.table()
    assert table["limb"].tolist() == ["right_foot", "left_foot"]
    assert table["x_m"].tolist() == [0.3, 0.4]
    assert table["touchdown_time_s"].tolist() == [0.5, 1.0]


def test_steps_taken_are_compared_with_the_nearest_planned_step_of_the_limb():
    """A step 10 ms late and (3, 4) mm off, one 30 ms early and 1 cm short: the largest
    errors, and their means, the time error signed (early is negative)."""
    taken = pd.DataFrame(
        [
            ("right_foot", 0.1, 0.51, 0.303, 0.004, 0.0, 0.01, 0.3),
            ("right_foot", 1.1, 1.47, 0.79, 0.0, 0.0, 0.0, 0.49),
        ],
        columns=list(COLUMNS),
    )
    planned = pd.DataFrame(
        [("right_foot", 0.1, 0.5, 0.3, 0.0, 0.0, 0.0), ("right_foot", 1.1, 1.5, 0.8, 0, 0, 0)],
        columns=list(PLANNED_COLUMNS),
    )
    compared = compare_with_plan(taken, planned)
    assert compared["planned_touchdown_time_s"][0] == 0.5
    assert compared["touchdown_time_error_s"][0] == pytest.approx(0.01)
    assert compared["touchdown_position_error_m"][0] == pytest.approx(0.005)
    assert compared["touchdown_time_error_s"][1] == pytest.approx(-0.03)
    summary = footstep_summary(compared, None, None, None)
    assert summary["touchdown_time_error_max_s"] == pytest.approx(0.03)
    assert summary["touchdown_position_error_max_m"] == pytest.approx(0.01)
    assert summary["touchdown_time_error_mean_s"] == pytest.approx(-0.01)
    assert summary["touchdown_position_error_mean_m"] == pytest.approx(0.0075)


def test_the_runner_compares_with_the_plan_not_the_scenario(monkeypatch):
    """A planner whose plans put every footstep 1 m to the side of the scenario's: the
    comparison is with what the plan said (errors of about 1 m), so the runner read the plan."""
    from planners import preview_control

    original = preview_control.PreviewControlPlanner.plan

    def shifted(self, t, state):
        plan = original(self, t, state)
        if not hasattr(self, "_shifted"):
            self._shifted = {}
        key = tuple(s.touchdown_time for s in plan.footsteps)
        if key not in self._shifted:
            self._shifted[key] = tuple(
                replace(s, position_world=s.position_world + np.array([0.0, 1.0, 0.0]))
                for s in plan.footsteps
            )
        return replace(plan, footsteps=self._shifted[key])

    monkeypatch.setattr(preview_control.PreviewControlPlanner, "plan", shifted)
    result = run_episode(
        EpisodeSpec(
            planner="preview_control",
            stabilizer="centroidal_feedback",
            sim="mujoco",
            scenario="walk",
            duration=2.0,
        )
    )
    assert result.summary["steps_taken"] == 1
    assert result.footsteps["touchdown_position_error_m"][0] > 0.9  # the scenario's: < 0.05


@pytest.mark.xfail(
    strict=True,
    reason="measured on walk (2026-11-24): touchdowns up to 151 ms early and 27 mm off with the "
    "paper's ik layer, up to 13 ms late and 16 mm off with ik_feedforward (the feet drift back "
    "about 1.5 mm per step); issue 15 asks 5 mm and one period",
)
@pytest.mark.parametrize("whole_body", ["ik", "ik_feedforward"])
@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
def test_touchdowns_agree_with_the_plan_within_5_mm_and_one_period(sim, whole_body):
    result = run_episode(
        EpisodeSpec(
            planner="preview_control",
            stabilizer="centroidal_feedback",
            sim=sim,
            scenario="walk",
            whole_body=whole_body,
        )
    )
    summary = result.summary
    assert summary["steps_taken"] == 10
    assert summary["touchdown_time_error_max_s"] <= 0.002
    assert summary["touchdown_position_error_max_m"] <= 0.005
