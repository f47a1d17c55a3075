"""Run a sweep: expand the spec, run the episodes on an executor, write each finished episode
to the result store at once, show progress (tqdm: count, ETA, falls and errors).

`run_one` is what a worker runs for one episode; it returns the summary row and the trace
(when the episode keeps one). Failures are rows: the runner records controller and simulator
failures itself, an episode whose worker died or raised becomes a row with status "error" and
the message, and one that overran its wall-clock budget (`SweepSpec.wall_budget_s` of its
simulated duration) a row with status "timeout", the stage it was in and the simulated time it
reached.

What a sweep checks before it touches its result directory: the spec (by the caller), the
executor and its address (a bounded TCP check), the directory's writability and the resume
rules (`bench.dataset.ResultStore.prepare`). SIGTERM ends a sweep like Ctrl-C: the workers are
stopped and every finished episode stays.
"""

from __future__ import annotations

import collections
import contextlib
import functools
import math
import random
import signal
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from bench.branching import branch_key, can_fork, run_group
from bench.dataset import (
    RETRIED_STATUSES,
    ResultStore,
    UnrecordableResult,
    failure_row,
    read_episodes,
    summary_row,
)
from bench.executors import EpisodeTimeout, make_executor, worker_progress
from bench.push_protocol import robot_mass
from bench.runner import EpisodeResult, run_episode
from bench.sweep_spec import Episode, SweepSpec
from robots.perturbation import NOMINAL
from robots.robot_registry import DEFAULT_ROBOT, make_robot


def run_one(episode: Episode) -> tuple[dict[str, Any], pd.DataFrame | None, pd.DataFrame | None]:
    """Run one episode in this process: (summary row, trace or None, footsteps or None; both
    only for the episodes that keep a trace). In a local worker the episode publishes its
    stage and simulated time for the parent's timeout handling."""
    begin = time.perf_counter()
    result = run_episode(episode.run, progress=worker_progress())
    return _row(episode, result, time.perf_counter() - begin)


def _row(
    episode: Episode, result: EpisodeResult, wall_s: float | None
) -> tuple[dict[str, Any], pd.DataFrame | None, pd.DataFrame | None]:
    row = summary_row(episode.labels(), result.summary, result.trace, episode.run.duration, wall_s)
    if not episode.keep_trace:
        return row, None, None
    return row, result.trace, result.footsteps


@dataclass(frozen=True)
class EpisodeGroup:
    """Episodes that differ only in their push (`bench.branching.branch_key`), run as one up to
    the push, and their wall-clock budgets [s]."""

    episodes: tuple[Episode, ...]
    budgets_s: tuple[float, ...]

    @property
    def protocol(self) -> str | None:
        return self.episodes[0].protocol

    @property
    def split_budget_s(self) -> float:
        """[s] the budget until the group splits at its push (`bench.executors.SPLIT_SLOT`):
        one episode's, which the shared part is a part of (a hang before the push is caught
        after it, not after the sum of the group's)."""
        return self.budgets_s[0]


def run_branched(group: EpisodeGroup) -> list[Any]:
    """Run `group` in this process (`bench.branching.run_group`): per episode, what `run_one`
    returns, or the exception of a branch that overran its budget or died."""
    results = run_group(
        [episode.run for episode in group.episodes], worker_progress(), group.budgets_s
    )
    return [
        result if isinstance(result, BaseException) else _row(episode, result, result.wall_s)
        for episode, result in zip(group.episodes, results, strict=True)
    ]


BRANCH_GROUP_SIZE = 20
"""At most this many episodes branch from one run (a push protocol's level): larger groups
would save little more (one common part per 20 episodes) and would leave a worker idle at the
end of a sweep while the other finishes a long group, and the progress bar would move in
large jumps."""


def group_for_branching(
    episodes: list[Episode],
    budget: Callable[[Episode], float],
    size: int = BRANCH_GROUP_SIZE,
) -> list[Episode | EpisodeGroup]:
    """`episodes` with those that share a protocol and a `branch_key` gathered into groups of
    at most `size`, each at the place of its first episode (the order is otherwise kept)."""
    groups: dict[Any, list[Episode]] = {}
    order: list[Any] = []
    for episode in episodes:
        key = branch_key(episode.run)
        key = (episode.protocol, key) if key is not None else ("single", episode.episode_id)
        if key not in groups:
            groups[key] = []
            order.append(key)
        groups[key].append(episode)
    items: list[Episode | EpisodeGroup] = []
    for key in order:
        members = groups[key]
        for start in range(0, len(members), size):
            chunk = members[start : start + size]
            if len(chunk) == 1:
                items.append(chunk[0])
            else:
                items.append(EpisodeGroup(tuple(chunk), tuple(budget(e) for e in chunk)))
    return items


