"""The report's tables, in the papers' shapes, computed from a sweep's episode rows
(`bench.dataset.ROW_SCHEMA`). Each function returns a pandas DataFrame with plain columns
(no index), rows ordered by controller then simulator.

Episodes are grouped as follows: "walks" are the rows of scenario `walk` without a push (the
walking quality, latency and projection tables); "pushes" are the rows with a `push_phase`
(the survival table). Where a group has several episodes (several seeds), a table reports
the median over them (the mean for the projection errors, which are means already).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import pandas as pd

from reports.outcomes import (
    ENDED,
    ended_before_push,
    is_controller_failure,
    judged,
    judged_push,
    refusal_reason,
)
from reports.robustness import nominal, protocol_pushes
from reports.statistics import (
    fraction_cell,
    median_interval,
    simulator_band,
    wilson_interval,
)

KEYS = ["controller", "sim"]
TABLE_IV_STAGES = (
    "centroidal_control",  # Table IV's "Total control" (planner + stabilizer)
    "reference",
    "preview",
    "projection",
    "distribution",
    "centroidal_total",  # the sum of the four rows above
)
LOOP_STAGES = ("planner", "stabilizer", "whole_body", "control_total")
PROJECTION_COLUMNS = (
    "planned_force_N",
    "planned_moment_Nm",
    "desired_force_N",
    "desired_moment_Nm",
    "feedback_force_N",
    "feedback_moment_Nm",
)


def walks(episodes: pd.DataFrame) -> pd.DataFrame:
    """The nominal walks (`reports.robustness.nominal`): scenario walk without a push."""
    rows = nominal(episodes)
    return rows[(rows["scenario"] == "walk") & rows["push_phase"].isna()]


TIMED_WALKS = ("walk", "walk_push")
"""The scenarios a controller's cost per period is taken from (`timed_walks`)."""


BRANCHED_SCENARIOS = ("stand_push", "walk_push")
"""bench.branching.BRANCHED_SCENARIOS (reports/ imports nothing of bench/; a test checks that
the two agree): the pushed episodes a sweep runs as one group, forked at the push."""
PUSH_TIMING_DELAY_PERIODS = 5
"""bench.branching.PUSH_TIMING_DELAY_PERIODS (the same test checks it): a pushed episode is
timed from this many control periods after the one its push is applied in."""
SHARED_RUN_KEYS = (
    "controller",
    "sim",
    "robot",
    "scenario",
    "seed",
    "replica",
    "perturbation",
    "push_time_s",
    "push_step",
    "push_swing_fraction",
    "speed",
    "friction",
    "scale",
    "estimator",
    "whole_body",
    "git_commit",
    "results_dir",
)
"""The row columns that the episodes of one branched group share (`bench.branching.branch_key`:
everything but the push's impulse and direction), and the run's commit and result directory.
Rows that agree on all of them may still be two runs (a group holds at most 20 episodes):
counting them as one errs towards fewer runs."""


def independently_timed(rows: pd.DataFrame) -> pd.DataFrame:
    """The rows whose timings (`lat_*`) are separate measurements: a plain episode, and a
    protocol push's, timed from just after its push on (`timed_from_s`, the runner's: in a
    branched group the periods before are shared); of the pushed episodes that ended before
    their push (`timed_from_s` None: in a group, copies of one run) and of pushed rows written
    before `timed_from_s` (2026-11-28: each branch held the group's periods as well as its
    own), one per group (`SHARED_RUN_KEYS`)."""
    timed = rows["timed_from_s"] if "timed_from_s" in rows else pd.Series(math.nan, rows.index)
    shared = rows["scenario"].isin(BRANCHED_SCENARIOS) & timed.isna()
    keys = [k for k in SHARED_RUN_KEYS if k in rows.columns]
    first = ~rows.loc[shared, keys].duplicated()  # NaN equals NaN here
    return pd.concat([rows[~shared], rows[shared][first]]).sort_index()


