"""Faults injected into sweeps (issue 14): a hung episode, a worker killed by a signal, the
sweep's parent killed (SIGTERM, SIGKILL), a corrupt episode file, a results disk that fails;
two sweeps on one directory; --overwrite with a bad executor; --resume with another spec.

After each fault the finished episodes are kept and `--resume` (with `--retry-errors` where
the fault left error or timeout rows) produces the same episode set, with the same non-timing
columns, as one uninterrupted run (`reference`).
"""

from __future__ import annotations

import errno
import json
import os
import re
import signal
import socket
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pandas as pd
import pytest

from bench import dataset
from bench.dataset import ResultStore, ResultStoreError, spec_differences
from bench.executors import worker_progress
from bench.sweep import run_one, run_sweep
from bench.sweep_spec import spec_from_mapping
from tests.bench.test_sweep import ROOT, physical

# short budgets: these episodes take well under a second of wall-clock time each
BUDGET = {"timeout_base_s": 5.0, "timeout_per_sim_s": 1.0}


def fault_spec(**extra):
    """A 0.3 s stand and two 0.5 s standing pushes in each simulator (6 episodes); a field
    given as None is left out (push=None: the stand only)."""
    data = {
        "controllers": ["hold+posture"],
        "sims": ["all"],
        "scenarios": ["stand"],
        "duration": 0.3,
        "traces": ["stand"],
        "push": {"dv": [0.3], "count": 2, "survival_time": 0.3, "standing_push_time": 0.1},
        **BUDGET,
        **extra,
    }
    return spec_from_mapping({k: v for k, v in data.items() if v is not None})


CLI_SPEC = """
controllers = ["hold+posture"]
sims = ["all"]
scenarios = ["stand"]
duration = 0.3
traces = ["stand"]
timeout_base_s = 5.0
timeout_per_sim_s = 1.0

[push]
dv = [0.3]
count = 2
survival_time = 0.3
standing_push_time = 0.1
"""


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> pd.DataFrame:
    """The uninterrupted run of `fault_spec`."""
    frame = run_sweep(fault_spec(), tmp_path_factory.mktemp("reference"), progress=False)
    assert set(frame["status"]) == {"ok"}
    assert len(frame) == 6
    return frame


def same_as_reference(frame: pd.DataFrame, reference: pd.DataFrame) -> None:
    pd.testing.assert_frame_equal(physical(frame), physical(reference))


def resume(out: Path, retry_errors: bool = False) -> pd.DataFrame:
    return run_sweep(
        fault_spec(), out, resume=True, retry_errors=retry_errors, workers=2, progress=False
    )


# ------------------------------------------------------------------------- fault workers

_TARGET_ENV = "CENTROBENCH_TEST_TARGET"


def _is_target(episode) -> bool:
    """The episode named in the environment ("*": every episode)."""
    return os.environ[_TARGET_ENV] in ("*", episode.episode_id)


def hanging_work(episode):
    """run_one, except that the target episode says it is in the planner stage at t = 0.25 s
    and then hangs inside C code that holds the GIL (a regular expression that backtracks for
    ever), as a solver without an iteration limit would."""
    if _is_target(episode):
        progress = worker_progress()  # None in a Ray task
        if progress is not None:
            progress[0], progress[1] = 2.0, 0.25  # bench.runner.PROGRESS_STAGES[2]: planner
        re.match(r"(a+)+$", "a" * 64 + "b")  # exponential backtracking, in C
    return run_one(episode)


def killed_work(episode):
    """run_one, except that the target episode's worker says so on stderr and is killed
    (SIGKILL) every time."""
    if _is_target(episode):
        print("about to be killed", file=sys.stderr, flush=True)
        os.kill(os.getpid(), signal.SIGKILL)
    return run_one(episode)


def death_signal_work(_item) -> int:
    """The signal this worker gets when its parent dies."""
    from bench.executors import parent_death_signal

    return parent_death_signal()


class _Unreadable:
    """Pickles in a worker and fails to unpickle in the parent (as `EpisodeTimeout` did
    before 2026-11-27)."""

    def __reduce__(self):
        return (_fail_to_unpickle, ("the message",))


