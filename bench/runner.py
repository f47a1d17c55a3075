"""The control-loop runner: one episode, every stage timed, failures recorded as data.

Each control period (DESIGN.md, the loop): scheduled pushes are applied, then
estimator -> planner -> stabilizer -> whole-body layer -> simulator, each stage timed with
`time.perf_counter_ns`. A stage that raises, an output with NaN, or a simulator error ends the
episode with status "error" and the message; a fall ends it with status "fell" and the fall
time. The runner itself never raises for these: the trace up to that point is kept.

Ground truth, for the record only (no controller sees it): the centre of mass (`com_true_*`)
and, in scenarios with hand targets (`Scenario.hand_targets`, `hand_error_limb`), the hand
error `hand_error_m` [m], the distance from that limb's contact frame (the palm) to its target
active at the period's start (NaN while none is; no column in scenarios without targets),
from the same forward-kinematics pass as the centre of mass, with the two points it is the
distance between: `hand_actual_{x,y,z}` (that palm position) and `hand_target_{x,y,z}` (the
target, NaN while none is). `hand_error_final_m` in the summary is the last period's (None
without targets, or with none active at the end); `hand_task` says whether the planner drives
the hand to them (`Planner.tracks_hand_targets`; None without targets).
"""

from __future__ import annotations

import copy
import math
import time
import traceback
from collections.abc import MutableSequence, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import pandas as pd

from bench.actuation import TorqueUse
from bench.branching import (
    BRANCHED_SCENARIOS,
    PUSH_TIMING_DELAY_PERIODS,
    Brancher,
    BranchesDone,
)
from bench.footsteps import (
    FootstepRecorder,
    PlannedFootstepRecorder,
    compare_with_plan,
    footstep_summary,
)
from bench.momentum import EVERY as MOMENTUM_EVERY
from bench.momentum import AngularMomentumErrors
from bench.provenance import provenance
from bench.scenarios import make_scenario
from centroidal.gravity import check_modelled_gravity
from centroidal.rotations import to_matrix, yaw_of
from centroidal.support import margin_inside, support_halfplanes, surface_vertices_world
from estimators.base import DEFAULT_ESTIMATOR, make_estimator
from planners.base import planner_spec
from robots.humanoid import humanoid
from robots.jvrc1 import jvrc1
from robots.model import RobotModel, cached_model
from robots.perturbation import NOMINAL, Perturbation, simulated_robot, simulated_scene
from robots.robot_registry import DEFAULT_ROBOT, make_robot
from robots.scene import Scenario
from robots.types import CentroidalPlan, JointCommand, RobotState, WholeBodyTargets
from sims.base import clear_backend_caches, make_simulator
from sims.sensor_model import CommandDelay, SensorModel
from stabilizers.base import stabilizer_spec
from wholebody.base import DEFAULT_WHOLE_BODY, make_whole_body

STAGES = ("estimator", "planner", "stabilizer", "whole_body", "sim")
# codes of the stage an episode is in, as written to a progress probe (see `run_episode`)
PROGRESS_STAGES = ("setup", *STAGES)
CONTROL_STAGES = STAGES[:-1]
CENTROIDAL_STAGES = ("reference", "preview", "projection", "distribution")  # Table IV rows
AXES = ("fx", "fy", "fz", "mx", "my", "mz")
WXYZ = ("w", "x", "y", "z")
_NO_TARGET = (math.nan, math.nan, math.nan)  # hand_target_* while no target is active


@dataclass(frozen=True)
class EpisodeSpec:
    """What to run. `duration` None: the scenario's own; push_* only for scenarios with a push."""

    planner: str
    stabilizer: str
    sim: str
    scenario: str
    seed: int = 0
    duration: float | None = None
    push_impulse: float | None = None
    push_direction_deg: float | None = None
    estimator: str = DEFAULT_ESTIMATOR
    scale: float = 1.0
    push_time: float | None = None  # [s], stand_push only
    push_step: int | None = None  # walk_push only: the single-support phase pushed
    friction: float | None = None  # None: the scenario's
    whole_body: str = DEFAULT_WHOLE_BODY  # the whole-body layer (`wholebody.base`)
    speed: float | None = None  # [m/s] forward speed of walk / walk_push (None: the default)
    steps: int | None = None  # steps of walk / walk_push (None: their 10)
    robot: str = DEFAULT_ROBOT  # `robots.robot_registry`
    replica: int = 0  # > 0: a replica of the episode (`replica_changes`)
    push_swing_fraction: float | None = None  # walk_push: where in the swing (None: 0.5)
    push_direction_name: str | None = None  # walk_push: relative to the support foot
    perturbation: Perturbation | None = None  # None: nominal (`robots.perturbation`)


