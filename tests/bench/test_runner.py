"""The control-loop runner: failures are data, the summary contract, and the minimal
controllers standing and being pushed in both simulators."""

import copy
import json
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from bench import runner
from bench.branching import PUSH_TIMING_DELAY_PERIODS
from bench.results import read_trace, write_trace
from bench.runner import EpisodeSpec, run_episode, summary_json_ready
from centroidal.gravity import GRAVITY, check_modelled_gravity
from robots.robot_registry import make_robot
from robots.scene import Scene
from stabilizers import base as stabilizer_registry
from stabilizers.posture import PostureStabilizer

SIMS = ["mujoco", "pybullet"]
CONTRACT = {
    "planner",
    "stabilizer",
    "sim",
    "scenario",
    "seed",
    "status",
    "fell",
    "fall_time",
    "duration",
    "real_time_factor",
    "latency_us",
    "com_error_rms_m",
    "error",
    "versions",
    "git_commit",
    "cpu",
}
STAGES = {"estimator", "planner", "stabilizer", "whole_body", "sim", "control_total"}


class _Failing(PostureStabilizer):
    """Raises, or returns NaN, from t = 0.1 s on."""

    mode = "raise"

    def stabilize(self, t, plan, state):
        targets = super().stabilize(t, plan, state)
        if t >= 0.1 - 1e-9:
            if self.mode == "raise":
                raise RuntimeError("boom")
            targets.com_position_world[:] = np.nan
        return targets


class _NaN(_Failing):
    mode = "nan"


@pytest.fixture
def failing(monkeypatch):
    stabilizer_registry.STABILIZERS.names()  # load the registry first
    for name, cls in (("failing", _Failing), ("nan", _NaN)):
        monkeypatch.setitem(
            stabilizer_registry.STABILIZERS.specs,
            name,
            stabilizer_registry.StabilizerSpec(name, cls, "test"),
        )


@pytest.mark.parametrize(
    ("name", "message"),
    [("failing", "stabilizer: RuntimeError: boom"), ("nan", "stabilizer returned a non-finite")],
)
def test_a_failing_stage_is_recorded_and_the_trace_kept(failing, name, message):
    result = run_episode(EpisodeSpec("hold", name, "mujoco", "stand", duration=1.0))
    summary = result.summary
    assert summary["status"] == "error"
    assert message in summary["error"]
    assert summary["fell"] is False
    assert len(result.trace) == 50  # the periods before t = 0.1 s
    assert result.trace["time"].iloc[-1] == pytest.approx(0.098)
    assert summary["duration"] == pytest.approx(0.1)


def test_a_bad_spec_is_an_error_row_not_an_exception():
    result = run_episode(EpisodeSpec("nonexistent", "posture", "mujoco", "stand"))
    assert result.summary["status"] == "error"
    assert "unknown planner 'nonexistent'; choose one of: " in result.summary["error"]
    assert "hold, linear_mpc, preview_control, preview_zmp" in result.summary["error"]
    assert len(result.trace) == 0


def test_a_scene_with_other_gravity_is_a_setup_error(monkeypatch):
    """The controllers model g = 9.81 m/s^2 (the LIPM's omega, the weight, the IMU's
    gravity-free acceleration): a scene with another gravity ends as a set-up error that says
    so, before any simulator runs; the scene's default passes."""
    make_scenario = runner.make_scenario

    def lunar(*args):
        scenario = make_scenario(*args)
        return replace(scenario, scene=replace(scenario.scene, gravity=1.62))

    assert Scene().gravity == GRAVITY
    check_modelled_gravity(Scene().gravity)
    monkeypatch.setattr(runner, "make_scenario", lunar)
    result = run_episode(EpisodeSpec("hold", "posture", "mujoco", "stand", duration=0.1))
    assert result.summary["status"] == "error"
    assert result.summary["error_stage"] == "setup"
    assert (
        "the scene's gravity is 1.62 m/s^2, the controllers model 9.81" in (result.summary["error"])
    )
    assert len(result.trace) == 0


@pytest.fixture(scope="module")
def standing():
    return {sim: run_episode(EpisodeSpec("hold", "posture", sim, "stand")) for sim in SIMS}