def _fail_to_unpickle(text: str):
    return f"{text:.0f}"  # ValueError: Unknown format code 'f' for object of type 'str'


def unreadable_work(item: int):
    """Item 1's result cannot be read by the parent; the others return themselves."""
    return _Unreadable() if item == 1 else item


# ------------------------------------------------------------------------------- tests


def test_hung_episode_is_a_timeout_row_with_its_stage_and_resume_reruns_it(
    tmp_path: Path, monkeypatch, reference
):
    spec = fault_spec()
    target = spec.episodes()[1]
    monkeypatch.setenv(_TARGET_ENV, target.episode_id)
    out = tmp_path / "out"
    begin = time.monotonic()
    frame = run_sweep(spec, out, workers=2, progress=False, work=hanging_work)
    elapsed = time.monotonic() - begin
    budget = spec.wall_budget_s(0.5)  # the pushed episode: 0.1 + 0.1 + 0.3 s simulated
    assert target.run.scenario == "stand_push"
    assert target.run.duration == pytest.approx(0.5)
    assert elapsed < budget + 60  # the sweep went on (the hang itself would never end)
    row = frame.set_index("episode_id").loc[target.episode_id]
    assert row["status"] == "timeout"
    assert row["error_stage"] == "planner"
    assert row["duration"] == pytest.approx(0.25)
    assert f"budget of {budget:.0f} s" in row["error"]
    assert "tests/bench/test_sweep_faults.py" in row["error"]  # the stack's location
    assert pd.isna(row["survived"])  # a timeout says nothing about the controller
    others = frame[frame["episode_id"] != target.episode_id]
    assert set(others["status"]) == {"ok"}
    # the code that ran it, as on the rows that finished; the worker that ran it is not known
    ok = others.iloc[0]
    for column in ("git_commit", "centrobench_version", "versions_json", "mass_kg"):
        assert row[column] == ok[column]
    assert row["requested_duration"] == pytest.approx(0.5)
    assert pd.isna(row["worker"])
    files = {p.name: p.stat().st_mtime_ns for p in (out / "episodes").iterdir()}
    pd.testing.assert_frame_equal(resume(out), frame)  # a plain resume: nothing is missing
    assert {p.name: p.stat().st_mtime_ns for p in (out / "episodes").iterdir()} == files
    same_as_reference(resume(out, retry_errors=True), reference)


def test_hung_ray_task_is_cancelled_and_recorded_as_a_timeout(tmp_path: Path, monkeypatch):
    ray = pytest.importorskip("ray", reason="Ray is a dev dependency; reinstall with make")
    # Ray counts a task's budget from its submission, so it includes the start-up of a fresh
    # Ray worker (its imports: seconds, more on a loaded machine): a base of 30 s
    spec = fault_spec(push=None, timeout_base_s=30.0)
    target = spec.episodes()[0]
    monkeypatch.setenv(_TARGET_ENV, target.episode_id)  # Ray's local workers inherit it
    try:
        frame = run_sweep(
            spec, tmp_path / "out", executor="ray", workers=2, progress=False, work=hanging_work
        )
    finally:
        ray.shutdown()
    rows = frame.set_index("episode_id")
    assert rows.loc[target.episode_id, "status"] == "timeout"
    assert "in an unknown stage" in rows.loc[target.episode_id, "error"]
    assert set(rows.drop(index=target.episode_id)["status"]) == {"ok"}


def test_worker_killed_by_a_signal_is_an_error_row_and_resume_reruns_it(
    tmp_path: Path, monkeypatch, reference
):
    spec = fault_spec()
    target = spec.episodes()[4]
    monkeypatch.setenv(_TARGET_ENV, target.episode_id)
    out = tmp_path / "out"
    frame = run_sweep(spec, out, workers=2, progress=False, work=killed_work)
    row = frame.set_index("episode_id").loc[target.episode_id]
    assert row["status"] == "error"
    assert "killed by SIGKILL" in row["error"]
    assert row["error"].endswith("its last words: about to be killed, twice")
    same_as_reference(resume(out, retry_errors=True), reference)


