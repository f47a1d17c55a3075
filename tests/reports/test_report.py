"""The report built from a small hand-made result set: every table has the expected rows and
columns, and its numbers equal those computed directly from the fixture."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from bench.dataset import ROW_SCHEMA, ResultStore
from reports import tables
from reports.build import build_report
from reports.statistics import fraction_cell, wilson_interval

CONTROLLERS = ("a+x", "b+y")
SIMS = ("mujoco", "pybullet")
LEVELS = (0.2, 0.4)  # dv [m/s]
MASS = 50.0  # [kg]
# survived pushes out of 4, per controller, sim, level (hand-picked)
SURVIVED = {
    ("a+x", "mujoco"): (4, 2),
    ("a+x", "pybullet"): (3, 1),
    ("b+y", "mujoco"): (4, 4),
    ("b+y", "pybullet"): (4, 3),
}
PUSHES = 4
# walk numbers per controller, sim: (com rms [m], planned force error [N], preview median [µs])
WALKS = {
    ("a+x", "mujoco"): (0.004, 0.01, 10.0),
    ("a+x", "pybullet"): (0.006, 0.02, 12.0),
    ("b+y", "mujoco"): (0.005, 0.03, 20.0),
    ("b+y", "pybullet"): (0.005, 0.05, 22.0),
}


def _row(**values) -> dict:
    row = {name: None for name in ROW_SCHEMA.names}
    row.update(
        versions_json=json.dumps({"mujoco": "4.0.0", "pybullet": "3.2.7"}),
        centrobench_version="0.1.0",
        git_commit="abc123",
        cpu="test CPU",
        seed=0,
        scale=1.0,
        mass_kg=MASS,
    )
    row.update(values)
    return row


@pytest.fixture(scope="module")
def results(tmp_path_factory) -> tuple[Path, pd.DataFrame]:
    root = tmp_path_factory.mktemp("results")
    store = ResultStore(root)
    store.prepare({"name": "fixture"}, "digest", resume=False, overwrite=False)
    rows = []
    for (controller, sim), survived_per_level in SURVIVED.items():
        planner, stabilizer = controller.split("+")
        for dv, survived in zip(LEVELS, survived_per_level, strict=True):
            for k in range(PUSHES):
                alive = k < survived
                rows.append(
                    _row(
                        episode_id=f"{controller}-{sim}-{dv}-{k}",
                        controller=controller,
                        planner=planner,
                        stabilizer=stabilizer,
                        sim=sim,
                        scenario="stand_push",
                        push_phase="standing",
                        push_dv_mps=dv,
                        push_index=k,
                        push_impulse_Ns=MASS * dv,
                        status="ok" if alive else "fell",
                        fell=not alive,
                        survived=alive,
                    )
                )
        rms, planned_force, preview = WALKS[(controller, sim)]
        rows.append(
            _row(
                episode_id=f"{controller}-{sim}-walk",
                controller=controller,
                planner=planner,
                stabilizer=stabilizer,
                sim=sim,
                scenario="walk",
                status="ok",
                fell=False,
                com_error_rms_m=rms,
                planned_force_N=planned_force,
                planned_moment_Nm=2 * planned_force,
                e_com=rms**2,
                e_zmp=3 * rms**2,
                e_velocity=rms,
                touchdown_time_error_mean_s=-2 * rms,
                touchdown_position_error_mean_m=5 * rms,
                final_position_error_m=7 * rms,
                walk_speed_mps=0.25,
                lat_preview_median_us=preview,
                lat_preview_p99_us=3 * preview,
            )
        )
    for row in rows:
        trace = None
        if row["scenario"] == "walk":
            time = np.arange(0.0, 1.0, 0.002)
            trace = pd.DataFrame({"time": time})
            for prefix in ("com_ref", "com_planned", "com_actual", "zmp_planned", "zmp_actual"):
                trace[f"{prefix}_x"] = 0.25 * time
                trace[f"{prefix}_y"] = 0.0
        store.write(row, trace)
    return root, pd.DataFrame(rows)


def test_survival_table_counts_the_fixture(results):
    _root, fixture = results
    table = tables.survival_table(fixture, "standing")
    assert list(table["controller"]) == ["a+x", "a+x", "b+y", "b+y"]
    assert list(table["sim"]) == ["mujoco", "pybullet"] * 2
    labels = [tables.level_label(dv, MASS * dv) for dv in LEVELS]
    assert list(table.columns) == [
        "controller",
        "sim",
        *labels,
        "not judged",
        "fell before the push",
    ]
    assert labels == ["0.2 m/s (10.0 N s)", "0.4 m/s (20.0 N s)"]
    for _, row in table.iterrows():
        expected = SURVIVED[(row["controller"], row["sim"])]
        assert [row[label] for label in labels] == [fraction_cell(k, PUSHES) for k in expected]
        assert row["not judged"] == ""


def _push_rows(
    statuses: list[str], survived: list[bool | None], stages: list[str | None] | None = None
) -> pd.DataFrame:
    stages = stages or [None] * len(statuses)
    return pd.DataFrame(
        [
            _row(
                episode_id=f"p{k}",
                controller="a+x",
                sim="mujoco",
                scenario="stand_push",
                push_phase="standing",
                push_dv_mps=0.2,
                push_index=k,
                push_impulse_Ns=MASS * 0.2,
                status=status,
                error_stage=stage,
                survived=alive,
            )
            for k, (status, alive, stage) in enumerate(zip(statuses, survived, stages, strict=True))
        ]
    )


def test_errors_and_timeouts_are_not_counted_as_failed_pushes():
    rows = _push_rows(
        ["ok", "ok", "ok", "fell", "error", "timeout", "error"],
        [True, True, True, False, None, None, False],  # an old error row said False
    )
    table = tables.survival_table(rows, "standing")
    # 3 survived of the 4 judged; Wilson: centre (0.75 + 0.4802) / 1.9604 = 0.6275, half-width
    # 1.96 sqrt(0.046875 + 0.060023) / 1.9604 = 0.3269: 0.301-0.954
    assert table.loc[0, "0.2 m/s (10.0 N s)"] == "3/4 (30-95 %)"
    assert table.loc[0, "not judged"] == "2 error, 1 timeout"
    rates = tables.survival_rates(rows, "standing")
    assert rates.loc[0, "rate"] == pytest.approx(0.75)
    assert (rates.loc[0, "rate_low"], rates.loc[0, "rate_high"]) == wilson_interval(3, 4)
    assert rates.loc[0, "not_judged"] == 3


def test_a_controller_that_fails_did_not_survive_its_push():
    """An error raised by the controller's own stages (a planner whose solver gives up on a
    falling robot) is judged, as not survived; one of the set-up or the simulator, and a
    timeout, are not judged. Rows of result files written before (survived None) count the
    same."""
    rows = _push_rows(
        ["ok", "fell", "error", "error", "error", "error", "timeout"],
        [True, False, None, False, None, None, None],
        [None, None, "planner", "whole_body", "setup", "sim", "planner"],
    )
    table = tables.survival_table(rows, "standing")
    # 1 survived of 4 judged: Wilson centre (0.25 + 0.4802) / 1.9604 = 0.3725, half-width
    # 1.96 sqrt(0.046875 + 0.060023) / 1.9604 = 0.3269: 0.046-0.699
    assert table.loc[0, "0.2 m/s (10.0 N s)"] == "1/4 (5-70 %)"
    assert table.loc[0, "not judged"] == "2 error, 1 timeout"
    rates = tables.survival_rates(rows, "standing")
    assert (rates.loc[0, "survived"], rates.loc[0, "pushes"]) == (1, 4)
    assert rates.loc[0, "not_judged"] == 3


def test_a_level_with_no_judged_push_has_no_rate():
    rates = tables.survival_rates(_push_rows(["error", "timeout"], [None, None]), "standing")
    assert rates.loc[0, "pushes"] == 0
    assert np.isnan(rates.loc[0, "rate"])


def test_report_says_the_specs_survival_time(tmp_path: Path):
    root = tmp_path / "results"
    store = ResultStore(root)
    store.prepare({"name": "t", "push": {"survival_time": 0.7}}, "d", resume=False, overwrite=False)
    for row in _push_rows(["ok", "fell"], [True, False]).to_dict("records"):
        store.write(row, None)
    build_report(root, tmp_path / "report")
    markdown = (tmp_path / "report" / "report.md").read_text()
    assert "no fall within 0.7 s after it" in markdown
    assert "within 3 s" not in markdown


def test_corrupt_trace_and_foreign_file_are_left_out_with_a_note(results, tmp_path: Path):
    import shutil

    root = tmp_path / "copy"
    shutil.copytree(results[0], root)
    trace = sorted((root / "traces").glob("*.parquet"))[0]
    trace.write_bytes(b"PAR1 not really")
    pd.DataFrame({"x": [1]}).to_parquet(root / "episodes" / "foreign.parquet")
    (root / "episodes" / "broken.parquet").write_bytes(b"\x00" * 10)
    paths = build_report(root, tmp_path / "report")
    markdown = (tmp_path / "report" / "report.md").read_text()
    assert "walk.png" in {p.name for p in paths}  # the other controller's walk is plotted
    assert f"traces/{trace.name}: unreadable, not plotted" in markdown
    assert "foreign.parquet: not an episode row" in markdown
    assert "broken.parquet: unreadable" in markdown
    assert "| a+x          | pybullet | 3/4" in markdown  # the tables are whole


def test_agreement_table_differences(results):
    _, fixture = results
    table = tables.agreement_table(fixture).set_index(["controller", "quantity"])
    assert sorted(set(table.index.get_level_values(0))) == list(CONTROLLERS)
    for controller in CONTROLLERS:
        rate = {
            sim: 100 * sum(SURVIVED[(controller, sim)]) / (PUSHES * len(LEVELS)) for sim in SIMS
        }
        row = table.loc[(controller, "standing push survival")]
        assert row["mujoco"] == pytest.approx(rate["mujoco"])
        assert row["mujoco - pybullet"] == pytest.approx(rate["mujoco"] - rate["pybullet"])
        low, high = min(rate.values()), max(rate.values())
        assert row["band"] == f"{low:.3g} to {high:.3g}"
        rms = {sim: 1e3 * WALKS[(controller, sim)][0] for sim in SIMS}
        row = table.loc[(controller, "walk CoM tracking RMS")]
        assert row["pybullet"] == pytest.approx(rms["pybullet"])
        assert row["mujoco - pybullet"] == pytest.approx(rms["mujoco"] - rms["pybullet"])
        # not decided by the simulator: the plan's projection error, the controller's time
        assert (controller, "planned wrench projection error, force") not in table.index
        assert (controller, "control time per period, median") not in table.index
        # no walking pushes in the fixture: no row for them
        assert (controller, "walking push survival") not in table.index


def test_agreement_table_leaves_out_the_tracking_errors_of_walks_that_fell(results):
    """A walk that fell has a CoM tracking RMS that measures how far the robot toppled before
    the fall was detected: the simulators do not "disagree" on tracking there."""
    _, fixture = results
    controller = CONTROLLERS[0]
    fell = (fixture["controller"] == controller) & (fixture["sim"] == "pybullet")
    fell &= (fixture["scenario"] == "walk") & fixture["push_phase"].isna()
    assert fell.sum() == 1
    fixture = fixture.copy()
    fixture.loc[fell, "status"] = "fell"
    table = tables.agreement_table(fixture).set_index(["controller", "quantity"])
    row = table.loc[(controller, "walk CoM tracking RMS")]
    assert row["mujoco"] == pytest.approx(1e3 * WALKS[(controller, "mujoco")][0])
    assert math.isnan(row["pybullet"])
    assert math.isnan(row["mujoco - pybullet"])


def test_latency_projection_and_walking_tables(results):
    _, fixture = results
    latency = tables.latency_table(fixture)
    projection = tables.projection_table(fixture)
    quality = tables.walking_quality_table(fixture)
    for table in (latency, projection, quality):
        assert list(zip(table["controller"], table["sim"], strict=True)) == list(WALKS)
    assert "preview median µs" in latency
    assert "centroidal_total p99 µs" in latency
    assert list(projection.columns[2:]) == list(tables.PROJECTION_COLUMNS)
    for k, key in enumerate(WALKS):
        rms, force, preview = WALKS[key]
        assert latency["preview median µs"].iloc[k] == preview
        assert latency["preview p99 µs"].iloc[k] == 3 * preview
        assert projection["planned_force_N"].iloc[k] == pytest.approx(force)
        assert projection["planned_moment_Nm"].iloc[k] == pytest.approx(2 * force)
        assert quality["com_error_rms_mm"].iloc[k] == pytest.approx(1e3 * rms)
        assert quality["e_zmp"].iloc[k] == pytest.approx(3 * rms**2)
        assert quality["status"].iloc[k] == "ok"
        # where the feet landed (signed: early is negative) and the goal, in the table's units
        assert quality["touchdown_time_error_mean_ms"].iloc[k] == pytest.approx(-2e3 * rms)
        assert quality["touchdown_position_error_mean_mm"].iloc[k] == pytest.approx(5e3 * rms)
        assert quality["goal_error_cm"].iloc[k] == pytest.approx(7e2 * rms)


def test_report_files_hold_every_table(results, tmp_path: Path):
    root, _ = results
    benchmark = tmp_path / "benchmark.json"
    benchmark.write_text(
        json.dumps(
            {
                "benchmarks": [
                    {
                        "name": "test_x",
                        "fullname": "tests/x.py::test_x",
                        "stats": {
                            "median": 2e-5,
                            "mean": 2.5e-5,
                            "stddev": 1e-6,
                            "min": 1e-5,
                            "rounds": 7,
                        },
                    }
                ]
            }
        )
    )
    paths = build_report(root, tmp_path / "report", benchmark_json=benchmark)
    names = {p.name for p in paths}
    assert {"report.md", "report.html", "survival.png", "walk.png"} <= names
    markdown = (tmp_path / "report" / "report.md").read_text()
    page = (tmp_path / "report" / "report.html").read_text()
    for title in (
        "Latency per stage",
        "Wrench projection errors",
        "Push survival, standing",
        "Walking quality",
        "5. Where MuJoCo and PyBullet disagree",
        "pytest-benchmark",
    ):
        assert title in markdown
        assert title in page
    assert "| a+x          | pybullet | 3/4" in markdown
    # the benchmark's own row: median 20 µs, mean 25, stddev 1, min 10, 7 rounds (a bare
    # "| 20 " matched Table IV's "20 / 60" cell too)
    row = next(line for line in markdown.splitlines() if "tests/x.py::test_x" in line)
    cells = [float(cell) for cell in row.strip(" |").split("|")[1:]]
    assert cells == [20.0, 25.0, 1.0, 10.0, 7.0]
    assert "abc123" in markdown
    assert "test CPU" in markdown
    assert "mujoco 4.0.0" in markdown


def test_the_maximum_speed_table_joins_the_report_when_its_walks_are_there(results, tmp_path):
    """`centrobench speed --out RESULTS` leaves speed.parquet; the report shows Table 1's
    shape from it: the highest speed walked and eq. 18's errors there, or none."""
    import shutil

    root, _ = results
    copy = tmp_path / "results"
    shutil.copytree(root, copy)
    pd.DataFrame(
        [
            {
                "controller": "a+x",
                "sim": "mujoco",
                "speed_command_mps": 0.05,
                "status": "ok",
                "speed_walked_mps": 0.051,
                "e_com": 0.4,
                "e_zmp": 0.8,
                "e_velocity": 3.0,
            },
            {
                "controller": "a+x",
                "sim": "mujoco",
                "speed_command_mps": 0.1,
                "status": "ok",
                "speed_walked_mps": 0.097,
                "e_com": 0.25,
                "e_zmp": 0.75,
                "e_velocity": 1.5,
            },
            {
                "controller": "a+x",
                "sim": "mujoco",
                "speed_command_mps": 0.15,
                "status": "fell",
                "speed_walked_mps": None,
                "e_com": 9.0,
                "e_zmp": 9.0,
                "e_velocity": 9.0,
            },
            {
                "controller": "b+y",
                "sim": "mujoco",
                "speed_command_mps": 0.05,
                "status": "fell",
                "speed_walked_mps": None,
                "e_com": 9.0,
                "e_zmp": 9.0,
                "e_velocity": 9.0,
            },
        ]
    ).to_parquet(copy / "speed.parquet")
    build_report(copy, tmp_path / "report")
    markdown = (tmp_path / "report" / "report.md").read_text()
    assert "2. How fast each controller walks (Ficht & Behnke Table 1)" in markdown
    section = markdown.split("2. How fast each controller walks")[1].split("\n## ")[0]
    rows = {
        line.split("|")[1].strip(): [cell.strip() for cell in line.split("|")[2:-1]]
        for line in section.splitlines()
        if line.startswith(("| a+x", "| b+y"))
    }
    # sim, v_ref, v_fell, how v_fell ended, v, e_c, e_z, e_v, walks: at the highest speed
    # walked, not the one that fell, which bounds the answer from above
    assert rows["a+x"] == ["mujoco", "0.1", "0.15", "fell", "0.097", "0.25", "0.75", "1.5", "3"]
    assert rows["b+y"][2:4] == ["0.05", "fell"]  # walked at no speed: the lowest it tried fell
    assert rows["b+y"][1] == "–"  # the report's empty cell
    assert rows["b+y"][4:8] == ["–"] * 4
    assert rows["b+y"][8] == "1"