@pytest.mark.parametrize("sim", SIMS)
def test_hold_posture_stands_ten_seconds(standing, sim):
    result = standing[sim]
    summary = result.summary
    assert summary["status"] == "ok"
    assert summary["fell"] is False
    assert summary["fall_time"] is None
    assert summary["duration"] == pytest.approx(10.0)
    com = result.trace[["com_actual_x", "com_actual_y"]].to_numpy()
    assert np.linalg.norm(com - com[0], axis=1).max() < 0.002  # measured 0.7 mm
    # the feet carry the weight after the first 0.5 s (the start's settling): measured to 7e-5
    fz = (
        result.trace["wrench_measured_left_foot_fz"] + result.trace["wrench_measured_right_foot_fz"]
    )
    weight = make_robot("centrobench_humanoid").total_mass * 9.81
    assert np.abs(fz.iloc[250:] / weight - 1).max() < 1e-3


@pytest.mark.parametrize("sim", SIMS)
def test_a_planner_that_does_not_project_records_no_projection_error(standing, sim):
    """`hold` publishes its planned wrench as the "projected" one (no eqs. 9-10): the summary
    has no planned projection error for it (None, not a vacuous 0), while preview control's
    walks have one (tests/planners/test_preview_control.py)."""
    trace = standing[sim].trace
    planned = trace[[f"wrench_planned_{a}" for a in ("fx", "fy", "fz", "mx", "my", "mz")]]
    projected = trace[[f"wrench_projected_{a}" for a in ("fx", "fy", "fz", "mx", "my", "mz")]]
    np.testing.assert_array_equal(planned.to_numpy(), projected.to_numpy())
    errors = standing[sim].summary["projection_error"]
    assert errors["planned_force_N"] is None
    assert errors["planned_moment_Nm"] is None


@pytest.mark.parametrize("sim", SIMS)
def test_summary_contract(standing, sim):
    summary = summary_json_ready(standing[sim].summary)
    assert set(summary) >= CONTRACT
    assert set(summary["latency_us"]) >= STAGES
    for stats in summary["latency_us"].values():
        assert 0 < stats["median"] <= stats["p99"] <= stats["max"]
    # each period's control total is the sum of its stages (the median of the sum against the
    # sum of the medians, asserted here to 5 % until 2026-12-03, is a timing ratio that a
    # loaded machine broke: speed is measured in benchmarks, not asserted)
    trace = standing[sim].trace
    parts = sum(trace[f"t_{s}_us"] for s in sorted(STAGES - {"sim", "control_total"}))
    np.testing.assert_allclose(trace["t_control_total_us"], parts, rtol=1e-9)
    for package in ("mujoco", "pybullet", "pin", "qpsolvers"):
        assert summary["versions"][package]
    json.dumps(summary)  # serialisable as it stands


@pytest.mark.parametrize("sim", SIMS)
def test_the_engines_own_work_is_timed_inside_the_simulator_stage(standing, sim):
    """`t_sim_engine_us` (the engine's stepping, and MuJoCo's sensor forward pass) is measured
    inside the simulator stage `t_sim_us`: positive and never more than it, every period."""
    trace = standing[sim].trace
    engine, stage = trace["t_sim_engine_us"].to_numpy(), trace["t_sim_us"].to_numpy()
    assert (engine > 0).all()
    assert (engine <= stage).all()
    assert standing[sim].summary["latency_us"]["sim_engine"]["median"] > 0


@pytest.mark.parametrize("sim", SIMS)
def test_small_push_survived_large_push_falls(sim):
    small = run_episode(
        EpisodeSpec(
            "hold",
            "posture",
            sim,
            "stand_push",
            duration=5.0,
            push_impulse=10.0,
            push_direction_deg=0.0,
        )
    )
    assert small.summary["status"] == "ok"
    large = run_episode(
        EpisodeSpec(
            "hold",
            "posture",
            sim,
            "stand_push",
            duration=5.0,
            push_impulse=40.0,
            push_direction_deg=90.0,
        )
    )
    assert large.summary["status"] == "fell"
    assert large.summary["fell"] is True
    assert 2.0 < large.summary["fall_time"] < 5.0
    # pushed to the left: the CoM left the support to the left
    assert large.trace["com_actual_y"].iloc[-1] > 0.05


def test_trace_round_trips_through_parquet(standing, tmp_path):
    result = standing["mujoco"]
    path = write_trace(result.trace, summary_json_ready(result.summary), tmp_path / "t.parquet")
    trace, summary = read_trace(path)
    assert summary["status"] == "ok"
    assert list(trace.columns) == list(result.trace.columns)
    np.testing.assert_array_equal(trace["com_actual_x"], result.trace["com_actual_x"])
    assert trace["contact_left_foot"].dtype == bool