def timed_walks(episodes: pd.DataFrame) -> pd.DataFrame:
    """The nominal walks, pushed or not (scenarios `TIMED_WALKS`), each a separate timing
    (`independently_timed`): the episodes a controller's time per period is the median over
    (the same code every period; in the main job the walk and the 20 walking pushes, timed
    from just after their push on, whether they fell after it or not)."""
    rows = nominal(episodes)
    return independently_timed(rows[rows["scenario"].isin(TIMED_WALKS)])


def interval_cell(low: float, high: float, digits: int = 0) -> str:
    """ "low-high" with `digits` decimals (none: µs), "–" when there is no interval."""
    return "–" if math.isnan(low) else f"{low:.{digits}f}-{high:.{digits}f}"


def pushes(episodes: pd.DataFrame, phase: str) -> pd.DataFrame:
    """The pushes of the protocol in `phase` (`reports.robustness.protocol_pushes`)."""
    return protocol_pushes(episodes, phase)


def latency_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Murooka Table IV's rows (and the loop's stages) per controller x simulator, from the
    walks: median and p99 [µs] of each stage over the episode's control periods."""
    columns = []
    for stage in (*TABLE_IV_STAGES, *LOOP_STAGES):
        columns += [f"lat_{stage}_median_us", f"lat_{stage}_p99_us"]
    # rows of result sets written before a stage was recorded have no column for it
    table = walks(episodes).reindex(columns=[*KEYS, *columns])
    table = table.groupby(KEYS, sort=True)[columns].median().reset_index()
    table.columns = [
        c.removeprefix("lat_").replace("_median_us", " median µs").replace("_p99_us", " p99 µs")
        for c in table.columns
    ]
    return table


def projection_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Murooka Sec. V-G per controller x simulator, from the walks: mean planned projection
    error ||w^p - w^p'|| and desired projection error ||w^d - w^d'|| (force [N], moment [N m]),
    and the mean feedback wrench ||w^d - w^p'||."""
    return walks(episodes).groupby(KEYS, sort=True)[list(PROJECTION_COLUMNS)].mean().reset_index()


def level_label(dv: float, impulse: float, impulse_high: float | None = None) -> str:
    """A push level's column: dv [m/s] and the impulse J = m dv [N s] it is for the robot,
    or the range of impulses over the robots pushed (`impulse_high`, when they differ)."""
    if impulse_high is None or round(impulse_high, 1) == round(impulse, 1):
        return f"{dv:g} m/s ({impulse:.1f} N s)"
    return f"{dv:g} m/s ({impulse:.1f}-{impulse_high:.1f} N s)"


PAPER_LOOP_US = {"direct_centroidal": 143.0}
"""The papers' own per-period times [µs] of their whole control loop, by controller name
prefix: Ficht & Behnke Sec. 4, "a single passthrough of the whole control loop with computing
joint targets took on average 143 µs" (on the robot's computer, at 100 Hz)."""


