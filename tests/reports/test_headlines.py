"""The report's headline tables (`reports.headlines`) on a hand-made fixture: the papers'
benchmarks set our numbers beside the paper's figure for the same motion and method, and
n/a rows for the controllers that cannot run one; the cost table's ratio to the engine."""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd
import pytest

from bench.dataset import ResultStore
from reports import headlines
from reports.build import build_report
from reports.statistics import fraction_cell
from tests.reports.rows import result_row


def _row(**values) -> dict:
    row = result_row(mass_kg=58.0)
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
    # ... 3.1 cm from the target at the end: the test's 2 cm missed
    assert _value(table, reach, "Test 1", "hand error", "outcome") == (
        "completed, hand off its target"
    )
    # the perturbed episode stays out
    assert not ((table["controller"] == preview) & (table["sim"] == "pybullet")).any()


def test_reaches_without_a_hand_task_or_after_a_fall_give_no_hand_error():
    """A controller that drives no hand stands ~0.9 m from the target, and a fall's hand
    distance is taken as the robot topples: neither is a reaching result beside the paper's."""
    rows = [
        _row(
            controller="hold+posture",
            planner="hold",
            sim="mujoco",
            scenario="reach",
            status="ok",
            hand_error_final_m=0.896,
            hand_task=False,
        ),
        _row(
            controller="capturability_hierarchy",
            planner="capturability_hierarchy",
            sim="mujoco",
            scenario="reach_push",
            status="fell",
            fell=True,
            fall_time=5.3,
            hand_error_final_m=0.33,
            hand_task=True,
        ),
    ]
    table = headlines.paper_benchmarks(pd.DataFrame(rows))
    hold = _value(table, "hold+posture", "Test 1", "hand error", "outcome")
    assert hold == "completed, no hand task"
    assert math.isnan(_value(table, "hold+posture", "Test 1", "hand error", "ours"))
    fell = "capturability_hierarchy"
    assert _value(table, fell, "Test 2", "hand error", "outcome") == "fell at 5.3 s"
    assert math.isnan(_value(table, fell, "Test 2", "hand error", "ours"))


def test_cost_is_the_control_time_in_engine_steps_of_the_same_run(episodes):
    table = headlines.cost_table(episodes).set_index(["controller", "sim"])
    for key, (control, engine) in WALKS.items():
        assert table.loc[key, "control median µs"] == control
        assert table.loc[key, "control p99 µs"] == 2 * control
        assert table.loc[key, "control / engine"] == pytest.approx(control / engine)
        assert table.loc[key, "from"] == "walk"


def test_a_controller_without_a_walk_is_costed_from_its_other_episodes():
    """Sherikov et al.'s hierarchy has no walk in the main job: its cost per period comes
    from its reaching tests and pushes (the median over them), named in `from`, instead of
    its leaving the table (it was the one controller slower than real time, and unseen)."""
    rows = [_walk("a+x", "mujoco", 300.0, 40.0)]
    for scenario, control in (("reach", 2500.0), ("stand_push", 2300.0), ("reach_push", 2700.0)):
        row = _walk("hier", "mujoco", control, 40.0)
        row.update(scenario=scenario, episode_id=f"hier-{scenario}")
        rows.append(row)
    table = headlines.cost_table(pd.DataFrame(rows)).set_index(["controller", "sim"])
    assert table.loc[("hier", "mujoco"), "control median µs"] == 2500.0
    assert table.loc[("hier", "mujoco"), "from"] == "reach, reach_push, stand_push"
    assert table.loc[("a+x", "mujoco"), "from"] == "walk"


def _walking_push(controller, sim, control, engine, index, timed_from_s) -> dict:
    """A walking-push row of `_walk`'s kind (push `index`; `timed_from_s` the runner's)."""
    row = _walk(controller, sim, control, engine)
    row.update(
        scenario="walk_push",
        push_phase="walking",
        push_time_s=3.1,
        timed_from_s=timed_from_s,
        episode_id=f"p{index}",
    )
    return row


def test_cost_is_the_median_over_the_walks_with_its_interval():
    """The cost of a controller is the median over its walks, pushed or not (21 in the main
    job: the same code every period), with the order statistics' 95 % interval: for 21
    episodes the 6th and the 16th of the sorted episode medians; n counts them. A walking
    push counts when it timed its own periods (a branch, from just after the push on:
    `timed_from_s`)."""
    rows = [_walk("a+x", "mujoco", 300.0, 40.0)]
    for index in range(20):
        rows.append(_walking_push("a+x", "mujoco", 310.0 + 10.0 * index, 40.0, index, 3.11))
    table = headlines.cost_table(pd.DataFrame(rows)).set_index(["controller", "sim"])
    row = table.loc[("a+x", "mujoco")]
    # the sorted medians: 300, 310, ..., 500; median 400; 6th = 350, 16th = 450
    assert row["control median µs"] == 400.0
    assert row["95 % interval"] == "350-450"
    assert row["n"] == 21
    assert row["from"] == "walk, walk_push"
    # one walk alone has no interval
    alone = headlines.cost_table(pd.DataFrame(rows[:1])).iloc[0]
    assert (alone["95 % interval"], alone["n"]) == ("–", 1)