@pytest.mark.parametrize("sim", SIMS)
def test_cli_run_json(sim):
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "bench.cli",
            "run",
            "--planner",
            "hold",
            "--stabilizer",
            "posture",
            "--sim",
            sim,
            "--scenario",
            "stand",
            "--duration",
            "1",
            "--json",
        ],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    lines = result.stdout.strip().splitlines()
    assert len(lines) == 1
    summary = json.loads(lines[0])
    assert summary["fell"] is False
    assert summary["sim"] == sim
    assert set(summary["latency_us"]) >= STAGES


def test_mujoco_blow_up_is_an_error_not_a_fall():
    """An absurd push makes MuJoCo's accelerations non-finite; MuJoCo then resets the state
    (the robot would lie on the ground: a 'fall'). The warning counters say what happened."""
    result = run_episode(
        EpisodeSpec(
            planner="hold",
            stabilizer="posture",
            sim="mujoco",
            scenario="stand_push",
            duration=0.3,
            push_time=0.1,
            push_impulse=1e9,
            push_direction_deg=0.0,
        )
    )
    summary = result.summary
    assert summary["status"] == "error"
    assert not summary["fell"]
    assert summary["error_stage"] == "sim"
    assert "mujoco: unstable simulation at t = " in summary["error"]
    assert "QACC" in summary["error"]  # MuJoCo's own message, kept off stdout
    assert 0.1 <= summary["duration"] < 0.3


def test_mujoco_warning_is_kept_off_stdout():
    code = (
        "import json; from bench.runner import EpisodeSpec, run_episode, summary_json_ready\n"
        "r = run_episode(EpisodeSpec(planner='hold', stabilizer='posture', sim='mujoco', "
        "scenario='stand_push', duration=0.3, push_time=0.1, push_impulse=1e9))\n"
        "print(json.dumps(summary_json_ready(r.summary)))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=True
    ).stdout
    assert json.loads(out)["status"] == "error"  # stdout is exactly the JSON document


class _RecordingSim:
    """A simulator that keeps a copy of the ground-truth state of every sensor reading it
    returns (reset, then each step), and otherwise passes everything through."""

    def __init__(self, sim) -> None:
        self._sim = sim
        self.states = []

    def __getattr__(self, name):
        return getattr(self._sim, name)

    def _keep(self, sensors):
        self.states.append(copy.deepcopy(sensors.ground_truth()))
        return sensors

    def reset(self, *args):
        return self._keep(self._sim.reset(*args))

    def step(self, command):
        return self._keep(self._sim.step(command))


def test_hand_error_is_the_true_palm_distance_to_the_target(monkeypatch):
    """`reach` (Sherikov et al. 2014, Test 1) for 0.2 s, holding still: each period's
    `hand_error_m` is the distance from the target to the right palm placed by forward
    kinematics of the simulator's true state at that period's start (computed here by
    `frame_pose`, from copies the simulator handed out); at t = 0 the robot stands as
    `standing_state`, so it is the target's offset |(0.5, -0.1, 0.05)| m; held still, the palm
    barely moves by 0.2 s; and the summary's final error is the last period's."""
    import bench.runner as runner
    from robots.humanoid import humanoid
    from robots.model import cached_model

    sims = []
    make_simulator = runner.make_simulator

    def recording(name):
        sims.append(_RecordingSim(make_simulator(name)))
        return sims[-1]

    monkeypatch.setattr(runner, "make_simulator", recording)
    result = run_episode(EpisodeSpec("hold", "posture", "mujoco", "reach", duration=0.2))
    summary, trace = result.summary, result.trace
    assert summary["status"] == "ok"
    assert len(trace) == 100
    error = trace["hand_error_m"].to_numpy()
    assert np.isfinite(error).all()  # a target from t = 0 on
    offset = float(np.linalg.norm([0.5, -0.1, 0.05]))
    assert error[0] == pytest.approx(offset, abs=1e-6)
    assert abs(error[-1] - offset) < 0.005
    model = cached_model(humanoid())
    scenario = runner.make_scenario("reach", model)
    states = sims[0].states  # states[k]: what period k starts from (the last: after the end)
    assert len(states) == len(trace) + 1
    for k in (0, 50, len(trace) - 1):
        palm = model.frame_pose(states[k], "right_palm")[0]
        target = scenario.hand_target_at("right_hand", trace["time"].iloc[k])
        assert error[k] == pytest.approx(np.linalg.norm(target - palm), abs=1e-12)
    assert summary["hand_error_final_m"] == error[-1]
    assert summary["hand_task"] is False  # hold drives no hand: its error is where it stayed


