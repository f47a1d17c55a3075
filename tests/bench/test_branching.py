"""Pushed episodes branched from one run at the push time (`bench.branching`): the same
results as run alone, bit for bit; a branch that hangs or dies takes only itself; a sweep
with branching writes the rows of one without."""

from __future__ import annotations

import gc
import os
import pickle
import signal
from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import pytest

from bench.branching import (
    PUSH_TIMING_DELAY_PERIODS,
    Brancher,
    BranchesDone,
    branch_key,
    run_group,
)
from bench.executors import EpisodeTimeout
from bench.runner import EpisodeSpec, run_episode
from bench.sweep import EpisodeGroup, group_for_branching, run_sweep
from tests.bench.test_sweep import physical, small_spec

TIMING_KEYS = {"latency_us", "latency_by_contacts_us", "real_time_factor", "worker"}
"""Summary entries that differ between any two runs of an episode (wall-clock timings, and
the process that ran it)."""


def _pushes(sim: str, scenario: str = "stand_push", **extra) -> list[EpisodeSpec]:
    """Three episodes of one controller that differ only in the push's direction (one of them
    survives, two fall: the branches part ways)."""
    if scenario == "stand_push":
        extra = {"duration": 3.0, "push_time": 1.5, **extra}
    return [
        EpisodeSpec(
            "preview_control",
            "centroidal_feedback",
            sim,
            scenario,
            push_impulse=21.0,
            push_direction_deg=direction,
            **extra,
        )
        for direction in (0.0, 90.0, 200.0)
    ]


def _assert_same(branched, alone) -> None:
    timings = [c for c in alone.trace.columns if c.startswith("t_")]
    assert branched.trace.drop(columns=timings).equals(alone.trace.drop(columns=timings))
    for key in alone.summary.keys() - TIMING_KEYS:
        assert repr(branched.summary[key]) == repr(alone.summary[key]), key
    if alone.footsteps is None:
        assert branched.footsteps is None
    else:
        assert branched.footsteps.equals(alone.footsteps)


@pytest.mark.parametrize(
    ("sim", "scenario"),
    [("mujoco", "stand_push"), ("pybullet", "stand_push"), ("mujoco", "walk_push")],
)
def test_branched_episodes_are_the_episodes_run_alone_bit_for_bit(sim, scenario):
    """preview_control + centroidal_feedback, pushed from three directions at one time: the
    group's results equal the three episodes run one by one (traces, footsteps and summaries,
    but for the wall-clock timings), and they differ from each other after the push."""
    specs = _pushes(sim, scenario)
    branched = run_group(specs)
    alone = [run_episode(spec) for spec in specs]
    for b, a in zip(branched, alone, strict=True):
        _assert_same(b, a)
    assert len({round(r.trace["com_actual_y"].iloc[-1], 9) for r in alone}) == 3
    for result in branched:  # each reports its own wall-clock time, not the group's
        assert 0 < result.wall_s < sum(r.wall_s for r in branched)
    # ... and times its own periods: from just after the push on (not the copies of the
    # group's before, nor the fork's first periods); run alone, the same window
    # (`_assert_same` compared timed_from_s)
    push_time = specs[0].push_time if scenario == "stand_push" else None
    for b, a in zip(branched, alone, strict=True):
        start = b.summary["timed_from_s"]
        assert start > 0
        if push_time is not None:
            delay = PUSH_TIMING_DELAY_PERIODS * 0.002
            assert abs(start - (push_time + delay)) < 0.002 + 1e-9
        for result in (b, a):
            own = result.trace["t_control_total_us"][result.trace["time"] >= start - 1e-9]
            assert 0 < len(own) < len(result.trace)
            median = result.summary["latency_us"]["control_total"]["median"]
            assert median == pytest.approx(float(own.median()), rel=1e-12)


