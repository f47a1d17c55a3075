"""`centrobench report RESULTS --out DIR`: report.md and report.html (figures beside them as
PNG files) from a sweep's result directory (`bench.dataset` layout: sweep.json,
episodes/*.parquet, traces/*.parquet). Reads result files only; runs nothing.
"""

from __future__ import annotations

import datetime
import html
import json
import re
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from reports import headlines, plots, robustness, tables
from reports.paper_figures import MOTION_FIGURES

TITLE = "centrobench report"


REQUIRED_COLUMNS = ("episode_id", "controller", "sim", "scenario", "status")


def read_results(root: str | Path) -> tuple[pd.DataFrame, dict | None, list[str]]:
    """(episode rows, sweep.json record or None, notes on the files left out) of a result
    directory. A file that is not readable Parquet, has no episode columns or is not the one
    row of the episode it is named after is left out with a note (the rules of
    `bench.dataset.read_episode_file`, which reports/ does not import), and so is a
    sweep.json that is not JSON; the report is built from the rest."""
    root = Path(root)
    folder = root / "episodes"
    paths = sorted(folder.glob("*.parquet")) if folder.exists() else []
    tables, notes = [], []
    # a few threads (Arrow reads without the GIL), and one conversion to pandas at the end
    with ThreadPoolExecutor(_READ_THREADS) as pool:
        read = list(pool.map(_read_table, paths))
    for path, (table, error) in zip(paths, read, strict=True):
        if table is None:  # any unreadable file is left out, with a note
            notes.append(f"{path.name}: unreadable ({' '.join(str(error).split())[:120]})")
            continue
        missing = [c for c in REQUIRED_COLUMNS if c not in table.column_names]
        if missing:
            notes.append(f"{path.name}: not an episode row (no {', '.join(missing)})")
            continue
        if table.num_rows != 1 or table.column("episode_id")[0].as_py() != path.stem:
            # a copy ("x (1).parquet") or a merged file would count its episodes twice
            notes.append(
                f"{path.name}: {table.num_rows} rows, not the one row of episode {path.stem}"
            )
            continue
        tables.append(table)
    if not tables:
        raise FileNotFoundError(f"no readable episode results under {folder}")
    try:  # rows of files of different versions: missing columns null
        frame = pa.concat_tables(tables, promote_options="permissive").to_pandas()
    except (pa.ArrowException, ValueError):  # columns whose types Arrow cannot unify
        frame = pd.concat([t.to_pandas() for t in tables], ignore_index=True)
    episodes = frame.sort_values("episode_id", ignore_index=True)
    record = None
    record_path = root / "sweep.json"
    if record_path.exists():
        try:
            record = json.loads(record_path.read_text())
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
            notes.append(f"sweep.json: unreadable ({exc})")
    if record is not None and (
        not isinstance(record, dict) or not isinstance(record.get("spec"), dict)
    ):
        notes.append("sweep.json: not a sweep record (no 'spec' table)")  # was left unsaid
        record = None
    return episodes, record, notes


_READ_THREADS = 4  # `read_results`'s reading threads (the main job's 1414 files: 11 s one by one)


def _read_table(path: Path) -> tuple[pa.Table | None, Exception | None]:
    """(the file's table, None) or (None, why it cannot be read)."""
    try:
        with pq.ParquetFile(path) as file:
            return file.read(use_threads=False), None
    except Exception as exc:  # any unreadable file is left out, with a note
        return None, exc


RESULTS_DIR = "results_dir"
"""The column `read_all_results` adds: the directory an episode row was read from (its traces
are there)."""


def read_all_results(
    roots: Sequence[str | Path],
) -> tuple[pd.DataFrame, list[dict | None], list[str]]:
    """`read_results` of several result directories (sweeps run apart, for example the main job
    and a controller that is not in it), as one table with the column `RESULTS_DIR`; their
    records in order; the notes. An episode id in two directories is counted once (the first
    directory's) with a note; a directory without results raises as `read_results` does."""
    frames, records, notes = [], [], []
    seen: dict[str, Path] = {}
    for root in (Path(r) for r in roots):
        episodes, record, root_notes = read_results(root)
        prefix = f"{root}: " if len(roots) > 1 else ""
        notes += [prefix + note for note in root_notes]
        twice = episodes["episode_id"].isin(list(seen))
        for episode_id in episodes.loc[twice, "episode_id"]:
            notes.append(
                f"episode {episode_id} is in {seen[episode_id]} and {root}: kept the first"
            )
        episodes = episodes[~twice].assign(**{RESULTS_DIR: str(root)})
        seen.update(dict.fromkeys(episodes["episode_id"], root))
        frames.append(episodes)
        records.append(record)
    episodes = pd.concat(frames, ignore_index=True).sort_values("episode_id", ignore_index=True)
    return episodes, records, notes


def label_ours(episodes: pd.DataFrame) -> pd.DataFrame:
    """The episodes with " (ours)" after the name of a controller that is our variant of a
    paper's method rather than a method or row of the paper (`bench.controllers.
    OURS_CONTROLLERS`: "direct_centroidal/bent_no_inertia (ours)"), so that no table shows one
    of ours under a name that reads as the paper's."""
    from bench.controllers import OURS_CONTROLLERS

    ours = episodes["controller"].isin(OURS_CONTROLLERS)
    return episodes.assign(
        controller=episodes["controller"].where(~ours, episodes["controller"] + " (ours)")
    )


