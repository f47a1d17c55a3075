"""Ficht & Behnke's Table 1 protocol: the highest commanded forward speed at which a controller
walks without falling, and its walking quality there (eq. 18).

Per controller and simulator, `walk` with a gait command of `steps` steps at speed v: a
ladder of speeds (`start`, `start + increment`, ... up to `maximum`) is climbed until a walk
falls (or ends in an error or a "timeout": then the speed found is a lower bound, and the
table says so), then the interval between the highest speed walked and the lowest that fell
is bisected on a grid of `resolution` (0.01 m/s, the issue's) until it is one
step wide. Outcomes are taken as monotonic in the speed, as a ladder and a bisection must. The
pairs are searched side by side in the local executor's worker processes, each on its own:
a pair's next speed is handed out as soon as its last one has been walked (no rounds that
wait for the slowest walk, and one set of workers for the whole search), so the table does
not depend on how the walks were scheduled, only the rows' order does.

`steps` = 12 gives the gait-phase controllers (`direct_centroidal`, f_g = 1.98 Hz) 21 steps
of their own at the commanded speed (the paper's "20 steps"; and the steps of its start at a
limited acceleration, `planners.five_mass_gait.GAIT_ACCELERATION_MPS2`, for which its walks
are given speed / acceleration seconds more, and their walked speed is measured after that
time, `steady_speed`) and the fixed-schedule ones 12 steps of 0.9 s.

With `replicas` R > 1 every speed is walked R times, replica 0 as the nominal walk and the
others each with a small seeded change (`bench.runner.replica_changes`: a horizontal initial
base velocity of sigma 1 cm/s), and a speed counts as walked when at least `required` of them
walk: R - R // 5, 4 of 5 as the push protocol's robust thresholds (DESIGN.md: "replicate each
magnitude"); the search is then on those outcomes. The walking quality at the speed found is
that of the first replica that walked it (replica 0's unless it fell; `reports.tables.
speed_table`).

Ctrl-C or SIGTERM stops the workers and raises `SpeedInterrupted`, which carries the rows of
the walks that had ended (`centrobench speed` writes them to speed.partial.parquet).
"""

from __future__ import annotations

import sys
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

import pandas as pd

from bench.push_protocol import MAX_REPLICAS  # the same bound as a push's replicas


@dataclass(frozen=True)
class SpeedProtocol:
    start: float = 0.05  # [m/s]
    increment: float = 0.05  # [m/s]
    maximum: float = 0.8  # [m/s]
    resolution: float = 0.01  # [m/s]
    steps: int = 12
    replicas: int = 1  # walks per speed (replica 0 the nominal one)

    def __post_init__(self) -> None:
        if not 0 < self.resolution <= self.increment:
            raise ValueError("resolution must be positive and at most the increment")
        if not 0 < self.start <= self.maximum:
            raise ValueError("start must be positive and at most the maximum")
        for name in ("start", "increment"):  # the ladder's rungs on the bisection's grid
            steps = getattr(self, name) / self.resolution
            if abs(steps - round(steps)) > 1e-9:
                raise ValueError(
                    f"{name} {getattr(self, name):g} must be a whole multiple of the resolution "
                    f"{self.resolution:g} (the ladder's speeds are on its grid)"
                )
        if not 1 <= self.replicas <= MAX_REPLICAS:
            raise ValueError(f"replicas must be an integer in [1, {MAX_REPLICAS}]")

    @property
    def required(self) -> int:
        """The replicas that must walk for a speed to count as walked: R - R // 5 (all of
        fewer than 5; 4 of 5, as the push protocol's robust thresholds)."""
        return self.replicas - self.replicas // 5


class SpeedInterrupted(KeyboardInterrupt):
    """Ctrl-C or SIGTERM stopped `run_speed_protocol`: `trials` holds the rows of the walks
    that had ended (the searches are incomplete); `terminated` is True for SIGTERM."""

    def __init__(self, trials: pd.DataFrame, terminated: bool) -> None:
        super().__init__("SIGTERM" if terminated else "interrupted")
        self.trials = trials
        self.terminated = terminated


