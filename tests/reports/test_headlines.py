"""The report's headline tables (`reports.headlines`) on a hand-made fixture: the papers'
benchmarks set our numbers beside the paper's figure for the same motion and method, and
n/a rows for the controllers that cannot run one; the cost table's ratio to the engine."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pandas as pd
import pytest

from bench.dataset import ROW_SCHEMA, ResultStore
from reports import headlines
from reports.build import build_report


def _row(**values) -> dict:
    row = {name: None for name in ROW_SCHEMA.names}
    row.update(
        versions_json=json.dumps({"mujoco": "4.0.0"}),
        git_commit="abc123",
        cpu="test CPU",
        seed=0,
        scale=1.0,
        mass_kg=58.0,
        perturbation="nominal",
        replica=0,
    )
    row.update(values)
    row["episode_id"] = f"{row['controller']}-{row['sim']}-{row['scenario']}"
    return row


ROWS = [
    _row(
        controller="preview_control+centroidal_feedback",
        planner="preview_control",
        sim="mujoco",
        scenario="handrail_stairs",
        status="ok",
        lat_centroidal_control_median_us=250.0,
        lat_projection_median_us=80.0,
        lat_distribution_median_us=70.0,
        planned_force_N=1.5,
        planned_moment_Nm=2.0,
        desired_force_N=3.0,
        desired_moment_Nm=4.0,
    ),
    _row(
        controller="linear_mpc+centroidal_feedback",
        planner="linear_mpc",
        sim="pybullet",
        scenario="ladder",
        status="fell",
        fell=True,
        fall_time=7.82,
        lat_centroidal_control_median_us=900.0,
        desired_force_N=12.0,
    ),
    _row(
        controller="hold+posture",
        planner="hold",
        sim="mujoco",
        scenario="ladder",
        status="n/a",
        error="n/a: hold+posture cannot run ladder (multi_contact)",
    ),
    _row(
        controller="capturability_hierarchy",
        planner="capturability_hierarchy",
        sim="mujoco",
        scenario="reach",
        status="ok",
        hand_error_final_m=0.031,
    ),
    _row(  # a perturbed motion: not a headline number
        controller="preview_control+centroidal_feedback",
        planner="preview_control",
        sim="pybullet",
        scenario="handrail_stairs",
        status="ok",
        perturbation="noise=4",
        lat_centroidal_control_median_us=1.0,
    ),
]
WALKS = {  # (controller, sim): (control median, engine median) [µs]
    ("a+x", "mujoco"): (300.0, 40.0),
    ("a+x", "pybullet"): (330.0, 150.0),
}


def _walk(controller, sim, control, engine) -> dict:
    return _row(
        controller=controller,
        sim=sim,
        scenario="walk",
        status="ok",
        lat_control_total_median_us=control,
        lat_control_total_p99_us=2 * control,
        lat_sim_engine_median_us=engine,
        lat_planner_median_us=control / 3,
    )


def fixture_rows() -> list[dict]:
    return [*ROWS, *(_walk(c, s, *v) for (c, s), v in WALKS.items())]


@pytest.fixture(scope="module")
def episodes() -> pd.DataFrame:
    return pd.DataFrame(fixture_rows())


def _value(table, controller, benchmark_word, quantity_word, column):
    rows = table[
        (table["controller"] == controller)
        & table["benchmark"].str.contains(benchmark_word, regex=False)
        & table["quantity"].str.contains(quantity_word, regex=False)
    ]
    assert len(rows) == 1, rows
    return rows.iloc[0][column]


def test_paper_benchmarks_set_ours_beside_the_papers_figure(episodes):
    table = headlines.paper_benchmarks(episodes)
    preview = "preview_control+centroidal_feedback"
    # Table IV (B): 186 µs total, 56 µs projection; Sec. V-G (B), preview control: 3.7 N
    assert _value(table, preview, "(B)", "total control", "paper") == 186.0
    assert _value(table, preview, "(B)", "total control", "ours") == 250.0
    assert _value(table, preview, "(B)", "project planned", "paper") == 56.0
    assert _value(table, preview, "(B)", "desired projection error, force", "paper") == 3.7
    # the linear MPC on the ladder: Sec. V-G's 9.3 N; Table IV is not its figure
    mpc = "linear_mpc+centroidal_feedback"
    assert _value(table, mpc, "(C)", "desired projection error, force", "paper") == 9.3
    assert _value(table, mpc, "(C)", "desired projection error, force", "ours") == 12.0
    assert math.isnan(_value(table, mpc, "(C)", "total control", "paper"))
    assert set(table.loc[table["controller"] == mpc, "outcome"]) == {"fell at 7.8 s"}
    # a controller that cannot climb: one n/a row without numbers
    hold = table[table["controller"] == "hold+posture"]
    assert list(hold["outcome"]) == ["n/a"]
    assert math.isnan(hold["ours"].iloc[0])
    # the reach: its final hand error [cm]
    reach = "capturability_hierarchy"
    assert _value(table, reach, "Test 1", "hand error", "ours") == pytest.approx(3.1)
    # the perturbed episode stays out
    assert not ((table["controller"] == preview) & (table["sim"] == "pybullet")).any()


def test_cost_is_the_control_time_in_engine_steps_of_the_same_run(episodes):
    table = headlines.cost_table(episodes).set_index(["controller", "sim"])
    for key, (control, engine) in WALKS.items():
        assert table.loc[key, "control median µs"] == control
        assert table.loc[key, "control p99 µs"] == 2 * control
        assert table.loc[key, "control / engine"] == pytest.approx(control / engine)


def test_the_report_opens_with_the_headline_tables(episodes, tmp_path: Path):
    store = ResultStore(tmp_path / "results")
    store.prepare({"name": "fixture"}, "digest", resume=False, overwrite=False)
    for row in fixture_rows():
        store.write(row, None)
    build_report(tmp_path / "results", tmp_path / "report")
    markdown = (tmp_path / "report" / "report.md").read_text()
    titles = [line[3:] for line in markdown.splitlines() if line.startswith("## ")]
    assert titles[:3] == [
        "3. The papers' own benchmarks",
        "4. What each controller costs per control period",
        "5. Where MuJoCo and PyBullet disagree",
    ]  # no pushes, no speed walks in the fixture: questions 1 and 2 have nothing to show
    assert "| 186 " in markdown.split("## 4.")[0]