def test_corrupt_episode_file_is_set_aside_and_run_again(tmp_path: Path, reference):
    out = tmp_path / "out"
    run_sweep(fault_spec(), out, workers=2, progress=False)
    victim = sorted((out / "episodes").glob("*.parquet"))[2]
    victim.write_bytes(victim.read_bytes()[:100])  # truncated: unreadable Parquet
    foreign = out / "episodes" / "foreign.parquet"
    pd.DataFrame({"x": [1.0]}).to_parquet(foreign)  # readable, but not an episode row
    same_as_reference(resume(out), reference)
    kept = sorted(p.name.split(".")[0] for p in (out / "corrupt").iterdir())
    assert kept == sorted(["foreign", victim.stem])  # kept aside, not deleted


def test_full_results_disk_stops_the_sweep_and_resume_completes_it(
    tmp_path: Path, monkeypatch, reference
):
    """A full disk, simulated: the third episode file cannot be written (ENOSPC). (An
    unwritable directory cannot simulate it here: the tests may run as root, whom permission
    bits do not stop.)"""
    out = tmp_path / "out"
    written = []
    original = dataset._atomic_write_table

    def failing_write(table, path):
        if path.parent.name == "episodes" and len(written) == 2:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        original(table, path)
        if path.parent.name == "episodes":
            written.append(path)

    monkeypatch.setattr(dataset, "_atomic_write_table", failing_write)
    with pytest.raises(ResultStoreError, match=r"cannot write the results in .*No space left"):
        run_sweep(fault_spec(), out, workers=2, progress=False)
    assert len(list((out / "episodes").glob("*.parquet"))) == 2  # the finished ones stay
    assert not list((out / "episodes").glob(".*.tmp"))  # no half-written file left
    monkeypatch.setattr(dataset, "_atomic_write_table", original)
    same_as_reference(resume(out), reference)


def _workers(pid: int) -> set[int]:
    """The sweep worker processes among `pid`'s children (not multiprocessing's resource
    tracker)."""
    path = Path(f"/proc/{pid}/task/{pid}/children")
    children = {int(p) for p in path.read_text().split()} if path.exists() else set()
    result = set()
    for child in children:
        try:
            command = Path(f"/proc/{child}/cmdline").read_bytes()
        except FileNotFoundError:
            continue
        if b"spawn_main" in command:
            result.add(child)
    return result


def _alive(pid: int) -> bool:
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except FileNotFoundError:
        return False
    return "State:\tZ" not in status  # a zombie has exited


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGKILL])
def test_killing_the_sweep_ends_its_workers_and_resume_completes_it(
    tmp_path: Path, signum, reference
):
    spec_file = tmp_path / "spec.toml"
    spec_file.write_text(CLI_SPEC)
    out = tmp_path / "out"
    command = [sys.executable, "-m", "bench.cli", "sweep", "--spec", str(spec_file)]
    command += ["--out", str(out), "--workers", "2", "--no-progress"]
    # a SIGKILLed sweep cannot remove its workers' folder (`LocalExecutor`): it goes in tmp_path
    env = {**os.environ, "TMPDIR": str(tmp_path)}
    process = subprocess.Popen(command, cwd=ROOT, stderr=subprocess.PIPE, text=True, env=env)
    deadline = time.monotonic() + 120
    workers: set[int] = set()
    while time.monotonic() < deadline and process.poll() is None:
        workers = _workers(process.pid)
        if len(workers) >= 2 and list((out / "episodes").glob("*.parquet")):
            break
        time.sleep(0.05)
    assert len(workers) >= 2, "the sweep should have started its workers"
    process.send_signal(signum)
    process.wait(timeout=60)
    stderr = process.stderr.read() if process.stderr else ""
    if signum == signal.SIGTERM:
        assert process.returncode == 143, stderr
        assert "terminated (SIGTERM)" in stderr
        assert "Traceback" not in stderr
    end = time.monotonic() + 15
    while time.monotonic() < end and any(_alive(pid) for pid in workers):
        time.sleep(0.1)
    assert not [pid for pid in workers if _alive(pid)], "workers outlived their parent"
    finished = len(list((out / "episodes").glob("*.parquet")))
    assert 1 <= finished < 6, "kill the sweep in the middle"
    same_as_reference(resume(out), reference)