def test_hand_task_is_the_planners_flag():
    """The summary's `hand_task` is the planner's `tracks_hand_targets`: true only for the
    planner that drives the hand (Sherikov's hierarchy), in a scenario with targets."""
    from planners.base import PLANNERS

    flags = {
        name: PLANNERS.get(name).factory(0.002).tracks_hand_targets for name in PLANNERS.names()
    }
    assert {name for name, flag in flags.items() if flag} == {"capturability_hierarchy"}


def test_only_the_hierarchys_plan_is_its_state():
    """`plans_com_trajectory`: every planner but Sherikov's hierarchy plans its CoM ahead of
    the state; the hierarchy's plan's CoM is the state it was computed from (it has no CoM
    tracking error: tests/bench/test_capturability_hierarchy.py)."""
    from planners.base import PLANNERS

    flags = {
        name: PLANNERS.get(name).factory(0.002).plans_com_trajectory for name in PLANNERS.names()
    }
    assert {name for name, flag in flags.items() if not flag} == {"capturability_hierarchy"}


@pytest.mark.parametrize("sim", SIMS)
def test_a_planned_com_has_a_tracking_error(standing, sim):
    """`hold` plans its CoM (settling above the support): the summary records that, and a CoM
    tracking error that the standing robot's sway makes positive."""
    summary = standing[sim].summary
    assert summary["plans_com_trajectory"] is True
    assert summary["com_error_rms_m"] > 0.0


def test_the_hierarchy_records_that_it_drives_the_hand():
    result = run_episode(
        EpisodeSpec(
            "capturability_hierarchy",
            "passthrough",
            "mujoco",
            "reach",
            duration=0.02,
            estimator="ground_truth",
            whole_body="inverse_dynamics",
        )
    )
    assert result.summary["status"] == "ok"
    assert result.summary["hand_task"] is True


def test_no_hand_error_without_hand_targets():
    result = run_episode(EpisodeSpec("hold", "posture", "mujoco", "stand", duration=0.1))
    assert result.summary["status"] == "ok"
    assert "hand_error_m" not in result.trace
    assert result.summary["hand_error_final_m"] is None
    assert result.summary["hand_task"] is None
    json.dumps(summary_json_ready(result.summary))


def test_a_planner_without_murookas_stages_has_no_table_iv_rows():
    """Table IV's "calculate reference" and the sum of its four stages belong to Murooka's
    planners: hold (and Ficht & Behnke's gait) time their whole plan as the planner's stage,
    so that the report does not show it as Murooka's reference row, nor a 0 µs sum."""
    result = run_episode(EpisodeSpec("hold", "posture", "mujoco", "stand", duration=0.1))
    latency = result.summary["latency_us"]
    assert result.summary["status"] == "ok"
    assert latency["planner"]["median"] > 0
    assert "reference" not in latency
    assert "centroidal_total" not in latency


def test_a_push_episode_is_timed_from_periods_after_its_push_and_untimed_if_it_ends_first():
    """A protocol push is timed from `PUSH_TIMING_DELAY_PERIODS` periods after the period its
    push is applied in (branched or alone: `bench.branching`); an episode that ends within
    them has no timings at all (not those of the periods before its push)."""
    dt = 0.002
    spec = EpisodeSpec(
        "hold",
        "posture",
        "mujoco",
        "stand_push",
        push_time=0.1,
        push_impulse=10.0,
        push_direction_deg=0.0,
        duration=0.1 + (PUSH_TIMING_DELAY_PERIODS + 20) * dt,
    )
    timed = run_episode(spec).summary
    assert timed["timed_from_s"] == pytest.approx(0.1 + PUSH_TIMING_DELAY_PERIODS * dt)
    assert timed["latency_us"]["control_total"]["median"] > 0
    short = run_episode(replace(spec, duration=0.1 + 2 * dt)).summary
    assert short["status"] == "ok"
    assert short["timed_from_s"] > short["duration"]
    assert short["latency_us"] == {}
