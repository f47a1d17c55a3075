"""A sweep's results on disk: a Parquet dataset written as episodes finish.

    DIR/sweep.json                      the spec (and its digest) the results belong to
    DIR/episodes/<episode_id>.parquet   one summary row per finished episode (`ROW_SCHEMA`)
    DIR/traces/<episode_id>.parquet     the per-period trace, for the episodes that keep one
    DIR/traces/<episode_id>.footsteps.parquet   their steps taken (`bench.footsteps`)
    DIR/.lock                           held (flock) by the sweep writing into DIR
    DIR/corrupt/                        unreadable or foreign files found by a resume
    DIR/.previous-*/                    with --overwrite: the old results, until the new
                                        sweep has written its first episode

Each file is written to a temporary name and renamed, so a file that exists is complete: an
interrupted sweep keeps every finished episode, and `--resume` runs only the missing ids.
One sweep at a time writes into a directory (`ResultStore.locked`: an flock, which the kernel
releases when its process dies however it dies, so a lock is never stale).
`read_episodes(DIR)` reads the summary rows as one DataFrame.
"""

from __future__ import annotations

import contextlib
import datetime
import fcntl
import json
import os
import shutil
import socket
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from bench.limits import CONTROL_PERIOD_S
from bench.metrics import feedback_magnitude, walking_quality
from reports.outcomes import ENDED, is_controller_failure
from robots.perturbation import PERTURBATION_FIELDS

LATENCY_STAGES = (
    "estimator",
    "planner",
    "stabilizer",
    "whole_body",
    "sim",
    "sim_engine",
    "control_total",
    "reference",
    "preview",
    "projection",
    "distribution",
    "centroidal_total",
    "centroidal_control",
)

_STRING, _FLOAT, _INT, _BOOL = pa.string(), pa.float64(), pa.int64(), pa.bool_()
ROW_SCHEMA = pa.schema(
    [
        ("episode_id", _STRING),
        ("controller", _STRING),
        ("robot", _STRING),
        ("planner", _STRING),
        ("stabilizer", _STRING),
        ("whole_body", _STRING),
        ("sim", _STRING),
        ("scenario", _STRING),
        ("seed", _INT),
        ("estimator", _STRING),
        ("scale", _FLOAT),
        ("friction", _FLOAT),
        ("speed", _FLOAT),
        ("mass_kg", _FLOAT),
        ("push_phase", _STRING),
        ("push_dv_mps", _FLOAT),
        ("push_index", _INT),
        ("push_time_s", _FLOAT),
        ("push_step", _INT),
        ("push_impulse_Ns", _FLOAT),
        ("push_direction_deg", _FLOAT),
        ("push_swing_fraction", _FLOAT),
        ("push_direction_name", _STRING),
        ("replica", _INT),
        ("perturbation", _STRING),
        *[(name, _INT if name.endswith("delay") else _FLOAT) for name in PERTURBATION_FIELDS],
        ("status", _STRING),
        ("error", _STRING),
        ("error_stage", _STRING),
        ("fell", _BOOL),
        ("fall_time", _FLOAT),
        ("fall_reason", _STRING),
        ("duration", _FLOAT),
        ("requested_duration", _FLOAT),
        ("survived", _BOOL),
        ("real_time_factor", _FLOAT),
        ("wall_s", _FLOAT),
        ("com_error_rms_m", _FLOAT),
        ("zmp_margin_min_m", _FLOAT),
        ("solver_failures", _INT),
        ("planned_force_N", _FLOAT),
        ("planned_moment_Nm", _FLOAT),
        ("desired_force_N", _FLOAT),
        ("desired_moment_Nm", _FLOAT),
        ("feedback_force_N", _FLOAT),
        ("feedback_moment_Nm", _FLOAT),
        ("walk_speed_mps", _FLOAT),
        ("steps_taken", _INT),
        ("mean_step_length_m", _FLOAT),
        ("mean_step_duration_s", _FLOAT),
        ("distance_walked_m", _FLOAT),
        ("final_position_error_m", _FLOAT),
        ("touchdown_time_error_max_s", _FLOAT),
        ("touchdown_position_error_max_m", _FLOAT),
        ("touchdown_time_error_mean_s", _FLOAT),
        ("touchdown_position_error_mean_m", _FLOAT),
        ("final_yaw_error_rad", _FLOAT),
        ("hand_error_final_m", _FLOAT),
        ("hand_task", _BOOL),
        ("plans_com_trajectory", _BOOL),
        ("push_shift_s", _FLOAT),
        ("angular_momentum_error_base_vs_constant", _FLOAT),
        ("angular_momentum_error_all_vs_constant", _FLOAT),
        ("angular_momentum_error_constant_vs_euler", _FLOAT),
        ("torque_share_max", _FLOAT),
        ("torque_share_joint", _STRING),
        ("torque_saturated_fraction", _FLOAT),
        ("solver_iterations_mean", _FLOAT),
        ("solver_iterations_max", _FLOAT),
        ("e_com", _FLOAT),
        ("e_zmp", _FLOAT),
        ("e_velocity", _FLOAT),
        *[(f"lat_{s}_median_us", _FLOAT) for s in LATENCY_STAGES],
        *[(f"lat_{s}_p99_us", _FLOAT) for s in LATENCY_STAGES],
        ("timed_from_s", _FLOAT),
        ("has_trace", _BOOL),
        ("centrobench_version", _STRING),
        ("versions_json", _STRING),
        ("git_commit", _STRING),
        ("cpu", _STRING),
        ("worker", _STRING),
    ]
)
# columns that depend on the machine's speed or on where an episode ran, not on the physics
TIMING_COLUMNS = tuple(
    name
    for name in ROW_SCHEMA.names
    if name.startswith("lat_") or name in ("wall_s", "real_time_factor", "worker")
)