def label_estimators(episodes: pd.DataFrame) -> pd.DataFrame:
    """The episodes with a controller's estimator in its label when it is not the default one
    ("capturability_hierarchy [ground_truth]"), so that every table says which controllers
    were given another state (a perfect one, or a method's own filter) than the others; the
    sweep spec's `estimator` does not say it (a controller may come with its own)."""
    from estimators import DEFAULT_ESTIMATOR

    if "estimator" not in episodes:
        return episodes
    other = episodes["estimator"].notna() & (episodes["estimator"] != DEFAULT_ESTIMATOR)
    labels = episodes["controller"].where(
        ~other, episodes["controller"] + " [" + episodes["estimator"].astype(str) + "]"
    )
    return episodes.assign(controller=labels)


def label_robots(episodes: pd.DataFrame) -> pd.DataFrame:
    """The episodes with their `robot` filled in (rows written before robots could be chosen
    have none: the default robot's) and, when more than one robot is present, the robot in
    the controller's label ("preview_control+centroidal_feedback @ jvrc1"), so that every table
    sets the robots' rows side by side; with one robot the labels are unchanged."""
    from robots.robot_registry import DEFAULT_ROBOT

    robots = episodes["robot"] if "robot" in episodes else pd.Series(None, index=episodes.index)
    episodes = episodes.assign(robot=robots.fillna(DEFAULT_ROBOT))
    if episodes["robot"].nunique() > 1:
        episodes = episodes.assign(controller=episodes["controller"] + " @ " + episodes["robot"])
    return episodes


def _trace_dir(row: pd.Series) -> Path:
    return Path(row[RESULTS_DIR]) / "traces"


def survival_time_s(record: dict | None) -> float:
    """The spec's survival window after a push [s] (a job's: that of its first protocol with
    pushes; the protocol's default, 3 s, when the record does not say)."""
    spec = (record or {}).get("spec", {})
    tables = [spec, *(p for p in spec.get("protocols") or [] if isinstance(p, dict))]
    push = next((t["push"] for t in tables if isinstance(t.get("push"), dict)), {})
    value = push.get("survival_time", 3.0)
    return float(value) if isinstance(value, int | float) else 3.0


def _speed_trials(results: Path, notes: list[str]) -> pd.DataFrame | None:
    """The maximum-speed protocol's walks (`speed.parquet`, written by `centrobench speed`)
    if the results directory has them; an unreadable file is a note, not an error."""
    path = results / "speed.parquet"
    if not path.exists():
        return None
    try:
        return pq.read_table(path).to_pandas()
    except Exception as exc:
        notes.append(f"speed.parquet: unreadable ({' '.join(str(exc).split())[:120]})")
        return None


def header(episodes: pd.DataFrame, record: dict | None) -> dict[str, str]:
    """Provenance: centrobench version, git commits, date, CPUs, package versions, spec."""
    versions: dict[str, set[str]] = {}
    for text in episodes["versions_json"].dropna().unique():
        for package, version in json.loads(text).items():
            versions.setdefault(package, set()).add(str(version))
    return {
        "centrobench": ", ".join(sorted(set(episodes["centrobench_version"].dropna()))) or "?",
        "git commit": ", ".join(sorted(set(episodes["git_commit"].dropna()))) or "?",
        "report date (UTC)": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M"),
        "CPU": ", ".join(sorted(set(episodes["cpu"].dropna()))) or "?",
        "versions": "; ".join(f"{p} {', '.join(sorted(v))}" for p, v in sorted(versions.items())),
        "episodes": f"{len(episodes)}",
        "sweep spec": json.dumps(record["spec"], sort_keys=True) if record else "?",
    }