def _work_on(item: Episode | EpisodeGroup) -> Any:
    """What a worker runs for a sweep item: one episode, or a group of branched ones."""
    return run_branched(item) if isinstance(item, EpisodeGroup) else run_one(item)


def _failure_row(episode: Episode, exc: BaseException) -> dict[str, Any]:
    run = asdict(episode.run)
    base = {
        k: run[k] for k in ("robot", "planner", "stabilizer", "sim", "scenario", "seed", "scale")
    }
    base.update(
        estimator=run["estimator"],
        friction=run["friction"],
        whole_body=run["whole_body"],
        speed=run["speed"],
        replica=run["replica"],
        requested_duration=run["duration"],
        mass_kg=_nominal_mass(run["scale"], run["robot"]),
        **(episode.run.perturbation or NOMINAL).columns(),
    )
    if isinstance(exc, NotApplicable):
        return failure_row(episode.labels(), base, f"n/a: {exc}", status="n/a")
    if isinstance(exc, EpisodeTimeout):
        return failure_row(
            episode.labels(),
            base,
            f"timeout: {exc}",
            status="timeout",
            stage=exc.stage,
            duration=exc.sim_time_s,
        )
    return failure_row(episode.labels(), base, f"{type(exc).__name__}: {exc}")


def _nominal_mass(scale: float, robot: str) -> float | None:
    """The robot's total mass [kg] as the runner records it (`mass_kg`), or None when the
    robot cannot be built (a failure row must never fail)."""
    try:
        return robot_mass(scale, robot)
    except Exception:
        return None


class NotApplicable(Exception):
    """The controller cannot run the scenario (`bench.controllers.refusal`): recorded as an
    "n/a" row with the reason, never run."""


@functools.cache
def simulated_duration(
    scenario: str, scale: float, duration: float | None, robot: str = DEFAULT_ROBOT
) -> float:
    """Simulated seconds of an episode: `duration`, or the scenario's own length."""
    if duration is not None:
        return duration
    from bench.scenarios import make_scenario
    from robots.model import RobotModel

    return float(make_scenario(scenario, RobotModel(make_robot(robot, scale))).duration)


class SweepTerminated(KeyboardInterrupt):
    """SIGTERM reached the sweep: handled like Ctrl-C (workers stopped, results kept)."""


@contextlib.contextmanager
def terminate_as_interrupt() -> Iterator[None]:
    """Within the block, SIGTERM raises `SweepTerminated` (main thread only)."""
    try:
        previous = signal.signal(signal.SIGTERM, _raise_terminated)
    except ValueError:  # not the main thread: leave signals alone
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _raise_terminated(signum: int, frame: Any) -> None:
    raise SweepTerminated("SIGTERM")


def run_sweep(
    spec: SweepSpec,
    out: str | Path,
    executor: str = "local",
    workers: int | None = None,
    address: str | None = None,
    resume: bool = False,
    overwrite: bool = False,
    progress: bool = True,
    work: Callable[[Episode], tuple] = run_one,
    retry_errors: bool = False,
    on_start: Callable[[int, int, list[str]], None] | None = None,
    branching: bool = True,
) -> pd.DataFrame:
    """Run `spec`'s episodes (with `resume`: only those not yet in `out`; with
    `retry_errors` also those that ended in an error or a timeout) and return every finished
    episode's row in `out`. KeyboardInterrupt or SIGTERM stops the workers; the finished
    episodes stay in `out`. Everything is checked before `out` is touched: ValueError for the
    arguments and the executor, `ResultStoreError` for the directory. `on_start(total,
    to_run, notes)` is called once they have passed, before the first episode runs (`notes`:
    the corrupt episode files a resume moved aside).

    `branching`: episodes that differ only in their push run as one up to it
    (`bench.branching`; the same results, bit for bit, in less time), on the local executor
    with the default `work`; the Ray executor and a custom `work` run every episode alone."""
    if resume and overwrite:
        raise ValueError("--resume and --overwrite exclude each other")
    if retry_errors and not resume:
        raise ValueError("--retry-errors goes with --resume")
    store = ResultStore(out)
    store.check_usable()
    episodes = spec.episodes()
    counts = collections.Counter(e.episode_id for e in episodes)
    if len(counts) != len(episodes):  # one file per id: a second run would overwrite the first
        twice = next(i for i, n in counts.items() if n > 1)
        raise ValueError(f"sweep spec {spec.name!r} lists episode {twice} more than once")
    runner = make_executor(executor, workers=workers, address=address)
    bar = None
    try:
        with store.locked(), terminate_as_interrupt():
            try:
                finished = store.prepare(
                    spec.to_dict(),
                    spec.digest(),
                    resume=resume,
                    overwrite=overwrite,
                    identity=spec.identity(),
                    retry=RETRIED_STATUSES if retry_errors else (),
                    expected=set(counts),
                )
                todo = [e for e in episodes if e.episode_id not in finished]
                for episode in [e for e in todo if e.refused is not None]:  # not run: n/a
                    store.write(_failure_row(episode, NotApplicable(episode.refused)), None)
                    store.discard_aside()
                todo = [e for e in todo if e.refused is None]
                random.Random(0).shuffle(todo)  # costs mixed over the run: the ETA holds
                # ... except that the longest episodes go first (a stable sort keeps the
                # shuffle among equals): a long walk started last would leave workers idle;
                # a job's protocols run one after the other, in the spec's order.
                order = {protocol.name: k for k, protocol in enumerate(spec.protocols)}
                todo.sort(key=lambda e: (order.get(e.protocol, 0), _longest_first(e)))
                if on_start is not None:
                    notes = [f"{p.name} moved to corrupt/: {why}" for p, why in store.bad_files]
                    on_start(len(episodes), len(todo), notes)
                bar = _progress(len(episodes), len(episodes) - len(todo), progress)
                budget = _budget(spec)
                items: list[Any] = list(todo)
                if branching and work is run_one and executor == "local" and can_fork():
                    items, work = group_for_branching(todo, budget), _work_on
                results = runner.map_unordered(work, items, budget=_item_budget(budget))
                with contextlib.closing(results):  # its workers stop even on an exception
                    _run_episodes(results, store, bar, _protocol_counts(episodes))
            except BaseException:
                store.restore_aside()  # no-op once an episode was written
                raise
            store.discard_aside()
    finally:
        runner.close()
        if bar is not None:
            bar.close()
    return read_episodes(out)


