"""A result row for hand-made report fixtures: every column of `bench.dataset.ROW_SCHEMA`, None
unless given, with the provenance columns a result file carries and a nominal episode's
defaults."""

from __future__ import annotations

import json

from bench.dataset import ROW_SCHEMA


def result_row(**values) -> dict:
    row = {name: None for name in ROW_SCHEMA.names}
    row.update(
        versions_json=json.dumps({"mujoco": "4.0.0"}),
        git_commit="abc123",
        cpu="test CPU",
        seed=0,
        scale=1.0,
        perturbation="nominal",
        replica=0,
    )
    row.update(values)
    return row