@dataclass
class EpisodeResult:
    summary: dict
    trace: pd.DataFrame = field(repr=False)
    footsteps: pd.DataFrame | None = field(default=None, repr=False)
    """The steps taken (`bench.footsteps.FootstepRecorder.table`), None if none recorded."""
    wall_s: float | None = None
    """[s] wall-clock time of `run_episode` for this episode (set-up and loop; for a branched
    episode the common part and its own continuation, `bench.branching`)."""


class StageError(RuntimeError):
    pass


def _check_finite(stage: str, *arrays) -> None:
    """StageError if any entry is NaN or infinite: one sum over all arrays (a NaN or an
    infinity makes the sum non-finite; finite entries would need to exceed 1e308 to)."""
    total = 0.0
    for array in arrays:
        if array is not None:
            total += float(array.sum())
    if not math.isfinite(total):
        raise StageError(f"{stage} returned a non-finite value")


def _check_plan(plan: CentroidalPlan) -> None:
    _check_finite(
        "planner",
        plan.com_planned_world,
        plan.com_velocity_planned_world,
        plan.wrench_projected_world,
        plan.base_orientation_planned_world,
        plan.limb_target_position_world,
    )


def _check_targets(targets: WholeBodyTargets) -> None:
    _check_finite(
        "stabilizer",
        targets.com_position_world,
        targets.base_orientation_world,
        targets.limb_position_world,
        targets.contact_wrench_desired_limb,
        targets.joint_torque,
    )


def _check_command(command: JointCommand) -> None:
    _check_finite("whole_body", command.position, command.velocity, command.torque_feedforward)


class _Trace:
    """Per-period columns in preallocated arrays (float64 unless said): a scalar per `put`
    name, a (periods, k) block per `put_vector` prefix (one row write per period);
    `frame` names the block columns prefix_name."""

    def __init__(self, n_periods: int, limbs: tuple[str, ...]) -> None:
        self.n = 0
        self.capacity = n_periods
        self.blocks: dict[str, tuple[np.ndarray, tuple[str, ...] | None]] = {}
        self.limbs = limbs
        # column names built once, not every period
        self.limb_columns = [
            (f"contact_{limb}", f"wrench_measured_{limb}", f"wrench_desired_{limb}")
            for limb in limbs
        ]
        self.timing_columns: dict[str, str] = {}

    def timing_column(self, stage: str) -> str:
        name = self.timing_columns.get(stage)
        if name is None:
            name = self.timing_columns[stage] = f"t_{stage}_us"
        return name

    def put(self, name: str, value: float, dtype=np.float64) -> None:
        block = self.blocks.get(name)
        if block is None:
            column = (
                np.full(self.capacity, np.nan, dtype=dtype)
                if dtype == np.float64
                else np.zeros(self.capacity, dtype=dtype)
            )
            block = self.blocks[name] = (column, None)
        block[0][self.n] = value

    def put_vector(self, prefix: str, values, names=("x", "y", "z")) -> None:
        block = self.blocks.get(prefix)
        if block is None:
            block = self.blocks[prefix] = (np.full((self.capacity, len(names)), np.nan), names)
        block[0][self.n] = values

    def frame(self) -> pd.DataFrame:
        columns = {}
        for name, (array, names) in self.blocks.items():
            if names is None:
                columns[name] = array[: self.n]
            else:
                for k, part in enumerate(names):
                    columns[f"{name}_{part}"] = array[: self.n, k]
        return pd.DataFrame(columns)


MIN_P99_SAMPLES = 100
"""Periods a stage's p99 needs: at fewer, the 99th percentile lies between the two largest
values, the maximum in all but name; the p99 is then NaN (and left out of the report's
medians), the maximum still recorded."""