def summary_row(
    labels: dict[str, Any],
    summary: dict[str, Any],
    trace: pd.DataFrame | None,
    requested_duration: float | None,
    wall_s: float | None,
) -> dict[str, Any]:
    """One `ROW_SCHEMA` row from the sweep's labels, the runner's summary and its trace."""
    row: dict[str, Any] = {name: None for name in ROW_SCHEMA.names}
    row.update(labels)
    if row.get("push_time_s") is not None and summary.get("push_shift_s"):
        # the labels give the protocol's push time; a replica's push came this much later
        row["push_time_s"] = row["push_time_s"] + summary["push_shift_s"]
    for key in (
        "robot",
        "planner",
        "stabilizer",
        "whole_body",
        "sim",
        "scenario",
        "seed",
        "estimator",
        "scale",
        "friction",
        "speed",
        "mass_kg",
        "replica",
        "perturbation",
        *PERTURBATION_FIELDS,
        "status",
        "error",
        "error_stage",
        "fell",
        "fall_time",
        "fall_reason",
        "duration",
        "real_time_factor",
        "com_error_rms_m",
        "zmp_margin_min_m",
        "solver_failures",
        "steps_taken",
        "mean_step_length_m",
        "mean_step_duration_s",
        "distance_walked_m",
        "final_position_error_m",
        "touchdown_time_error_max_s",
        "touchdown_position_error_max_m",
        "touchdown_time_error_mean_s",
        "touchdown_position_error_mean_m",
        "final_yaw_error_rad",
        "hand_error_final_m",
        "hand_task",
        "plans_com_trajectory",
        "push_shift_s",
        "timed_from_s",
        "torque_share_max",
        "torque_share_joint",
        "torque_saturated_fraction",
        "git_commit",
        "cpu",
        "worker",
    ):
        if key in summary:
            row[key] = summary[key]
    row.update(summary.get("projection_error") or {})
    for key, value in (summary.get("angular_momentum_error") or {}).items():
        row[f"angular_momentum_error_{key}"] = value
    iterations = summary.get("solver_iterations") or {}
    row["solver_iterations_mean"] = iterations.get("mean")
    row["solver_iterations_max"] = iterations.get("max")
    for stage, values in (summary.get("latency_us") or {}).items():
        if stage in LATENCY_STAGES:
            row[f"lat_{stage}_median_us"] = values["median"]
            row[f"lat_{stage}_p99_us"] = values["p99"]
    versions = summary.get("versions") or {}
    row["centrobench_version"] = versions.get("centrobench")
    row["versions_json"] = json.dumps(versions, sort_keys=True)
    row["requested_duration"] = requested_duration
    row["wall_s"] = wall_s
    if trace is not None and len(trace):
        row.update(walking_quality(trace, summary.get("plans_com_trajectory") is not False))
        row.update(feedback_magnitude(trace))
    if labels.get("push_phase") is not None and is_controller_failure(
        row["status"], row.get("error_stage")
    ):
        row["survived"] = False  # its controller failed (`reports.outcomes`)
    elif labels.get("push_phase") is not None and row["status"] in JUDGED_STATUSES:
        # survival: no fall before the end, `survival_time` after the push; an episode that
        # ended in any other error or a timeout says nothing about the controller (survived
        # None: `reports.outcomes`)
        # the runner runs round(requested / dt) control periods: a complete episode may end
        # up to half a period short of a requested duration that is no whole number of them
        # (the walking pushes' 6.2325 s ran 6.232 s, and were counted as falls before this)
        complete = (
            requested_duration is None
            or row["duration"] >= requested_duration - CONTROL_PERIOD_S / 2 - 1e-9
        )
        row["survived"] = row["status"] == "ok" and complete
    return row