def test_latency_against_the_papers_figures_for_the_controllers_that_have_one():
    """Ficht & Behnke's 143 µs for its whole loop: our control stages' median per period
    against it, for every direct_centroidal variant, and no row for the others."""
    episodes = pd.DataFrame(
        [
            {
                "controller": "direct_centroidal",
                "sim": "mujoco",
                "scenario": "walk",
                "push_phase": None,
                "lat_control_total_median_us": 286.0,
            },
            {
                "controller": "direct_centroidal/no_inertia",
                "sim": "pybullet",
                "scenario": "walk",
                "push_phase": None,
                "lat_control_total_median_us": 429.0,
            },
            {
                "controller": "a+x",
                "sim": "mujoco",
                "scenario": "walk",
                "push_phase": None,
                "lat_control_total_median_us": 100.0,
            },
            {
                "controller": "direct_centroidal",
                "sim": "mujoco",
                "scenario": "stand_push",
                "push_phase": "standing",
                "lat_control_total_median_us": 999.0,
            },
        ]
    )
    table = tables.paper_latency_table(episodes).set_index("controller")
    assert list(table.index) == ["direct_centroidal", "direct_centroidal/no_inertia"]
    assert table.loc["direct_centroidal", "ratio"] == pytest.approx(2.0)
    assert table.loc["direct_centroidal/no_inertia", "ratio"] == pytest.approx(3.0)
    assert (table["paper µs"] == 143.0).all()