def test_cost_in_engine_steps_is_each_runs_ratio_so_a_slower_machine_leaves_it():
    """control / engine is the median over the runs of each run's control median over its
    engine median, with its interval: 21 walks on a machine whose speed drifts by up to 2x
    from run to run (control and engine slower together) have a wide interval in µs and the
    same 7.5 engine steps in every run."""
    rows = [_walk("a+x", "mujoco", 300.0, 40.0)]
    for index in range(1, 21):
        slower = 1.0 + index / 20.0  # up to 2x
        rows.append(_walking_push("a+x", "mujoco", 300 * slower, 40 * slower, index, 3.11))
    row = headlines.cost_table(pd.DataFrame(rows)).set_index(["controller", "sim"]).iloc[0]
    assert row["95 % interval"] == "375-525"  # 300 x 1.25 and 300 x 1.75: the 6th and 16th
    assert row["control / engine"] == pytest.approx(7.5)
    assert row["control / engine 95 %"] == "7.50-7.50"


def test_copies_of_one_run_count_once_in_the_cost():
    """A walking-push group that fell before its push is one run copied into 20 rows
    (`timed_from_s` None): one timing, not 20 (20 equal medians made a 0-wide interval)."""
    rows = [_walk("a+x", "mujoco", 300.0, 40.0)]
    for index in range(20):
        rows.append(_walking_push("a+x", "mujoco", 500.0, 40.0, index, None))
    row = headlines.cost_table(pd.DataFrame(rows)).iloc[0]
    assert row["n"] == 2
    assert row["95 % interval"] == "–"
    assert row["control median µs"] == 400.0  # the median of 300 and 500


def _push(controller, sim, phase, index, alive) -> dict:
    row = _row(
        controller=controller,
        sim=sim,
        scenario="stand_push" if phase == "standing" else "walk_push",
        push_phase=phase,
        push_dv_mps=0.3,
        push_index=index,
        push_impulse_Ns=17.5,
        status="ok" if alive else "fell",
        fell=not alive,
        survived=alive,
    )
    row["episode_id"] += f"-{index}"
    return row