JUDGED_STATUSES = ENDED  # the statuses of an episode run to its end (and `reports.outcomes`)
RETRIED_STATUSES = ("error", "timeout")  # what `--resume --retry-errors` runs again


def failure_row(
    labels: dict[str, Any],
    base: dict[str, Any],
    message: str,
    status: str = "error",
    stage: str | None = None,
    duration: float | None = None,
) -> dict[str, Any]:
    """The row of an episode that produced no summary: its worker died or it raised (status
    "error"), or it overran its wall-clock budget (status "timeout", with the `stage` it was
    in and the simulated `duration` [s] it reached). Its code's provenance (`git_commit`,
    `versions_json`, `centrobench_version`) is that of the process that writes the row, the
    sweep's; `cpu` and `worker` stay null, since the worker that ran it is not known here."""
    from bench.provenance import git_commit, versions

    row: dict[str, Any] = {name: None for name in ROW_SCHEMA.names}
    row.update(
        git_commit=git_commit(),
        centrobench_version=versions().get("centrobench"),
        versions_json=json.dumps(versions(), sort_keys=True),
    )
    row.update(base)
    row.update(labels)
    row.update(status=status, error=message, error_stage=stage, fell=False, duration=duration)
    return row


class ResultStoreError(RuntimeError):
    """The result directory cannot be used as asked; one line that says why and what to do."""


class UnrecordableResult(ValueError):
    """An episode's row, trace or footsteps do not fit the results' schema (a value of the wrong
    type, a NaN in an integer column): the sweep records the episode as an error instead."""


def read_episode_file(path: Path) -> pa.Table:
    """One episode file as a one-row `ROW_SCHEMA` table; ValueError saying why it is not one
    (unreadable Parquet, another schema, not one row, or a row of another episode). A file of
    an older centrobench that lacks later columns is read with those columns null."""
    try:
        with pq.ParquetFile(path) as file:  # half the time of pq.read_table, the same table
            table = file.read(use_threads=False)
    except (OSError, pa.ArrowException) as exc:
        raise ValueError(f"not a readable Parquet file ({' '.join(str(exc).split())})") from None
    names = set(table.schema.names)
    unknown = sorted(names - set(ROW_SCHEMA.names))
    if unknown or "episode_id" not in names or "status" not in names:
        raise ValueError(
            "not a centrobench episode row (columns "
            + (f"{', '.join(unknown[:3])} unknown" if unknown else "episode_id, status missing")
            + ")"
        )
    for name in ROW_SCHEMA.names:
        if name not in names:
            table = table.append_column(name, pa.nulls(len(table), ROW_SCHEMA.field(name).type))
    try:
        if not table.schema.equals(ROW_SCHEMA):  # (an older file's; a cast costs 0.6 ms)
            table = table.select(ROW_SCHEMA.names).cast(ROW_SCHEMA)
    except (pa.ArrowException, ValueError) as exc:
        raise ValueError(f"columns of the wrong type ({' '.join(str(exc).split())})") from None
    if table.num_rows != 1 or table.column("episode_id")[0].as_py() != path.stem:
        raise ValueError(f"{table.num_rows} rows, not the one row of episode {path.stem}")
    return table


def scan_episodes(root: str | Path) -> tuple[pa.Table | None, list[tuple[Path, str]]]:
    """(the valid episode rows under `root` as one table or None, [(file, why it is not
    valid)])."""
    folder = Path(root) / "episodes"
    paths = sorted(folder.glob("*.parquet")) if folder.exists() else []
    tables, bad = [], []
    # a few threads: Arrow reads without the GIL (the 1414 files of issue 22's content: 6.9 s
    # one by one with pq.read_table and a cast, 3.0 s so, measured with `read_episodes`)
    with ThreadPoolExecutor(READ_THREADS) as pool:
        for path, (table, why) in zip(paths, pool.map(_read_or_why, paths), strict=True):
            if table is None:
                bad.append((path, why))
            else:
                tables.append(table)
    return (pa.concat_tables(tables) if tables else None), bad