def test_several_result_directories_make_one_report(results, tmp_path: Path):
    """A sweep of a controller that is not in the main job, reported beside it: `centrobench
    report MAIN OTHER` puts both directories' push survival in one table (same levels), finds
    each walk's trace in its own directory, and counts an episode present in both once."""
    from bench.cli import build_parser
    from reports.build import _walk_traces, read_all_results

    root, fixture = results
    other = tmp_path / "other"
    store = ResultStore(other)
    store.prepare({"name": "other"}, "digest2", resume=False, overwrite=False)
    survived = (3, 0)  # of PUSHES, per level
    for dv, alive_count in zip(LEVELS, survived, strict=True):
        for k in range(PUSHES):
            alive = k < alive_count
            store.write(
                _row(
                    episode_id=f"c+z-mujoco-{dv}-{k}",
                    controller="c+z",
                    planner="c",
                    stabilizer="z",
                    sim="mujoco",
                    scenario="stand_push",
                    push_phase="standing",
                    push_dv_mps=dv,
                    push_index=k,
                    push_impulse_Ns=MASS * dv,
                    status="ok" if alive else "fell",
                    fell=not alive,
                    survived=alive,
                ),
                None,
            )
    time = np.arange(0.0, 1.0, 0.002)
    trace = pd.DataFrame({"time": time})
    for prefix in ("com_ref", "com_planned", "com_actual", "zmp_planned", "zmp_actual"):
        trace[f"{prefix}_x"] = 0.2 * time
        trace[f"{prefix}_y"] = 0.0
    walk = _row(
        episode_id="c+z-mujoco-walk", controller="c+z", planner="c", stabilizer="z",
        sim="mujoco", scenario="walk", status="ok", fell=False, com_error_rms_m=0.007,
    )  # fmt: skip
    store.write(walk, trace)
    duplicate = fixture.iloc[0].to_dict()  # the first directory's episode, again
    store.write({**duplicate, "status": "error"}, None)

    episodes, records, notes = read_all_results([root, other])
    assert len(episodes) == len(fixture) + PUSHES * len(LEVELS) + 1
    assert [r["spec"]["name"] for r in records] == ["fixture", "other"]
    assert any(duplicate["episode_id"] in note and "kept the first" in note for note in notes)
    kept = episodes[episodes["episode_id"] == duplicate["episode_id"]]
    assert list(kept["status"]) == [duplicate["status"]]
    table = tables.survival_table(episodes, "standing")
    labels = [tables.level_label(dv, MASS * dv) for dv in LEVELS]
    row = table[table["controller"] == "c+z"].iloc[0]
    assert [row[label] for label in labels] == [fraction_cell(k, PUSHES) for k in survived]
    assert len(table) == len(SURVIVED) + 1
    walks = _walk_traces(episodes, [])
    assert any(label.startswith("c+z (mujoco") for label in walks)
    assert any(label.startswith("a+x (mujoco") for label in walks)

    paths = build_report([root, other], tmp_path / "report")
    markdown = paths[0].read_text()
    assert "| c+z " in markdown
    assert "kept the first" in markdown
    assert str(other) in markdown
    args = build_parser().parse_args(["report", str(root), str(other), "--out", "x"])
    assert args.results == [str(root), str(other)]