def _latency(trace: pd.DataFrame) -> dict[str, dict[str, float]]:
    """Per timed stage (the trace's t_<stage>_us columns): mean, median, p99 (NaN under
    MIN_P99_SAMPLES periods) and maximum [µs] over the periods that timed it."""
    result = {}
    for column in trace.columns:
        if column.startswith("t_") and column.endswith("_us"):
            values = trace[column].to_numpy()
            values = values[~np.isnan(values)]
            if len(values):
                result[column[2:-3]] = {
                    "mean": float(values.mean()),
                    "median": float(np.median(values)),
                    "p99": (
                        float(np.percentile(values, 99))
                        if len(values) >= MIN_P99_SAMPLES
                        else math.nan
                    ),
                    "max": float(values.max()),
                }
    return result


TABLE_IV_ROWS = ("centroidal_control", "reference", "preview", "projection", "distribution")
"""Murooka Table IV's rows: "Total control" (planner and stabilizer) and its four stages."""


def _latency_by_contacts(trace: pd.DataFrame) -> dict[str, dict[str, dict[str, float]]]:
    """Table IV's rows per number of planned contacts (Murooka: "the higher the number of
    robot contacts, the more time is required for wrench projection and distribution"):
    {"n": {stage: {"periods", "mean", "median", "p99"}}} [µs], for each n that occurs and
    each stage the controller times."""
    if "contacts_planned" not in trace.columns:
        return {}
    counts = trace["contacts_planned"].to_numpy()
    result: dict[str, dict[str, dict[str, float]]] = {}
    for n in np.unique(counts):
        mask = counts == n
        stages = {}
        for stage in TABLE_IV_ROWS:
            column = f"t_{stage}_us"
            if column not in trace.columns:
                continue
            values = trace[column].to_numpy()[mask]
            values = values[~np.isnan(values)]
            if len(values):
                stages[stage] = {
                    "periods": len(values),
                    "mean": float(values.mean()),
                    "median": float(np.median(values)),
                    "p99": (
                        float(np.percentile(values, 99))
                        if len(values) >= MIN_P99_SAMPLES
                        else math.nan
                    ),
                }
        if stages:
            result[str(int(n))] = stages
    return result


def clear_setup_caches() -> None:
    """Forget every per-process set-up cache (robots, pinocchio models, compiled MuJoCo models,
    idle PyBullet clients): the next episode sets up from scratch, as in a new worker."""
    humanoid.cache_clear()
    jvrc1.cache_clear()
    cached_model.cache_clear()
    clear_backend_caches()


def run_episode(
    spec: EpisodeSpec,
    progress: MutableSequence[float] | None = None,
    record_configuration: bool = False,
    branches: tuple[Sequence[EpisodeSpec], Sequence[float]] | None = None,
) -> EpisodeResult | list:
    """Run one episode (see `_run_episode`); with `branches` = (specs, wall-clock budgets [s]),
    specs[0] being `spec`, run them as one episode forked at their first push, one process per
    episode (`bench.branching.run_group`), and return their results in order (an exception in
    place of a branch that overran its budget, died or could not be forked)."""
    begin = time.perf_counter()
    if branches is None:
        result = _run_episode(spec, progress, record_configuration, None)
        result.wall_s = time.perf_counter() - begin
        return result
    specs, budgets = branches
    brancher = Brancher(len(specs), budgets, progress)
    try:
        result = _run_episode(spec, progress, record_configuration, brancher, specs, begin)
        result.wall_s = time.perf_counter() - begin - brancher.waited_s
    except BranchesDone:  # the parent, once every branch has ended
        return brancher.results
    except BaseException as exc:
        if brancher.is_child:
            brancher.finish_child(exc)  # a child never returns into its parent's caller
        raise
    if brancher.is_child:
        brancher.finish_child(result)
    # ended before the push: as every episode of the group would
    return [result, *(copy.deepcopy(result) for _ in specs[1:])]


