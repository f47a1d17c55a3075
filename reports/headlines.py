"""The report's opening (issue 22): one table per question a user asks of a comparison, each
from the nominal episodes (`reports.robustness.nominal`):

1. which pushes each controller survives, standing and walking (`robustness.headline_survival`);
2. how fast each walks (Ficht & Behnke Table 1, `tables.speed_table`, from `centrobench speed`);
3. how each does on the papers' own benchmarks (`paper_benchmarks`: Murooka et al.'s Table IV
   and Sec. V-G on the motions of Fig. 4 (A)-(C), Sherikov et al.'s reaching Tests 1-2);
4. what each costs per control period (`cost_table`);
5. where the two simulators disagree (`tables.agreement_table`).
"""

from __future__ import annotations

import math

import pandas as pd

from reports.outcomes import failure_label, is_controller_failure
from reports.paper_figures import (
    MOTION_LABELS,
    PAPER_SCENARIO,
    PAPER_SEC_V_G,
    PAPER_TABLE_IV_US,
    VARIANT_LABELS,
)
from reports.robustness import nominal
from reports.statistics import median_interval
from reports.tables import (
    REACH_PASS_HAND_ERROR_M,
    drives_hand,
    independently_timed,
    interval_cell,
    timed_walks,
)

KEYS = ["controller", "sim"]
REACH_LABELS = {
    "reach": "Sherikov Test 1: reach",
    "reach_push": "Sherikov Test 2: reach with pushes",
}
"""Sherikov, Dimitrov & Wieber 2014, Sec. VII-B/C, by scenario."""

TABLE_IV_ROWS = (
    ("centroidal_control", "Table IV total control [µs], median"),
    ("reference", "Table IV calculate reference [µs], median"),
    ("preview", "Table IV preview control [µs], median"),
    ("projection", "Table IV project planned wrench [µs], median"),
    ("distribution", "Table IV distribute desired wrench [µs], median"),
)
SEC_V_G_ROWS = (
    ("planned_force_N", "Sec. V-G planned projection error, force [N], mean"),
    ("planned_moment_Nm", "Sec. V-G planned projection error, moment [N m], mean"),
    ("desired_force_N", "Sec. V-G desired projection error, force [N], mean"),
    ("desired_moment_Nm", "Sec. V-G desired projection error, moment [N m], mean"),
)
BENCHMARK_COLUMNS = [*KEYS, "benchmark", "outcome", "quantity", "ours", "paper"]


def outcome(row: pd.Series) -> str:
    """How an episode ended, in words: completed, fell at t s, its controller's failure
    ("planner failed at t s", `reports.outcomes`), or its status (n/a, error, timeout)."""
    if row["status"] == "ok":
        return "completed"
    if row["status"] == "fell":
        fall = row.get("fall_time")
        return "fell" if fall is None or pd.isna(fall) else f"fell at {float(fall):.1f} s"
    if is_controller_failure(row["status"], row.get("error_stage")):
        return failure_label(row.get("error_stage"), row.get("duration"))
    return str(row["status"])


