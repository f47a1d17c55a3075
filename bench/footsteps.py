"""Footsteps taken, measured (DESIGN.md: "footsteps taken" is a measurement, not a copy of the
plan): every lift-off and touchdown of a foot, from the simulator's contact flags, with the
sole's pose at touchdown from the simulator's ground truth.

A foot's contact flag chatters for a few milliseconds when it lands (measured: 2-8 ms of
on/off at each touchdown in both simulators), so contact intervals are debounced: a gap
shorter than `MIN_GAP_S` does not end a contact, and the touchdown is the first instant of the
merged contact. A foot that lands early also bounces (measured on the bent-knee five-mass
walks: a lift of 4-7 mm for about 0.06 s after most touchdowns of a sagging swing foot, each
counted as a step until 2026-12-01; no other controller's `walk` bounces): a loss of
contact shorter than `BOUNCE_MAX_S` after which the foot lands again within `BOUNCE_RADIUS_M`
of where it had landed is a bounce, not a step, and the touchdown stays the first. A step of
any gait here lasts longer (the shortest swing, the five-mass gait's at eq. 16's 2 f_g, is
0.25 s), and a step in place lasts longer too. The runner calls `FootstepRecorder.observe`
every period (a comparison of the flags with the last ones; work only when they change) and
`table` once at the end.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pandas as pd

from robots.types import Footstep

MIN_GAP_S = 0.02  # [s] shorter loss of contact: chatter, not a lift-off
BOUNCE_MAX_S = 0.1  # [s] shorter loss of contact, landing where it was: a bounce
BOUNCE_RADIUS_M = 0.01  # [m] horizontally, from the last touchdown: landing where it was
COLUMNS = (
    "limb",
    "liftoff_time_s",
    "touchdown_time_s",
    "x_m",
    "y_m",
    "z_m",
    "yaw_rad",
    "swing_length_m",
)
PLANNED_COLUMNS = ("limb", "liftoff_time_s", "touchdown_time_s", "x_m", "y_m", "z_m", "yaw_rad")


class FootstepRecorder:
    """Raw contact changes of the feet, with the sole pose at every raw touchdown.

    `pose_of(limb)` returns the limb's contact frame position (3,) [m] and yaw [rad] in the
    world now (the simulator's ground truth); it is called only when a foot's flag rises."""

    def __init__(
        self,
        limbs: tuple[str, ...],
        feet: tuple[int, ...],
        pose_of: Callable[[str], tuple[np.ndarray, float]],
    ) -> None:
        self.limbs, self.feet, self.pose_of = limbs, feet, pose_of
        self.last: list[bool] | None = None
        self.events: list[tuple[float, int, bool, np.ndarray | None, float]] = []
        self.initial: dict[int, tuple[np.ndarray, float]] = {}

    def observe(self, t: float, flags: list[bool]) -> None:
        """The contact flags (one per limb) at time t [s]."""
        if flags == self.last:
            return
        for k in self.feet:
            now = flags[k]
            if self.last is None:
                if now:
                    self.initial[k] = self.pose_of(self.limbs[k])
                continue
            if now != self.last[k]:
                pose = self.pose_of(self.limbs[k]) if now else (None, math.nan)
                self.events.append((t, k, now, pose[0], pose[1]))
        self.last = list(flags)

    def table(self) -> pd.DataFrame:
        """One row per step taken (a lift-off followed by a touchdown, after debouncing):
        limb, lift-off and touchdown times [s], sole position [m] and yaw [rad] at touchdown,
        and the swing's horizontal length [m] (from where the foot stood before)."""
        rows = []
        for k in self.feet:
            events = [e for e in self.events if e[1] == k]
            standing = self.initial.get(k)
            where = None if standing is None else standing[0]
            liftoff = None
            index = 0
            while index < len(events):
                t, _, down, position, yaw = events[index]
                if not down:
                    following = events[index + 1] if index + 1 < len(events) else None
                    if following is not None and _merged(t, following, where):
                        index += 2
                        continue
                    liftoff = t
                elif liftoff is None:
                    if where is None:  # the foot's first contact: where it stands
                        where = position
                else:
                    length = (
                        math.nan if where is None else float(np.hypot(*(position[:2] - where[:2])))  # type: ignore[index]
                    )
                    rows.append((self.limbs[k], liftoff, t, *position, yaw, length))  # type: ignore[misc]
                    where, liftoff = position, None
                index += 1
        frame = pd.DataFrame(rows, columns=list(COLUMNS))
        return frame.sort_values("touchdown_time_s", ignore_index=True)


def _merged(liftoff_time: float, touchdown: tuple, where: np.ndarray | None) -> bool:
    """Whether a lift-off at `liftoff_time` [s] and the `touchdown` event after it are one
    contact: chatter (a gap under `MIN_GAP_S`) or a bounce (under `BOUNCE_MAX_S`, landing
    within `BOUNCE_RADIUS_M` of `where`, the foot's last touchdown position [m])."""
    gap = touchdown[0] - liftoff_time
    if gap < MIN_GAP_S:
        return True
    if gap >= BOUNCE_MAX_S or where is None:
        return False
    return bool(np.hypot(*(touchdown[3][:2] - where[:2])) < BOUNCE_RADIUS_M)


def compare_with_plan(taken: pd.DataFrame, planned: pd.DataFrame) -> pd.DataFrame:
    """`taken` with, per step, the planned footstep of the same limb whose touchdown time is
    nearest: planned_touchdown_time_s, planned_x_m, planned_y_m, planned_yaw_rad, and the
    errors touchdown_time_error_s (taken - planned) [s] and touchdown_position_error_m (the
    horizontal distance [m]); NaN where the plan intended no step of that limb."""
    result = taken.copy()
    columns = {
        "planned_touchdown_time_s": "touchdown_time_s",
        "planned_x_m": "x_m",
        "planned_y_m": "y_m",
        "planned_yaw_rad": "yaw_rad",
    }
    for column in columns:
        result[column] = np.nan
    for index, row in taken.iterrows():
        same = planned[planned["limb"] == row["limb"]]
        if len(same):
            nearest = same.iloc[
                int(np.argmin(np.abs(same["touchdown_time_s"] - row["touchdown_time_s"])))
            ]
            for column, source in columns.items():
                result.loc[index, column] = nearest[source]
    result["touchdown_time_error_s"] = (
        result["touchdown_time_s"] - result["planned_touchdown_time_s"]
    )
    result["touchdown_position_error_m"] = np.hypot(
        result["x_m"] - result["planned_x_m"], result["y_m"] - result["planned_y_m"]
    )
    return result


def footstep_summary(
    steps: pd.DataFrame,
    com_start_world: np.ndarray | None,
    com_end_world: np.ndarray | None,
    goal_offset_world: tuple[float, float] | None,
) -> dict[str, float | int | None]:
    """The summary's footstep fields: steps taken, mean swing length [m], mean time between
    successive touchdowns [s], horizontal distance the CoM walked [m] (the runner passes the
    simulator's ground truth, not the estimate), and its final
    horizontal distance from the gait command's goal (start + the command's offset) [m]; with
    the plan's footsteps compared (`compare_with_plan`), the largest touchdown time error
    (absolute) [s] and horizontal position error [m] of any step, and their means over the
    steps (the time error signed: negative when the feet land early, as a sagging swing leg's
    do) [s, m]."""
    touchdowns = steps["touchdown_time_s"].to_numpy()
    result: dict[str, float | int | None] = {
        "steps_taken": len(steps),
        "mean_step_length_m": float(steps["swing_length_m"].mean()) if len(steps) else None,
        "mean_step_duration_s": float(np.diff(touchdowns).mean()) if len(steps) > 1 else None,
        "distance_walked_m": None,
        "final_position_error_m": None,
        "touchdown_time_error_max_s": None,
        "touchdown_position_error_max_m": None,
        "touchdown_time_error_mean_s": None,
        "touchdown_position_error_mean_m": None,
    }
    if "touchdown_time_error_s" in steps and steps["touchdown_time_error_s"].notna().any():
        time_error = steps["touchdown_time_error_s"]
        position_error = steps["touchdown_position_error_m"]
        result["touchdown_time_error_max_s"] = float(time_error.abs().max())
        result["touchdown_position_error_max_m"] = float(position_error.max())
        result["touchdown_time_error_mean_s"] = float(time_error.mean())
        result["touchdown_position_error_mean_m"] = float(position_error.mean())
    if com_start_world is not None and com_end_world is not None:
        travel = np.asarray(com_end_world[:2]) - np.asarray(com_start_world[:2])
        result["distance_walked_m"] = float(np.hypot(*travel))
        if goal_offset_world is not None:
            result["final_position_error_m"] = float(
                np.hypot(*(travel - np.asarray(goal_offset_world)))
            )
    return result


class PlannedFootstepRecorder:
    """The footsteps the plans intended (`CentroidalPlan.footsteps`): for each, the last version
    a plan published before its touchdown time, kept once that time has passed. The runner
    calls `observe` every period (work only when the plan's tuple changes or a touchdown time
    passes) and `table` once at the end."""

    def __init__(self) -> None:
        self.last: tuple | None = None
        self.pending: dict[str, Footstep] = {}  # limb -> its next step in the latest plan
        self.due = math.inf  # earliest pending touchdown time [s]
        self.kept: list[Footstep] = []

    def observe(self, t: float, footsteps: tuple) -> None:
        """The plan's upcoming footsteps (touchdown order) at time t [s]."""
        if self.due <= t:
            for limb, step in list(self.pending.items()):
                if step.touchdown_time <= t:
                    self.kept.append(step)
                    del self.pending[limb]
            self._update_due()
        if footsteps is self.last:
            return
        self.last = footsteps
        pending = {}
        for step in footsteps:  # each limb's first upcoming step is its next one
            pending.setdefault(step.limb, step)
        self.pending = pending  # a step the plan no longer lists is no longer intended
        self._update_due()

    def _update_due(self) -> None:
        self.due = min((s.touchdown_time for s in self.pending.values()), default=math.inf)

    def table(self) -> pd.DataFrame:
        """One row per intended footstep whose touchdown time has passed: limb, lift-off and
        touchdown times [s], position [m] and yaw [rad]."""
        rows = [
            (s.limb, s.liftoff_time, s.touchdown_time, *s.position_world, s.yaw) for s in self.kept
        ]
        return pd.DataFrame(rows, columns=list(PLANNED_COLUMNS))