def _run_episode(
    spec: EpisodeSpec,
    progress: MutableSequence[float] | None,
    record_configuration: bool,
    brancher: Brancher | None,
    branch_specs: Sequence[EpisodeSpec] = (),
    call_start: float = 0.0,
) -> EpisodeResult:
    """Run one episode; never raises for a controller or simulator failure.

    `record_configuration`: the trace also holds the ground-truth configuration every period
    (`base_position_true_*`, `base_orientation_true_{w,x,y,z}`, `q_true_<joint>`), for a
    replay (`bench.replay`).

    Timing (`latency_us`, `latency_by_contacts_us`) is over the periods from `timed_from_s`
    [s] in the summary on: 0 for a plain scenario; for a protocol push's (`stand_push`,
    `walk_push`, `BRANCHED_SCENARIOS`) the start of the period `PUSH_TIMING_DELAY_PERIODS`
    after the one its first push is applied in, branched or run alone, so that its timings are
    the same window either way and, in a branched group (`brancher`), its own (the periods
    before were run once for the group and every branch holds a copy of them), without the
    periods right after the fork (copy-on-write); None when it ended before its push (its
    timings are then over the whole run, and in a branched group every episode holds that one
    run's); none at all when it ended within those periods after the push.

    `progress` (two floats, for example shared memory that a sweep's parent process reads
    when an episode overruns its wall-clock budget): [0] the index in `PROGRESS_STAGES` of the
    stage running now, [1] the simulated time [s] of the current period."""
    if progress is None:
        progress = [0.0, 0.0]
    progress[0], progress[1] = 0.0, 0.0
    summary: dict = {
        "robot": spec.robot,
        "planner": spec.planner,
        "stabilizer": spec.stabilizer,
        "sim": spec.sim,
        "scenario": spec.scenario,
        "seed": spec.seed,
        "estimator": spec.estimator,
        "whole_body": spec.whole_body,
        "scale": spec.scale,
        "friction": spec.friction,
        "speed": spec.speed,
        "mass_kg": None,
        "status": "ok",
        "fell": False,
        "fall_time": None,
        "fall_reason": None,
        "duration": 0.0,
        "real_time_factor": None,
        "latency_us": {},
        "com_error_rms_m": None,
        "projection_error": None,
        "zmp_margin_min_m": None,
        "solver_failures": 0,
        "error": None,
        "error_stage": None,
        "steps_taken": None,
        "mean_step_length_m": None,
        "mean_step_duration_s": None,
        "distance_walked_m": None,
        "final_position_error_m": None,
        "touchdown_time_error_max_s": None,
        "touchdown_position_error_max_m": None,
        "touchdown_time_error_mean_s": None,
        "touchdown_position_error_mean_m": None,
        "final_yaw_error_rad": None,
        "hand_error_final_m": None,
        "hand_task": None,
        "plans_com_trajectory": None,
        # a replica's pushes start this much later [s] than its protocol's (`replica_changes`)
        "push_shift_s": 0.0,
        "angular_momentum_error": None,
        **TorqueUse((), np.zeros(0)).summary(),
        "latency_by_contacts_us": {},
        # a protocol push's episode is timed from just after its push (set then); a plain one
        # from 0
        "timed_from_s": None if spec.scenario in BRANCHED_SCENARIOS else 0.0,
        "replica": spec.replica,
        **(spec.perturbation or NOMINAL).columns(),
    }
    trace = _Trace(0, ())
    sim = None
    try:
        np.random.seed(spec.seed)  # noqa: NPY002 - seeds any legacy-API randomness too
        robot = make_robot(spec.robot, spec.scale)  # both cached per process: set-up once a worker
        model = cached_model(robot)
        perturbation = spec.perturbation or NOMINAL
        simulated = simulated_robot(robot, perturbation, spec.seed)  # the controller has `model`
        truth = model if simulated is robot else cached_model(simulated)  # for the record
        torque_use = TorqueUse(simulated.joint_names, simulated.array("torque_limit"))
        scenario = _pushed(spec, model)
        scene = scenario.scene
        check_modelled_gravity(scene.gravity)
        # the ground the simulator has (the controllers keep the scenario's: flat)
        simulated_ground = simulated_scene(scene, perturbation, spec.seed, spec.scale)
        summary.update(friction=scene.friction, mass_kg=robot.total_mass)
        hand_limb = hand_error_limb(scenario)
        hand_frame = None if hand_limb is None else robot.limb(hand_limb).contact_frame
        dt = scene.control_dt
        planner = planner_spec(spec.planner).factory(dt)
        summary["plans_com_trajectory"] = bool(getattr(planner, "plans_com_trajectory", True))
        if hand_limb is not None:  # whether the hand error is that of a driven hand
            summary["hand_task"] = bool(getattr(planner, "tracks_hand_targets", False))
        stabilizer = stabilizer_spec(spec.stabilizer).factory(dt)
        estimator = make_estimator(spec.estimator, model, dt)
        whole_body = make_whole_body(spec.whole_body, model, dt)
        sim = make_simulator(spec.sim)
        sensor_model = (
            SensorModel(perturbation, spec.seed, robot.n_joints, len(robot.limbs), dt, spec.replica)
            if perturbation.changes_sensors
            else None
        )
        delay = (
            CommandDelay(perturbation.command_delay, perturbation.gain_scale)
            if perturbation.command_delay or perturbation.gain_scale != 1.0
            else None
        )
        initial, push_shift = replica_changes(model.standing_state(), spec.seed, spec.replica)
        summary["push_shift_s"] = push_shift
    except Exception as exc:  # bad spec: recorded, not raised
        summary.update(
            status="error", error=f"setup: {type(exc).__name__}: {exc}", error_stage="setup"
        )
        summary.update(provenance())
        return EpisodeResult(summary, trace.frame())

    n_periods = round(scenario.duration / dt)
    trace = _Trace(n_periods, robot.limb_names)
    pending = _shifted_pushes(scenario, push_shift)
    if brancher is not None:
        brancher.prepare(
            [pending, *(_shifted_pushes(_pushed(s, model), push_shift) for s in branch_specs[1:])]
        )
    support = _SupportPolygon(robot)
    recorder = FootstepRecorder(
        robot.limb_names,
        tuple(k for k, limb in enumerate(robot.limbs) if limb.name.endswith("foot")),
        lambda limb: _sole_pose(truth, sim, limb),
    )
    planned_steps = PlannedFootstepRecorder()
    momentum = AngularMomentumErrors(truth)  # Murooka Sec. V-F, from the ground truth
    stage = "setup"
    wall_start = time.perf_counter()
    com_true_start = com_true_end = None  # [m] ground truth: walked, whatever was estimated
    yaw_true = [math.nan, math.nan]  # [rad] the base's heading at the start and the end
    try:
        com_true_start = truth.com_position_world(initial)
        yaw_true[0] = yaw_of(initial.base_orientation_world)
        measured = sensors = sim.reset(simulated, simulated_ground, initial)
        if sensor_model is not None:
            sensors = sensor_model.observe(measured)
        estimator.reset(initial, sensors)
        state = estimator.estimate(sensors)
        planner.reset(model, scenario, state)
        stabilizer.reset(model, scenario, state)
        whole_body.reset(model, initial)
        for k in range(n_periods):
            t = k * dt
            progress[1] = t
            if brancher is not None and brancher.due(t + dt / 2):
                # a copy of this process per episode of the group; the parent leaves the loop
                pending = brancher.split(time.perf_counter() - call_start)
                wall_start += brancher.waited_s
            if pending and pending[0].time < t + dt / 2 and summary["timed_from_s"] is None:
                # before it: a branched group's shared periods, and the fork's first periods
                summary["timed_from_s"] = (k + PUSH_TIMING_DELAY_PERIODS) * dt
            while pending and pending[0].time < t + dt / 2:
                push = pending.pop(0)
                sim.push(push.link, np.array(push.impulse_world), push.duration)
            timings = {}
            stage = "estimator"
            progress[0] = 1.0
            start = time.perf_counter_ns()
            state = estimator.estimate(sensors)
            timings["estimator"] = time.perf_counter_ns() - start
            _check_finite("estimator", state.base_position_world, state.com_position_world)
            true_state = measured.ground_truth()  # for the record only
            if k % MOMENTUM_EVERY == 0:
                momentum.observe(true_state)
            if hand_frame is None:
                com_true = truth.com_state_world(true_state)
            else:  # the palm from the same forward-kinematics pass
                com, com_velocity, hand_true = truth.com_state_and_frame_position_world(
                    true_state, hand_frame
                )
                com_true = (com, com_velocity)
            stage = "planner"
            progress[0] = 2.0
            start = time.perf_counter_ns()
            plan = planner.plan(t, state)
            timings["planner"] = time.perf_counter_ns() - start
            _check_plan(plan)
            estimator.follow(plan)
            stage = "stabilizer"
            progress[0] = 3.0
            start = time.perf_counter_ns()
            targets = stabilizer.stabilize(t, plan, state)
            timings["stabilizer"] = time.perf_counter_ns() - start
            _check_targets(targets)
            stage = "whole_body"
            progress[0] = 4.0
            start = time.perf_counter_ns()
            command = whole_body.command(targets, state)
            timings["whole_body"] = time.perf_counter_ns() - start
            _check_command(command)
            stage = "sim"
            progress[0] = 5.0
            if delay is not None:
                command = delay.apply(command)
            start = time.perf_counter_ns()
            measured = sensors = sim.step(command)
            timings["sim"] = time.perf_counter_ns() - start
            torque_use.observe(measured.joint_torque)
            if sensor_model is not None:
                sensors = sensor_model.observe(measured)
            timings["sim_engine"] = sim.engine_ns

            summary["solver_failures"] = int(plan.solver_failures)
            recorder.observe(t, state.contact_flag_limb.tolist())
            planned_steps.observe(t, plan.footsteps)
            _record(trace, t, state, plan, targets, timings)
            if record_configuration:
                trace.put_vector("base_position_true", true_state.base_position_world)
                trace.put_vector("base_orientation_true", true_state.base_orientation_world, WXYZ)
                trace.put_vector("q_true", true_state.joint_position, robot.joint_names)
            trace.put_vector("com_true", com_true[0])
            trace.put_vector("com_velocity_true", com_true[1])
            trace.put("zmp_margin_m", support.margin(plan))
            if hand_frame is not None:
                target = scenario.hand_target_at(hand_limb, t)
                trace.put_vector("hand_actual", hand_true)
                trace.put_vector("hand_target", _NO_TARGET if target is None else target)
                trace.put(
                    "hand_error_m",
                    math.nan if target is None else math.dist(hand_true, target),
                )
            trace.n += 1
            reason = sim.fall_reason()
            if reason is not None:
                summary.update(
                    status="fell", fell=True, fall_time=float(measured.time), fall_reason=reason
                )
                break
    except Exception as exc:
        message = f"{stage}: {type(exc).__name__}: {exc}"
        frames = traceback.extract_tb(exc.__traceback__)
        if frames:
            last = frames[-1]
            message += f" (at {last.filename.rsplit('/', 1)[-1]}:{last.lineno})"
        summary.update(status="error", error=message, error_stage=stage)
    finally:
        try:
            last = sim.ground_truth()
            com_true_end = truth.com_position_world(last)
            yaw_true[1] = yaw_of(last.base_orientation_world)
        except Exception:  # a simulator that failed may have no state left
            com_true_end = None
        sim.close()
    wall = time.perf_counter() - wall_start
    frame = trace.frame()
    simulated = trace.n * dt
    summary["duration"] = simulated
    summary["real_time_factor"] = simulated / wall if wall > 0 else None
    # the periods the episode's timings are over (`timed_from_s`): a pushed one's from just
    # after its push (none if it ended before then)
    timed = frame.iloc[round((summary["timed_from_s"] or 0.0) / dt) :]
    summary["latency_us"] = _latency(timed)
    summary["latency_by_contacts_us"] = _latency_by_contacts(timed)
    # a plan whose CoM is the state it was computed from has no CoM tracking error
    if len(frame) and summary["plans_com_trajectory"] is not False:
        error = (
            frame[["com_actual_x", "com_actual_y", "com_actual_z"]].to_numpy()
            - frame[["com_planned_x", "com_planned_y", "com_planned_z"]].to_numpy()
        )
        summary["com_error_rms_m"] = float(np.sqrt(np.mean(np.sum(error**2, axis=1))))
    if len(frame):
        projects = getattr(planner, "projects_wrench", True)  # a planner from before the flag
        summary["projection_error"] = _projection_error(frame, projects)
        summary["zmp_margin_min_m"] = float(frame["zmp_margin_m"].min())
    if "solver_iterations" in frame and len(frame):
        iterations = frame["solver_iterations"].to_numpy()
        summary["solver_iterations"] = {
            "mean": float(iterations.mean()),
            "p99": float(np.percentile(iterations, 99)),
            "max": float(iterations.max()),
        }
    summary["angular_momentum_error"] = momentum.summary()
    summary.update(torque_use.summary())
    if "hand_error_m" in frame and len(frame):
        last = float(frame["hand_error_m"].iloc[-1])
        summary["hand_error_final_m"] = last if math.isfinite(last) else None
    footsteps = compare_with_plan(recorder.table(), planned_steps.table())
    summary.update(
        footstep_summary(footsteps, com_true_start, com_true_end, scenario.goal_offset_world)
    )
    if scenario.goal_yaw is not None and all(map(math.isfinite, yaw_true)):
        turned = yaw_true[1] - yaw_true[0]
        summary["final_yaw_error_rad"] = float(
            abs(math.remainder(turned - scenario.goal_yaw, 2 * math.pi))
        )
    summary.update(provenance())
    return EpisodeResult(summary, frame, footsteps)