def sections(
    episodes: pd.DataFrame,
    benchmark: dict | None = None,
    survival_time: float = 3.0,
    solve_times: dict[str, dict[str, float]] | None = None,
    speed: pd.DataFrame | None = None,
) -> list[tuple[str, str, pd.DataFrame]]:
    """(title, explanation, table) in report order: the headline tables first (one per
    question, `reports.headlines`), then the details; `survival_time` [s] is the spec's;
    `solve_times` the hierarchy's solve times of the reach episodes with a stored trace
    (`tables.reach_table`); `speed` the maximum-speed protocol's walks (`centrobench speed`)."""
    result = _headline_sections(episodes, speed, survival_time)
    result += [
        (
            "Episodes by status",
            "Every episode of the sweep, by how it ended (ok; fell; error: the controller or "
            "the simulator failed; timeout: past its wall-clock budget; n/a: the controller "
            "cannot run the scenario and was not run). A column appears when an episode "
            "ended so.",
            tables.status_table(episodes),
        ),
        (
            "Not run",
            "The n/a episodes, per controller and reason: a controller that cannot run a "
            "scenario (it lacks a capability the scenario needs, or reads a state its "
            "estimator does not give) is not run, and the push, threshold and degradation "
            "tables leave these episodes out.",
            tables.refusal_table(episodes),
        ),
        (
            "Latency per stage (Murooka Table IV)",
            "Median and p99 per control period [µs] in each walk: Table IV's rows (Total "
            "control = centroidal_control, the planner and the stabilizer with the feedback "
            "and damping; reference, preview, projection, distribution and centroidal_total, "
            "their sum; – where a controller has no such stage). The loop's stages are in §4.",
            _latency_cells(tables.latency_table(episodes)),
        ),
        (
            "Latency against the papers' figures",
            "Control time per period [µs] (estimator, planner, stabilizer, whole-body "
            "layer; the median over the controller's walks, pushed or not, of each one's "
            "median, with its 95 % interval and n, as in §4) against the paper's own figure "
            "for its whole loop (Ficht & Behnke: 143 µs on the robot's computer at 100 Hz; "
            "ours run at 500 Hz), and the ratio. Only controllers whose paper gives one.",
            tables.paper_latency_table(episodes),
        ),
        (
            "Wrench projection errors (Murooka Sec. V-G)",
            "Means over each walk's periods: planned (||w^p - w^p'||) and desired "
            "(||w^d - w^d'||) projection errors and the feedback wrench ||w^d - w^p'||, "
            "force [N] and moment [N m]. Empty where the stabilizer distributes no wrench.",
            tables.projection_table(episodes),
        ),
    ]
    for phase in ("standing", "walking"):
        table = tables.survival_table(episodes, phase)
        if tables.level_count(episodes, phase) > 1:  # with one level, §1 is this table
            result.append(
                (
                    f"Push survival, {phase} (Ficht & Behnke Table 2)",
                    "Pushes survived out of those judged per level, with the 95 % Wilson "
                    "interval: a push to the torso for "
                    "0.1 s from a direction drawn uniformly on the circle (the same directions "
                    f"for every controller); survived = no fall within {survival_time:g} s "
                    "after it. Levels are velocity changes dv = J / m, with the impulse J for "
                    "the robot (a range over the robots when several were pushed). Judged: "
                    "the episodes that ended ok or fell, and those whose "
                    "controller failed (an error raised by its estimator, planner, stabilizer "
                    "or whole-body layer, such as a solver that gives up), which count as not "
                    "survived; those that ended in another error (set-up, simulator, worker) "
                    "or a timeout are counted under 'not judged' (rerun them with "
                    "`centrobench sweep ... --resume --retry-errors`), and those in which the "
                    "robot fell before the push came under 'fell before the push' (they say "
                    "nothing of push recovery).",
                    table,
                )
            )
    result += _robustness_sections(episodes)
    replays = robustness.replay_choices(episodes)
    if len(replays):
        result.append(
            (
                "Replays",
                "One walk and the first fall of each controller, to watch: the robot and the "
                "scene in 3-D with the time, CoM, ZMP and contact forces (`centrobench replay "
                "RESULTS EPISODE_ID --out FILE` runs the episode again and draws it; "
                "`centrobench report --replays` makes these into the report's "
                f"{robustness.REPLAY_FOLDER}/ folder). replay: the file, where it was made.",
                replays.drop(columns=["results_dir"]),
            )
        )
    result += [
        (
            "Walking quality (Ficht & Behnke eq. 18)",
            "Integral square errors of the CoM (e_com, m s), ZMP (e_zmp, m s) and CoM velocity "
            "(e_velocity, m/s) against the plan, normalised by walking time and forward speed; "
            "CoM tracking error RMS [mm]; where the feet landed against the plan's footsteps: "
            "mean touchdown time error [ms] (negative: early, as a swing leg that sags lands) "
            "and mean touchdown position error [mm]; distance from the gait command's goal at "
            "the end [cm]; medians over the walks that did not fall (walks ok: how many; a "
            "fall's errors measure the fall).",
            tables.walking_quality_table(episodes),
        ),
    ]
    if len(tables.reaches(episodes)):
        result.append(
            (
                "Reaching tests (Sherikov et al. Tests 1-2)",
                "Sherikov, Dimitrov & Wieber 2014, Sec. VII-B/C: the right hand driven to a "
                "target that moves (Test 1, scenario reach), and the same with two 15 N s "
                "pushes (Test 2, reach_push). Per episode: how it ended, the final hand error "
                "[cm], the steps taken, pass (ended ok with a final hand error under "
                f"{100 * tables.REACH_PASS_HAND_ERROR_M:g} cm) and the hierarchy's solve time "
                "per control period [ms] (mean, p99, max; from the stored trace, empty "
                "without one). The paper's mean is "
                f"{plots.PAPER_SOLVE_MEAN_MS} ms, on an Intel Core i5-3360M.",
                tables.reach_table(episodes, solve_times),
            )
        )
    if benchmark is not None:
        result.append(
            (
                "pytest-benchmark",
                f"From {benchmark.get('machine_info', {}).get('cpu', {}).get('brand_raw', '?')}, "
                f"{benchmark.get('datetime', '?')}.",
                tables.benchmark_table(benchmark),
            )
        )
    return result


