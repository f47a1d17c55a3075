"""Result files: Parquet with explicit dtypes, provenance in the file's metadata."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq


def write_trace(trace: pd.DataFrame, summary: dict, path: str | Path) -> Path:
    """Write an episode's per-period trace to Parquet; the summary (with versions, commit and
    CPU) goes into the file's key-value metadata under b"centrobench_summary"."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    table = pa.Table.from_pandas(trace, preserve_index=False)
    metadata = dict(table.schema.metadata or {})
    metadata[b"centrobench_summary"] = json.dumps(summary).encode()
    pq.write_table(table.replace_schema_metadata(metadata), path)
    return path


def read_trace(path: str | Path) -> tuple[pd.DataFrame, dict]:
    """The trace and the summary written by `write_trace`."""
    table = pq.read_table(path)
    summary = json.loads(table.schema.metadata[b"centrobench_summary"])
    return table.to_pandas(), summary
