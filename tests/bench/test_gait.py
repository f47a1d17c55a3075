"""Gait commands walked: the commanded forward speed is reached over the steady steps."""

import numpy as np
import pytest

from bench.runner import EpisodeSpec, run_episode
from bench.scenarios import WALK_TURN_GAIT, GaitCommand, make_scenario, walk
from robots.humanoid import humanoid
from robots.model import RobotModel


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
@pytest.mark.parametrize("speed", [0.1, 0.2])
def test_walk_reaches_the_commanded_speed(sim, speed):
    """preview_control + centroidal_feedback walking `walk --speed`: over the steady steps (the
    right foot's touchdowns of steps 3 and 9, away from the half first and last steps), the
    soles' ground-truth advance per second is within 5 % of the command."""
    result = run_episode(
        EpisodeSpec(
            planner="preview_control",
            stabilizer="centroidal_feedback",
            sim=sim,
            scenario="walk",
            speed=speed,
        )
    )
    assert result.summary["status"] == "ok", result.summary["error"]
    steps = result.footsteps
    assert steps["limb"][2] == steps["limb"][8] == "right_foot"
    advance = steps["x_m"][8] - steps["x_m"][2]
    duration = steps["touchdown_time_s"][8] - steps["touchdown_time_s"][2]
    assert advance / duration == pytest.approx(speed, rel=0.05)


GOAL_MISSES = {
    # the CoM ends this far from the goal [cm], MuJoCo / PyBullet (MuJoCo's re-measured
    # 2026-12-03; PyBullet's of 2026-11-24 unchanged)
    ("walk_side", "ik_feedforward"): "6.5 / 6.6 cm (the feet land 6 mm behind per step)",
    ("walk_side", "ik"): "13.7 / 14.0 cm",
    ("walk_turn", "ik"): "6.8 / 6.6 cm and 6.7 / 5.9 deg",
}


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
@pytest.mark.parametrize(
    ("scenario", "whole_body"),
    [
        pytest.param(
            scenario,
            layer,
            marks=[pytest.mark.xfail(strict=True, reason=GOAL_MISSES[scenario, layer])]
            if (scenario, layer) in GOAL_MISSES
            else [],
        )
        for scenario in ("walk_side", "walk_turn")
        for layer in ("ik", "ik_feedforward")
    ],
)
def test_side_and_turning_walks_end_at_their_goals(sim, scenario, whole_body):
    """`walk_side` (0.45 m to the left) and `walk_turn` (90 deg to the left) with
    preview_control + centroidal_feedback and either whole-body layer: ten steps, and the
    ground-truth CoM and base heading end within 5 cm and 5 deg of the gait command's goal
    (issue 15). Where they do not, the test is a strict xfail naming the measured miss."""
    result = run_episode(
        EpisodeSpec(
            planner="preview_control",
            stabilizer="centroidal_feedback",
            sim=sim,
            scenario=scenario,
            whole_body=whole_body,
        )
    )
    summary = result.summary
    assert summary["status"] == "ok", summary["error"]
    assert summary["steps_taken"] == 10
    assert result.footsteps["limb"][0] == "left_foot"  # leftward walks lead with the left foot
    assert summary["final_position_error_m"] < 0.05
    assert summary["final_yaw_error_rad"] < np.deg2rad(5.0)


def test_turning_walk_footholds():
    """`walk_turn`'s footholds turn 10 deg per step up to 90 deg, keep the standing width across
    the path, and a turning path that does not turn gives the straight walk's footholds."""
    model = RobotModel(humanoid())
    scenario = make_scenario("walk_turn", model)
    touchdowns = [p for p in scenario.phases if len(p.contacts) == 2][1:]
    yaws = [
        [2 * np.arctan2(c.orientation_world[3], c.orientation_world[0]) for c in p.contacts]
        for p in touchdowns
    ]
    assert np.degrees(max(max(y) for y in yaws)) == pytest.approx(90.0)
    left, right = (np.array(c.position_world) for c in scenario.phases[-1].contacts)
    assert np.linalg.norm(left - right) == pytest.approx(0.18)  # the standing width
    assert left[0] < right[0]  # facing +y, the left foot is on the -x side
    assert scenario.goal_yaw == pytest.approx(np.pi / 2)
    assert np.hypot(*scenario.goal_offset_world) == pytest.approx(
        np.linalg.norm((left + right)[:2] / 2 - [0.0, 0.0]), abs=1e-9
    )
    straight = walk(model)
    no_turn = walk(model, gait=GaitCommand(turn=-1e-300))  # the turning code path, no turn
    for a, b in zip(straight.phases, no_turn.phases, strict=True):
        for ca, cb in zip(a.contacts, b.contacts, strict=True):
            np.testing.assert_allclose(ca.position_world, cb.position_world, atol=1e-12)
    assert WALK_TURN_GAIT.turn_per_step(1.0) == pytest.approx(np.deg2rad(10.0))