class SpeedSearch:
    """The ladder-then-bisection search of one controller in one simulator: `next_speed()` is
    the speed to walk next [m/s] (None: the search is done), `record(speed, walked)` its
    outcome; `best` is the highest speed walked (None: none)."""

    def __init__(self, protocol: SpeedProtocol) -> None:
        self.protocol = protocol
        self.best: float | None = None
        self.failed: float | None = None  # the lowest speed that fell, above `best`
        self.tried: list[tuple[float, bool]] = []

    def _grid(self, speed: float) -> float:
        return round(round(speed / self.protocol.resolution) * self.protocol.resolution, 10)

    def next_speed(self) -> float | None:
        p = self.protocol
        if self.failed is None:  # climbing the ladder
            speed = p.start if self.best is None else self.best + p.increment
            return self._grid(speed) if speed <= p.maximum + 1e-9 else None
        low = 0.0 if self.best is None else self.best
        if self.failed - low <= p.resolution + 1e-9:
            return None
        middle = self._grid((low + self.failed) / 2)
        if not low < middle < self.failed:
            middle = self._grid(low + p.resolution)
        return middle if low < middle < self.failed else None

    def record(self, speed: float, walked: bool) -> None:
        self.tried.append((speed, walked))
        if walked:
            self.best = speed if self.best is None else max(self.best, speed)
        else:
            self.failed = speed if self.failed is None else min(self.failed, speed)


def speed_episode(item: tuple) -> dict[str, Any]:
    """Walk `walk` at the item's (controller, sim, speed [m/s], steps[, replica]); the row of
    the outcome. Runs in a worker process (module level: picklable)."""
    from bench.controllers import controller_spec
    from bench.metrics import walking_quality
    from bench.runner import EpisodeSpec, run_episode
    from planners.five_mass_gait import GAIT_ACCELERATION_MPS2
    from robots.gait import GaitCommand

    controller, sim, speed, steps = item[:4]
    replica = item[4] if len(item) > 4 else 0
    spec = controller_spec(controller)
    gait = GaitCommand(speed=speed, steps=steps)
    # [s] the five-mass gait's start to the speed (its planners are the only ones that start
    # at a limited acceleration): its walks are that much longer (the start adds at most
    # v / (2 a) and a step) and their steady steps are counted after it
    ramp = speed / GAIT_ACCELERATION_MPS2 if spec.planner.startswith("five_mass") else 0.0
    duration = gait.start_double_support + gait.steps * gait.step_period
    duration += gait.end_double_support + ramp
    result = run_episode(
        EpisodeSpec(
            spec.planner,
            spec.stabilizer,
            sim,
            "walk",
            estimator=spec.episode_estimator,
            whole_body=spec.whole_body,
            speed=speed,
            steps=steps,
            duration=duration,
            replica=replica,
        )
    )
    summary = result.summary
    return {
        "controller": controller,
        "sim": sim,
        "speed_command_mps": speed,
        "replica": replica,
        "estimator": spec.episode_estimator,
        "git_commit": summary.get("git_commit"),
        "cpu": summary.get("cpu"),
        "status": summary["status"],
        "error": summary["error"],
        "fall_time": summary["fall_time"],
        "speed_walked_mps": steady_speed(result.footsteps, ramp),
        "steps_taken": summary["steps_taken"],
        **walking_quality(result.trace, summary.get("plans_com_trajectory") is not False),
    }


def steady_speed(footsteps: pd.DataFrame | None, start_s: float = 0.0) -> float | None:
    """The mean forward speed walked [m/s] over the steady steps: the advance of one foot's
    soles per second between its first and last touchdowns, leaving out the first two and the
    last two touchdowns (the half first and the closing steps) and those within `start_s` [s]
    of the first lift-off (a walk whose gait command speeds up at a limited acceleration a
    reaches the speed v after v / a: `speed_episode` leaves that out for the five-mass gait,
    the only planner that starts so); None with too few touchdowns."""
    if footsteps is None or len(footsteps) < 7:
        return None
    middle = footsteps.iloc[2:-2]
    middle = middle[middle["touchdown_time_s"] > footsteps["liftoff_time_s"].iloc[0] + start_s]
    if middle.empty:
        return None
    same = middle[middle["limb"] == middle["limb"].iloc[0]]
    if len(same) < 2:
        return None
    duration = same["touchdown_time_s"].iloc[-1] - same["touchdown_time_s"].iloc[0]
    return float((same["x_m"].iloc[-1] - same["x_m"].iloc[0]) / duration) if duration > 0 else None