def paper_benchmarks(episodes: pd.DataFrame) -> pd.DataFrame:
    """Per controller x simulator x benchmark (the motions (A)-(C), the reaching tests), how
    its episode ended and, where it ran, our number beside the paper's: Table IV's stage
    times of the centroidal control [µs] (the paper's are for its own preview control, on an
    i7-9750H in C++), Sec. V-G's projection errors (for preview control and the linear MPC on
    (B) and (C)), the final hand error of a reach [cm] (passed: ended within
    `tables.REACH_PASS_HAND_ERROR_M` of the target; the paper prints no number). A controller
    that cannot run a benchmark has its "n/a" row, without numbers; one that fell has the
    motions' numbers up to its fall, and no hand error (the hand's distance when the fall was
    detected); one whose planner drives no hand (`drives_hand`) has its reach outcome marked
    "no hand task" and no hand error."""
    rows = nominal(episodes)
    benchmarks = [*MOTION_LABELS, *VARIANT_LABELS, *REACH_LABELS]
    rows = rows[rows["scenario"].isin(benchmarks) & rows["push_phase"].isna()]
    result = []
    for _, row in rows.sort_values([*KEYS, "scenario"]).iterrows():
        scenario, planner = row["scenario"], row.get("planner")
        base = {
            "controller": row["controller"],
            "sim": row["sim"],
            "benchmark": (
                MOTION_LABELS.get(scenario)
                or VARIANT_LABELS.get(scenario)
                or REACH_LABELS[scenario]
            ),
            "outcome": outcome(row),
        }
        if row["status"] not in ("ok", "fell"):
            result.append({**base, "quantity": "", "ours": math.nan, "paper": math.nan})
            continue
        if scenario in REACH_LABELS:
            ours = 100.0 * _number(row.get("hand_error_final_m"))
            if not drives_hand(row):
                base["outcome"] += ", no hand task"  # its hand error is where the hand stayed
                ours = math.nan
            elif row["status"] == "fell":
                ours = math.nan  # where the hand was when the fall was detected says nothing
            elif row["status"] == "ok" and math.isnan(ours):
                base["outcome"] = "completed, hand error not recorded"
            elif row["status"] == "ok":  # the paper's test: the hand at its target at the end
                passed = ours < 100.0 * REACH_PASS_HAND_ERROR_M
                base["outcome"] = "passed" if passed else "completed, hand off its target"
            quantity = "final hand error [cm]"
            result.append({**base, "quantity": quantity, "ours": ours, "paper": math.nan})
            continue
        paper_scenario = PAPER_SCENARIO.get(scenario, scenario)  # a variant: the paper's motion
        table_iv = PAPER_TABLE_IV_US[paper_scenario] if planner == "preview_control" else {}
        for stage, label in TABLE_IV_ROWS:
            ours = _number(row.get(f"lat_{stage}_median_us"))
            paper = table_iv.get(stage, math.nan)
            result.append({**base, "quantity": label, "ours": ours, "paper": paper})
        sec_v_g = PAPER_SEC_V_G.get((paper_scenario, planner), {})
        for column, label in SEC_V_G_ROWS:
            ours = _number(row.get(column))
            paper = sec_v_g.get(column, math.nan)
            result.append({**base, "quantity": label, "ours": ours, "paper": paper})
    return pd.DataFrame(result, columns=BENCHMARK_COLUMNS)


def cost_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Per controller x simulator, from its walks (`tables.timed_walks`: the nominal walk and
    the walking pushes, each pushed one from just after its push on): the control time per period
    (estimator, planner, stabilizer, whole-body layer) [µs], the median over the runs of each
    run's median, with its distribution-free 95 % interval (`statistics.median_interval`,
    empty under 6 runs) and the runs' count `n`; the median of their p99; the simulator
    engine's own step for the same periods (`sim_engine`, the median over the runs [µs]); the
    control's cost in engine steps: each run's control median over its engine median (the two
    measured side by side, in the same periods, so that a machine slower or faster for the
    whole run leaves it unchanged), the median over the runs with its 95 % interval; and each
    stage's median [µs]. In the main job 20 of the 21 runs are the branches
    of one group, run one after the other in one worker: the interval says how the timing
    varies from run to run over those minutes, not over the whole sweep or on another
    machine. A controller without a walk (Sherikov et al.'s hierarchy, in the main job) is
    given from its other nominal episodes; `from` names the scenarios of a row's runs."""
    everything = nominal(episodes)
    rows = timed_walks(everything)
    missing = ~everything.set_index(KEYS).index.isin(rows.set_index(KEYS).index)
    others = independently_timed(everything[missing])
    rows = pd.concat(
        [
            rows.assign(**{"from": rows["scenario"].astype(str)}),
            others.assign(**{"from": others["scenario"].astype(str)}),
        ]
    )
    columns = {
        "control median µs": "lat_control_total_median_us",
        "control p99 µs": "lat_control_total_p99_us",
        "engine median µs": "lat_sim_engine_median_us",
        "estimator µs": "lat_estimator_median_us",
        "planner µs": "lat_planner_median_us",
        "stabilizer µs": "lat_stabilizer_median_us",
        "whole-body µs": "lat_whole_body_median_us",
    }
    rows = rows.reindex(columns=[*KEYS, "from", *columns.values()])
    rows["ratio"] = rows["lat_control_total_median_us"] / rows["lat_sim_engine_median_us"]
    groups = rows.groupby(KEYS, sort=True)
    table = groups[list(columns.values())].median()
    table.columns = list(columns)
    control = groups["lat_control_total_median_us"]
    intervals = control.agg(median_interval)
    table.insert(1, "95 % interval", [interval_cell(*interval) for interval in intervals])
    table.insert(2, "n", control.count())
    ratio = groups["ratio"]
    table.insert(5, "control / engine", ratio.median())
    table.insert(
        6,
        "control / engine 95 %",
        [interval_cell(*interval, digits=2) for interval in ratio.agg(median_interval)],
    )
    sources = groups["from"].agg(lambda s: ", ".join(sorted(set(s))))
    table.insert(0, "from", sources)
    return table.reset_index()


def _number(value) -> float:
    return math.nan if value is None or pd.isna(value) else float(value)