def test_a_branch_over_its_budget_ends_alone_as_a_timeout():
    """The second episode's budget is 1 ms, less than its common part took: its branch is
    ended and becomes an `EpisodeTimeout` that says where it was (at the push); the others
    finish as alone. The group's results cross to the sweep's process pickled, as a pool
    worker returns them: the timeout arrives whole (it did not unpickle before 2026-11-27, and
    the sweep ended in a ValueError with the group's rows lost)."""
    specs = _pushes("mujoco")
    progress = [0.0, 0.0, 0.0]  # a worker's slot: stage, simulated time, split done
    results = pickle.loads(
        pickle.dumps(run_group(specs, progress, budgets_s=[600.0, 0.001, 600.0]))
    )
    assert progress[2] == 1.0  # the group said it split (`bench.executors.SPLIT_SLOT`)
    timeout = results[1]
    assert isinstance(timeout, EpisodeTimeout)
    assert isinstance(timeout.budget_s, float)
    assert timeout.budget_s < 0.001  # its budget less the common part it shared
    assert timeout.stage is not None
    assert timeout.sim_time_s is not None
    assert timeout.sim_time_s >= 1.5 - 1e-9  # it was forked at the push
    for k in (0, 2):
        _assert_same(results[k], run_episode(specs[k]))


@pytest.mark.parametrize("killed", [0, 1])
def test_a_branch_that_dies_takes_only_itself(monkeypatch, killed):
    """A branch process killed right after the fork is a RuntimeError naming the signal; the
    group's other episodes finish as alone (the first episode too runs in a branch of its
    own: the process that forked them runs none)."""
    split = Brancher.split

    def split_and_kill_one(self, common_s):
        pending = split(self, common_s)
        if self.index == killed:
            os.kill(os.getpid(), signal.SIGKILL)
        return pending

    monkeypatch.setattr(Brancher, "split", split_and_kill_one)
    specs = _pushes("mujoco")
    results = run_group(specs)
    assert isinstance(results[killed], RuntimeError)
    assert "SIGKILL" in str(results[killed])
    for k in {0, 1, 2} - {killed}:
        _assert_same(results[k], run_episode(specs[k]))


def test_a_branch_that_cannot_be_forked_is_an_error_and_the_others_run(monkeypatch):
    """os.fork failing for the second episode (no memory, too many processes) makes that
    episode a RuntimeError saying so; the first and the third run."""
    fork, calls = os.fork, []

    def failing_second_fork():
        calls.append(1)
        if len(calls) == 2:
            raise OSError(11, "Resource temporarily unavailable")
        return fork()

    monkeypatch.setattr(os, "fork", failing_second_fork)
    results = run_group(_pushes("mujoco"))
    assert isinstance(results[1], RuntimeError)
    assert "could not branch" in str(results[1])
    assert results[0].summary["status"] in ("ok", "fell")
    assert results[2].summary["status"] in ("ok", "fell")


def test_a_group_that_ends_before_its_push_ends_every_episode_so():
    """An episode that cannot start (an unknown estimator) ends the same way for every episode
    of its group: an error row each, never run apart."""
    specs = [replace(spec, estimator="no_such_estimator") for spec in _pushes("mujoco")]
    results = run_group(specs)
    assert len(results) == 3
    for result in results:
        assert result.summary["status"] == "error"
        assert "no_such_estimator" in result.summary["error"]
        assert result.summary["timed_from_s"] is None  # one run's copies, not its own


def test_a_group_whose_robot_falls_before_the_push_times_one_run_for_all():
    """hold + posture cannot walk: its walking-push group falls before the push, and every
    episode is a copy of that one run, whose timings are no episode's own."""
    specs = [
        replace(spec, planner="hold", stabilizer="posture")
        for spec in _pushes("mujoco", "walk_push")
    ]
    results = run_group(specs)
    assert {r.summary["status"] for r in results} == {"fell"}
    for result in results:  # the whole run's timings, as it had no push of its own
        assert result.summary["timed_from_s"] is None
        whole = result.trace["t_control_total_us"].median()
        assert result.summary["latency_us"]["control_total"]["median"] == whole


def test_only_episodes_that_differ_in_their_push_share_a_run():
    base = _pushes("mujoco")[0]
    assert branch_key(base) == branch_key(replace(base, push_direction_deg=33.0))
    assert branch_key(base) == branch_key(replace(base, push_impulse=5.0))
    assert branch_key(base) != branch_key(replace(base, push_time=1.0))
    assert branch_key(base) != branch_key(replace(base, sim="pybullet"))
    assert branch_key(base) != branch_key(replace(base, seed=1))
    assert branch_key(replace(base, scenario="walk")) is None
    with pytest.raises(ValueError, match="branch_key"):
        run_group([base, replace(base, push_time=1.0)])


