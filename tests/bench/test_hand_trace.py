"""The hand columns of the trace in scenarios with hand targets (Sherikov et al. 2014's
reaching tests): the true palm `hand_actual_*`, the active target `hand_target_*` (NaN while
none is), and `hand_error_m` the distance between the two."""

from dataclasses import replace

import numpy as np
import pytest

import bench.runner as runner
from bench.runner import EpisodeSpec, run_episode
from robots.humanoid import humanoid
from robots.model import cached_model
from tests.bench.episodes import run_controller

AXES = ("x", "y", "z")
HAND_COLUMNS = [f"hand_{kind}_{axis}" for kind in ("actual", "target") for axis in AXES]


def _points(trace, kind: str) -> np.ndarray:
    return trace[[f"hand_{kind}_{axis}" for axis in AXES]].to_numpy()


def test_reach_records_the_palm_and_its_target():
    """0.5 s of `reach` walking with the paper's controller in MuJoCo: the target columns are
    the scenario's target at each period's time, the palm starts where `standing_state`
    places it (the simulator starts there), and the error is their distance every period."""
    result = run_controller("capturability_hierarchy", "mujoco", "reach", duration=0.5)
    assert result.summary["status"] == "ok"
    trace = result.trace
    assert set(HAND_COLUMNS) <= set(trace.columns)
    actual, target = _points(trace, "actual"), _points(trace, "target")
    assert np.isfinite(actual).all()
    assert np.isfinite(target).all()
    model = cached_model(humanoid())
    scenario = runner.make_scenario("reach", model)
    for k in range(0, len(trace), 25):
        expected = scenario.hand_target_at("right_hand", float(trace["time"].iloc[k]))
        np.testing.assert_allclose(target[k], expected, rtol=0, atol=1e-12)
    palm = model.frame_positions_world(model.standing_state(), ["right_palm"])[0]
    np.testing.assert_allclose(actual[0], palm, rtol=0, atol=1e-6)
    assert np.ptp(actual[:, 0]) > 1e-3  # the palm moves: a column of the palm, not a constant
    distance = np.linalg.norm(actual - target, axis=1)
    np.testing.assert_allclose(trace["hand_error_m"].to_numpy(), distance, rtol=1e-12, atol=1e-12)


def test_target_is_nan_until_the_first_one_is_active(monkeypatch):
    """`reach` with its targets 0.2 s later: before that, the target columns and the error
    are NaN while the palm is recorded; from then on all are finite."""
    make_scenario = runner.make_scenario

    def delayed(*args):
        scenario = make_scenario(*args)
        targets = tuple(replace(t, time=t.time + 0.2) for t in scenario.hand_targets)
        return replace(scenario, hand_targets=targets)

    monkeypatch.setattr(runner, "make_scenario", delayed)
    result = run_episode(EpisodeSpec("hold", "posture", "mujoco", "reach", duration=0.4))
    assert result.summary["status"] == "ok"
    trace = result.trace
    before = (trace["time"] < 0.2 - 1e-9).to_numpy()
    assert before.any()
    assert (~before).any()
    target, actual = _points(trace, "target"), _points(trace, "actual")
    assert np.isnan(target[before]).all()
    assert np.isnan(trace["hand_error_m"].to_numpy()[before]).all()
    assert np.isfinite(target[~before]).all()
    assert np.isfinite(actual).all()
    distance = np.linalg.norm(actual[~before] - target[~before], axis=1)
    np.testing.assert_allclose(trace["hand_error_m"].to_numpy()[~before], distance, rtol=1e-12)
    assert result.summary["hand_error_final_m"] == pytest.approx(distance[-1], rel=1e-12)


def test_no_hand_columns_without_hand_targets():
    result = run_episode(EpisodeSpec("hold", "posture", "mujoco", "stand", duration=0.1))
    assert result.summary["status"] == "ok"
    assert not [c for c in result.trace.columns if c.startswith("hand_")]