def _headline_sections(
    episodes: pd.DataFrame, speed: pd.DataFrame | None, survival_time: float
) -> list[tuple[str, str, pd.DataFrame]]:
    """One table per question (`reports.headlines`), those with something to show."""
    result = []
    survival = robustness.headline_survival(episodes)
    if len(survival):
        result.append(
            (
                "1. Which pushes each controller survives",
                "Per controller and push phase: the protocol's pushes (levels: the velocity "
                "change dv = J / m and the impulse J the robot was given) survived over all "
                "levels in each simulator, with the 95 % Wilson interval, and the band between "
                "the two simulators' rates [%]. A push to the torso for 0.1 s from a direction "
                "drawn uniformly on the circle (the same directions for every controller); "
                f"survived: no fall within {survival_time:g} s after it. Counted apart: the "
                "episodes in which the robot fell before the push came (they say nothing of "
                "push recovery) and those not judged (an error of the set-up, simulator or "
                "worker, or a timeout; a controller's own failure counts as not surviving); "
                "a controller that cannot run the pushes is under Not run. "
                "With several levels, the push survival tables below give each.",
                survival,
            )
        )
    if speed is not None and len(speed):
        result.append(
            (
                "2. How fast each controller walks (Ficht & Behnke Table 1)",
                "Per controller and simulator (`centrobench speed`): the highest commanded "
                "forward speed v_ref it walked a walk at without falling (a ladder of speeds "
                "refined by bisection), v_fell the lowest speed tried above it, which it did "
                "not walk (the answer lies between them; v_fell ended: how, where a timeout "
                "or an error, not a fall, would make v_ref a lower bound), the mean speed v "
                "walked at v_ref "
                "over the steady steps, "
                "and eq. 18's e_c [m s], e_z [m s], e_v [m/s] against its own plan there; "
                "walks: how many the search took. With replicas (`centrobench speed "
                "--replicas 5`) a speed counts as walked when 4 of 5 walk it; at v_ref and "
                "above: the replicas that walked the speed found and the lowest one tried "
                "above it (without replicas, one walk per speed decides).",
                tables.speed_table(speed),
            )
        )
    benchmarks = headlines.paper_benchmarks(episodes)
    if len(benchmarks):
        result.append(
            (
                "3. The papers' own benchmarks",
                "Murooka et al.'s motions of Fig. 4 (A)-(C) with Table IV's stage times "
                "(the paper's: its preview control in C++ on an i7-9750H, without the "
                "whole-body IK) and Sec. V-G's mean projection errors (its preview control and "
                "linear MPC on (B) and (C)); Sherikov et al.'s reaching tests with the final "
                "hand error. outcome: how the episode ended (a reach passed when its hand ended "
                f"within {100 * tables.REACH_PASS_HAND_ERROR_M:g} cm of the target; numbers up "
                "to a fall; n/a: the controller cannot run it, why under Not run). Where ours "
                "and the paper's are not the same experiment: our (B) hands grasp the rails "
                "(a weld that can pull), so its planned and desired projection errors are zero by "
                "construction, where the paper's hands were most likely pressed on them "
                '(our variant with the hands resting on the rails, "(B) ... hands resting '
                '(ours)", is set beside the same figures); a '
                "motion that fell was measured only up to its fall (the outcome says when), "
                "not over the paper's whole motion, and a reach that fell has no hand error "
                "(the hand's distance as the robot toppled); a controller whose planner does "
                'not drive the hand stands through the reach: "no hand task", no hand error.',
                benchmarks,
            )
        )
    cost = headlines.cost_table(episodes)
    if len(cost):
        result.append(
            (
                "4. What each controller costs per control period",
                "From the controller's walks (the nominal walk, and the walking pushes timed "
                f"from {tables.PUSH_TIMING_DELAY_PERIODS} periods after their push on, whether "
                "they fell after it or not: the same code every period, without the periods "
                "right after a branch's fork; the "
                "copies of one run that fell before its push count once): the "
                "control time per 2 ms period (estimator, planner, stabilizer, whole-body "
                "layer) [µs], the median over the runs of each one's median, with its "
                "distribution-free 95 % interval (from the order statistics; none under 6 "
                "runs) and n, the runs; the median p99; the simulator engine's own step for "
                "the same periods in the same runs; control / engine: each run's control "
                "median over its engine median, the median over the runs and its 95 % "
                "interval (the cost in engine steps, measured side by side: a machine slower "
                "or faster for a whole run leaves it unchanged, so compare controllers and "
                "runs by it); and the stages' medians. The walking pushes of a cell ran one "
                "after the other in one worker: the intervals show how the timing varied from "
                "run to run over those minutes, not over the whole sweep or on another "
                "machine. A controller without a walk from its other episodes (`from` names "
                "the scenarios).",
                cost,
            )
        )
    agreement = tables.agreement_table(episodes)
    if len(agreement):
        result.append(
            (
                "5. Where MuJoCo and PyBullet disagree",
                "The headline numbers that the simulator decides, per controller in each "
                "simulator, the band between the simulators (low to high) and their difference "
                "(MuJoCo minus PyBullet): push survival over all of the protocol's levels [%], "
                "and from the nominal walk, when it did not fall (a fall's errors measure the "
                "fall), the CoM tracking error and the eq. 18 errors; what each value is from "
                "(a rate's pushes survived / judged with its 95 % Wilson interval, a median's "
                "walks), so that a difference within the intervals is not read as a "
                "disagreement. Not here: the control "
                "time (the controller's code on this machine, §4) and the planned projection "
                "error (the plan's, the same in both).",
                agreement,
            )
        )
    return result