def _shifted_pushes(scenario: Scenario, shift: float) -> list:
    """The scenario's pushes, each `shift` [s] later (a replica's jitter), in time order."""
    return sorted((replace(p, time=p.time + shift) for p in scenario.pushes), key=lambda p: p.time)


def _pushed(spec: EpisodeSpec, model: RobotModel) -> Scenario:
    """`spec`'s scenario (of a branch of a group, for its pushes: it shares the rest)."""
    return make_scenario(
        spec.scenario,
        model,
        spec.duration,
        spec.push_impulse,
        spec.push_direction_deg,
        spec.push_time,
        spec.push_step,
        spec.friction,
        spec.speed,
        spec.steps,
        spec.push_swing_fraction,
        spec.push_direction_name,
    )


REPLICA_STREAM = 7_004
REPLICA_PUSH_JITTER_S = 0.02
"""A replica's pushes start up to this much earlier or later [s] (uniform; 10 control
periods)."""
REPLICA_VELOCITY_SIGMA_MPS = 0.01
"""A replica starts with a horizontal base velocity of this standard deviation [m/s] per axis
(the whole robot sliding at about 1 cm/s, which the soles' friction stops)."""


def replica_changes(initial: RobotState, seed: int, replica: int) -> tuple[RobotState, float]:
    """(initial state, push time shift [s]) of replica `replica` of an episode: replica 0 is
    the episode itself (no change); the others differ by a small seeded perturbation of the
    initial state and the push timing (DESIGN.md: "replicate each magnitude"), drawn from
    `default_rng([seed, REPLICA_STREAM, replica])`."""
    if replica == 0:
        return initial, 0.0
    rng = np.random.default_rng([seed, REPLICA_STREAM, replica])
    shift = float(rng.uniform(-REPLICA_PUSH_JITTER_S, REPLICA_PUSH_JITTER_S))
    velocity = np.zeros(3)
    velocity[:2] = rng.normal(0.0, REPLICA_VELOCITY_SIGMA_MPS, 2)
    return replace(initial, base_linear_velocity_world=velocity), shift