def paper_latency_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Per controller x simulator with a paper figure (`PAPER_LOOP_US`), from its walks
    (`timed_walks`): the control time per period [µs] (estimator, planner, stabilizer and
    whole-body layer: the paper's "whole control loop" without the robot's I/O), the median
    over the episodes of each one's median, with its distribution-free 95 % interval and
    the episodes' count; the paper's figure, and the ratio of the median to it."""
    columns = [*KEYS, "control median µs", "95 % interval", "n", "paper µs", "ratio"]
    rows = timed_walks(episodes)
    result = []
    for (controller, sim), group in rows.groupby(KEYS, sort=True):
        paper = next((v for k, v in PAPER_LOOP_US.items() if controller.startswith(k)), None)
        if paper is None:
            continue
        values = group["lat_control_total_median_us"].dropna()
        measured = float(values.median())
        result.append(
            {
                "controller": controller,
                "sim": sim,
                "control median µs": measured,
                "95 % interval": interval_cell(*median_interval(values)),
                "n": len(values),
                "paper µs": paper,
                "ratio": measured / paper,
            }
        )
    return pd.DataFrame(result, columns=columns)


def survival_table(episodes: pd.DataFrame, phase: str = "standing") -> pd.DataFrame:
    """Ficht & Behnke Table 2: rows controller x simulator, a column per level (dv, and the
    impulse in N s: the robot's when one robot was pushed, else the range over the robots),
    cells "survived/pushes (95 % Wilson interval)" over the judged pushes
    (`reports.outcomes.judged_push`: ended "ok" or "fell", or the controller failed, which
    counts as not survived; `reports.statistics.fraction_cell`); the episodes that ended in
    another error or a timeout say nothing about the controller and are counted in their own
    column, "not judged", and those that fell before the push came in theirs, "fell before
    the push"."""
    rows = pushes(episodes, phase)
    if rows.empty:
        return pd.DataFrame(columns=KEYS)
    rates = survival_rates(episodes, phase)
    impulses = rows.groupby("push_dv_mps")["push_impulse_Ns"].agg(["min", "max"])
    counts = zip(rates["survived"], rates["pushes"], strict=True)
    cells = (
        rates.assign(cell=[fraction_cell(k, n) for k, n in counts])
        .set_index([*KEYS, "push_dv_mps"])["cell"]
        .unstack()
    )
    cells.columns = [
        level_label(dv, impulses.loc[dv, "min"], impulses.loc[dv, "max"]) for dv in cells.columns
    ]
    cells = cells.fillna("0/0")
    not_judged = (
        rows[~judged(rows)]
        .groupby(KEYS)["status"]
        .agg(lambda s: ", ".join(f"{n} {k}" for k, n in sorted(s.value_counts().items())))
    )
    cells["not judged"] = [not_judged.get(key, "") for key in cells.index]
    before = rows[ended_before_push(rows)].groupby(KEYS).size()
    cells["fell before the push"] = [int(before.get(key, 0)) or "" for key in cells.index]
    return cells.reset_index()


def level_count(episodes: pd.DataFrame, phase: str) -> int:
    """How many push levels (dv) the protocol pushes of `phase` have."""
    return int(pushes(episodes, phase)["push_dv_mps"].nunique())


def survival_rates(episodes: pd.DataFrame, phase: str = "standing") -> pd.DataFrame:
    """Long form of the survival table over the judged pushes (`reports.outcomes.judged_push`):
    controller, sim, dv, impulse, survived, pushes, rate with its 95 % Wilson interval
    (rate_low, rate_high), `not_judged` (error, timeout) and `before_push` (fell before the
    push came)."""
    rows = pushes(episodes, phase)
    counted = judged_push(rows)
    grouped = rows.assign(
        survived=rows["survived"].fillna(False).astype(bool) & counted,
        judged=counted,
        not_judged=~judged(rows),
        before_push=ended_before_push(rows),
    ).groupby([*KEYS, "push_dv_mps"], sort=True)
    table = grouped.agg(
        impulse_Ns=("push_impulse_Ns", "mean"),
        survived=("survived", "sum"),
        pushes=("judged", "sum"),
        not_judged=("not_judged", "sum"),
        before_push=("before_push", "sum"),
    ).reset_index()
    table["rate"] = table["survived"] / table["pushes"].where(table["pushes"] > 0)
    counts = zip(table["survived"], table["pushes"], strict=True)
    intervals = [wilson_interval(k, n) for k, n in counts]
    table["rate_low"] = [low for low, _ in intervals]
    table["rate_high"] = [high for _, high in intervals]
    return table


def walking_quality_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Ficht & Behnke Table 1's walking quality (eq. 18) per controller x simulator, from
    the walks: status, forward speed of the plan, e_c [m s], e_z [m s], e_v [m/s], the CoM
    tracking error (RMS of ||c - c^p|| [mm]), where the feet landed against the plan's
    footsteps (the mean touchdown time error [ms], negative when early, and the mean
    horizontal touchdown position error [mm]) and how far from the gait command's goal the
    walk ended [cm]; medians over a cell's walks that did not fall (`walks ok`: how many of
    the cell's walks, "k/n"; a fall's errors measure the fall, as in `agreement_table`: until
    2026-12-03 this table took the falls in and the two disagreed)."""
    rows = walks(episodes)
    everything = rows.groupby(KEYS, sort=True).agg(
        status=("status", lambda s: ",".join(sorted(set(s)))),
        walks=("status", "size"),
        ok=("status", lambda s: int((s == "ok").sum())),
    )
    table = (
        rows[rows["status"] == "ok"]
        .groupby(KEYS, sort=True)
        .agg(
            walk_speed_mps=("walk_speed_mps", "median"),
            e_com=("e_com", "median"),
            e_zmp=("e_zmp", "median"),
            e_velocity=("e_velocity", "median"),
            com_error_rms_mm=("com_error_rms_m", lambda s: 1e3 * s.median()),
            touchdown_time_error_mean_ms=(
                "touchdown_time_error_mean_s",
                lambda s: 1e3 * s.median(),
            ),
            touchdown_position_error_mean_mm=(
                "touchdown_position_error_mean_m",
                lambda s: 1e3 * s.median(),
            ),
            goal_error_cm=("final_position_error_m", lambda s: 1e2 * s.median()),
        )
        .reindex(everything.index)
    )
    walked = [f"{k}/{n}" for k, n in zip(everything["ok"], everything["walks"], strict=True)]
    table.insert(0, "walks ok", walked)
    table.insert(0, "status", everything["status"])
    return table.reset_index()


AGREEMENT_QUANTITIES = (
    ("standing push survival", "%"),
    ("walking push survival", "%"),
    ("walk CoM tracking RMS", "mm"),
    ("walk e_com (eq. 18)", "m s"),
    ("walk e_zmp (eq. 18)", "m s"),
    ("walk e_velocity (eq. 18)", "m/s"),
)
"""The headline numbers `agreement_table` gives per simulator with their band: (name, unit).
Only what the simulator decides: not the control time (the controller's code, timed on the
machine) nor the planned projection error (a property of the plan before any contact)."""


def _headline_numbers(
    episodes: pd.DataFrame,
) -> tuple[dict[str, pd.Series], dict[str, pd.Series]]:
    """Each of `AGREEMENT_QUANTITIES` as a Series indexed by (controller, sim), and what each
    value is from, as printed: "k/n (95 % Wilson)" for a survival rate, "n walks" for a
    walk's median."""
    numbers, counts = {}, {}
    for phase in ("standing", "walking"):
        rates = survival_rates(episodes, phase)
        totals = rates.groupby(KEYS)[["survived", "pushes"]].sum()
        quantity = f"{phase} push survival"
        numbers[quantity] = 100.0 * totals["survived"] / totals["pushes"]
        counts[quantity] = pd.Series(
            [
                fraction_cell(int(k), int(n))
                for k, n in zip(totals["survived"], totals["pushes"], strict=True)
            ],
            index=totals.index,
            dtype=object,
        )
    completed = walks(episodes)
    # a walk that fell: its errors measure the fall, not the tracking (eq. 18's are not given)
    walked = completed[completed["status"] == "ok"].groupby(KEYS)
    walk_counts = walked.size().map(lambda n: f"{n} walk{'s' if n != 1 else ''}")
    numbers["walk CoM tracking RMS"] = 1e3 * walked["com_error_rms_m"].median()
    for name in ("e_com", "e_zmp", "e_velocity"):
        numbers[f"walk {name} (eq. 18)"] = walked[name].median()
    for quantity in list(numbers)[2:]:
        counts[quantity] = walk_counts
    return numbers, counts


