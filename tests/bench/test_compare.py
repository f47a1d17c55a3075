"""The Sec. V-G comparison table and the MPC horizon timing."""

import os
import signal
import time

import numpy as np
import pytest

from bench.cli import main
from bench.compare import COMPARISON_COLUMNS, compare, horizon_timing
from bench.runner import EpisodeSpec, run_episode


@pytest.fixture(scope="module")
def table():
    return compare(["hold", "preview_control"], "stand", ["mujoco"], duration=0.4, workers=1)


def test_one_row_per_planner_and_simulator(table):
    assert list(table.columns) == [*COMPARISON_COLUMNS, "error"]
    assert table[["planner", "sim"]].values.tolist() == [
        ["hold", "mujoco"],
        ["preview_control", "mujoco"],
    ]
    assert (table["status"] == "ok").all()
    assert table["horizon_samples"].tolist()[1] == 400  # Table I: 2 s at 5 ms


def test_numbers_are_the_episode_summary(table):
    """The table's columns equal what one episode's summary and trace give directly."""
    result = run_episode(
        EpisodeSpec("preview_control", "centroidal_feedback", "mujoco", "stand", duration=0.4)
    )
    row = table.iloc[1]
    errors = result.summary["projection_error"]
    for key in ("planned_force_N", "planned_moment_Nm", "desired_force_N", "desired_moment_Nm"):
        assert row[key] == pytest.approx(errors[key], rel=1e-9, abs=1e-12)
    assert row["com_error_rms_mm"] == pytest.approx(1e3 * result.summary["com_error_rms_m"])
    trace = result.trace
    feedback = trace["wrench_desired_fz"] - trace["wrench_projected_fz"]
    assert row["feedback_force_N"] >= np.mean(np.abs(feedback)) - 1e-9  # norm >= |z part|