def hand_error_limb(scenario: Scenario) -> str | None:
    """The limb whose hand error an episode records: the right hand if it has targets (when
    several limbs have, as in Sherikov et al. 2014's tests, which drive the right hand), else
    the limb of the first target listed; None for a scenario without hand targets."""
    limbs = [target.limb for target in scenario.hand_targets]
    if not limbs:
        return None
    return "right_hand" if "right_hand" in limbs else limbs[0]


def _sole_pose(model: RobotModel, sim, limb: str) -> tuple[np.ndarray, float]:
    """The world position [m] and yaw [rad] of `limb`'s contact frame now (ground truth)."""
    frame = model.robot.limb(limb).contact_frame
    position, rotation = model.frame_pose(sim.ground_truth(), frame)
    return np.array(position, dtype=float), math.atan2(rotation[1, 0], rotation[0, 0])


class _SupportPolygon:
    """The support polygon of the plan's contacts (limb rectangles at their target poses),
    rebuilt only when the contacts change."""

    def __init__(self, robot) -> None:
        self.limbs = robot.limbs
        self.key = None
        self.halfplanes = None
        self._index_of: dict[tuple[str, ...], list[int]] = {}

    def margin(self, plan: CentroidalPlan) -> float:
        names = plan.contact_limbs
        index = self._index_of.get(names)
        if index is None:
            index = self._index_of[names] = [
                k for k, limb in enumerate(self.limbs) if limb.name in names
            ]
        key = (names, plan.limb_target_position_world[index].round(6).tobytes())
        if key != self.key:
            points = [
                surface_vertices_world(
                    self.limbs[k].half_extents,
                    plan.limb_target_position_world[k],
                    to_matrix(plan.limb_target_orientation_world[k]),
                )
                for k in index
            ]
            self.halfplanes = support_halfplanes(np.vstack(points)[:, :2]) if points else None
            self.key = key
        if self.halfplanes is None or not math.isfinite(float(plan.zmp_planned_world.sum())):
            return float("nan")
        return margin_inside(self.halfplanes, plan.zmp_planned_world[:2])


