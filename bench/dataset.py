"""A sweep's results on disk: a Parquet dataset written as episodes finish.

    DIR/sweep.json                      the spec (and its digest) the results belong to
    DIR/episodes/<episode_id>.parquet   one summary row per finished episode (`ROW_SCHEMA`)
    DIR/traces/<episode_id>.parquet     the per-period trace, for the episodes that keep one

Each file is written to a temporary name and renamed, so a file that exists is complete: an
interrupted sweep keeps every finished episode, and `--resume` runs only the missing ids.
`read_episodes(DIR)` reads the summary rows as one DataFrame (pyarrow dataset).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from bench.metrics import feedback_magnitude, walking_quality

LATENCY_STAGES = (
    "estimator",
    "planner",
    "stabilizer",
    "whole_body",
    "sim",
    "control_total",
    "reference",
    "preview",
    "projection",
    "distribution",
    "centroidal_total",
)

_STRING, _FLOAT, _INT, _BOOL = pa.string(), pa.float64(), pa.int64(), pa.bool_()
ROW_SCHEMA = pa.schema(
    [
        ("episode_id", _STRING),
        ("controller", _STRING),
        ("planner", _STRING),
        ("stabilizer", _STRING),
        ("sim", _STRING),
        ("scenario", _STRING),
        ("seed", _INT),
        ("estimator", _STRING),
        ("scale", _FLOAT),
        ("friction", _FLOAT),
        ("mass_kg", _FLOAT),
        ("push_phase", _STRING),
        ("push_dv_mps", _FLOAT),
        ("push_index", _INT),
        ("push_time_s", _FLOAT),
        ("push_step", _INT),
        ("push_impulse_Ns", _FLOAT),
        ("push_direction_deg", _FLOAT),
        ("status", _STRING),
        ("error", _STRING),
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
        ("e_com", _FLOAT),
        ("e_zmp", _FLOAT),
        ("e_velocity", _FLOAT),
        *[(f"lat_{s}_median_us", _FLOAT) for s in LATENCY_STAGES],
        *[(f"lat_{s}_p99_us", _FLOAT) for s in LATENCY_STAGES],
        ("has_trace", _BOOL),
        ("centrobench_version", _STRING),
        ("versions_json", _STRING),
        ("git_commit", _STRING),
        ("cpu", _STRING),
    ]
)
# columns that depend on the machine's speed, not on the simulated physics
TIMING_COLUMNS = tuple(
    name
    for name in ROW_SCHEMA.names
    if name.startswith("lat_") or name in ("wall_s", "real_time_factor")
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
    for key in (
        "planner",
        "stabilizer",
        "sim",
        "scenario",
        "seed",
        "estimator",
        "scale",
        "friction",
        "mass_kg",
        "status",
        "error",
        "fell",
        "fall_time",
        "fall_reason",
        "duration",
        "real_time_factor",
        "com_error_rms_m",
        "zmp_margin_min_m",
        "solver_failures",
        "git_commit",
        "cpu",
    ):
        if key in summary:
            row[key] = summary[key]
    row.update(summary.get("projection_error") or {})
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
        row.update(walking_quality(trace))
        row.update(feedback_magnitude(trace))
    if labels.get("push_phase") is not None:
        # survival: no fall (and no error) before the end, 3 s after the push
        complete = requested_duration is None or row["duration"] >= requested_duration - 1e-6
        row["survived"] = row["status"] == "ok" and complete
    return row


def error_row(labels: dict[str, Any], base: dict[str, Any], message: str) -> dict[str, Any]:
    """The row of an episode that produced no summary (its worker died, or it raised)."""
    row: dict[str, Any] = {name: None for name in ROW_SCHEMA.names}
    row.update(base)
    row.update(labels)
    row.update(status="error", error=message, fell=False)
    if labels.get("push_phase") is not None:
        row["survived"] = False
    return row


class ResultStore:
    """The directory of one sweep's results (see the module docstring)."""

    def __init__(self, root: str | Path) -> None:
        self.root = Path(root)
        self.episodes_dir = self.root / "episodes"
        self.traces_dir = self.root / "traces"

    def prepare(self, spec: dict[str, Any], digest: str, resume: bool, overwrite: bool) -> None:
        """Create the directory for `spec`. An existing directory with results is an error
        unless `resume` (same spec only) or `overwrite` (its results are deleted)."""
        existing = self.finished_ids()
        recorded = self.spec_record()
        if existing and not (resume or overwrite):
            raise FileExistsError(
                f"{self.root} already holds {len(existing)} episodes; pass --resume to complete "
                "that sweep or --overwrite to start again"
            )
        if resume and recorded is not None and recorded.get("digest") != digest:
            raise FileExistsError(
                f"{self.root} holds the results of another spec (digest "
                f"{recorded.get('digest')}); --resume needs the same spec (digest {digest})"
            )
        if overwrite:
            for folder in (self.episodes_dir, self.traces_dir):
                for path in folder.glob("*.parquet") if folder.exists() else ():
                    path.unlink()
        self.episodes_dir.mkdir(parents=True, exist_ok=True)
        self.traces_dir.mkdir(parents=True, exist_ok=True)
        _atomic_write_text(
            self.root / "sweep.json", json.dumps({"digest": digest, "spec": spec}, indent=2)
        )

    def spec_record(self) -> dict | None:
        path = self.root / "sweep.json"
        return json.loads(path.read_text()) if path.exists() else None

    def finished_ids(self) -> set[str]:
        if not self.episodes_dir.exists():
            return set()
        return {p.stem for p in self.episodes_dir.glob("*.parquet")}

    def write(self, row: dict[str, Any], trace: pd.DataFrame | None) -> None:
        """Write the trace first, then the row: a row on disk means a finished episode."""
        episode_id = row["episode_id"]
        if trace is not None and len(trace):
            table = pa.Table.from_pandas(trace, preserve_index=False)
            _atomic_write_table(table, self.traces_dir / f"{episode_id}.parquet")
            row = {**row, "has_trace": True}
        else:
            row = {**row, "has_trace": False}
        table = pa.Table.from_pylist([row], schema=ROW_SCHEMA)
        _atomic_write_table(table, self.episodes_dir / f"{episode_id}.parquet")

    def trace(self, episode_id: str) -> pd.DataFrame:
        return pq.read_table(self.traces_dir / f"{episode_id}.parquet").to_pandas()


def read_episodes(root: str | Path) -> pd.DataFrame:
    """Every finished episode's row under `root` (a sweep directory), sorted by episode id."""
    folder = Path(root) / "episodes"
    if not folder.exists() or not any(folder.glob("*.parquet")):
        raise FileNotFoundError(f"no episode results under {folder}")
    frame = pq.read_table(folder, schema=ROW_SCHEMA).to_pandas()
    return frame.sort_values("episode_id", ignore_index=True)


def _atomic_write_table(table: pa.Table, path: Path) -> None:
    temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    pq.write_table(table, temporary)
    os.replace(temporary, path)


def _atomic_write_text(path: Path, text: str) -> None:
    temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    temporary.write_text(text)
    os.replace(temporary, path)