def test_numbers_at_solver_tolerance_print_as_below_it():
    """9.1e-07 N of projection error is solver tolerance, not a number to set beside the
    paper's 2.2 N: cells under 1e-6 in magnitude print as bounds; 0, NaN and the rest as
    before."""
    from reports.build import _format

    table = pd.DataFrame({"x": [9.141e-07, -3e-07, 0.0, math.nan, 2.2, 1.2345e-5, 123456.0]})
    assert list(_format(table)["x"]) == [
        "< 1e-6",
        "> -1e-6",
        "0",
        "–",
        "2.2",
        "1.234e-05",
        "1.235e+05",
    ]


def test_columns_with_nothing_in_them_are_left_out_of_the_printed_tables():
    """ "not judged", "fell before the push" and "replay" are columns only a few sweeps fill:
    empty in every row, they are left out of the printed table; one filled cell keeps them."""
    from reports.build import OPTIONAL_COLUMNS, _without_empty

    table = pd.DataFrame(
        {
            "controller": ["a", "b"],
            "not judged": ["", ""],
            "fell before the push": ["", 3],
            "replay": [None, math.nan],
        }
    )
    kept = _without_empty(table, OPTIONAL_COLUMNS)
    assert list(kept.columns) == ["controller", "fell before the push"]


def test_the_latency_table_prints_table_iv_stages_only(results):
    """The loop's stages are §4's: the per-stage table prints Table IV's rows."""
    from reports.build import _latency_cells

    _, fixture = results
    cells = _latency_cells(tables.latency_table(fixture))
    stages = [column.removesuffix(" µs") for column in cells.columns[2:]]
    assert stages == list(tables.TABLE_IV_STAGES)