def _projection_error(frame: pd.DataFrame, projects: bool) -> dict[str, float | None]:
    """Murooka Sec. V-G: means of ||f-bar^p - f-bar^p'||, ||n-bar^p - n-bar^p'|| (planned; None
    when the planner does not project, `projects` False: its "projected" wrench is the planned
    one, and a zero error would claim a projection that never happened) and of the same for the
    desired wrench (None when the stabilizer distributes no wrench)."""

    def mean_norm(a: str, b: str, axes) -> float | None:
        columns_a = [f"{a}_{x}" for x in axes]
        columns_b = [f"{b}_{x}" for x in axes]
        if not set(columns_a + columns_b) <= set(frame.columns):
            return None
        difference = np.column_stack([frame[a].to_numpy() for a in columns_a]) - np.column_stack(
            [frame[b].to_numpy() for b in columns_b]
        )
        return float(np.nanmean(np.linalg.norm(difference, axis=1)))

    force, moment = AXES[:3], AXES[3:]
    return {
        "planned_force_N": mean_norm("wrench_planned", "wrench_projected", force)
        if projects
        else None,
        "planned_moment_Nm": mean_norm("wrench_planned", "wrench_projected", moment)
        if projects
        else None,
        "desired_force_N": mean_norm("wrench_desired", "wrench_distributed", force),
        "desired_moment_Nm": mean_norm("wrench_desired", "wrench_distributed", moment),
    }