def test_a_second_sweep_on_the_same_directory_is_refused(tmp_path: Path):
    out = tmp_path / "out"
    holder = re.escape(f"in use by another sweep (pid {os.getpid()}")
    with ResultStore(out).locked(), pytest.raises(ResultStoreError, match=holder):
        run_sweep(fault_spec(), out, workers=1, progress=False)
    assert not (out / "episodes").exists()  # nothing was written by the refused sweep


def test_the_lock_of_a_killed_sweep_is_not_stale(tmp_path: Path):
    out = tmp_path / "out"
    code = (
        "import sys, time; from bench.dataset import ResultStore\n"
        f"with ResultStore({str(out)!r}).locked():\n"
        "    print('locked', flush=True); time.sleep(600)\n"
    )
    holder = subprocess.Popen(
        [sys.executable, "-c", code], cwd=ROOT, stdout=subprocess.PIPE, text=True
    )
    assert holder.stdout is not None
    assert holder.stdout.readline().strip() == "locked"
    with pytest.raises(ResultStoreError, match=f"pid {holder.pid}"), ResultStore(out).locked():
        pass
    holder.kill()
    holder.wait(timeout=30)
    with ResultStore(out).locked():  # the kernel dropped the dead holder's lock
        pass


def _closed_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.mark.parametrize(
    ("flags", "message"),
    [
        (["--address", "127.0.0.1:6379"], "--address is for the ray executor"),
        (["--executor", "ray", "--address", "127.0.0.1:{port}"], "no Ray cluster at 127.0.0.1"),
        (["--executor", "ray", "--address", "nonsense"], "--address must be HOST:PORT"),
        (["--retry-errors"], "--retry-errors goes with --resume"),
    ],
)
def test_overwrite_keeps_the_results_when_the_rest_of_the_command_is_wrong(
    tmp_path: Path, capsys, flags, message
):
    from bench.cli import main

    if "--executor" in flags:
        pytest.importorskip("ray", reason="Ray is a dev dependency; reinstall with make")
    out = tmp_path / "out"
    run_sweep(fault_spec(push=None, sims=["mujoco"]), out, workers=1, progress=False)
    before = {p.name: p.read_bytes() for p in (out / "episodes").iterdir()}
    flags = [f.format(port=_closed_port()) for f in flags]
    argv = ["sweep", "--controllers", "hold+posture", "--sims", "mujoco", "--scenarios", "stand"]
    argv += ["--duration", "0.3", "--out", str(out), "--overwrite", "--no-progress", *flags]
    begin = time.monotonic()
    assert main(argv) == 2
    assert time.monotonic() - begin < 30  # a bounded check, not ray.init's retries
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("centrobench: error:")
    assert message in err[0]
    assert {p.name: p.read_bytes() for p in (out / "episodes").iterdir()} == before


def test_overwrite_moves_old_results_aside_until_the_new_sweep_has_started(tmp_path: Path):
    out = tmp_path / "out"
    old = run_sweep(fault_spec(push=None, sims=["mujoco"]), out, workers=1, progress=False)
    old_files = {p.name for p in (out / "episodes").iterdir()}

    def interrupt(total: int, todo: int, notes: list[str]) -> None:  # before any new episode
        raise KeyboardInterrupt

    new_spec = fault_spec(push=None, sims=["pybullet"])
    with pytest.raises(KeyboardInterrupt):
        run_sweep(new_spec, out, overwrite=True, workers=1, progress=False, on_start=interrupt)
    assert {p.name for p in (out / "episodes").iterdir()} == old_files  # restored
    assert json.loads((out / "sweep.json").read_text())["digest"] != new_spec.digest()
    assert not list(out.glob(".previous-*"))

    new = run_sweep(new_spec, out, overwrite=True, workers=1, progress=False)
    assert set(new["sim"]) == {"pybullet"}
    assert set(old["sim"]) == {"mujoco"}
    assert not list(out.glob(".previous-*"))  # deleted once the new sweep had started