def test_the_walk_plot_is_drawn_around_the_plan_not_the_fall():
    """A walk that fell has an actual ZMP far from the plan (5 m here): the axes span the
    planned CoM and ZMP with a 0.1 m margin, as before the fall."""
    from reports.plots import PLANNED_MARGIN_M, planned_limits

    time = pd.Series([0.0, 1.0, 2.0])
    trace = pd.DataFrame({"time": time})
    for quantity, values in (
        ("com_ref", [0.0, 0.1, 0.2]),
        ("com_planned", [0.0, 0.12, 0.2]),
        ("zmp_planned", [-0.05, 0.15, 0.25]),
        ("zmp_actual", [0.0, 0.1, -5.0]),
        ("com_actual", [0.0, 0.1, 0.9]),
    ):
        trace[f"{quantity}_x"] = values
    low, high = planned_limits(trace, "x")
    assert low == pytest.approx(-0.05 - PLANNED_MARGIN_M)
    assert high == pytest.approx(0.25 + PLANNED_MARGIN_M)
    assert (
        planned_limits(
            trace.assign(com_ref_x=math.nan, com_planned_x=math.nan, zmp_planned_x=math.nan), "x"
        )
        is None
    )


def test_the_sweep_spec_is_folded_and_indented(tmp_path: Path):
    """The header's spec is one JSON object of several kB: it is shown folded and indented,
    one field per line, at the end of the report, not as one line across the header."""
    root = tmp_path / "results"
    store = ResultStore(root)
    spec = {"name": "t", "push": {"survival_time": 0.7}}
    store.prepare(spec, "d", resume=False, overwrite=False)
    for row in _push_rows(["ok", "fell"], [True, False]).to_dict("records"):
        store.write(row, None)
    build_report(root, tmp_path / "report")
    markdown = (tmp_path / "report" / "report.md").read_text()
    page = (tmp_path / "report" / "report.html").read_text()
    folded = markdown.split("\n## Sweep spec\n")
    assert len(folded) == 2  # the last section, after every table and figure
    assert "\n## " not in folded[1]
    assert folded[1].startswith("\n<details><summary>sweep spec</summary>")
    assert '\n    "survival_time": 0.7\n' in folded[1]
    assert "- **sweep spec**: at the end of the report" in markdown
    assert "<details><summary>sweep spec</summary><pre>{\n  &quot;name&quot;" in page
    assert page.rindex("<h2>") == page.index("<h2>Sweep spec</h2>")  # the last section