def _record(
    trace: _Trace,
    t: float,
    state,
    plan: CentroidalPlan,
    targets: WholeBodyTargets,
    timings: dict[str, int],
) -> None:
    put, vector = trace.put, trace.put_vector
    put("time", t)
    put("contacts_planned", len(plan.contact_limbs), np.int8)
    vector("com_ref", plan.com_reference_world)
    vector("com_planned", plan.com_planned_world)
    vector("com_desired", targets.com_desired_world)
    vector("com_actual", state.com_position_world)
    vector("com_velocity_planned", plan.com_velocity_planned_world)
    vector("com_velocity_actual", state.com_velocity_world)
    vector("base_angular_velocity_planned", plan.base_angular_velocity_planned_world)
    vector("base_quat", state.base_orientation_world, ("w", "x", "y", "z"))
    vector("zmp_planned", plan.zmp_planned_world[:2], ("x", "y"))
    vector("zmp_desired", targets.zmp_desired_world[:2], ("x", "y"))
    vector("zmp_actual", state.zmp_world[:2], ("x", "y"))
    flags = state.contact_flag_limb.tolist()
    desired = targets.contact_wrench_desired_limb
    for k, (contact, measured, desired_name) in enumerate(trace.limb_columns):
        put(contact, flags[k], np.bool_)
        vector(measured, state.contact_wrench_limb[k], AXES)
        if desired is not None:
            vector(desired_name, desired[k], AXES)
    vector("wrench_planned", plan.wrench_planned_world, AXES)
    vector("wrench_projected", plan.wrench_projected_world, AXES)
    if targets.wrench_desired_world is not None:
        vector("wrench_desired", targets.wrench_desired_world, AXES)
        vector("wrench_distributed", targets.wrench_distributed_world, AXES)
    if plan.solver_iterations is not None:
        put("solver_iterations", plan.solver_iterations)
    column = trace.timing_column
    control = 0
    for name, ns in timings.items():
        put(column(name), ns / 1e3)
        if name in CONTROL_STAGES:
            control += ns
    put("t_control_total_us", control / 1e3)
    centroidal, staged = 0, False
    for source in (plan.timings_ns, targets.timings_ns or {}):
        for name, ns in source.items():
            put(column(name), ns / 1e3)
            if name in CENTROIDAL_STAGES:
                centroidal += ns
                staged = True
    # a controller without Murooka's stages has no Table IV sum (not a sum of 0 µs)
    put("t_centroidal_total_us", centroidal / 1e3 if staged else math.nan)
    # Murooka Table IV's "Total control": the whole centroidal control (planner and stabilizer:
    # the four rows above plus the feedback, the damping and all between), not the estimator
    # or the whole-body layer ("only the proposed centroidal control is included")
    put("t_centroidal_control_us", (timings["planner"] + timings["stabilizer"]) / 1e3)


def summary_json_ready(summary: dict) -> dict:
    """The summary with numpy scalars turned into Python numbers (for json.dumps)."""

    def convert(value):
        if isinstance(value, dict):
            return {k: convert(v) for k, v in value.items()}
        if isinstance(value, np.generic):
            return value.item()
        return value

    return convert(summary)


__all__ = ["EpisodeResult", "EpisodeSpec", "run_episode", "summary_json_ready"]
