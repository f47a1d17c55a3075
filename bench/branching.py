"""Pushed episodes that share everything before their first push, run once up to it.

The push protocols run many episodes that differ only in their push (20 directions per level,
several levels): the same controller, simulator, robot, scenario, seed and push time. Up to
the push they are the same computation, period for period. `run_group` runs that common part
once and then forks the process at the push time, once per episode: each child continues
with its own pushes, sends its result back through a pipe and exits; the parent waits for
each child in turn (one process computes at a time, so a worker still uses one core) and runs
no episode of its own, so that nothing one episode does (a hang, an exception) can take the
others' results with it. A forked child is a copy of the process, simulator
state, controller state, random generators and trace included, so every episode's result is
the one it would have had alone, bit for bit (`tests/bench/test_branching.py`; only the
wall-clock timings differ, as between any two runs). The wall-clock time an episode reports
is its own: the common part plus its own continuation, not the time spent waiting for the
others.

A child that overruns its wall-clock budget (its episode's, less the common part's time) is
killed and becomes an `EpisodeTimeout` with the stage and simulated time it had reached; one
that dies becomes a `RuntimeError` with its exit, and one that cannot be forked a
`RuntimeError` saying so; either way the other episodes of the group go on. An episode that
ends before the push time (a fall, an error) ends every episode of its group the same way, as
each would alone.

Linux only (`can_fork`); `branch_key` says which episodes may share a run.
"""

from __future__ import annotations

import contextlib
import ctypes
import gc
import math
import os
import pickle
import select
import signal
import sys
import time
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

from bench.executors import SPLIT_SLOT, EpisodeTimeout, progress_stage

BRANCHED_SCENARIOS = ("stand_push", "walk_push")
"""Scenarios whose episodes differ only in their push (impulse and direction)."""

PUSH_TIMING_DELAY_PERIODS = 5
"""A pushed episode of `BRANCHED_SCENARIOS` is timed from this many control periods after the
period its first push is applied in, branched or run alone (`bench.runner`; 10 ms at 2 ms),
so that a branch's timings leave out the periods right after its fork. A forked child first
runs on the parent's memory pages and copies each page it writes to (copy-on-write): measured
(2026-11-29, `preview_control` walking pushes in MuJoCo, each branch against the same episode
run alone right after it, 10 pairs), the first period after the fork took a median 8.5x the
same period run alone (4.3-9.6x), periods 1-4 1.6x, 5-49 1.4x and 50-199 1.2x; from 200 on
1.0x. With the collector's objects frozen before the fork (`gc.freeze`, as `Brancher.split`
does: a collection in the child otherwise writes to every tracked object's header), 6.1x, 1.4x,
1.0x and 1.0x. The first period's copying cannot be avoided (the child writes to every object
it uses); leaving out the first 5 periods leaves out most of it, in both ways of running."""


def can_fork() -> bool:
    """Whether this platform branches episodes: Linux only (os.fork, and PR_SET_PDEATHSIG so
    that no branch outlives the worker that forked it)."""
    return hasattr(os, "fork") and sys.platform.startswith("linux")


def branch_key(spec: Any) -> Any | None:
    """What an `EpisodeSpec` shares with the episodes it may branch from: the spec without
    its push impulse and direction (the push's time, step and swing fraction stay: they decide
    where the common part ends); None for a scenario without a protocol push."""
    if spec.scenario not in BRANCHED_SCENARIOS:
        return None
    return replace(spec, push_impulse=None, push_direction_deg=None, push_direction_name=None)