READ_THREADS = 4  # `scan_episodes`'s reading threads


def _read_or_why(path: Path) -> tuple[pa.Table | None, str]:
    """(`read_episode_file`'s table, "") or (None, why the file is not an episode row)."""
    try:
        return read_episode_file(path), ""
    except ValueError as exc:
        return None, str(exc)


class ResultStore:
    """The directory of one sweep's results (see the module docstring)."""

    def __init__(self, root: str | Path) -> None:
        self.root = Path(root)
        self.episodes_dir = self.root / "episodes"
        self.traces_dir = self.root / "traces"
        self.corrupt_dir = self.root / "corrupt"
        self.record_path = self.root / "sweep.json"
        self.aside: Path | None = None  # the old results, moved aside by --overwrite
        self.bad_files: list[tuple[Path, str]] = []  # moved to corrupt/ by the last resume

    # ------------------------------------------------------------------------ checks
    def check_usable(self) -> None:
        """ResultStoreError unless the directory exists and is writable, or can be created
        (checked without creating anything)."""
        root = self.root
        if root.exists() and not root.is_dir():
            raise ResultStoreError(f"--out {root} is a file, not a directory")
        probe = root
        while not probe.exists():
            probe = probe.parent
        if not probe.is_dir():
            raise ResultStoreError(f"--out {root}: {probe} is a file, not a directory")
        if not os.access(probe, os.W_OK | os.X_OK):
            raise ResultStoreError(f"--out {root}: {probe} is not writable")
        for folder in (self.episodes_dir, self.traces_dir):
            if folder.exists() and not os.access(folder, os.W_OK | os.X_OK):
                raise ResultStoreError(f"--out {root}: {folder} is not writable")

    def spec_record(self) -> dict | None:
        """sweep.json's content, None if there is none; ResultStoreError if it is corrupt."""
        if not self.record_path.exists():
            return None
        try:
            record = json.loads(self.record_path.read_text())
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise ResultStoreError(
                f"{self.record_path} is not a readable sweep record ({exc}); move it away, "
                "or pass --overwrite to start again"
            ) from None
        if not isinstance(record, dict) or not isinstance(record.get("spec"), dict):
            raise ResultStoreError(
                f"{self.record_path} is not a sweep record (no 'spec' table); move it away, "
                "or pass --overwrite to start again"
            )
        return record

    def episode_files(self) -> list[Path]:
        return sorted(self.episodes_dir.glob("*.parquet")) if self.episodes_dir.exists() else []

    # ------------------------------------------------------------------------ the lock
    @contextlib.contextmanager
    def locked(self) -> Iterator[None]:
        """Hold the directory's lock for the block; ResultStoreError naming the holder if
        another process holds it. The kernel drops an flock when its holder dies."""
        path = self.root / ".lock"
        try:
            self.root.mkdir(parents=True, exist_ok=True)
            handle = open(path, "a+")  # noqa: SIM115 - held for the block
        except OSError as exc:
            raise ResultStoreError(_io_message(self.root, exc)) from exc
        try:
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                handle.seek(0)
                holder = " ".join(handle.read().split()) or "another process"
                raise ResultStoreError(
                    f"{self.root} is in use by another sweep ({holder}); wait for it to "
                    "finish or choose another --out"
                ) from None
            handle.seek(0)
            handle.truncate()
            started = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M:%S UTC")
            handle.write(f"pid {os.getpid()} on {socket.gethostname()}, since {started}\n")
            handle.flush()
            yield
        finally:
            handle.close()  # releases the flock

    # ------------------------------------------------------------------------ preparing
    def prepare(
        self,
        spec: dict[str, Any],
        digest: str,
        resume: bool,
        overwrite: bool,
        identity: dict[str, Any] | None = None,
        retry: tuple[str, ...] = (),
        expected: set[str] | None = None,
    ) -> set[str]:
        """Make the directory ready for `spec` (call inside `locked`) and return the ids of
        the episodes already done, which the sweep skips.

        Without `resume` or `overwrite` a directory with results is refused. `resume` needs
        the same spec (`identity`: the fields that decide the results; a difference is named)
        and a sweep.json; unreadable or foreign episode files are moved to corrupt/ and their
        episodes run again, as are those whose status is in `retry`. `overwrite` moves the
        old results to .previous-*/ (`discard_aside` deletes them once the new sweep has
        written an episode, `restore_aside` puts them back if it never does; a sweep killed
        before either leaves them to the next `prepare`, `recover_aside`)."""
        try:
            self.recover_aside()
        except OSError as exc:
            raise ResultStoreError(_io_message(self.root, exc)) from exc
        existing = self.episode_files()
        if existing and not (resume or overwrite):
            raise ResultStoreError(
                f"{self.root} already holds {len(existing)} episodes; pass --resume to "
                "complete that sweep or --overwrite to start again"
            )
        done: set[str] = set()
        if resume:
            recorded = self.spec_record()
            if recorded is None and existing:
                raise ResultStoreError(
                    f"{self.root} holds {len(existing)} episodes but no sweep.json, so their "
                    "spec is unknown; --resume needs it (pass --overwrite to start again)"
                )
            if recorded is not None and recorded.get("digest") != digest:  # name the fields
                fields = spec_differences(recorded["spec"], identity or spec)
                raise ResultStoreError(
                    f"{self.root} holds the results of another spec (fields that differ: "
                    f"{', '.join(fields) or 'unknown'}); --resume needs the same spec"
                )
            done = self._valid_ids(retry, expected)
        try:
            for leftover in [*self.root.glob(".trash-*"), *self.root.glob("*/.*.tmp")]:
                # a deletion or a write that a killed sweep left unfinished
                if leftover.is_dir():
                    shutil.rmtree(leftover, ignore_errors=True)
                else:
                    leftover.unlink(missing_ok=True)
            if overwrite:
                self._move_aside()
            self.episodes_dir.mkdir(parents=True, exist_ok=True)
            self.traces_dir.mkdir(parents=True, exist_ok=True)
            _atomic_write_text(
                self.record_path, json.dumps({"digest": digest, "spec": spec}, indent=2)
            )
        except OSError as exc:
            raise ResultStoreError(_io_message(self.root, exc)) from exc
        return done

    def _valid_ids(self, retry: tuple[str, ...], expected: set[str] | None = None) -> set[str]:
        """Ids of the valid episode files whose status is not in `retry`; invalid files are
        moved to corrupt/ (their episodes run again). ResultStoreError when a file holds an
        episode that is not among `expected` (the spec's ids): the spec is the same, but what
        the code derives from it (a push's impulse from the robot's mass, a walking push's
        time from the gait) has changed since, and resuming would run every such episode again
        beside its old result."""
        table, bad = scan_episodes(self.root)
        for path, _ in bad:
            self.corrupt_dir.mkdir(exist_ok=True)
            stamp = datetime.datetime.now(datetime.UTC).strftime("%Y%m%dT%H%M%S")
            os.replace(path, self.corrupt_dir / f"{path.stem}.{stamp}.parquet")
        self.bad_files = bad
        if table is None:
            return set()
        ids = table.column("episode_id").to_pylist()
        foreign = sorted(set(ids) - expected) if expected is not None else []
        if foreign:
            raise ResultStoreError(
                f"{self.root} holds {len(foreign)} episodes that this spec no longer derives "
                f"(for example {foreign[0]}): the code or the robot changed since they ran; "
                "--resume would run them again beside the old ones, pass --overwrite or "
                "another --out"
            )
        statuses = table.column("status").to_pylist()
        return {i for i, status in zip(ids, statuses, strict=True) if status not in retry}

    def _move_aside(self) -> None:
        names = [
            n for n in ("episodes", "traces", "corrupt", "sweep.json") if (self.root / n).exists()
        ]
        if not names:
            return
        stamp = datetime.datetime.now(datetime.UTC).strftime("%Y%m%dT%H%M%S")
        self.aside = self.root / f".previous-{stamp}-{os.getpid()}"
        self.aside.mkdir()
        for name in names:
            os.replace(self.root / name, self.aside / name)

    def recover_aside(self) -> None:
        """Finish what a killed --overwrite (SIGKILL, the OOM killer, a power cut) left
        undone: the results it moved aside (.previous-*) are put back if it wrote no episode
        (as `restore_aside` would have), else deleted (as `discard_aside` would have); the
        newest first, so that the last results the directory held are the ones restored."""
        for aside in sorted(self.root.glob(".previous-*"), reverse=True):
            if aside.is_dir():
                self.aside = aside
                if self.episode_files():
                    self.discard_aside()
                else:
                    self.restore_aside()

    def discard_aside(self) -> None:
        """Delete the results that --overwrite moved aside (the new sweep has started). They
        are renamed to a .trash-* folder first, so that an interrupted deletion can never be
        taken for results to restore."""
        aside, self.aside = self.aside, None
        if aside is not None:
            trash = aside.with_name(aside.name.replace(".previous-", ".trash-", 1))
            os.replace(aside, trash)
            shutil.rmtree(trash, ignore_errors=True)

    def restore_aside(self) -> None:
        """Put back the results that --overwrite moved aside (the new sweep wrote nothing)."""
        if self.aside is None:
            return
        for name in ("episodes", "traces", "corrupt", "sweep.json"):
            source = self.aside / name
            if source.exists():
                target = self.root / name
                if target.is_dir():
                    shutil.rmtree(target)
                elif target.exists():
                    target.unlink()
                os.replace(source, target)
        shutil.rmtree(self.aside, ignore_errors=True)
        self.aside = None

    # ------------------------------------------------------------------------ writing
    def write(
        self,
        row: dict[str, Any],
        trace: pd.DataFrame | None,
        footsteps: pd.DataFrame | None = None,
    ) -> None:
        """Write the trace first, then the row: a row on disk means a finished episode.
        ResultStoreError when the disk refuses (full, read-only, gone); UnrecordableResult when
        the row, trace or footsteps do not convert to the schema (nothing of the row is
        written then)."""
        try:
            self._write(row, trace, footsteps)
        except OSError as exc:
            raise ResultStoreError(_io_message(self.root, exc)) from exc
        except (pa.ArrowException, TypeError, ValueError) as exc:
            raise UnrecordableResult(f"{type(exc).__name__}: {exc}") from exc

    def _write(
        self, row: dict[str, Any], trace: pd.DataFrame | None, footsteps: pd.DataFrame | None
    ) -> None:
        episode_id = row["episode_id"]
        has_trace = trace is not None and len(trace) > 0
        # every table converted before any file is written: one that does not convert leaves
        # nothing behind (no trace without its row)
        files = []
        if has_trace and footsteps is not None:
            table = pa.Table.from_pandas(footsteps, preserve_index=False)
            files.append((table, self.traces_dir / f"{episode_id}.footsteps.parquet"))
        if has_trace:
            table = pa.Table.from_pandas(trace, preserve_index=False)
            files.append((table, self.traces_dir / f"{episode_id}.parquet"))
        table = pa.Table.from_pylist([{**row, "has_trace": has_trace}], schema=ROW_SCHEMA)
        files.append((table, self.episodes_dir / f"{episode_id}.parquet"))  # the row last
        for table, path in files:
            _atomic_write_table(table, path)

    def trace(self, episode_id: str) -> pd.DataFrame:
        return pq.read_table(self.traces_dir / f"{episode_id}.parquet").to_pandas()


