"""Murooka et al. 2022's comparison of planners (Sec. V-E, V-G) as pandas tables.

`compare` runs each planner (with one stabilizer) on a scenario in each simulator and returns
one row per planner x simulator: the mean planned and desired projection errors (Sec. V-G), the
mean feedback wrench ||w-bar^d - w-bar^p'|| (eq. 12's Delta w-bar^d), the CoM tracking error,
the scales of the planned CoM acceleration and angular momentum (Sec. V-G: "no significant
differences were found in the scale of feedback wrench (11), CoM acceleration, and angular
momentum"), the planner's per-update compute time (median, p99) and its horizon in samples.
`horizon_timing` measures the linear MPC's update time against its horizon length for each
formulation and solver (Sec. V-E: Audren's MPC takes 20 ms for 20 samples).
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence

import numpy as np
import pandas as pd

from bench.executors import EpisodeTimeout, make_executor
from bench.metrics import feedback_magnitude
from bench.runner import EpisodeSpec, run_episode
from reports.paper_figures import PAPER_SCENARIO, PAPER_SEC_V_G
from robots.model import RobotModel, cached_model
from robots.robot_registry import DEFAULT_ROBOT, make_robot

COMPARISON_COLUMNS = (
    "planner",
    "sim",
    "status",
    "planned_force_N",
    "planned_moment_Nm",
    "desired_force_N",
    "desired_moment_Nm",
    "feedback_force_N",
    "feedback_moment_Nm",
    "com_error_rms_mm",
    "com_acceleration_mps2",
    "angular_momentum_kgm2ps",
    "update_median_us",
    "update_p99_us",
    "horizon_samples",
    "solver_failures",
)


def _horizon_samples(planner: str) -> int | None:
    from planners.base import planner_spec

    return getattr(planner_spec(planner).factory(0.002), "horizon", None)


def _row(spec: EpisodeSpec) -> dict:
    result = run_episode(spec)
    summary, trace = result.summary, result.trace
    errors = summary["projection_error"] or {}
    row = {
        "planner": spec.planner,
        "sim": spec.sim,
        "status": summary["status"],
        **{k: errors.get(k) for k in COMPARISON_COLUMNS[3:7]},
        "com_error_rms_mm": None
        if summary["com_error_rms_m"] is None
        else 1e3 * summary["com_error_rms_m"],
        "horizon_samples": _horizon_samples(spec.planner),
        "solver_failures": summary["solver_failures"],
        "error": summary["error"] or summary["fall_reason"],
    }
    row.update({k: v for k, v in feedback_magnitude(trace).items() if v is not None})
    if len(trace) and summary["mass_kg"]:  # Sec. V-G's "scale of CoM acceleration"
        force = trace[["wrench_projected_fx", "wrench_projected_fy", "wrench_projected_fz"]]
        row["com_acceleration_mps2"] = float(
            np.linalg.norm(force.to_numpy(), axis=1).mean() / summary["mass_kg"]
        )
    if len(trace):  # Sec. V-G's "scale of ... angular momentum"
        row["angular_momentum_kgm2ps"] = planned_angular_momentum_scale(
            trace, cached_model(make_robot(spec.robot, spec.scale))
        )
    update = summary["latency_us"].get("planner", {})
    row["update_median_us"] = update.get("median")
    row["update_p99_us"] = update.get("p99")
    return row


def planned_angular_momentum_scale(trace: pd.DataFrame, model: RobotModel) -> float:
    """[kg m^2/s] the mean of ||L^p|| over the trace, the planned centroidal angular momentum
    L^p = I omega^p of Murooka eq. 6 (I the constant diagonal inertia, `RobotModel.
    constant_inertia`, that preview control and the linear MPC plan with; omega^p the plan's
    base angular velocity, world axes, as each planner reports it: preview control's planned
    state at the period's start, the linear MPC's after one period with the projected wrench,
    one period's integration apart)."""
    omega = trace[[f"base_angular_velocity_planned_{axis}" for axis in "xyz"]].to_numpy()
    return float(np.linalg.norm(omega * np.diag(model.constant_inertia()), axis=1).mean())


def paper_rows(scenario: str, planners: Sequence[str]) -> pd.DataFrame | None:
    """`PAPER_SEC_V_G`'s rows for `scenario` and `planners` (those the paper has), as a table
    with the comparison's error columns; None if the paper has none for the scenario."""
    scenario = PAPER_SCENARIO.get(scenario, scenario)
    rows = [
        {"planner": planner, "sim": "paper (Choreonoid)", **PAPER_SEC_V_G[(scenario, planner)]}
        for planner in planners
        if (scenario, planner) in PAPER_SEC_V_G
    ]
    if not rows:
        return None
    return pd.DataFrame(rows, columns=["planner", "sim", *COMPARISON_COLUMNS[3:7]])


def compare(
    planners: Sequence[str],
    scenario: str,
    sims: Sequence[str],
    stabilizer: str = "centroidal_feedback",
    workers: int | None = None,
    progress: Callable[[dict], None] | None = None,
    duration: float | None = None,
    robot: str = DEFAULT_ROBOT,
    work: Callable[[EpisodeSpec], dict] = _row,
    budget_s: float | None = None,
) -> pd.DataFrame:
    """One episode per planner x simulator (in parallel processes, the sweeps' executor), as a
    DataFrame with the columns of `COMPARISON_COLUMNS` plus `error`, in the order planners x
    sims. A failed episode is a row with its status: the runner's, or "timeout" for one that
    overran its wall-clock budget (`budget_s` [s]; None: a sweep's default budget for its
    simulated time, `SweepSpec.wall_budget_s`) and "error" for one whose worker died; the
    other rows are kept. `duration` [s] shortens the scenario (None: its own); `robot` a
    registered robot; `progress` is called with each row as its episode ends."""
    from bench.sweep import simulated_duration
    from bench.sweep_spec import SweepSpec

    specs = [
        EpisodeSpec(p, stabilizer, s, scenario, duration=duration, robot=robot)
        for p in planners
        for s in sims
    ]
    if budget_s is None:
        simulated_s = simulated_duration(scenario, 1.0, duration, robot)
        budget_s = SweepSpec(controllers=(), sims=()).wall_budget_s(simulated_s)  # its defaults
    executor = make_executor("local", workers or min(len(specs), os.cpu_count() or 1))
    index = {id(spec): k for k, spec in enumerate(specs)}  # the executor hands back each item
    rows: dict[int, dict] = {}
    try:
        for spec, result in executor.map_unordered(work, specs, lambda _: budget_s):
            row = result if isinstance(result, dict) else _failure_row(spec, result)
            rows[index[id(spec)]] = row
            if progress is not None:
                progress(row)
    finally:
        executor.close()
    ordered = [rows[k] for k in range(len(specs))]
    return pd.DataFrame(ordered, columns=[*COMPARISON_COLUMNS, "error"])


def _failure_row(spec: EpisodeSpec, exc: BaseException) -> dict:
    """The row of an episode that returned no row: "timeout" for one that overran its budget
    (`bench.executors.EpisodeTimeout`), "error" for any other failure (its worker died)."""
    status = "timeout" if isinstance(exc, EpisodeTimeout) else "error"
    return {
        "planner": spec.planner,
        "sim": spec.sim,
        "status": status,
        "error": f"{status}: {type(exc).__name__}: {exc}",
    }


def horizon_timing(
    formulations: Sequence[str],
    horizons: Sequence[int] = (10, 20, 40, 80),
    updates: int = 20,
    scenario: str = "walk",
    start_time: float = 0.0,
    robot: str = DEFAULT_ROBOT,
) -> pd.DataFrame:
    """Median and p99 [ms] of `linear_mpc`'s update (planner call) per formulation and horizon
    length, over `updates` consecutive periods from `start_time` on `scenario` with the robot's
    standing state (no simulator): rows formulation x horizon.

    The planner is reset with the standing state, which is where the walk starts, so the
    default start is 0 s (the horizon then spans the double support and the first steps). A
    later start would time the planner catching up with a reference that has moved on without
    it, which never happens in an episode (at 0.9 s: face:quadprog 2.9 ms instead of 0.9 ms
    at 20 samples, more faces active; native:piqp 4.7 instead of 4.3 ms)."""
    from dataclasses import replace

    from bench.scenarios import make_scenario
    from planners.linear_mpc import LinearMpcPlanner
    from robots.model import RobotModel

    model = RobotModel(make_robot(robot))
    setting = make_scenario(scenario, model)
    state = model.standing_state()
    state = replace(
        state,
        com_position_world=model.com_position_world(state),
        com_velocity_world=np.zeros(3),
    )
    rows = []
    for name in formulations:
        for horizon in horizons:
            planner = LinearMpcPlanner(0.002, formulation=name, horizon=horizon)
            planner.reset(model, setting, state)
            times = []
            for k in range(updates + 1):
                t = start_time + k * 0.002
                begin = time.perf_counter()
                planner.plan(t, state)
                if k:  # the first call builds caches
                    times.append(1e3 * (time.perf_counter() - begin))
            rows.append(
                {
                    "formulation": name,
                    "horizon_samples": horizon,
                    "median_ms": float(np.median(times)),
                    "p99_ms": float(np.percentile(times, 99)),
                    "solver_failures": planner.solver_failures,
                }
            )
    return pd.DataFrame(rows)
