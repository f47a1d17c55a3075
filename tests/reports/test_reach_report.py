"""The report's reaching section (Sherikov, Dimitrov & Wieber 2014, Tests 1-2): its table,
its two figures per episode (Fig. 3's top view, Fig. 2's solve time), and how they join the
report built from a result directory."""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest
from matplotlib.patches import Polygon

from bench import scenarios
from bench.dataset import ROW_SCHEMA, ResultStore
from reports import plots, tables
from reports.build import build_report

PNG = b"\x89PNG\r\n\x1a\n"
HALF = (0.11, 0.06)  # sole half extents [m] of the plots' fixture
DT = 0.01
SOLVE_US = 1500.0  # the fixture's solve time per period, but one period
SOLVE_PEAK_US = 4000.0


def _trace(duration: float = 2.0, target_from: float = 0.5) -> pd.DataFrame:
    """A walk forward along x at 0.1 m/s; the hand 0.3 m ahead of the CoM and 0.2 m to the
    right; a target from `target_from` [s] on (NaN before), moved at 1.5 s; the solve taking
    `SOLVE_US` each period but one of `SOLVE_PEAK_US`, with 1 iteration (3 at the peak)."""
    time = np.arange(0.0, duration, DT)
    trace = pd.DataFrame({"time": time})
    for prefix in ("com_true", "com_actual"):
        trace[f"{prefix}_x"] = 0.1 * time
        trace[f"{prefix}_y"] = 0.02 * np.sin(2 * np.pi * time)
        trace[f"{prefix}_z"] = 0.8
    trace["hand_actual_x"] = trace["com_true_x"] + 0.3
    trace["hand_actual_y"] = -0.2
    trace["hand_actual_z"] = 0.9
    trace["hand_target_x"] = np.where(time < 1.5, 0.5, 0.6)
    trace["hand_target_y"] = -0.2
    trace["hand_target_z"] = 0.85
    trace.loc[time < target_from, ["hand_target_x", "hand_target_y", "hand_target_z"]] = np.nan
    trace["hand_error_m"] = np.linalg.norm(
        trace[["hand_actual_x", "hand_actual_y", "hand_actual_z"]].to_numpy()
        - trace[["hand_target_x", "hand_target_y", "hand_target_z"]].to_numpy(),
        axis=1,
    )
    solve = np.full(len(time), SOLVE_US)
    solve[len(time) // 2] = SOLVE_PEAK_US
    trace[plots.HIERARCHY_TIME_COLUMN] = solve
    trace["solver_iterations"] = np.where(solve > SOLVE_US, 3.0, 1.0)
    return trace


def _footsteps() -> pd.DataFrame:
    return pd.DataFrame(
        {
            "limb": ["left_foot", "right_foot", "left_foot"],
            "liftoff_time_s": [0.2, 0.6, 1.0],
            "touchdown_time_s": [0.5, 0.9, 1.3],
            "x_m": [0.1, 0.2, 0.3],
            "y_m": [0.1, -0.1, 0.1],
            "z_m": [0.0, 0.0, 0.0],
            "yaw_rad": [0.0, np.pi / 2, 0.0],
            "swing_length_m": [0.1, 0.2, 0.2],
        }
    )


@pytest.fixture
def captured(monkeypatch) -> list:
    """The figures the plots close (kept open for inspection)."""
    figures = []
    close = plt.close
    monkeypatch.setattr(plots.plt, "close", figures.append)
    yield figures
    for figure in figures:
        close(figure)


def _is_png(path: Path) -> bool:
    return path.exists() and path.stat().st_size > 1000 and path.read_bytes()[:8] == PNG


def test_top_view_draws_soles_paths_and_pushes(tmp_path, captured):
    trace, steps = _trace(), _footsteps()
    path = plots.top_view_plot(
        trace, steps, HALF, tmp_path / "top.png", title="t", pushes=(1.0, 99.0)
    )
    assert path == tmp_path / "top.png"
    assert _is_png(path)
    (axis,) = captured[0].axes
    soles = [p for p in axis.patches if isinstance(p, Polygon)]
    assert len(soles) == len(steps)
    for sole, step in zip(soles, steps.itertuples(), strict=True):
        corners = sole.get_xy()[:4]
        np.testing.assert_allclose(corners.mean(axis=0), (step.x_m, step.y_m), atol=1e-12)
        # along the foot's own x: 2 * 0.11 long; turned 90 deg, the long side is along y
        long_axis = np.array([np.cos(step.yaw_rad), np.sin(step.yaw_rad)])
        along = (corners - corners.mean(axis=0)) @ long_axis
        assert np.ptp(along) == pytest.approx(2 * HALF[0])
    left, right = (soles[0], soles[1])
    assert left.get_facecolor() != right.get_facecolor()  # the feet are told apart
    assert soles[0].get_facecolor() == soles[2].get_facecolor()
    lines = {line.get_label(): line for line in axis.lines}
    assert lines["CoM"].get_color() == "black"
    np.testing.assert_array_equal(lines["CoM"].get_xdata(), trace["com_true_x"])
    assert lines["hand"].get_linestyle() == "--"
    assert lines["target"].get_linestyle() == ":"
    # the target's two positions (it jumps at 1.5 s) marked once each
    np.testing.assert_allclose(lines["target positions"].get_xdata(), [0.5, 0.6])
    np.testing.assert_allclose(lines["target positions"].get_ydata(), [-0.2, -0.2])
    # the push inside the trace is marked on the CoM path, the one after it is not
    np.testing.assert_allclose(lines["push"].get_xdata(), [0.1 * 1.0], atol=1e-9)
    np.testing.assert_allclose(
        lines["push"].get_ydata(), [0.02 * np.sin(2 * np.pi * 1.0)], atol=1e-9
    )
    assert axis.get_aspect() == 1.0


@pytest.mark.parametrize("steps", [None, _footsteps().iloc[:0]], ids=["none", "empty"])
def test_top_view_without_steps_or_targets(tmp_path, captured, steps):
    trace = _trace(target_from=99.0)  # no target ever active: all NaN
    assert trace["hand_target_x"].isna().all()
    path = plots.top_view_plot(trace, steps, HALF, tmp_path / "top.png")
    assert _is_png(path)
    (axis,) = captured[0].axes
    assert not axis.patches
    assert "target" not in {line.get_label() for line in axis.lines}
    assert "CoM" in {line.get_label() for line in axis.lines}


def test_top_view_draws_the_standing_feet_when_given(tmp_path, captured):
    feet = {"left_foot": (0.0, 0.1, 0.0), "right_foot": (0.0, -0.1, 0.0)}
    plots.top_view_plot(_trace(), None, HALF, tmp_path / "top.png", initial_feet=feet)
    (axis,) = captured[0].axes
    assert len(axis.patches) == 2
    assert all(p.get_linestyle() == "--" for p in axis.patches)


def test_solve_time_plot_shows_time_iterations_and_the_papers_mean(tmp_path, captured):
    trace = _trace()
    path = plots.solve_time_plot(trace, tmp_path / "solve.png", title="t")
    assert path == tmp_path / "solve.png"
    assert _is_png(path)
    above, below = captured[0].axes
    assert above.get_shared_x_axes().joined(above, below)
    solve = next(line for line in above.lines if len(line.get_xdata()) == len(trace))
    np.testing.assert_allclose(solve.get_ydata(), trace[plots.HIERARCHY_TIME_COLUMN] / 1e3)
    paper = [line for line in above.lines if "paper" in line.get_label()]
    assert len(paper) == 1
    assert list(paper[0].get_ydata()) == [0.92, 0.92]
    assert paper[0].get_linestyle() == "--"
    (iterations,) = below.lines
    np.testing.assert_array_equal(iterations.get_ydata(), trace["solver_iterations"])
    assert above.get_yscale() == "linear"  # the longest solve: under 3 times the median


def test_solve_time_plot_goes_logarithmic_for_rare_long_solves(tmp_path, captured):
    trace = _trace()
    trace.loc[10, plots.HIERARCHY_TIME_COLUMN] = 1000 * SOLVE_US
    plots.solve_time_plot(trace, tmp_path / "solve.png")
    assert captured[0].axes[0].get_yscale() == "log"


def test_solve_time_plot_without_its_columns(tmp_path):
    trace = _trace()[["time", "com_true_x", "com_true_y"]]
    assert _is_png(plots.solve_time_plot(trace, tmp_path / "solve.png"))


def test_the_reports_copies_of_the_scenarios_constants_agree():
    assert tables.REACH_PASS_HAND_ERROR_M == scenarios.REACH_PASS_HAND_ERROR_M
    assert tuple(push[0] for push in scenarios.REACH_PUSHES) == tables.REACH_PUSH_TIMES_S
    from bench.branching import BRANCHED_SCENARIOS, PUSH_TIMING_DELAY_PERIODS

    assert tables.BRANCHED_SCENARIOS == BRANCHED_SCENARIOS
    assert tables.PUSH_TIMING_DELAY_PERIODS == PUSH_TIMING_DELAY_PERIODS


def test_solve_time_stats_of_a_trace():
    values = np.full(1000, 2000.0)
    values[10] = 9000.0
    trace = pd.DataFrame({"t_hierarchy_us": np.append(values, np.nan)})
    stats = tables.solve_time_stats(trace)
    assert stats == {"mean": pytest.approx(2007.0), "p99": 2000.0, "max": 9000.0}
    assert tables.solve_time_stats(trace.iloc[:0]) == {}
    assert tables.solve_time_stats(pd.DataFrame({"time": [0.0]})) == {}


def _episode(episode_id: str, scenario: str, status: str, error, **values) -> dict:
    row = {name: None for name in ROW_SCHEMA.names}
    row.update(
        episode_id=episode_id,
        controller="capturability_hierarchy",
        planner="capturability_hierarchy",
        stabilizer="passthrough",
        sim="mujoco",
        scenario=scenario,
        seed=0,
        scale=1.0,
        status=status,
        fell=status == "fell",
        hand_error_final_m=error,
        versions_json=json.dumps({"mujoco": "4.0.0"}),
        centrobench_version="0.1.0",
        git_commit="abc123",
        cpu="test CPU",
    )
    row.update(values)
    return row


def test_reach_table_rows_and_pass():
    episodes = pd.DataFrame(
        [
            _episode("e1", "reach", "ok", 0.01, steps_taken=6),  # passes
            _episode("e2", "reach_push", "ok", 0.05, steps_taken=9),  # too far
            _episode("e3", "reach", "fell", 0.005, sim="pybullet"),  # close, but fell
            _episode("e4", "reach_push", "error", None, sim="pybullet", error_stage="planner"),
            _episode("e5", "walk", "ok", None),
            _episode("e6", "stand", "ok", None),
        ]
    )
    solve = {"e1": {"mean": 1500.0, "p99": 2500.0, "max": 4000.0}}
    table = tables.reach_table(episodes, solve)
    assert list(zip(table["sim"], table["scenario"], table["status"], strict=True)) == [
        ("mujoco", "reach", "ok"),
        ("mujoco", "reach_push", "ok"),
        ("pybullet", "reach", "fell"),
        ("pybullet", "reach_push", "error"),
    ]
    assert list(table["pass"]) == ["yes", "no", "no", "no"]
    np.testing.assert_allclose(table["hand error cm"].iloc[:2], [1.0, 5.0])
    # after a fall the hand's distance at the fall's detection is no hand error: none shown
    assert table["hand error cm"].iloc[2:].isna().all()
    assert list(table["steps"].iloc[:2]) == [6, 9]
    assert table["steps"].iloc[2:].isna().all()
    assert list(table.loc[0, ["solve mean ms", "solve p99 ms", "solve max ms"]]) == [1.5, 2.5, 4.0]
    assert table.iloc[1:][["solve mean ms", "solve p99 ms", "solve max ms"]].isna().all().all()
    assert tables.reach_table(episodes[episodes["scenario"] == "walk"]).empty


def test_reach_rows_of_a_planner_without_a_hand_task_show_no_hand_error():
    """A fixed-schedule controller stands through `reach`: its hand stays ~0.9 m from the
    target, which is no measure of reaching; with `hand_task` False the row says so."""
    episodes = pd.DataFrame(
        [
            _episode("e1", "reach", "ok", 0.896, controller="hold+posture", hand_task=False),
            _episode("e2", "reach", "ok", 0.01, hand_task=True),
            _episode("e3", "reach", "ok", 0.01),  # a row written before hand_task: as before
        ]
    )
    table = tables.reach_table(episodes)  # by controller: the hierarchy's two, then hold's
    assert list(table["controller"]) == [*2 * ["capturability_hierarchy"], "hold+posture"]
    assert list(table["pass"]) == ["yes", "yes", "n/a (no hand task)"]
    np.testing.assert_allclose(table["hand error cm"].iloc[:2], [1.0, 1.0])
    assert np.isnan(table["hand error cm"].iloc[2])
    # a row written before hand_task: only the hierarchy's planner drove a hand then
    old = _episode("e4", "reach", "ok", 0.896, controller="hold+posture", planner="hold")
    assert tables.reach_table(pd.DataFrame([old])).loc[0, "pass"] == "n/a (no hand task)"


def test_a_reach_that_ended_in_an_error_shows_no_hand_error():
    """The hand's distance when a controller failed is no final hand error."""
    episodes = pd.DataFrame(
        [_episode("e1", "reach", "error", 0.3, hand_task=True, error_stage="planner")]
    )
    table = tables.reach_table(episodes)
    assert np.isnan(table.loc[0, "hand error cm"])
    assert table.loc[0, "pass"] == "no"  # the controller's failure: the test failed


@pytest.mark.parametrize(
    ("status", "stage", "expected"),
    [
        ("timeout", None, "not judged"),  # the machine's budget: no test of the controller
        ("error", "sim", "not judged"),
        ("error", None, "not judged"),
        ("n/a", None, "n/a (not run)"),
    ],
)
def test_a_reach_that_says_nothing_of_the_controller_is_not_a_failed_test(status, stage, expected):
    """Until 2026-12-03 a timed-out reach read pass "no", as if the hierarchy had missed."""
    row = _episode("e1", "reach", status, None, hand_task=True, error_stage=stage)
    assert tables.reach_table(pd.DataFrame([row])).loc[0, "pass"] == expected


def test_reach_table_takes_hierarchy_latency_columns_when_rows_have_them():
    episodes = pd.DataFrame([_episode("e1", "reach", "ok", 0.01, lat_hierarchy_p99_us=3000.0)])
    table = tables.reach_table(episodes)
    assert table.loc[0, "solve p99 ms"] == 3.0
    assert np.isnan(table.loc[0, "solve mean ms"])
    assert np.isnan(table.loc[0, "solve max ms"])


@pytest.fixture
def reach_results(tmp_path) -> Path:
    """A result directory: a reach with its trace and steps, a reach_push with a trace and no
    steps file, a reach whose trace is corrupt, a reach without a trace, a reach with a trace
    by a controller that drives no hand, and a walk."""
    root = tmp_path / "results"
    store = ResultStore(root)
    store.prepare({"name": "reach"}, "digest", resume=False, overwrite=False)
    trace = _trace()
    store.write(_episode("r1", "reach", "ok", 0.01, steps_taken=3), trace, _footsteps())
    store.write(_episode("r2", "reach_push", "fell", 0.3), trace, None)
    store.write(_episode("r3", "reach", "ok", 0.015, sim="pybullet"), trace, _footsteps())
    store.write(_episode("r4", "reach_push", "ok", 0.01, sim="pybullet"), None)
    standing = _episode("s1", "reach", "ok", 0.9, controller="hold+posture", hand_task=False)
    store.write(standing, trace, _footsteps())  # drives no hand: no figure
    walk = _trace()[["time"]]
    for prefix in ("com_ref", "com_planned", "com_actual", "zmp_planned", "zmp_actual"):
        walk[f"{prefix}_x"] = 0.1 * walk["time"]
        walk[f"{prefix}_y"] = 0.0
    store.write(_episode("w1", "walk", "ok", None, controller="a+x"), walk)
    (root / "traces" / "r3.parquet").write_bytes(b"PAR1 not really")
    return root


def _section_rows(markdown: str) -> list[list[str]]:
    section = markdown.split("## Reaching tests (Sherikov et al. Tests 1-2)")[1].split("\n## ")[0]
    return [
        [cell.strip() for cell in line.split("|")[1:-1]]
        for line in section.splitlines()
        if line.startswith("| capturability_hierarchy")
    ]


def test_report_has_the_reaching_section_and_figures(reach_results, tmp_path):
    out = tmp_path / "report"
    paths = build_report(reach_results, out)
    names = {p.name for p in paths}
    expected = {"reach_r1_top.png", "reach_r1_solve.png", "reach_r2_top.png", "reach_r2_solve.png"}
    assert expected <= names
    assert not {n for n in names if n.startswith(("reach_r3", "reach_r4", "reach_s1"))}
    for name in expected:
        assert _is_png(out / name)
    markdown = (out / "report.md").read_text()
    page = (out / "report.html").read_text()
    assert "Reaching tests (Sherikov et al. Tests 1-2)" in page
    for name in expected:
        assert f"]({name})" in markdown
        assert f'src="{name}"' in page
    rows = _section_rows(markdown)
    header = markdown.split("## Reaching tests")[1].splitlines()[4]
    columns = [cell.strip() for cell in header.split("|")[1:-1]]
    table = [dict(zip(columns, row, strict=True)) for row in rows]
    assert [(r["sim"], r["scenario"], r["pass"]) for r in table] == [
        ("mujoco", "reach", "yes"),
        ("mujoco", "reach_push", "no"),
        ("pybullet", "reach", "yes"),  # its trace is corrupt: the row stays, no solve times
        ("pybullet", "reach_push", "yes"),
    ]
    # solve times [ms] from the stored traces: all SOLVE_US but one period of SOLVE_PEAK_US
    n = len(_trace())
    mean_ms = (SOLVE_US * (n - 1) + SOLVE_PEAK_US) / n / 1e3
    for row in table[:2]:
        assert float(row["solve mean ms"]) == pytest.approx(mean_ms, rel=1e-3)
        assert float(row["solve p99 ms"]) == pytest.approx(SOLVE_US / 1e3)
        assert float(row["solve max ms"]) == pytest.approx(SOLVE_PEAK_US / 1e3)
    for row in table[2:]:
        assert [row[f"solve {s} ms"] for s in ("mean", "p99", "max")] == ["–"] * 3
    assert table[0]["hand error cm"] == "1"
    assert table[0]["steps"] == "3"
    assert "traces/r3.parquet: unreadable, not plotted" in markdown
    assert "traces/r2.footsteps.parquet: missing, steps not drawn" in markdown


def test_no_reaching_section_without_reach_episodes(reach_results, tmp_path):
    for path in (reach_results / "episodes").glob("[rs]*.parquet"):
        path.unlink()
    paths = build_report(reach_results, tmp_path / "report")
    assert not [p for p in paths if p.name.startswith("reach_")]
    markdown = (tmp_path / "report" / "report.md").read_text()
    assert "Reaching tests" not in markdown
    assert "walk.png" in {p.name for p in paths}


def test_a_reach_without_solve_times_gets_its_top_view_and_no_empty_solve_figure(tmp_path):
    """A controller without the hierarchy records no solve times: its reach has Fig. 3's
    top view, and no Fig. 2 (it was an empty plot: 28 of the main job's 32)."""
    root = tmp_path / "results"
    store = ResultStore(root)
    store.prepare({"name": "reach"}, "digest", resume=False, overwrite=False)
    trace = _trace().drop(columns=[plots.HIERARCHY_TIME_COLUMN])
    store.write(_episode("q1", "reach", "ok", 0.5, controller="a+x"), trace, _footsteps())
    names = {p.name for p in build_report(root, tmp_path / "report")}
    assert "reach_q1_top.png" in names
    assert "reach_q1_solve.png" not in names