def _robustness_sections(episodes: pd.DataFrame) -> list[tuple[str, str, pd.DataFrame]]:
    """The robustness sections (issue 21), those that have episodes."""
    result = []
    thresholds = robustness.robust_threshold_table(episodes)
    if len(thresholds):
        result.append(
            (
                "Robust push thresholds",
                "Per push (a direction, and for walking pushes a swing fraction), the largest "
                "level dv [m/s] survived in at least 4 of its 5 replicas (80 %, rounded up, of "
                "another count) at that level and at every level below ('< lowest' when the "
                "lowest level is not); replicas differ by a small seeded change of the initial "
                "state (base velocity, 1 cm/s) and the push time (within ±20 ms). Lower median "
                "(a level that was run), min and max over the pushes. Counted apart, without a "
                "threshold: incomplete, a push without its judged replicas at every level it "
                "was run at (an error, a timeout); before push, a push with a replica that "
                "fell before the push came.",
                thresholds,
            )
        )
    for phase in ("standing", "walking"):
        paired = robustness.paired_comparisons(episodes, phase)
        if len(paired):
            result.append(
                (
                    f"Paired comparisons, {phase} pushes",
                    "Two controllers on the same pushes (level, direction) in one simulator: "
                    "only A / only B are the pushes one survived and the other did not; p is "
                    "the exact McNemar test (two-sided binomial test of only A out of the "
                    "discordant pushes at 1/2); q is its Benjamini-Hochberg false discovery "
                    "rate over the table's tests (judge a difference by q: many pairs are "
                    "tested at once). Pushes that either controller fell before are left out. "
                    "Most significant first.",
                    paired,
                )
            )
    directions = robustness.direction_table(episodes)
    if len(directions):
        result.append(
            (
                "Walking pushes by timing and direction",
                "Walking pushes centred at a fraction of the single support, inward, outward, "
                "forward or backward relative to the support foot (or in the protocol's random "
                "directions): per level, the pushes survived out of those run, a push with "
                "replicas counting as survived in 4 of its 5 (no interval: a push's replicas "
                "are not independent trials, and each named direction is one push). Pushes "
                "fallen before they came, or without their judged replicas, are left out.",
                directions,
            )
        )
    degradation = robustness.degradation_table(episodes)
    if len(degradation):
        result.append(
            (
                "Degradation along the robustness dimensions",
                "One dimension at a time (sensor noise in multiples of the data sheets' or, "
                "noise_<channel>, one channel's standard deviation in SI units; delays in "
                "control periods; model errors, actuation, ground): survival with "
                "the 95 % Wilson interval (from 10 episodes on; a count alone below, as for a "
                "robustness walk: one episode, a finding, not a rate) and the median CoM "
                "tracking error [mm], per protocol "
                "(the pushes, or the plain scenario: survived = no fall); the nominal episodes "
                "are each dimension's nominal magnitude. A pushed episode that fell before "
                "its push counts here as not survived (not standing until the push is part of "
                "what a perturbation degrades); before push: how many did. A controller's own "
                "failure counts as not survived; a simulator's or worker's error or a timeout "
                "is not judged (not judged: how many); n/a rows are left out.",
                degradation[
                    [
                        *tables.KEYS,
                        "protocol",
                        "dimension",
                        "magnitude",
                        "survival",
                        "before_push",
                        "not_judged",
                        "com_rms_mm",
                    ]
                ].rename(columns={"before_push": "before push", "not_judged": "not judged"}),
            )
        )
        result.append(
            (
                "Where each controller loses half of its survival",
                "Per dimension: the nominal survival and the first magnitude (moving away from "
                "the nominal one) at which the survival rate is at most half of it (not "
                "stated, n < 10, where a magnitude has fewer than 10 episodes).",
                robustness.half_survival_table(degradation),
            )
        )
    return result