def _failure_row(item: tuple, exc: BaseException) -> dict[str, Any]:
    """The row of a walk that ended without a result: status "timeout" when it overran its
    wall-clock budget (`bench.executors.EpisodeTimeout`: the machine's, not the controller's,
    failing; `reports.tables.speed_table` says so in "v_fell ended"), "error" otherwise (its
    worker died). Either counts as not walked, so the speed found is then a lower bound."""
    from bench.executors import EpisodeTimeout

    controller, sim, speed, _, replica = item
    timeout = isinstance(exc, EpisodeTimeout)
    return {
        "controller": controller,
        "sim": sim,
        "speed_command_mps": speed,
        "replica": replica,
        "status": "timeout" if timeout else "error",
        "error": f"timeout: {exc}" if timeout else f"{type(exc).__name__}: {exc}",
    }


def run_speed_protocol(
    controllers: Iterable[str],
    sims: Iterable[str],
    protocol: SpeedProtocol | None = None,
    workers: int | None = None,
    work: Callable[[tuple], dict[str, Any]] = speed_episode,
    budget_s: float = 600.0,
    progress: bool = True,
) -> pd.DataFrame:
    """Every trial's row (controller, sim, speed_command_mps, replica, status, ...,
    replicas_required), in the order the walks ended. A pair's next speed (its `replicas`
    walks) is queued once every walk of its last speed has ended. Ctrl-C or SIGTERM raises
    `SpeedInterrupted` with the rows of the walks that had ended."""
    from bench.executors import make_executor
    from bench.sweep import SweepTerminated, terminate_as_interrupt

    protocol = protocol or SpeedProtocol()
    searches = {(c, s): SpeedSearch(protocol) for c in controllers for s in sims}

    def walks(controller: str, sim: str) -> list[tuple]:
        speed = searches[controller, sim].next_speed()
        if speed is None:
            return []
        return [(controller, sim, speed, protocol.steps, r) for r in range(protocol.replicas)]

    queue: deque[tuple] = deque(item for pair in searches for item in walks(*pair))
    rows: list[dict[str, Any]] = []
    walked: dict[tuple[str, str, float], list[bool]] = {}  # a speed's outcomes so far
    done = sum(1 for search in searches.values() if search.next_speed() is None)
    if progress:
        print(
            f"speed (Ficht & Behnke Table 1): {len(searches)} searches, {protocol.replicas} "
            f"walk{'s' if protocol.replicas > 1 else ''} per speed",
            file=sys.stderr,
            flush=True,
        )
    executor = make_executor("local", workers)
    try:
        with terminate_as_interrupt():
            for item, result in executor.map_unordered(work, queue, budget=lambda _: budget_s):
                controller, sim, speed = item[:3]
                if isinstance(result, BaseException):
                    result = _failure_row(item, result)
                rows.append({**result, "replicas_required": protocol.required})
                outcomes = walked.setdefault((controller, sim, speed), [])
                outcomes.append(result["status"] == "ok")
                if len(outcomes) < protocol.replicas:
                    continue
                del walked[controller, sim, speed]
                search = searches[controller, sim]
                search.record(speed, sum(outcomes) >= protocol.required)
                following = walks(controller, sim)
                queue.extend(following)  # run in this same map: the executor reads the deque
                if not following:
                    done += 1
                    if progress:
                        best = "none" if search.best is None else f"{search.best:g} m/s"
                        print(
                            f"speed (Ficht & Behnke Table 1): {controller} in {sim}: {best} after "
                            f"{len(search.tried)} speeds; {done} of {len(searches)} searches done",
                            file=sys.stderr,
                            flush=True,
                        )
    except KeyboardInterrupt as exc:  # the rows so far go with it
        raise SpeedInterrupted(pd.DataFrame(rows), isinstance(exc, SweepTerminated)) from None
    finally:
        executor.close()
    return pd.DataFrame(rows)


__all__ = [
    "SpeedInterrupted",
    "SpeedProtocol",
    "SpeedSearch",
    "run_speed_protocol",
    "speed_episode",
    "steady_speed",
]
