"""Sweeps: local and Ray executors agree, a killed worker or an interrupted sweep loses only
the episodes in flight, and --resume completes the rest without repeating any."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from bench.dataset import TIMING_COLUMNS, read_episodes
from bench.sweep import run_one, run_sweep
from bench.sweep_spec import spec_from_mapping

ROOT = Path(__file__).parents[2]


def small_spec(count: int = 2, **extra):
    """Short episodes: a 0.3 s stand and `count` standing pushes per simulator."""
    return spec_from_mapping(
        {
            "controllers": ["hold+posture"],
            "sims": ["all"],
            "scenarios": ["stand"],
            "duration": 0.3,
            "traces": ["stand"],
            "push": {
                "dv": [0.3],
                "count": count,
                "survival_time": 0.3,
                "standing_push_time": 0.1,
            },
            **extra,
        }
    )


def physical(frame: pd.DataFrame) -> pd.DataFrame:
    """The columns that do not depend on the machine's speed."""
    return frame.drop(columns=[*TIMING_COLUMNS]).reset_index(drop=True)


_KILL_ENV = "CENTROBENCH_TEST_KILL"


def killing_work(episode):
    """run_one, except that it kills its own worker on the episode named in the environment:
    once (a marker file records it) or, with mode "always", every time."""
    target, marker, mode = os.environ[_KILL_ENV].split("|")
    if episode.episode_id == target and (mode == "always" or not Path(marker).exists()):
        Path(marker).write_text("killed")
        os.kill(os.getpid(), signal.SIGKILL)
    return run_one(episode)


def test_local_and_ray_give_identical_summaries(tmp_path: Path):
    ray = pytest.importorskip("ray", reason="Ray is a dev dependency; reinstall with make")
    # with sensor noise too: the same seed gives the same noise on both executors
    spec = small_spec(robustness={"noise": [1.0]})
    local = run_sweep(spec, tmp_path / "local", workers=2, progress=False)
    try:
        remote = run_sweep(spec, tmp_path / "ray", executor="ray", workers=2, progress=False)
    finally:
        ray.shutdown()
    assert len(local) == len(spec.episodes()) == 12
    assert set(local["status"]) == {"ok"}
    # the pushes moved the robot: the runs are not trivially equal
    assert local["com_error_rms_m"].max() > 0
    local, remote = (f.sort_values("episode_id") for f in (local, remote))
    pd.testing.assert_frame_equal(physical(local), physical(remote))
    order = ["sim", "scenario", "push_index"]
    noisy, nominal = (
        local[local["perturbation"] == label].sort_values(order) for label in ("noise=1", "nominal")
    )
    assert list(noisy["push_index"].fillna(-1)) == list(nominal["push_index"].fillna(-1))
    assert np.all(noisy["com_error_rms_m"].to_numpy() != nominal["com_error_rms_m"].to_numpy())


def test_killed_worker_loses_only_its_episode_which_is_run_again(tmp_path: Path, monkeypatch):
    spec = small_spec()
    episodes = spec.episodes()
    target = episodes[1].episode_id
    marker = tmp_path / "marker"
    monkeypatch.setenv(_KILL_ENV, f"{target}|{marker}|once")
    frame = run_sweep(spec, tmp_path / "out", workers=2, progress=False, work=killing_work)
    assert marker.exists()  # the worker running `target` was killed
    assert sorted(frame["episode_id"]) == sorted(e.episode_id for e in episodes)
    assert set(frame["status"]) == {"ok"}  # every episode, the killed one too, completed


def test_episode_that_always_kills_its_worker_is_an_error_row(tmp_path: Path, monkeypatch):
    spec = small_spec()
    target = spec.episodes()[0].episode_id
    monkeypatch.setenv(_KILL_ENV, f"{target}|{tmp_path / 'marker'}|always")
    frame = run_sweep(spec, tmp_path / "out", workers=2, progress=False, work=killing_work)
    assert len(frame) == 6
    failed = frame[frame["episode_id"] == target].iloc[0]
    assert failed["status"] == "error"
    assert "worker process was killed by SIGKILL during this episode, twice" in failed["error"]
    assert set(frame.loc[frame["episode_id"] != target, "status"]) == {"ok"}