def test_horizon_timing_rows():
    timing = horizon_timing(["dense:daqp", "sparse:clarabel"], [3, 6], updates=3)
    assert timing[["formulation", "horizon_samples"]].values.tolist() == [
        ["dense:daqp", 3],
        ["dense:daqp", 6],
        ["sparse:clarabel", 3],
        ["sparse:clarabel", 6],
    ]
    assert (timing["solver_failures"] == 0).all()
    assert (timing["median_ms"] > 0).all()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["compare", "--planners", "nope"], "unknown planner 'nope'"),
        (["compare", "--planners", "hold", "--scenario", "x"], "unknown scenario 'x'"),
        (
            ["compare", "--planners", "hold", "--horizons", "20", "--formulations", "dense:x"],
            "unknown formulation 'dense:x'",
        ),
        (
            ["compare", "--planners", "hold", "--horizons", "0"],
            "every --horizons value must be an integer in [1, 100], got '0'",
        ),
    ],
)
def test_bad_compare_requests_fail_with_one_line(argv, message, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err
    assert len(err.strip().splitlines()) == 1


def test_standing_still_plans_no_com_acceleration(table):
    """Sec. V-G's "scale of CoM acceleration" (the planned resultant force over m): standing
    still, about none."""
    assert table.iloc[1]["com_acceleration_mps2"] < 0.05


def test_standing_still_plans_no_angular_momentum(table):
    """Sec. V-G's "scale of ... angular momentum": standing still, preview control plans none
    (its reference orientation is constant), to well under a walk's."""
    assert table.iloc[1]["angular_momentum_kgm2ps"] < 1e-3


def test_angular_momentum_scale_is_the_constant_inertia_times_the_planned_rate(monkeypatch):
    """L^p = I omega^p (Murooka eq. 6): the trace's `base_angular_velocity_planned_*` are the
    plans' own rates, period by period (recorded here from the planner's output), and the scale
    is the mean of ||I omega^p|| over them, not zero on a turning walk, where the plan turns the
    base as the feet turn."""
    from bench.compare import planned_angular_momentum_scale
    from planners.preview_control import PreviewControlPlanner
    from robots.model import RobotModel
    from robots.robot_registry import make_robot

    rates = []
    plan = PreviewControlPlanner.plan

    def recording(self, t, state):
        result = plan(self, t, state)
        rates.append(np.array(result.base_angular_velocity_planned_world))
        return result

    monkeypatch.setattr(PreviewControlPlanner, "plan", recording)
    result = run_episode(
        EpisodeSpec("preview_control", "centroidal_feedback", "mujoco", "walk_turn", duration=2.0)
    )
    trace = result.trace
    recorded = trace[[f"base_angular_velocity_planned_{a}" for a in "xyz"]].to_numpy()
    np.testing.assert_array_equal(recorded, np.array(rates))
    inertia = np.diag(RobotModel(make_robot()).constant_inertia())
    scale = planned_angular_momentum_scale(trace, RobotModel(make_robot()))
    assert scale == pytest.approx(np.mean(np.linalg.norm(np.array(rates) * inertia, axis=1)))
    assert scale > 1e-3  # the turning walk's plan rotates the base


def test_the_papers_sec_v_g_rows_come_with_stairs_and_ladder_only():
    from bench.compare import paper_rows

    stairs = paper_rows("handrail_stairs", ["preview_control", "linear_mpc", "hold"])
    assert stairs["planner"].tolist() == ["preview_control", "linear_mpc"]
    # the paper: the MPC's planned wrench needs no projection, preview control's does on (B)
    assert stairs.iloc[1][["planned_force_N", "planned_moment_Nm"]].tolist() == [0.0, 0.0]
    assert stairs.iloc[0]["planned_force_N"] > 0
    assert paper_rows("walk", ["preview_control"]) is None
    # (B) with the hands resting is set beside the paper's (B)
    resting = paper_rows("handrail_stairs_resting", ["preview_control", "linear_mpc"])
    assert resting.equals(stairs)


def test_single_threaded_workers_sets_one_thread_inside_and_restores_the_environment(
    monkeypatch,
):
    import os

    from bench.executors import single_threaded_workers

    monkeypatch.delenv("OPENBLAS_NUM_THREADS", raising=False)
    monkeypatch.setenv("OMP_NUM_THREADS", "3")  # the user's own value is kept
    with single_threaded_workers():
        assert os.environ["OPENBLAS_NUM_THREADS"] == "1"
        assert os.environ["OMP_NUM_THREADS"] == "3"
    assert "OPENBLAS_NUM_THREADS" not in os.environ
    assert os.environ["OMP_NUM_THREADS"] == "3"


def _fake_row(spec: EpisodeSpec) -> dict:
    """No episode: MuJoCo's row at once; PyBullet's worker kills itself (a segfault's
    effect) or hangs, as the environment says."""
    if spec.sim == "pybullet":
        if os.environ.get("CENTROBENCH_TEST_COMPARE") == "die":
            os.kill(os.getpid(), signal.SIGKILL)
        time.sleep(600)
    return {"planner": spec.planner, "sim": spec.sim, "status": "ok"}


@pytest.mark.parametrize(
    ("fault", "status", "message"), [("die", "error", "WorkerDied"), ("hang", "timeout", "budget")]
)
def test_a_worker_that_dies_or_hangs_is_a_row_and_the_others_are_kept(
    monkeypatch, fault, status, message
):
    """Until 2026-12-04 `compare` ran a plain process pool: one worker's death threw away the
    rows already computed (BrokenProcessPool), and a hung episode hung it for ever. Now the
    episode is a row with its status and the other rows stay, in the planners x sims order."""
    monkeypatch.setenv("CENTROBENCH_TEST_COMPARE", fault)
    begin = time.monotonic()
    table = compare(
        ["hold"],
        "stand",
        ["pybullet", "mujoco"],
        duration=0.2,
        workers=2,
        work=_fake_row,
        budget_s=3.0,
    )
    assert time.monotonic() - begin < 60
    assert table[["sim", "status"]].values.tolist() == [["pybullet", status], ["mujoco", "ok"]]
    assert message in table["error"].iloc[0]