def _io_message(root: Path, exc: OSError) -> str:
    """One line for a results directory that the disk refused."""
    where = f" ({exc.filename})" if exc.filename else ""
    return f"cannot write the results in {root}: {exc.strerror or exc}{where}"


def spec_differences(recorded: dict[str, Any], current: dict[str, Any]) -> list[str]:
    """The names of the fields (push.* for the push table) whose values differ between two
    spec dicts; fields that say how a sweep runs (timeouts) are not compared."""
    from bench.sweep_spec import EXECUTION_FIELDS

    def normal(value: Any) -> Any:
        return json.loads(json.dumps(value))  # tuples as lists, as sweep.json stores them

    differing = []
    for name in sorted(set(recorded) | set(current)):
        if name in EXECUTION_FIELDS:
            continue
        a, b = normal(recorded.get(name)), normal(current.get(name))
        if isinstance(a, dict) and isinstance(b, dict):
            differing += [f"{name}.{k}" for k in sorted(set(a) | set(b)) if a.get(k) != b.get(k)]
        elif a != b:
            differing.append(name)
    return differing


def read_episodes(root: str | Path) -> pd.DataFrame:
    """Every valid episode row under `root` (a sweep directory), sorted by episode id
    (`scan_episodes` says which files were left out and why)."""
    table, _ = scan_episodes(root)
    if table is None:
        raise FileNotFoundError(f"no episode results under {Path(root) / 'episodes'}")
    return table.to_pandas().sort_values("episode_id", ignore_index=True)


def _atomic_write_table(table: pa.Table, path: Path) -> None:
    temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        pq.write_table(table, temporary)
        os.replace(temporary, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            temporary.unlink()


def _atomic_write_text(path: Path, text: str) -> None:
    temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        temporary.write_text(text)
        os.replace(temporary, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            temporary.unlink()
