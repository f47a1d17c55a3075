"""Gait commands walked: the commanded forward speed is reached over the steady steps."""

import numpy as np
import pytest

from bench.runner import EpisodeSpec, run_episode
from bench.scenarios import make_scenario
from robots.humanoid import humanoid
from robots.model import RobotModel


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
@pytest.mark.parametrize("speed", [0.1, 0.2])
def test_walk_reaches_the_commanded_speed(sim, speed):
    """preview_control + centroidal_feedback walking `walk --speed`: the CoM's mean forward
    speed from the start of the 3rd to the start of the 8th single support (the steady steps,
    away from the half first and last steps) is within 5 % of the command."""
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
    scenario = make_scenario("walk", RobotModel(humanoid()), speed=speed)
    single = [p for p in scenario.phases if len(p.contacts) == 1]
    begin, end = single[2].start, single[7].start
    trace = result.trace
    x_begin = np.interp(begin, trace["time"], trace["com_actual_x"])
    x_end = np.interp(end, trace["time"], trace["com_actual_x"])
    assert (x_end - x_begin) / (end - begin) == pytest.approx(speed, rel=0.05)
