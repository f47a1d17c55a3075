"""The per-episode stage times the runner summarises (`bench.runner._latency`)."""

import math

import numpy as np
import pandas as pd

from bench.runner import MIN_P99_SAMPLES, _latency


def test_a_stage_timed_over_fewer_than_100_periods_has_no_p99_only_its_maximum():
    """At 41 periods (an episode that fell at 0.082 s) the 99th percentile lies between the two
    largest times: it is not stated; from 100 periods on it is numpy's percentile."""
    rng = np.random.default_rng(0)
    short = pd.DataFrame({"t_planner_us": rng.uniform(50, 150, 41)})
    summary = _latency(short)["planner"]
    assert math.isnan(summary["p99"])
    assert summary["max"] == short["t_planner_us"].max()
    assert summary["median"] == np.median(short["t_planner_us"])
    times = rng.uniform(50, 150, MIN_P99_SAMPLES)
    assert _latency(pd.DataFrame({"t_planner_us": times}))["planner"]["p99"] == np.percentile(
        times, 99
    )


def test_a_summary_with_a_p99_not_stated_prints_as_strict_json():
    """`run --json` prints a NaN as null (Python's `NaN` token is not JSON: jq refuses it)."""
    import json

    from bench.cli import strict_json

    summary = {"latency_us": {"planner": {"p99": math.nan, "max": 3.0}}, "times": [1.0, math.inf]}
    text = json.dumps(strict_json(summary), allow_nan=False)
    assert json.loads(text) == {
        "latency_us": {"planner": {"p99": None, "max": 3.0}},
        "times": [1.0, None],
    }