def _protocol_counts(episodes: list[Episode]) -> dict[str, int]:
    """A job's episodes per protocol, in the job's order (empty for a sweep of one)."""
    counts: dict[str, int] = {}
    for episode in episodes:
        if episode.protocol is not None:
            counts[episode.protocol] = counts.get(episode.protocol, 0) + 1
    return counts


def _run_episodes(
    results: Iterator[tuple[Episode, Any]],
    store: ResultStore,
    bar,
    protocols: dict[str, int] | None = None,
) -> None:
    """Write every result as it comes (a failure as its row) and advance the progress bar;
    for a job, the bar names the protocol of the episode that finished last ("k/n name")."""
    falls = errors = 0
    names = list(protocols or {})
    for item, outcome in results:
        if isinstance(item, EpisodeGroup):  # a failed group (its worker died, or it overran)
            pairs = zip(item.episodes, _per_episode(item, outcome), strict=True)
        else:
            pairs = iter([(item, outcome)])
        for episode, result in pairs:
            if isinstance(result, BaseException):
                row, trace, footsteps = _failure_row(episode, result), None, None
            else:
                row, trace, *rest = result  # (row, trace[, footsteps])
                footsteps = rest[0] if rest else None
            try:
                store.write(row, trace, footsteps)
            except UnrecordableResult as exc:  # recorded as what it is, not lost each resume
                row = _failure_row(episode, RuntimeError(f"result could not be recorded: {exc}"))
                store.write(row, None, None)
            store.discard_aside()  # the new sweep has started: the old results go
            falls += row["status"] == "fell"
            errors += row["status"] in RETRIED_STATUSES
            if bar is not None:
                if episode.protocol in names:
                    bar.set_description(
                        f"{names.index(episode.protocol) + 1}/{len(names)} {episode.protocol}",
                        refresh=False,
                    )
                bar.set_postfix(fell=falls, errors=errors, refresh=False)
                bar.update(1)


def _per_episode(group: EpisodeGroup, outcome: Any) -> list[Any]:
    """A group's results per episode: the worker's list, or its one failure for every episode
    (the worker died, or the group overran the sum of its episodes' budgets)."""
    if isinstance(outcome, BaseException):
        return [outcome] * len(group.episodes)
    return list(outcome)


def _budget(spec: SweepSpec) -> Callable[[Episode], float]:
    """An episode's wall-clock budget [s] (`SweepSpec.wall_budget_s`)."""

    def budget(episode: Episode) -> float:
        run = episode.run
        return spec.wall_budget_s(
            simulated_duration(run.scenario, run.scale, run.duration, run.robot)
        )

    return budget


def _item_budget(budget: Callable[[Episode], float]) -> Callable[[Any], float]:
    """A sweep item's wall-clock budget [s]: an episode's, or the sum of a group's (each of
    its branches is held to its own inside the worker)."""

    def item_budget(item: Episode | EpisodeGroup) -> float:
        return sum(item.budgets_s) if isinstance(item, EpisodeGroup) else budget(item)

    return item_budget


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