class Brancher:
    """Forks an episode at its first push, once per episode of its group (`count` episodes;
    `budgets_s`: their wall-clock budgets [s]). The runner gives it every episode's pushes
    (`prepare`) and asks each period whether the push is `due`; after `split`, a child runs
    episode `index`, the parent holds every episode's result in `results`."""

    def __init__(self, count: int, budgets_s: Sequence[float], progress: Any) -> None:
        if len(budgets_s) != count:
            raise ValueError(f"{count} episodes but {len(budgets_s)} budgets")
        self.budgets_s = list(budgets_s)
        self.progress = progress
        self.pending: list[list] = []
        self.index = 0
        self.results: list[Any] = [None] * count
        self.waited_s = 0.0  # [s] wall-clock time this process spent not running its episode
        self.split_done = False
        self._write_fd: int | None = None

    def prepare(self, pending: Sequence[list]) -> None:
        """Every episode's pushes (time order); their first pushes must come at one time."""
        if len(pending) != len(self.results):
            raise ValueError(f"{len(self.results)} episodes but {len(pending)} push lists")
        if any(not p for p in pending) or len({p[0].time for p in pending}) != 1:
            raise ValueError("branched episodes need a first push at one and the same time")
        self.pending = [list(p) for p in pending]

    def due(self, until: float) -> bool:
        """Whether the group's first push comes before `until` [s] and has not been split."""
        return not self.split_done and bool(self.pending) and self.pending[0][0].time < until

    @property
    def is_child(self) -> bool:
        """Whether this process is a branch (it runs episode `index` and then exits)."""
        return self._write_fd is not None

    def split(self, common_s: float) -> list:
        """Fork one child per episode and return its pushes in it; in the parent, wait for
        each child in turn (each held to its budget less `common_s`, the wall-clock time [s]
        of the common part already spent) and raise `BranchesDone`: the parent runs no
        episode of its own, so that nothing one episode does can take the others' results."""
        self.split_done = True
        if self.progress is not None and len(self.progress) > SPLIT_SLOT:
            self.progress[SPLIT_SLOT] = 1.0  # the executor now holds this to the group's budget
        begin = time.perf_counter()
        parent = os.getpid()
        # before each fork, the objects so far (the earlier branches' results too) out of the
        # collector's reach in the child, whose collections would otherwise write to (and so
        # copy) every page holding a tracked object (`PUSH_TIMING_DELAY_PERIODS`); the parent
        # unfreezes them however it leaves (a child returns from inside the loop, frozen)
        was_frozen = gc.get_freeze_count() > 0
        try:
            for index in range(len(self.pending)):
                started = time.perf_counter()
                gc.freeze()
                try:
                    read_fd, write_fd = os.pipe()
                    try:
                        pid = os.fork()
                    except OSError:
                        os.close(read_fd)
                        os.close(write_fd)
                        raise
                except OSError as exc:  # no process or pipe for this one: its result says so
                    self.results[index] = RuntimeError(f"could not branch the episode: {exc}")
                    continue
                if pid == 0:  # the child: episode `index`
                    os.close(read_fd)
                    self.index, self._write_fd = index, write_fd
                    _die_with_parent(parent)
                    self.waited_s = time.perf_counter() - begin
                    return self.pending[index]
                os.close(write_fd)
                budget = self.budgets_s[index] - common_s
                self.results[index] = self._collect(pid, read_fd, started, budget)
        finally:
            if os.getpid() == parent and not was_frozen:
                gc.unfreeze()
        raise BranchesDone

    def finish_child(self, result: Any) -> None:
        """In a child: send `result` to the parent and exit (never returns)."""
        assert self._write_fd is not None
        try:
            try:
                data = pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL)
                if isinstance(result, BaseException):  # its class may not rebuild from args
                    pickle.loads(data)
            except Exception as exc:  # a result that does not pickle, or not back
                if isinstance(result, BaseException):
                    what = f"{type(result).__name__}: {result}"
                else:
                    what = f"the result could not be sent: {type(exc).__name__}: {exc}"
                data = pickle.dumps(RuntimeError(what))
            view = memoryview(data)
            while view:
                view = view[os.write(self._write_fd, view) :]
        finally:
            os._exit(0)

    def _collect(self, pid: int, fd: int, started: float, budget_s: float) -> Any:
        """The child's result, or the exception that stands for it (timeout, death). The
        child is reaped however this ends."""
        chunks = []
        status = None
        try:
            while True:
                left = budget_s - (time.perf_counter() - started)
                if left <= 0:
                    stage = progress_stage(self.progress[0]) if self.progress is not None else None
                    sim_time = float(self.progress[1]) if self.progress is not None else None
                    return EpisodeTimeout(budget_s, stage, sim_time)
                ready, _, _ = select.select([fd], [], [], min(left, 1.0))
                if not ready:
                    continue
                chunk = os.read(fd, 1 << 20)
                if not chunk:
                    break
                chunks.append(chunk)
            _, status = os.waitpid(pid, 0)
        finally:
            os.close(fd)
            if status is None:  # timed out, or interrupted: the child goes
                with contextlib.suppress(ProcessLookupError):
                    os.kill(pid, signal.SIGKILL)
                with contextlib.suppress(ChildProcessError):
                    os.waitpid(pid, 0)
        if chunks:
            with contextlib.suppress(Exception):
                return pickle.loads(b"".join(chunks))
        if os.WIFSIGNALED(status):
            number = os.WTERMSIG(status)
            try:
                name = signal.Signals(number).name
            except ValueError:  # a signal the enum does not name (real-time signals)
                name = f"signal {number}"
            how = f"was killed by {name}"
        else:
            how = f"exited with status {os.WEXITSTATUS(status)}"
        return RuntimeError(f"the episode's branch process {how} without a result")


def _die_with_parent(parent: int) -> None:
    """A child ends when the process that forked it (`parent`, its pid) does: SIGKILL from the
    kernel (Linux PR_SET_PDEATHSIG), and at once if the parent died before that took effect."""
    with contextlib.suppress(Exception):
        ctypes.CDLL(None).prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG
    if os.getppid() != parent:
        os._exit(1)


class BranchesDone(BaseException):
    """Raised in the parent once every branch has ended: it leaves the episode loop (through
    its clean-up, past its `except Exception`) to return the branches' results."""


def run_group(
    specs: Sequence[Any], progress: Any = None, budgets_s: Sequence[float] | None = None
) -> list[Any]:
    """Run the episodes `specs` (all with the same `branch_key`) as one run up to their first
    push: their `EpisodeResult`s in order, or for an episode whose branch overran its budget
    (`budgets_s`, wall-clock seconds each; default none) or died, the exception."""
    from bench.runner import run_episode

    keys = {branch_key(spec) for spec in specs}
    if len(keys) != 1 or None in keys:
        raise ValueError("run_group: the episodes must share one branch_key")
    if budgets_s is None:
        budgets_s = [math.inf] * len(specs)
    return run_episode(specs[0], progress=progress, branches=(list(specs), list(budgets_s)))