def build_report(
    results: str | Path | Sequence[str | Path],
    out: str | Path,
    benchmark_json: str | Path | None = None,
) -> list[Path]:
    """Write report.md, report.html and the figures into `out`; returns their paths. `results`:
    one result directory, or several whose episodes are reported together (`read_all_results`;
    the sweep record of the first is the header's)."""
    benchmark = None
    if benchmark_json is not None:  # first: a bad file fails before anything is read or made
        path = Path(benchmark_json)
        if not path.exists():
            raise FileNotFoundError(f"benchmark file {path} does not exist")
        try:
            benchmark = json.loads(path.read_bytes())
        except (OSError, ValueError, RecursionError) as exc:  # a folder; not UTF-8 or JSON
            reason = " ".join(str(exc.strerror if isinstance(exc, OSError) else exc).split())
            raise ValueError(f"benchmark file {path} is not readable JSON: {reason}") from None
        entries = benchmark.get("benchmarks") if isinstance(benchmark, dict) else None
        stats = ("median", "mean", "stddev", "min", "rounds")
        if not isinstance(entries, list) or not all(
            isinstance(entry, dict)
            and "name" in entry
            and isinstance(entry.get("stats"), dict)
            and all(isinstance(entry["stats"].get(key), int | float) for key in stats)
            for entry in entries
        ):
            raise ValueError(
                f"benchmark file {path} is not pytest-benchmark JSON: an object with a "
                f"'benchmarks' list whose entries have a name and stats {', '.join(stats)}; "
                "got "
                + (
                    "an object without that"
                    if isinstance(benchmark, dict)
                    else f"a JSON {type(benchmark).__name__.replace('NoneType', 'null')}"
                )
            )
    roots = [Path(results)] if isinstance(results, str | Path) else [Path(r) for r in results]
    if not roots:
        raise FileNotFoundError("no result directory given")
    episodes, records, notes = read_all_results(roots)
    episodes = label_robots(label_estimators(label_ours(episodes)))
    record = records[0]
    windows = {survival_time_s(r) for r in records}
    if len(windows) > 1:
        notes.append(
            "the sweeps judged survival over different windows after a push: "
            + ", ".join(f"{w:g} s" for w in sorted(windows))
            + f"; the header says the first's ({survival_time_s(record):g} s)"
        )
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    info = header(episodes, record)
    if len(roots) > 1:
        info["result directories"] = ", ".join(str(r) for r in roots)
        info["sweep spec"] = "; ".join(
            json.dumps(r["spec"], sort_keys=True) if r else "?" for r in records
        )
    reach_traces = _reach_traces(episodes, notes)
    solve_times = {
        episode_id: stats
        for episode_id, (_, trace, _) in reach_traces.items()
        if (stats := tables.solve_time_stats(trace, plots.HIERARCHY_TIME_COLUMN))
    }
    trials = [t for t in (_speed_trials(root, notes) for root in roots) if t is not None]
    speed = label_estimators(label_ours(pd.concat(trials, ignore_index=True))) if trials else None
    parts = sections(episodes, benchmark, survival_time_s(record), solve_times, speed)
    parts = [
        (title, text, _with_replay_files(table, out) if title == "Replays" else table)
        for title, text, table in parts
    ]
    parts = [(title, text, _without_empty(table, OPTIONAL_COLUMNS)) for title, text, table in parts]
    figures: list[tuple[str, Path]] = []
    rates = tables.survival_rates(episodes, "standing")
    if tables.level_count(episodes, "standing") > 1:  # one level is no curve
        figures.append(
            ("Standing push survival against dv", plots.survival_plot(rates, out / "survival.png"))
        )
    degradation = robustness.degradation_table(episodes)
    for dimension in sorted(set(degradation.get("dimension", []))):
        figures.append(
            (
                f"Degradation: {dimension}",
                plots.degradation_plot(
                    degradation, dimension, out / f"degradation_{dimension}.png"
                ),
            )
        )
    walk_traces = _walk_traces(episodes, notes)
    if walk_traces:
        figures.append(
            (
                "CoM and ZMP of one walk per controller",
                plots.walk_plot(walk_traces, out / "walk.png"),
            )
        )
    figures += _reach_figures(reach_traces, out)
    figures += _motion_figures(episodes, out, notes)
    if notes:
        info["files left out"] = "; ".join(notes)
    md = out / "report.md"
    md.write_text(_markdown(info, parts, figures))
    page = out / "report.html"
    page.write_text(_html(info, parts, figures))
    return [md, page, *(path for _, path in figures)]


OPTIONAL_COLUMNS = ("not judged", "fell before the push", "replay")
"""Columns a table shows only when a row has something in them (a sentence of its text says
what they would hold)."""


def _without_empty(table: pd.DataFrame, columns: Sequence[str]) -> pd.DataFrame:
    """`table` without those of `columns` that are empty ("", None or NaN) in every row."""
    empty = [
        column
        for column in columns
        if column in table.columns
        and table[column].map(lambda v: v is None or v == "" or v != v).all()
    ]
    return table.drop(columns=empty)


def _with_replay_files(table: pd.DataFrame, out: Path) -> pd.DataFrame:
    """The replays table with the column `replay`: the file's path relative to the report
    where `centrobench report --replays` (or the user) made it, else empty."""
    folder = robustness.REPLAY_FOLDER
    return table.assign(
        replay=[
            f"{folder}/{episode}.html" if (out / folder / f"{episode}.html").exists() else ""
            for episode in table["episode_id"]
        ]
    )


def _walk_traces(episodes: pd.DataFrame, notes: list[str]) -> dict[str, pd.DataFrame]:
    """One walk trace per controller (MuJoCo's when there is one); a trace that cannot be
    read or lacks the plotted columns is skipped with a note in `notes`."""
    walks = tables.walks(episodes)
    walks = walks[walks["has_trace"].fillna(False).astype(bool)]
    result = {}
    for controller, group in walks.sort_values(["controller", "sim"]).groupby("controller"):
        row = group.iloc[0]
        trace = _plotted_trace(row, plots.WALK_COLUMNS, notes)
        if trace is None:
            continue
        result[f"{controller} ({row['sim']}, {row['status']})"] = trace
    return result


def _plotted_trace(row: pd.Series, columns: Sequence[str], notes: list[str]) -> pd.DataFrame | None:
    """The episode's stored trace if it has every one of `columns`; None if there is none, or
    (with a note in `notes`) if it cannot be read or lacks one."""
    path = _trace_dir(row) / f"{row['episode_id']}.parquet"
    trace = _read_trace(path, notes)
    if trace is None:
        return None
    missing = [c for c in columns if c not in trace.columns]
    if missing:
        notes.append(f"traces/{path.name}: no {missing[0]} column, not plotted")
        return None
    return trace