def agreement_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Where the simulators disagree: every headline number that the simulator decides
    (`AGREEMENT_QUANTITIES`: push survival over all of the protocol's levels, standing and
    walking [%]; the nominal walk's CoM tracking error [mm] and eq. 18 errors, from walks
    that did not fall) per controller in each simulator, the band between the simulators
    (`band`: "low to high", `reports.statistics.simulator_band`) and MuJoCo minus PyBullet;
    "<sim> from" says what each value is from (a rate's k/n with its 95 % Wilson interval,
    a median's number of walks: a difference inside the intervals is no disagreement).
    Rows: controller x quantity, for the quantities measured in at least one simulator."""
    columns = _AGREEMENT_COLUMNS.union(episodes.columns)
    numbers, counts = _headline_numbers(episodes.reindex(columns=columns))
    sims = sorted(set(episodes["sim"]))
    rows = []
    for controller in sorted(set(episodes["controller"])):
        for quantity, unit in AGREEMENT_QUANTITIES:
            series = numbers[quantity]
            values = {sim: float(series.get((controller, sim), math.nan)) for sim in sims}
            if not any(math.isfinite(v) for v in values.values()):
                continue
            low, high = simulator_band(values)
            basis = {
                f"{sim} from": counts[quantity].get((controller, sim), "")
                if math.isfinite(values[sim])
                else ""
                for sim in sims
            }
            rows.append(
                {
                    "controller": controller,
                    "quantity": quantity,
                    "unit": unit,
                    **values,
                    **basis,
                    "band": f"{low:.3g} to {high:.3g}",
                    "mujoco - pybullet": values.get("mujoco", math.nan)
                    - values.get("pybullet", math.nan),
                }
            )
    sources = [f"{sim} from" for sim in sims]
    return pd.DataFrame(
        rows,
        columns=["controller", "quantity", "unit", *sims, *sources, "band", "mujoco - pybullet"],
    )


_AGREEMENT_COLUMNS = pd.Index(["com_error_rms_m", "e_com", "e_zmp", "e_velocity"])
"""The row columns `_headline_numbers` reads (absent from result sets written before them)."""


def status_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Episodes per controller x simulator by status (ok, fell, error)."""
    table = episodes.groupby([*KEYS, "status"]).size().unstack("status", fill_value=0)
    return table.reset_index()


def refusal_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """The "n/a" rows (never run: the controller cannot run the scenario) per controller x
    reason: the scenarios and simulators concerned and how many episodes; empty without any.
    The push and threshold tables leave these rows out (`reports.outcomes.ran`)."""
    rows = episodes[episodes["status"] == "n/a"]
    if rows.empty:
        return pd.DataFrame(columns=["controller", "reason", "scenarios", "sims", "episodes"])
    error = rows["error"] if "error" in rows else pd.Series(None, index=rows.index)
    rows = rows.assign(reason=[refusal_reason(e) or "?" for e in error])
    table = (
        rows.groupby(["controller", "reason"], sort=True)
        .agg(
            scenarios=("scenario", lambda s: ", ".join(sorted(set(s)))),
            sims=("sim", lambda s: ", ".join(sorted(set(s)))),
            episodes=("status", "size"),
        )
        .reset_index()
    )
    return table


def benchmark_table(benchmark: dict) -> pd.DataFrame:
    """A pytest-benchmark JSON document as a table: name, median, mean, stddev, min [µs], rounds."""
    rows = []
    for entry in benchmark.get("benchmarks", []):
        stats = entry["stats"]
        rows.append(
            {
                "benchmark": entry.get("fullname", entry["name"]),
                "median µs": 1e6 * stats["median"],
                "mean µs": 1e6 * stats["mean"],
                "stddev µs": 1e6 * stats["stddev"],
                "min µs": 1e6 * stats["min"],
                "rounds": stats["rounds"],
            }
        )
    return pd.DataFrame(rows)


def _statuses_cell(statuses: pd.Series) -> str:
    """How some episodes ended: "fell" when all alike and one, else "2 fell, 1 timeout"."""
    counts = statuses.value_counts().sort_index()
    if len(statuses) == 1:
        return str(statuses.iloc[0])
    return ", ".join(f"{n} {status}" for status, n in counts.items())


def speed_table(trials: pd.DataFrame) -> pd.DataFrame:
    """Table 1's shape per controller x simulator: the highest commanded speed walked [m/s]
    (NaN: none), the lowest speed tried above it, which was not walked (`v_fell_mps`, NaN:
    none; the answer lies between the two), the mean speed walked there over the steady steps
    [m/s], e_c [m s], e_z [m s], e_v [m/s] of eq. 18 there, and how many walks the search
    took. With replicas (`replica`, `replicas_required` from `centrobench speed --replicas`)
    a speed is walked when at least the required replicas walked it, the quality is that of
    the first replica that walked it (replica 0, unless it fell), and two more columns say how
    sure the answer is: "at v_ref", the replicas that walked the speed found, and "above",
    those that walked the lowest speed tried above it ("k/n"). "v_fell ended" says how the
    walks at v_fell ended ("fell"; a "timeout" or "error" there says nothing of the
    controller, and the speed found is then a lower bound set by the machine)."""
    columns = [
        *KEYS,
        "v_ref_mps",
        "v_fell_mps",
        "v_fell ended",
        "v_mps",
        "e_c",
        "e_z",
        "e_v",
        "walks",
    ]
    replicated = "replica" in trials.columns and trials["replica"].fillna(0).max() > 0
    if replicated:
        columns += ["at v_ref", "above"]
    if trials.empty:
        return pd.DataFrame(columns=columns)
    result = []
    for (controller, sim), group in trials.groupby(KEYS, sort=True):
        replica = group["replica"].fillna(0) if "replica" in group else pd.Series(0, group.index)
        required = (
            group["replicas_required"].fillna(1)
            if "replicas_required" in group
            else pd.Series(1, group.index)
        )
        by_speed = {
            speed: (int((runs["status"] == "ok").sum()), len(runs), int(required[runs.index].max()))
            for speed, runs in group.groupby("speed_command_mps", sort=True)
        }
        walked_speeds = [speed for speed, (ok, _, need) in by_speed.items() if ok >= need]
        row = {"controller": controller, "sim": sim, "walks": len(group)}
        if not walked_speeds:
            row.update(v_ref_mps=math.nan, v_mps=math.nan, e_c=math.nan, e_z=math.nan, e_v=math.nan)
        else:
            v_ref = max(walked_speeds)
            at_v_ref = group[group["speed_command_mps"] == v_ref].assign(replica=replica)
            walked_there = at_v_ref[at_v_ref["status"] == "ok"].sort_values("replica")
            first = walked_there.iloc[0]  # replica 0's walk, or the first replica that walked
            row.update(
                v_ref_mps=v_ref,
                v_mps=first.get("speed_walked_mps"),
                e_c=first.get("e_com"),
                e_z=first.get("e_zmp"),
                e_v=first.get("e_velocity"),
            )
        v_ref = row["v_ref_mps"]
        above = [speed for speed in by_speed if math.isnan(v_ref) or speed > v_ref]
        row["v_fell_mps"] = min(above) if above else math.nan
        row["v_fell ended"] = (
            _statuses_cell(group.loc[group["speed_command_mps"] == min(above), "status"])
            if above
            else ""
        )
        if replicated:
            at = by_speed.get(v_ref)
            row["at v_ref"] = f"{at[0]}/{at[1]}" if at else "–"
            row["above"] = f"{by_speed[min(above)][0]}/{by_speed[min(above)][1]}" if above else "–"
        result.append(row)
    return pd.DataFrame(result, columns=columns)


REACH_SCENARIOS = ("reach", "reach_push")
REACH_PASS_HAND_ERROR_M = 0.02
"""bench.scenarios.REACH_PASS_HAND_ERROR_M (reports/ imports nothing of bench/; a test checks
that the two agree): a reach is passed with no fall and a final hand error under this [m]."""
REACH_PUSH_TIMES_S = (2.5, 7.0)
"""The times [s] of `reach_push`'s pushes (bench.scenarios.REACH_PUSHES; a test checks)."""
SOLVE_STATS = ("mean", "p99", "max")


def reaches(episodes: pd.DataFrame) -> pd.DataFrame:
    """The rows of Sherikov et al. 2014's Tests 1 and 2 (scenarios `reach`, `reach_push`)."""
    rows = nominal(episodes)
    return rows[rows["scenario"].isin(REACH_SCENARIOS)]


HAND_PLANNERS = ("capturability_hierarchy",)
"""The planners that drove a hand before rows recorded `hand_task` (2026-11-28)."""


def drives_hand(row: pd.Series) -> bool:
    """Whether the episode's planner drove the hand to the reach's targets: the row's
    `hand_task` (`Planner.tracks_hand_targets`); for rows written before it was recorded,
    whether the planner is one of `HAND_PLANNERS`."""
    value = row.get("hand_task")
    if value is None or pd.isna(value):
        return row.get("planner") in HAND_PLANNERS
    return bool(value)


def solve_time_stats(trace: pd.DataFrame, column: str = "t_hierarchy_us") -> dict[str, float]:
    """Mean, p99 and max [µs] of a trace's per-period times in `column` (NaN periods left
    out, as the runner's `latency_us` summary does); empty when there are none."""
    if column not in trace.columns:
        return {}
    values = trace[column].to_numpy(dtype=float)
    values = values[~np.isnan(values)]
    if not len(values):
        return {}
    return {
        "mean": float(values.mean()),
        "p99": float(np.percentile(values, 99)),
        "max": float(values.max()),
    }


def reach_table(
    episodes: pd.DataFrame, solve_times: Mapping[str, Mapping[str, float]] | None = None
) -> pd.DataFrame:
    """Sherikov et al. 2014's Tests 1-2, one row per `reach` / `reach_push` episode: status,
    final hand error [cm] (only for an episode that ended ok with a planner that drives the
    hand, `drives_hand`), steps taken, pass (status ok and a final hand error under
    `REACH_PASS_HAND_ERROR_M`: "yes" / "no"; "n/a (no hand task)"; "not judged" after a
    timeout or an error that is not the controller's, `reports.outcomes`; "n/a (not run)")
    and the hierarchy's solve
    time per period [ms] (mean, p99, max). Solve times come from `solve_times` (episode id ->
    {mean, p99, max} [µs], `solve_time_stats` of its stored trace), else from the row's
    `lat_hierarchy_{stat}_us` columns where it has them (the episode rows of this version keep
    no hierarchy latency); a number that is in neither is left empty (NaN)."""
    columns = [
        *KEYS,
        "scenario",
        "seed",
        "status",
        "hand error cm",
        "steps",
        "pass",
        *(f"solve {stat} ms" for stat in SOLVE_STATS),
    ]
    rows = reaches(episodes)
    if rows.empty:
        return pd.DataFrame(columns=columns)
    sort = [c for c in (*KEYS, "scenario", "seed", "episode_id") if c in rows.columns]
    result = []
    for _, row in rows.sort_values(sort).iterrows():
        error = _number(row.get("hand_error_final_m"))
        hand = drives_hand(row)
        stored = (solve_times or {}).get(row.get("episode_id"), {})
        passed = "yes" if row["status"] == "ok" and error < REACH_PASS_HAND_ERROR_M else "no"
        if row["status"] == "n/a":
            passed = "n/a (not run)"
        elif row["status"] not in ENDED and not is_controller_failure(
            row["status"], row.get("error_stage")
        ):
            passed = "not judged"  # a timeout or a simulator's error: no test of the controller
        entry = {
            "controller": row["controller"],
            "sim": row["sim"],
            "scenario": row["scenario"],
            "seed": row.get("seed"),
            "status": row["status"],
            "hand error cm": 100.0 * error if hand and row["status"] == "ok" else math.nan,
            "steps": _number(row.get("steps_taken")),
            "pass": passed if hand else "n/a (no hand task)",
        }
        for stat in SOLVE_STATS:
            value = stored.get(stat)
            if value is None:
                value = row.get(f"lat_hierarchy_{stat}_us")
            entry[f"solve {stat} ms"] = _number(value) / 1e3
        result.append(entry)
    return pd.DataFrame(result, columns=columns)


def _number(value) -> float:
    """A float, NaN for None / NA / anything not a number."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        return math.nan
    return number