def test_results_a_killed_overwrite_moved_aside_come_back_on_the_next_sweep(
    tmp_path: Path, monkeypatch
):
    """A SIGKILL runs no clean-up: an --overwrite killed before its first episode left the
    old results in .previous-* for ever, and a resume of the old spec was refused as "another
    spec" (until 2026-12-04). The next sweep on the directory puts them back; had the killed
    sweep written an episode, it deletes them (its own episodes stay)."""
    from bench.dataset import ResultStore

    out = tmp_path / "out"
    old_spec = fault_spec(push=None, sims=["mujoco"])
    old = run_sweep(old_spec, out, workers=1, progress=False)

    def killed(total: int, todo: int, notes: list[str]) -> None:
        raise KeyboardInterrupt

    new_spec = fault_spec(push=None, sims=["pybullet"])
    with monkeypatch.context() as patch:  # as if killed: neither restored nor discarded
        patch.setattr(ResultStore, "restore_aside", lambda self: None)
        with pytest.raises(KeyboardInterrupt):
            run_sweep(new_spec, out, overwrite=True, workers=1, progress=False, on_start=killed)
    assert len(list(out.glob(".previous-*"))) == 1
    assert not list((out / "episodes").iterdir())
    again = run_sweep(old_spec, out, resume=True, workers=1, progress=False)
    pd.testing.assert_frame_equal(again, old)  # all back, none run again
    assert not list(out.glob(".previous-*"))

    with monkeypatch.context() as patch:  # killed after its first episode was written
        patch.setattr(ResultStore, "discard_aside", lambda self: None)
        new = run_sweep(new_spec, out, overwrite=True, workers=1, progress=False)
    assert len(list(out.glob(".previous-*"))) == 1
    resumed = run_sweep(new_spec, out, resume=True, workers=1, progress=False)
    pd.testing.assert_frame_equal(resumed, new)
    assert set(resumed["sim"]) == {"pybullet"}
    assert not list(out.glob(".previous-*"))


def test_resume_with_another_spec_names_the_fields_that_differ(tmp_path: Path):
    out = tmp_path / "out"
    run_sweep(fault_spec(push=None, sims=["mujoco"]), out, workers=1, progress=False)
    other = fault_spec(push={"dv": [0.3], "count": 3}, sims=["mujoco"], seeds=[1])
    with pytest.raises(ResultStoreError, match=r"fields that differ: push, seeds\)"):
        run_sweep(other, out, resume=True, workers=1, progress=False)
    # the budget says how the sweep runs, not what it measures: a resume may change it
    longer = fault_spec(push=None, sims=["mujoco"], timeout_base_s=100.0)
    assert len(run_sweep(longer, out, resume=True, workers=1, progress=False)) == 1


def test_spec_differences_name_nested_push_fields():
    a = fault_spec().to_dict()
    b = fault_spec(push={"dv": [0.3], "count": 5, "survival_time": 0.3}).to_dict()
    assert spec_differences(a, b) == ["push.count", "push.standing_push_time"]
    assert spec_differences(a, a) == []


def test_resume_needs_the_sweep_record(tmp_path: Path):
    out = tmp_path / "out"
    run_sweep(fault_spec(push=None, sims=["mujoco"]), out, workers=1, progress=False)
    record = out / "sweep.json"
    record.write_text("{not json")
    with pytest.raises(ResultStoreError, match=r"sweep\.json is not a readable sweep record"):
        run_sweep(fault_spec(push=None, sims=["mujoco"]), out, resume=True, progress=False)
    record.unlink()
    with pytest.raises(ResultStoreError, match=r"holds 1 episodes but no sweep\.json"):
        run_sweep(fault_spec(push=None, sims=["mujoco"]), out, resume=True, progress=False)