def _read_trace(path, notes: list[str]) -> pd.DataFrame | None:
    """The trace stored at `path`; None if there is none, or (with a note in `notes`) if it
    cannot be read: a corrupt trace means no plot, still a report."""
    if not path.exists():
        return None
    try:
        return pq.read_table(path).to_pandas()
    except Exception as exc:
        notes.append(f"traces/{path.name}: unreadable, not plotted ({type(exc).__name__})")
        return None


def _reach_traces(
    episodes: pd.DataFrame, notes: list[str]
) -> dict[str, tuple[pd.Series, pd.DataFrame, pd.DataFrame | None]]:
    """Per reach / reach_push episode with a stored trace whose planner drives the hand
    (`tables.drives_hand`): (its row, its trace, its steps taken or None). A trace that
    cannot be read is skipped with a note in `notes`; a steps file that is missing or cannot
    be read leaves the steps out of the top view, with a note."""
    rows = tables.reaches(episodes)
    if "has_trace" in rows.columns:
        rows = rows[rows["has_trace"].fillna(False).astype(bool)]
    # a controller that drives no hand stands: its top view has no reach to show
    rows = rows[rows.apply(tables.drives_hand, axis=1).astype(bool)] if len(rows) else rows
    result = {}
    for _, row in rows.sort_values(["controller", "sim", "scenario", "episode_id"]).iterrows():
        episode_id = row["episode_id"]
        path = _trace_dir(row) / f"{episode_id}.parquet"
        trace = _read_trace(path, notes)
        if trace is None:
            continue
        if "time" not in trace.columns:
            notes.append(f"traces/{path.name}: no time column, not plotted")
            continue
        steps_path = _trace_dir(row) / f"{episode_id}.footsteps.parquet"
        steps = None
        if not steps_path.exists():
            notes.append(f"traces/{steps_path.name}: missing, steps not drawn")
        else:
            try:
                steps = pq.read_table(steps_path).to_pandas()
            except Exception as exc:
                notes.append(
                    f"traces/{steps_path.name}: unreadable, steps not drawn ({type(exc).__name__})"
                )
            else:
                missing = [c for c in ("limb", "x_m", "y_m", "yaw_rad") if c not in steps.columns]
                if missing:
                    notes.append(f"traces/{steps_path.name}: no {missing[0]} column, not drawn")
                    steps = None
        result[episode_id] = (row, trace, steps)
    return result


def _sole_half_extents(scale: float, robot: str) -> tuple[float, float]:
    """The half length and half width [m] of `robot`'s sole at `scale` (its robot description,
    as the runner's; both feet are the same)."""
    from robots.robot_registry import make_robot

    half_length, half_width = make_robot(robot, scale).limb("left_foot").half_extents
    return float(half_length), float(half_width)


def _reach_figures(
    reach_traces: dict[str, tuple[pd.Series, pd.DataFrame, pd.DataFrame | None]], out: Path
) -> list[tuple[str, Path]]:
    """Sherikov et al. 2014 Figs. 3 and 2 for each reach episode with a trace: the top view of
    the CoM, hand, target and steps taken, and the hierarchy's solve time and iterations (only
    for an episode whose trace has solve times: a controller without the hierarchy has none,
    and its figure was an empty plot)."""
    figures = []
    for episode_id, (row, trace, steps) in reach_traces.items():
        scale = row.get("scale")
        scale = float(scale) if pd.notna(scale) else 1.0
        seed = row.get("seed")
        label = (
            f"{row['controller']} ({row['sim']}, {row['scenario']}"
            + (f", seed {int(seed)}" if pd.notna(seed) else "")
            + f", {row['status']})"
        )
        name = re.sub(r"[^A-Za-z0-9._-]", "_", str(episode_id))
        pushes = tables.REACH_PUSH_TIMES_S if row["scenario"] == "reach_push" else ()
        figures.append(
            (
                f"Reaching, top view (Sherikov Fig. 3): {label}",
                plots.top_view_plot(
                    trace,
                    steps,
                    _sole_half_extents(scale, row["robot"]),
                    out / f"reach_{name}_top.png",
                    title=f"{label}: steps taken, CoM, hand, target",
                    pushes=pushes,
                ),
            )
        )
        column = plots.HIERARCHY_TIME_COLUMN
        solve = trace[column] if column in trace else pd.Series(dtype=float)
        if not solve.notna().any():
            continue
        figures.append(
            (
                f"Reaching, solve time (Sherikov Fig. 2): {label}",
                plots.solve_time_plot(
                    trace, out / f"reach_{name}_solve.png", title=f"{label}: hierarchy solve"
                ),
            )
        )
    return figures