def test_runs_of_a_branched_group_count_once_when_they_share_their_timings():
    """Rows of a pushed scenario without `timed_from_s` (written before it, or ended before
    their push) share one run's timings: one per group; a row with it, and a plain
    scenario's row, are runs of their own."""
    base = {"controller": "a", "sim": "mujoco", "scenario": "walk_push", "push_time_s": 3.1}
    rows = pd.DataFrame(
        [
            {**base, "lat_control_total_median_us": 300.0},
            {**base, "lat_control_total_median_us": 310.0},
            {**base, "sim": "pybullet", "lat_control_total_median_us": 320.0},
            {**base, "scenario": "walk", "push_time_s": None},
            {**base, "scenario": "walk", "push_time_s": None},
        ]
    )
    kept = tables.independently_timed(rows)  # no timed_from_s column: rows before it
    assert list(kept.index) == [0, 2, 3, 4]
    rows["timed_from_s"] = [3.1, 3.1, None, 0.0, 0.0]
    assert list(tables.independently_timed(rows).index) == [0, 1, 2, 3, 4]


def test_rows_of_an_older_version_are_read_beside_today_s_in_order(results, tmp_path: Path):
    """`read_results` joins the files as Arrow tables: a file of an older centrobench that
    lacks a column gives a null there (NaN), the other rows keep their values, and the rows
    are those of reading each file to pandas, sorted by episode id."""
    import shutil

    import pyarrow.parquet as pq

    from reports.build import read_results

    root = tmp_path / "copy"
    shutil.copytree(results[0], root)
    files = sorted((root / "episodes").glob("*.parquet"))
    old = pq.read_table(files[0])
    pq.write_table(old.drop_columns(["com_error_rms_m"]), files[0])
    episodes, _, notes = read_results(root)
    assert notes == []
    expected = pd.concat([pd.read_parquet(f) for f in files], ignore_index=True)
    expected = expected.sort_values("episode_id", ignore_index=True)
    assert list(episodes["episode_id"]) == list(expected["episode_id"])
    first = episodes["episode_id"] == files[0].stem
    assert episodes.loc[first, "com_error_rms_m"].isna().all()
    others = ~first
    np.testing.assert_array_equal(
        episodes.loc[others, "com_error_rms_m"], expected.loc[others, "com_error_rms_m"]
    )
    assert episodes.loc[others, "com_error_rms_m"].notna().any()


@pytest.mark.parametrize("content", ["[1, 2]", '{"name": "x"}'])
def test_a_sweep_record_of_another_shape_is_left_out_with_a_note(results, tmp_path, content):
    """A sweep.json that is JSON but no sweep record was dropped without a word."""
    import shutil

    from reports.build import read_results

    root = tmp_path / "copy"
    shutil.copytree(results[0], root)
    (root / "sweep.json").write_text(content)
    episodes, record, notes = read_results(root)
    assert record is None
    assert notes == ["sweep.json: not a sweep record (no 'spec' table)"]
    assert len(episodes) == len(list((root / "episodes").glob("*.parquet")))