def test_a_sweep_groups_the_pushes_of_a_level_and_keeps_the_rest_alone():
    spec = small_spec(count=4)
    episodes = spec.episodes()
    items = group_for_branching(episodes, lambda e: 10.0)
    groups = [item for item in items if isinstance(item, EpisodeGroup)]
    singles = [item for item in items if not isinstance(item, EpisodeGroup)]
    assert sorted(len(g.episodes) for g in groups) == [4, 4]  # one per simulator
    assert {e.run.scenario for e in singles} == {"stand"}
    assert all(g.budgets_s == (10.0,) * 4 for g in groups)
    flattened = [e for item in items for e in getattr(item, "episodes", (item,))]
    assert sorted(e.episode_id for e in flattened) == sorted(e.episode_id for e in episodes)
    smaller = group_for_branching(episodes, lambda e: 10.0, size=3)
    assert sorted(len(g.episodes) for g in smaller if isinstance(g, EpisodeGroup)) == [3, 3]
    assert sum(not isinstance(g, EpisodeGroup) for g in smaller) == len(singles) + 2


def test_a_sweep_with_branching_writes_the_rows_of_one_without(tmp_path: Path):
    spec = small_spec(count=4)
    branched = run_sweep(spec, tmp_path / "branched", workers=2, progress=False)
    alone = run_sweep(spec, tmp_path / "alone", workers=2, progress=False, branching=False)
    order = "episode_id"
    assert len(branched) == len(alone) == len(spec.episodes())
    left = physical(branched.sort_values(order))
    right = physical(alone.sort_values(order))
    assert left.equals(right)


def test_children_run_with_the_parents_objects_frozen():
    """`Brancher.split` freezes the collector's objects before it forks, so that a child's
    collections do not write to (and copy) every page that holds one (`PUSH_TIMING_DELAY_
    PERIODS`), and the parent unfreezes them once its children are done (a worker runs many
    groups: nothing frozen may outlive one)."""
    gc.unfreeze()
    brancher = Brancher(2, [60.0, 60.0], None)
    push = SimpleNamespace(time=1.0)
    brancher.prepare([[push], [push]])
    me = os.getpid()
    try:
        brancher.split(0.0)
    except BranchesDone:
        assert brancher.results == [True, True]  # each child saw the objects frozen
        assert gc.get_freeze_count() == 0
    except BaseException:
        if os.getpid() != me:  # a child never goes back into pytest
            os._exit(1)
        raise
    else:  # in a child: report and exit at once
        brancher.finish_child(gc.get_freeze_count() > 0)


def test_the_parent_unfreezes_however_it_leaves(monkeypatch):
    """An exception in the parent between the freeze and the children's end (here a Ctrl-C
    at the fork, which creates no child) leaves nothing frozen behind it."""
    gc.unfreeze()
    brancher = Brancher(1, [60.0], None)
    brancher.prepare([[SimpleNamespace(time=1.0)]])

    def interrupted() -> int:
        raise KeyboardInterrupt

    monkeypatch.setattr(os, "fork", interrupted)
    with pytest.raises(KeyboardInterrupt):
        brancher.split(0.0)
    assert gc.get_freeze_count() == 0


class TwoPartError(Exception):
    """An exception whose class cannot be rebuilt from its args (pickle calls it with the
    message alone)."""

    def __init__(self, what: str, where: str) -> None:
        super().__init__(f"{what} at {where}")


def test_a_branchs_exception_that_would_not_unpickle_arrives_as_its_message():
    """Until 2026-12-03 such an exception was lost in the parent, and the episode read "branch
    process exited with status 0 without a result"."""
    import os
    import time

    from bench.branching import Brancher

    brancher = Brancher(1, [10.0], None)
    read_fd, write_fd = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(read_fd)
        brancher._write_fd = write_fd
        brancher.finish_child(TwoPartError("the solver gave up", "t = 1.2 s"))
    os.close(write_fd)
    result = brancher._collect(pid, read_fd, time.perf_counter(), 10.0)
    assert isinstance(result, RuntimeError)
    assert str(result) == "TwoPartError: the solver gave up at t = 1.2 s"