def _motion_figures(episodes: pd.DataFrame, out: Path, notes: list[str]) -> list[tuple[str, Path]]:
    """Murooka Figs. 5-7 (`plots.motion_plot`) for each episode of a multi-contact motion
    (`MOTION_FIGURES`) with a stored trace; a trace without the plotted columns (a controller
    without a desired wrench) is skipped with a note in `notes`."""
    if "scenario" not in episodes.columns or "has_trace" not in episodes.columns:
        return []
    rows = episodes[
        episodes["scenario"].isin(list(MOTION_FIGURES))
        & episodes["has_trace"].fillna(False).astype(bool)
    ]
    figures = []
    for _, row in rows.sort_values(["scenario", "controller", "sim", "episode_id"]).iterrows():
        trace = _plotted_trace(row, plots.MOTION_COLUMNS, notes)
        if trace is None:
            continue
        label = f"{row['controller']} ({row['sim']}, {row['scenario']}, {row['status']})"
        name = re.sub(r"[^A-Za-z0-9._-]", "_", str(row["episode_id"]))
        figure = MOTION_FIGURES[row["scenario"]]
        figures.append(
            (
                f"Multi-contact motion (Murooka {figure}): {label}",
                plots.motion_plot(
                    trace, float(row["mass_kg"]), out / f"motion_{name}.png", title=label
                ),
            )
        )
    return figures


def _latency_cells(table: pd.DataFrame) -> pd.DataFrame:
    """One "median / p99" cell per Table IV stage (the numeric table, with the loop's stages
    that §4 gives, is `tables.latency_table`)."""
    result = table[tables.KEYS].copy()
    for stage in tables.TABLE_IV_STAGES:
        column = f"{stage} median µs"
        if column in table.columns:
            median, p99 = table[column], table[f"{stage} p99 µs"]
            result[f"{stage} µs"] = [
                "–" if m != m else f"{m:.0f} / {p:.0f}" for m, p in zip(median, p99, strict=True)
            ]
    return result


NEGLIGIBLE = 1e-6
"""Below this magnitude a number prints as "< 1e-6": the projection errors of a plan inside
its cones are solver tolerance (9e-07 N beside the paper's 2.2 N read as a measurement), and
so are p-values this small."""


def _format(table: pd.DataFrame) -> pd.DataFrame:
    """The table's cells as printed: floats to 4 significant figures, NaN as "–", and
    magnitudes under `NEGLIGIBLE` (not 0) as "< 1e-6" ("> -1e-6" when negative)."""

    def cell(value):
        if isinstance(value, float):
            if value != value:
                return "–"
            if 0 < value < NEGLIGIBLE:
                return "< 1e-6"
            if -NEGLIGIBLE < value < 0:
                return "> -1e-6"
            return f"{value:.4g}"
        return value

    return table.map(cell)


SPEC_KEY = "sweep spec"


def _spec_text(info: dict[str, str]) -> str:
    """The header's sweep spec indented (a spec is one JSON object of several kB; several
    result directories' specs are one per line)."""
    texts = []
    for text in info[SPEC_KEY].split("; "):
        try:
            texts.append(json.dumps(json.loads(text), indent=2, sort_keys=True))
        except json.JSONDecodeError:
            texts.append(text)
    return "\n".join(texts)


def _markdown(info, parts, figures) -> str:
    lines = [f"# {TITLE}", ""]
    lines += [f"- **{key}**: {value}" for key, value in info.items() if key != SPEC_KEY]
    if SPEC_KEY in info:
        lines.append(f"- **{SPEC_KEY}**: at the end of the report")
    for title, text, table in parts:
        lines += ["", f"## {title}", "", text, ""]
        lines.append(_format(table).to_markdown(index=False) if len(table) else "(no rows)")
    for title, path in figures:
        lines += ["", f"## {title}", "", f"![{title}]({path.name})"]
    if SPEC_KEY in info:  # folded and last: indented, it is hundreds of lines
        lines += ["", "## Sweep spec", "", "<details><summary>sweep spec</summary>", "", "```json"]
        lines += [_spec_text(info), "```", "", "</details>"]
    return "\n".join(lines) + "\n"


def _html(info, parts, figures) -> str:
    body = [f"<h1>{TITLE}</h1>", "<ul>"]
    body += [
        f"<li><b>{html.escape(k)}</b>: {html.escape(v)}</li>"
        for k, v in info.items()
        if k != SPEC_KEY
    ]
    if SPEC_KEY in info:
        body.append(f"<li><b>{SPEC_KEY}</b>: at the end of the report</li>")
    body.append("</ul>")
    for title, text, table in parts:
        body += [f"<h2>{html.escape(title)}</h2>", f"<p>{html.escape(text)}</p>"]
        body.append(
            _format(table).to_html(index=False, border=0) if len(table) else "<p>(no rows)</p>"
        )
    for title, path in figures:
        body += [
            f"<h2>{html.escape(title)}</h2>",
            f'<img src="{path.name}" alt="{html.escape(title)}">',
        ]
    if SPEC_KEY in info:
        body += [
            "<h2>Sweep spec</h2>",
            "<details><summary>sweep spec</summary>"
            f"<pre>{html.escape(_spec_text(info))}</pre></details>",
        ]
    style = (
        "body{font-family:sans-serif;max-width:1200px;margin:2em auto}"
        "table{border-collapse:collapse;font-size:13px}td,th{padding:3px 8px;"
        "border-bottom:1px solid #ddd;text-align:right}img{max-width:100%}"
    )
    return (
        f"<!doctype html><html><head><meta charset='utf-8'><title>{TITLE}</title>"
        f"<style>{style}</style></head><body>{''.join(body)}</body></html>\n"
    )