def test_interrupted_sweep_keeps_finished_episodes_and_resume_completes_it(tmp_path: Path):
    out = tmp_path / "out"
    arguments = [
        sys.executable,
        "-m",
        "bench.cli",
        "sweep",
        "--controllers",
        "hold+posture",
        "--sims",
        "all",
        "--scenarios",
        "stand",
        "--duration",
        "0.3",
        "--push-dv",
        "0.3",
        "--push-count",
        "5",
        "--workers",
        "2",
        "--no-progress",
        "--out",
        str(out),
    ]
    # Ctrl-C's default handling in the sweep, even where this suite runs as a background job
    # (whose children start with SIGINT ignored, as the shell leaves background jobs)
    process = subprocess.Popen(
        arguments,
        cwd=ROOT,
        start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and process.poll() is None:
        if len(list((out / "episodes").glob("*.parquet"))) >= 2:
            break
        time.sleep(0.05)
    os.killpg(process.pid, signal.SIGINT)  # Ctrl-C reaches the driver and its workers
    process.wait(timeout=60)
    finished = {p.stem: p.stat().st_mtime_ns for p in (out / "episodes").glob("*.parquet")}
    spec = spec_from_mapping(json.loads((out / "sweep.json").read_text())["spec"])  # the CLI's
    ids = {e.episode_id for e in spec.episodes()}
    assert len(ids) == 2 * (1 + 5)  # per simulator: the stand and its 5 pushes
    assert 2 <= len(finished) < len(ids), "interrupt the sweep in the middle"
    assert set(finished) <= ids
    partial = read_episodes(out)  # every file on disk is complete
    assert len(partial) == len(finished)

    resumed = subprocess.run([*arguments, "--resume"], cwd=ROOT, timeout=300)
    assert resumed.returncode == 0
    frame = read_episodes(out)
    assert len(frame) == len(ids)
    assert set(frame["episode_id"]) == ids  # each of the spec's episodes once, no other
    for episode_id, mtime in finished.items():  # finished episodes were not run again
        assert (out / "episodes" / f"{episode_id}.parquet").stat().st_mtime_ns == mtime


def test_existing_results_need_resume_or_overwrite(tmp_path: Path):
    from bench.cli import main

    out = tmp_path / "out"
    spec = small_spec(count=1)
    run_sweep(spec, out, workers=1, progress=False)
    flags = [
        "sweep",
        "--controllers",
        "hold+posture",
        "--sims",
        "mujoco",
        "--scenarios",
        "stand",
        "--out",
        str(out),
    ]
    assert main(flags) == 2  # results exist: refuse to mix
    assert main([*flags, "--resume"]) == 2  # another spec: refuse to resume


def test_resume_refuses_results_the_spec_no_longer_derives(tmp_path: Path, monkeypatch):
    """A push's impulse is m dv with the robot's mass [kg]: after a change to the robot (here
    +0.1 kg) the same spec derives other episodes. Resuming would run each of them again beside
    its old result (until 2026-12-04: 6 rows for a spec of 3), so it is refused, nothing moved;
    a resume with the code unchanged still finds the sweep complete."""
    from bench import push_protocol
    from bench.dataset import ResultStoreError

    out = tmp_path / "out"
    spec = small_spec(count=1, sims=["mujoco"])
    total = len(spec.episodes())
    run_sweep(spec, out, workers=1, progress=False, work=recording_work_quiet)
    files = sorted(p.name for p in (out / "episodes").iterdir())
    assert len(files) == total
    again = run_sweep(spec, out, workers=1, progress=False, resume=True, work=recording_work_quiet)
    assert len(again) == total  # unchanged: nothing to run, nothing twice
    mass = push_protocol.robot_mass
    monkeypatch.setattr(push_protocol, "robot_mass", lambda *a: mass(*a) + 0.1)
    with pytest.raises(ResultStoreError, match="episodes that this spec no longer derives"):
        run_sweep(spec, out, workers=1, progress=False, resume=True, work=recording_work_quiet)
    assert sorted(p.name for p in (out / "episodes").iterdir()) == files


def recording_work_quiet(episode):
    """Runs nothing: an error row for each episode."""
    from bench.sweep import _failure_row

    return _failure_row(episode, RuntimeError("not run: resume test")), None


_ORDER_ENV = "CENTROBENCH_TEST_ORDER"


def recording_work(episode):
    """Records which episode starts (scenario and simulated time) and runs nothing."""
    from bench.sweep import _failure_row

    with open(os.environ[_ORDER_ENV], "a") as log:
        log.write(f"{episode.run.scenario} {episode.run.duration}\n")
    return _failure_row(episode, RuntimeError("not run: order test")), None


def test_longest_episodes_start_first(tmp_path: Path, monkeypatch):
    """A plain scenario at its own length (duration None: the walks of the main job) starts
    before the 4.6 s push episodes, so that no long episode is left for the end."""
    log = tmp_path / "order.txt"
    monkeypatch.setenv(_ORDER_ENV, str(log))
    spec = spec_from_mapping(
        {
            "controllers": ["hold+posture"],
            "sims": ["mujoco"],
            "scenarios": ["stand"],
            "push": {"dv": [0.3, 0.4], "count": 3},
        }
    )
    run_sweep(spec, tmp_path / "out", workers=1, progress=False, work=recording_work)
    started = log.read_text().splitlines()
    assert len(started) == 7  # 1 stand + 2 levels x 3 pushes
    assert started[0] == "stand None"
    assert all(line == "stand_push 4.6" for line in started[1:])  # 1.5 + 0.1 + 3 s


def test_a_two_node_ray_cluster_runs_episodes_on_both_nodes_as_local_does(
    tmp_path: Path, monkeypatch
):
    """Two Ray nodes of one CPU each on this machine (Ray's own test cluster utility): the
    sweep's episodes run on both and give the local executor's rows. Ray's switch for
    single-machine clusters keeps every node on the loopback address."""
    ray = pytest.importorskip("ray", reason="Ray is a dev dependency; reinstall with make")
    from ray._private import ray_constants
    from ray.cluster_utils import Cluster

    monkeypatch.setattr(ray_constants, "ENABLE_RAY_CLUSTER", False)  # nodes on 127.0.0.1
    spec = small_spec(count=3)
    local = run_sweep(spec, tmp_path / "local", workers=2, progress=False)
    cluster = Cluster(initialize_head=True, head_node_args={"num_cpus": 1})
    try:
        assert cluster.address.startswith("127.0.0.1:")
        cluster.add_node(num_cpus=1)
        cluster.wait_for_nodes()
        ray.init(address=cluster.address, include_dashboard=False, log_to_driver=False)
        assert len([n for n in ray.nodes() if n["Alive"]]) == 2
        remote = run_sweep(spec, tmp_path / "ray", executor="ray", workers=2, progress=False)
    finally:
        ray.shutdown()
        cluster.shutdown()
    assert len(remote) == len(spec.episodes()) == 8
    nodes = {worker.split(":")[1] for worker in remote["worker"]}
    assert len(nodes) == 2, remote["worker"].tolist()
    assert all(worker.startswith("ray:") for worker in remote["worker"])
    assert not any(worker.startswith("ray:") for worker in local["worker"])
    pd.testing.assert_frame_equal(physical(local), physical(remote))


def test_a_sweep_over_two_robots_reports_them_side_by_side(tmp_path: Path):
    """`robots = [...]`: every row says its robot and carries that robot's mass; the report
    labels each controller's rows with the robot, so both robots have their own rows in the
    survival table."""
    from reports.build import build_report

    spec = small_spec(count=1, sims=["mujoco"], robots=["centrobench_humanoid", "jvrc1"])
    frame = run_sweep(spec, tmp_path / "out", workers=1, progress=False)
    assert sorted(frame["robot"]) == ["centrobench_humanoid"] * 2 + ["jvrc1"] * 2
    masses = frame.groupby("robot")["mass_kg"].first()
    assert masses["jvrc1"] == pytest.approx(62.4)
    assert masses["centrobench_humanoid"] == pytest.approx(58.4)
    assert (frame["status"] == "ok").all(), frame["error"].tolist()
    build_report(tmp_path / "out", tmp_path / "report")
    report = (tmp_path / "report" / "report.md").read_text()
    survival = report[report.index("hold+posture @ centrobench_humanoid") :]
    assert "hold+posture @ jvrc1" in survival


def recording_protocol_work(episode):
    """Records which protocol each episode came from, in the order they start; runs none."""
    from bench.sweep import _failure_row

    with open(os.environ[_ORDER_ENV], "a") as log:
        log.write(f"{episode.protocol}\n")
    return _failure_row(episode, RuntimeError("not run: order test")), None


def test_a_jobs_protocols_run_one_after_the_other(tmp_path: Path, monkeypatch):
    """A job of two protocols: the second's episodes start only after every one of the first
    (its walk, the longest, does not jump the queue), and each episode runs once."""
    log = tmp_path / "order.txt"
    monkeypatch.setenv(_ORDER_ENV, str(log))
    spec = spec_from_mapping(
        {
            "controllers": ["hold+posture"],
            "sims": ["mujoco"],
            "protocols": [
                {"name": "pushes", "push": {"dv": [0.3], "count": 3}},
                {"name": "walks", "scenarios": ["walk"]},
            ],
        }
    )
    run_sweep(spec, tmp_path / "out", workers=1, progress=False, work=recording_protocol_work)
    assert log.read_text().splitlines() == ["pushes"] * 3 + ["walks"]


def test_a_spec_that_lists_an_episode_twice_is_refused_before_anything_runs(tmp_path):
    """Each episode is one file named by its id: the same seed twice would run twice and keep
    one row (the second overwriting the first), so the sweep refuses it and writes nothing."""
    from bench.sweep_spec import SweepSpec

    spec = SweepSpec(
        controllers=("hold+posture",), sims=("mujoco",), scenarios=("stand",), seeds=(0, 0)
    )
    with pytest.raises(ValueError, match=r"lists episode .* more than once"):
        run_sweep(spec, tmp_path / "out", workers=1, progress=False)
    assert not (tmp_path / "out").exists()


_POISON_ENV = "CENTROBENCH_TEST_POISON"


def poisoned_work(episode):
    """run_one, except that the episode named in the environment returns a row whose
    `fall_reason` is a number, which the results' schema (a string) refuses."""
    row, *rest = run_one(episode)
    if episode.episode_id == os.environ[_POISON_ENV]:
        row = {**row, "fall_reason": 3}
    return (row, *rest)


def test_a_result_that_does_not_fit_the_schema_is_an_error_row_and_the_sweep_goes_on(
    tmp_path: Path, monkeypatch
):
    """Until 2026-12-03 pyarrow's ArrowTypeError left the sweep, and every resume died at the
    same episode, which was never written: now it is an error row that says why, and the
    trace it kept is not left behind without its row (until 2026-12-04 it was)."""
    spec = small_spec()
    episodes = spec.episodes()
    target = next(e.episode_id for e in episodes if e.keep_trace)
    monkeypatch.setenv(_POISON_ENV, target)
    frame = run_sweep(spec, tmp_path / "out", workers=2, progress=False, work=poisoned_work)
    assert sorted(frame["episode_id"]) == sorted(e.episode_id for e in episodes)
    rows = frame.set_index("episode_id")
    assert rows.loc[target, "status"] == "error"
    assert "result could not be recorded" in rows.loc[target, "error"]
    assert set(rows.drop(index=target)["status"]) == {"ok"}
    assert not rows.loc[target, "has_trace"]
    traces = {p.name.split(".")[0] for p in (tmp_path / "out" / "traces").iterdir()}
    assert target not in traces
    assert traces == set(rows.index[rows["has_trace"]])  # the others' traces are there
