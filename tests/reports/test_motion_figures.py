"""Murooka Figs. 5-7 in the report: the actual resultant force obeys Newton's law against the
measured contact forces, and a motion episode with a trace gets its figure (one without the
plotted columns a note)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from bench.dataset import ResultStore
from bench.runner import EpisodeSpec, run_episode
from reports import plots
from reports.build import build_report
from tests.reports.rows import result_row

GRAVITY = 9.81


def test_actual_force_of_a_constant_acceleration_is_m_a():
    time = np.arange(0.0, 1.0, 0.002)
    trace = pd.DataFrame({"time": time})
    for axis, acceleration in zip("xyz", (0.5, -1.0, 2.0), strict=True):
        trace[f"com_velocity_true_{axis}"] = acceleration * time
    force = plots.actual_resultant_force(trace, 40.0)
    inside = slice(10, -10)  # the moving average's ends see zero padding
    np.testing.assert_allclose(force[inside], np.tile([20.0, -40.0, 80.0], (480, 1)), rtol=1e-9)


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
def test_actual_force_is_the_measured_contact_forces_minus_m_g(sim):
    """Newton: m c'' = sum of the contact forces - m g. On a straight walk over flat ground the
    soles' contact frames are the world's axes, so the feet's measured forces (smoothed like the
    differentiated CoM velocity) sum to the plot's actual force: within 1 % of m g (RMS) on
    every axis, where the force itself is more than three times that."""
    result = run_episode(
        EpisodeSpec("preview_control", "centroidal_feedback", sim, "walk", duration=3.0)
    )
    trace, mass = result.trace, result.summary["mass_kg"]
    actual = plots.actual_resultant_force(trace, mass)
    window = round(plots.ACTUAL_FORCE_SMOOTHING_S / 0.002)
    for k, axis in enumerate("xyz"):
        feet = sum(trace[f"wrench_measured_{foot}_f{axis}"] for foot in ("left_foot", "right_foot"))
        measured = np.convolve(
            feet - (mass * GRAVITY if axis == "z" else 0.0), np.ones(window) / window, mode="same"
        )
        inside = slice(window, -window)
        difference = actual[inside, k] - measured[inside]
        assert np.sqrt(np.mean(difference**2)) < 0.01 * mass * GRAVITY
        assert np.sqrt(np.mean(actual[inside, k] ** 2)) > 0.03 * mass * GRAVITY


def _row(**values) -> dict:
    defaults = {
        "centrobench_version": "0.1.0",
        "mass_kg": 50.0,
        "sim": "mujoco",
        "status": "ok",
        "fell": False,
        "planner": "preview_control",
        "stabilizer": "centroidal_feedback",
    }
    return result_row(**{**defaults, **values})


def _motion_trace(with_desired: bool) -> pd.DataFrame:
    time = np.arange(0.0, 2.0, 0.002)
    trace = pd.DataFrame({"time": time, "contacts_planned": np.where(time < 1.0, 3, 4)})
    for axis in "xyz":
        for column in ("com_ref", "com_planned", "com_true", "com_velocity_true"):
            trace[f"{column}_{axis}"] = 0.1 * time
        trace[f"wrench_projected_f{axis}"] = 1.0
        if with_desired:
            trace[f"wrench_desired_f{axis}"] = 2.0
            for hand in plots.MOTION_HANDS:
                for kind in ("desired", "measured"):
                    trace[f"wrench_{kind}_{hand}_f{axis}"] = 50.0
    return trace


def test_the_report_draws_each_motion_with_a_trace(tmp_path):
    root = tmp_path / "results"
    store = ResultStore(root)
    store.prepare({"name": "fixture"}, "digest", resume=False, overwrite=False)
    episodes = {
        "stairs": ("handrail_stairs", "preview_control+centroidal_feedback", True),
        "floors": ("moving_contacts", "linear_mpc+centroidal_feedback", True),
        "no_desired": ("ladder", "preview_control+passthrough", False),
        "walk": ("walk", "preview_control+centroidal_feedback", True),
    }
    for episode_id, (scenario, controller, complete) in episodes.items():
        store.write(
            _row(episode_id=episode_id, scenario=scenario, controller=controller),
            _motion_trace(complete),
        )
    out = tmp_path / "report"
    paths = build_report(root, out)
    page = (out / "report.md").read_text()
    assert "Multi-contact motion (Murooka Fig. 6): preview_control+centroidal_feedback" in page
    assert "Multi-contact motion (Murooka Figs. 5-7 style, Fig. 4 (E)): linear_mpc" in page
    assert (out / "motion_stairs.png") in paths
    assert (out / "motion_stairs.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (out / "motion_floors.png") in paths
    assert not (out / "motion_walk.png").exists()  # a walk is not a motion of Fig. 4
    assert not (out / "motion_no_desired.png").exists()
    assert "traces/no_desired.parquet: no wrench_desired_fx column, not plotted" in page


def test_motion_plot_writes_a_png_without_hand_columns(tmp_path):
    path = plots.motion_plot(
        _motion_trace(True).drop(columns=[c for c in _motion_trace(True).columns if "_hand_" in c]),
        50.0,
        Path(tmp_path) / "m.png",
        title="no hands",
    )
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
