"""Run a sweep: expand the spec, run the episodes on an executor, write each finished episode
to the result store at once, show progress (tqdm: count, ETA, falls and errors).

`run_one` is what a worker runs for one episode; it returns the summary row and the trace
(when the episode keeps one). Failures are rows: the runner records controller and simulator
failures itself, and an episode whose worker died or raised becomes a row with
status "error" and the message.
"""

from __future__ import annotations

import math
import random
import sys
import time
from collections.abc import Callable
from dataclasses import asdict
from pathlib import Path
from typing import Any

import pandas as pd

from bench.dataset import ResultStore, error_row, read_episodes, summary_row
from bench.executors import make_executor
from bench.runner import run_episode
from bench.sweep_spec import Episode, SweepSpec


def run_one(episode: Episode) -> tuple[dict[str, Any], pd.DataFrame | None]:
    """Run one episode in this process: (summary row, trace or None)."""
    begin = time.perf_counter()
    result = run_episode(episode.run)
    wall = time.perf_counter() - begin
    row = summary_row(episode.labels(), result.summary, result.trace, episode.run.duration, wall)
    return row, (result.trace if episode.keep_trace else None)


def _failure_row(episode: Episode, exc: BaseException) -> dict[str, Any]:
    run = asdict(episode.run)
    base = {k: run[k] for k in ("planner", "stabilizer", "sim", "scenario", "seed", "scale")}
    base.update(estimator=run["estimator"], friction=run["friction"])
    return error_row(episode.labels(), base, f"{type(exc).__name__}: {exc}")


def run_sweep(
    spec: SweepSpec,
    out: str | Path,
    executor: str = "local",
    workers: int | None = None,
    address: str | None = None,
    resume: bool = False,
    overwrite: bool = False,
    progress: bool = True,
    work: Callable[[Episode], tuple[dict[str, Any], pd.DataFrame | None]] = run_one,
) -> pd.DataFrame:
    """Run `spec`'s episodes (with `resume`: only those not yet in `out`) and return every
    finished episode's row in `out`. KeyboardInterrupt stops the workers; the finished
    episodes stay in `out`."""
    store = ResultStore(out)
    episodes = spec.episodes()
    store.prepare(spec.to_dict(), spec.digest(), resume=resume, overwrite=overwrite)
    finished = store.finished_ids() if resume else set()
    todo = [e for e in episodes if e.episode_id not in finished]
    random.Random(0).shuffle(todo)  # costs mixed over the run, so that the ETA holds
    # ... except that the longest episodes go first (a stable sort keeps the shuffle among
    # equals): a long walk started last would leave the other workers idle at the end.
    todo.sort(key=_longest_first)
    runner = make_executor(executor, workers=workers, address=address)
    bar = _progress(len(episodes), len(episodes) - len(todo), progress)
    falls = errors = 0
    try:
        for episode, result in runner.map_unordered(work, todo):
            if isinstance(result, BaseException):
                row, trace = _failure_row(episode, result), None
            else:
                row, trace = result
            store.write(row, trace)
            falls += row["status"] == "fell"
            errors += row["status"] == "error"
            if bar is not None:
                bar.set_postfix(fell=falls, errors=errors, refresh=False)
                bar.update(1)
    finally:
        runner.close()
        if bar is not None:
            bar.close()
    return read_episodes(out)


def _longest_first(episode: Episode) -> float:
    """Sort key: minus the simulated time [s]; a scenario's own length (duration None, the
    walks) counts as the longest."""
    duration = episode.run.duration
    return -math.inf if duration is None else -duration


def _progress(total: int, done: int, enabled: bool):
    if not enabled:
        return None
    from tqdm import tqdm

    return tqdm(
        total=total,
        initial=done,
        unit="episode",
        file=sys.stderr,
        dynamic_ncols=True,
        smoothing=0.05,
    )