def test_the_report_of_a_main_job_opens_with_every_headline_table(tmp_path: Path):
    """A small main job (two controllers, both simulators: walks, standing and walking
    pushes, motions, a reach, the speed search): the report opens with the five headline
    tables, in order, each with its rows."""
    rows = [*ROWS[:4]]
    for controller in ("a+x", "b+y"):
        for sim in ("mujoco", "pybullet"):
            rows.append(_walk(controller, sim, 300.0, 40.0))
            for phase in ("standing", "walking"):
                survived = 1 if (controller, sim, phase) == ("b+y", "pybullet", "standing") else 3
                rows += [_push(controller, sim, phase, k, k < survived) for k in range(4)]
    store = ResultStore(tmp_path / "results")
    store.prepare({"name": "fixture"}, "digest", resume=False, overwrite=False)
    for row in rows:
        store.write(row, None)
    speed = [
        {"controller": c, "sim": s, "speed_command_mps": 0.1, "status": "ok", "e_com": 0.1}
        for c in ("a+x", "b+y")
        for s in ("mujoco", "pybullet")
    ]
    pd.DataFrame(speed).to_parquet(tmp_path / "results" / "speed.parquet")
    paths = build_report(tmp_path / "results", tmp_path / "report")
    markdown = (tmp_path / "report" / "report.md").read_text()
    sections = markdown.split("\n## ")[1:]
    titles = [section.splitlines()[0] for section in sections]
    # one level per phase: §1 is the whole push table, not repeated per level, and one
    # level is no curve of survival against dv
    assert not any(title.startswith("Push survival") for title in titles)
    assert "survival.png" not in {path.name for path in paths}
    assert titles[:5] == [
        "1. Which pushes each controller survives",
        "2. How fast each controller walks (Ficht & Behnke Table 1)",
        "3. The papers' own benchmarks",
        "4. What each controller costs per control period",
        "5. Where MuJoCo and PyBullet disagree",
    ]

    def table_rows(section: str) -> list[list[str]]:
        lines = [line for line in section.splitlines() if line.startswith("|")][2:]
        return [[cell.strip() for cell in line.split("|")[1:-1]] for line in lines]

    survival, speeds, benchmarks, cost, agreement = (table_rows(s) for s in sections[:5])
    # 1: per controller and push phase, 3 of 4 in each simulator with its interval
    assert sorted((r[0], r[1]) for r in survival) == [
        ("a+x", "standing"),
        ("a+x", "walking"),
        ("b+y", "standing"),
        ("b+y", "walking"),
    ]
    # the one level, with the impulse the robot was given (the fixture's 0.3 m/s, 17.5 N s)
    assert {r[2] for r in survival} == {"0.3 m/s (17.5 N s)"}
    cells = {(r[0], r[1]): (r[3], r[4], r[5]) for r in survival}
    assert cells[("a+x", "standing")][:2] == (fraction_cell(3, 4), fraction_cell(3, 4))
    assert cells[("b+y", "standing")] == (fraction_cell(3, 4), fraction_cell(1, 4), "25-75")
    # 2: one row per controller and simulator
    assert sorted((r[0], r[1]) for r in speeds) == [
        ("a+x", "mujoco"),
        ("a+x", "pybullet"),
        ("b+y", "mujoco"),
        ("b+y", "pybullet"),
    ]
    # 3: the motions and the reach, with the paper's 186 µs beside ours for (B)
    assert {r[2] for r in benchmarks} == {
        "(B) handrail stairs",
        "(C) ladder",
        "Sherikov Test 1: reach",
    }
    assert any(r[2] == "(B) handrail stairs" and r[6] == "186" for r in benchmarks)
    # 4: one row per controller and simulator with a walk, the ratio to the engine; those
    # without a walk from their other episodes, which `from` names
    assert sorted((r[0], r[1], r[8]) for r in cost if r[2].startswith("walk")) == [
        ("a+x", "mujoco", "7.5"),
        ("a+x", "pybullet", "7.5"),
        ("b+y", "mujoco", "7.5"),
        ("b+y", "pybullet", "7.5"),
    ]
    assert {r[0] for r in cost if not r[2].startswith("walk")} >= {"capturability_hierarchy"}
    assert all(not r[2].startswith("walk") for r in cost if r[0] == "capturability_hierarchy")
    # 5: the push survival in both simulators, what each is from (k/n with the Wilson
    # interval: 3/4 is 30-95 %, 1/4 5-70 %), the band and MuJoCo minus PyBullet
    a_x = ["a+x", "standing push survival", "%", "75", "75", "3/4 (30-95 %)", "3/4 (30-95 %)"]
    assert [*a_x, "75 to 75", "0"] in agreement
    b_y = ["b+y", "standing push survival", "%", "75", "25", "3/4 (30-95 %)", "1/4 (5-70 %)"]
    assert [*b_y, "25 to 75", "50"] in agreement


@pytest.mark.parametrize(
    ("status", "stage", "expected"),
    [
        ("error", "planner", "planner failed at 3.9 s"),
        ("error", "whole_body", "whole-body failed at 3.9 s"),
        ("error", "sim", "error"),
        ("error", pd.NA, "error"),  # a worker's error has no stage
        ("timeout", "planner", "timeout"),
    ],
)
def test_an_episode_whose_controller_failed_says_which_stage(status, stage, expected):
    """`reports.outcomes`: an error raised by the controller's own stages is the controller's
    failure, named by its stage and when; any other error or a timeout keeps its status."""
    row = pd.Series(_row(controller="c", sim="mujoco", scenario="reach_push", status=status))
    row["error_stage"], row["duration"] = stage, 3.94
    assert headlines.outcome(row) == expected


def test_every_table_iv_row_and_the_resting_variant_are_beside_the_papers_figures():
    """Table IV has five rows (total, calculate reference, preview control, project,
    distribute: 186 / 22 / 10 / 56 / 56 µs for (B)); the report gave three, and left out our
    (B) with resting hands, which `PAPER_SCENARIO` sets beside the paper's (B)."""
    stages = dict(centroidal_control=250.0, reference=30.0, preview=12.0, projection=80.0,
                  distribution=70.0)  # fmt: skip
    rows = [
        _row(
            controller="preview_control+centroidal_feedback",
            planner="preview_control",
            sim="mujoco",
            scenario=scenario,
            status="ok",
            **{f"lat_{stage}_median_us": us for stage, us in stages.items()},
        )
        for scenario in ("handrail_stairs", "handrail_stairs_resting")
    ]
    table = headlines.paper_benchmarks(pd.DataFrame(rows))
    timing = table[table["quantity"].str.startswith("Table IV")]
    for benchmark in ("(B) handrail stairs", "(B) handrail stairs, hands resting (ours)"):
        mine = timing[timing["benchmark"] == benchmark]
        assert list(mine["ours"]) == [250.0, 30.0, 12.0, 80.0, 70.0]
        assert list(mine["paper"]) == [186.0, 22.0, 10.0, 56.0, 56.0]
    resting = table[table["benchmark"].str.contains("resting")]
    desired = resting[resting["quantity"].str.contains("desired projection error, force")]
    assert list(desired["paper"]) == [3.7]  # Sec. V-G's (B), preview control