def test_out_that_is_a_file_is_refused_before_anything_runs(tmp_path: Path, capsys):
    from bench.cli import main

    blocker = tmp_path / "file"
    blocker.write_text("")
    argv = ["sweep", "--controllers", "hold+posture", "--sims", "mujoco", "--scenarios"]
    argv += ["stand", "--duration", "0.3", "--out", str(blocker / "out"), "--no-progress"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "is a file, not a directory" in err[0]


_HUNG_DRIVER = """
import os, sys
sys.path.insert(0, {root!r})
from bench.sweep import run_sweep
from tests.bench.test_sweep_faults import fault_spec, hanging_work
os.environ["CENTROBENCH_TEST_TARGET"] = "*"
run_sweep(fault_spec(**{budget!r}), {out!r}, workers=2, progress=False, work=hanging_work)
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG, /proc")
def test_workers_hung_in_c_die_with_their_killed_parent(tmp_path: Path):
    """Both workers hang in C code that holds the GIL (their watcher threads cannot run), the
    parent is SIGKILLed: only the kernel's parent-death signal can end them, and it does."""
    budget = {"timeout_base_s": 600.0, "timeout_per_sim_s": 1.0}  # no timeout in this test
    code = _HUNG_DRIVER.format(root=str(ROOT), budget=budget, out=str(tmp_path / "out"))
    env = {**os.environ, "TMPDIR": str(tmp_path)}  # the killed driver's workers' folder
    driver = subprocess.Popen([sys.executable, "-c", code], cwd=ROOT, env=env)
    deadline = time.monotonic() + 120
    workers: set[int] = set()
    while time.monotonic() < deadline and driver.poll() is None:
        workers = _workers(driver.pid)
        if len(workers) == 2 and all(_hung(pid) for pid in workers):
            break
        time.sleep(0.1)
    assert len(workers) == 2, "the driver should have started two workers"
    driver.kill()
    driver.wait(timeout=30)
    end = time.monotonic() + 15
    while time.monotonic() < end and any(_alive(pid) for pid in workers):
        time.sleep(0.1)
    assert not [pid for pid in workers if _alive(pid)], "hung workers outlived their parent"


def _hung(pid: int) -> bool:
    """The process is running (state R) and has used more than 1 s of CPU: in the hang."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except FileNotFoundError:
        return False
    ticks = int(fields[11]) + int(fields[12])  # utime + stime
    return fields[0] == "R" and ticks > 3 * os.sysconf("SC_CLK_TCK")


def test_a_result_that_cannot_be_read_is_that_items_error_and_the_rest_arrive():
    """A worker's reply that fails to unpickle in the parent becomes that item's
    RuntimeError, naming the error; the other items' results arrive and the executor keeps
    going (before 2026-11-27 the ValueError ended the sweep, and the CLI took it for a usage
    error)."""
    from bench.executors import LocalExecutor

    executor = LocalExecutor(workers=1)
    try:
        results = dict(executor.map_unordered(unreadable_work, [0, 1, 2]))
    finally:
        executor.close()
    assert results[0] == 0
    assert results[2] == 2
    assert isinstance(results[1], RuntimeError)
    assert "could not be read" in str(results[1])
    assert "Unknown format code" in str(results[1])


def sleepy_work(seconds: float) -> float:
    time.sleep(seconds)
    return seconds


def test_workers_killed_while_idle_do_not_end_the_sweep():
    """A worker that had started and is killed while idle (the OOM killer picks a process with
    a large footprint) is replaced; until 2026-12-03 the fourth such death anywhere in a sweep
    ended it as "worker processes die at start-up", with the busy workers' episodes lost."""
    import threading

    from bench.executors import LocalExecutor

    executor = LocalExecutor(workers=2)
    kills: list[int] = []

    def kill_the_idle_worker_four_times() -> None:
        deadline = time.monotonic() + 60.0
        while len(kills) < 4 and time.monotonic() < deadline:
            pool = list(executor._pool)
            idle = [w for w in pool if w.task is None and w.ready and w.process.is_alive()]
            if idle and any(w.task is not None for w in pool):
                os.kill(idle[0].process.pid, signal.SIGKILL)
                kills.append(idle[0].process.pid)
            time.sleep(0.05)

    killer = threading.Thread(target=kill_the_idle_worker_four_times, daemon=True)
    try:
        results = executor.map_unordered(sleepy_work, [25.0, 0.0])
        first = next(results)  # the short item: from here one worker is idle, one busy
        killer.start()
        rest = list(results)
    finally:
        executor.close()
    killer.join(timeout=5.0)
    assert len(kills) == 4
    assert dict([first, *rest]) == {0.0: 0.0, 25.0: 25.0}


@dataclass(frozen=True)
class SplitItem:
    """An item that runs a shared part before it splits, like a branched group: it sleeps
    `before_s` [s], says it has split when `splits`, then sleeps `after_s`."""

    before_s: float
    after_s: float
    splits: bool
    split_budget_s: float = 2.0


def split_work(item: SplitItem) -> str:
    from bench.executors import SPLIT_SLOT

    time.sleep(item.before_s)
    if item.splits:
        worker_progress()[SPLIT_SLOT] = 1.0
    time.sleep(item.after_s)
    return "done"


def test_a_group_that_hangs_before_its_split_is_held_to_one_episodes_budget():
    """A branched group's budget is the sum of its episodes' (20 for a push level), but until it
    splits at the push it is held to one episode's (`EpisodeGroup.split_budget_s`): a hang in
    the shared part ends after that (here 2 s of a 60 s group budget); a group that has split
    goes on past it."""
    from bench.executors import EpisodeTimeout, LocalExecutor

    hung, splits = SplitItem(60.0, 0.0, False), SplitItem(0.2, 3.0, True)
    executor = LocalExecutor(workers=2)
    begin = time.monotonic()
    try:
        results = dict(executor.map_unordered(split_work, [hung, splits], budget=lambda i: 60.0))
    finally:
        executor.close()
    assert time.monotonic() - begin < 20.0
    assert isinstance(results[hung], EpisodeTimeout)
    assert "budget of 2 s" in str(results[hung])
    assert results[splits] == "done"


def test_of_two_dumps_in_a_workers_stack_file_the_location_is_the_last_ones():
    """A branch forked in a worker inherits its stack file: its crash's dump comes first, and
    the worker's own dump (asked for by SIGUSR1 at a hang) after it; the location is the
    worker's (until 2026-12-03 the branch's, the first found). The other threads of a crash's
    dump come after its own thread's and are not taken."""
    from bench.executors import stack_location

    crash = (
        "Fatal Python error: Segmentation fault\n\n"
        "Current thread 0x1 (most recent call first):\n"
        f'  File "{ROOT}/bench/branching.py", line 10 in child_thing\n\n'
        "Thread 0x2 (most recent call first):\n"
        f'  File "{ROOT}/bench/dataset.py", line 3 in other\n\n'
    )
    asked = (
        "Stack (most recent call first):\n"
        f'  File "{ROOT}/bench/runner.py", line 42 in _run_episode\n'
        f'  File "{ROOT}/bench/sweep.py", line 7 in run\n'
    )
    assert stack_location(crash + asked) == "bench/runner.py:42 in _run_episode"
    assert stack_location(crash) == "bench/branching.py:10 in child_thing"


def test_workers_get_sigkill_when_their_parent_dies():
    """The kernel's parent-death signal is set in every worker (what the test above relies
    on when the watcher thread cannot run)."""
    from bench.executors import LocalExecutor

    results = list(LocalExecutor(workers=1).map_unordered(death_signal_work, [0]))
    expected = signal.SIGKILL if sys.platform.startswith("linux") else 0
    assert results == [(0, expected)]


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc")
@pytest.mark.parametrize("command", ["sweep", "report"])
def test_unwritable_out_is_one_line(tmp_path: Path, capsys, command):
    """/proc takes no new folder, not even from root (whom permission bits do not stop)."""
    from bench.cli import main

    if command == "sweep":
        argv = ["sweep", "--controllers", "hold+posture", "--sims", "mujoco", "--scenarios"]
        argv += ["stand", "--duration", "0.3", "--no-progress", "--out", "/proc/centrobench"]
    else:
        run_sweep(fault_spec(push=None, sims=["mujoco"]), tmp_path / "r", progress=False)
        argv = ["report", str(tmp_path / "r"), "--out", "/proc/centrobench"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "/proc/centrobench" in err[0]
    assert "Traceback" not in err[0]
