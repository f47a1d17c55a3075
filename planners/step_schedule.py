"""The fixed step timing of Sherikov et al.'s controller (2014, Sec. III: "footstep placement,
provided that the duration and sequence of steps are predetermined to keep the model linear"):
which foot supports when, over the preview horizon, while the footstep positions stay free.

A walk is a sequence of steps of `single_s` single support then `double_s` double support
(the paper previews "two steps of 0.8 s", as in its [3], Herdt et al., with 0.7 s + 0.1 s);
step i swings the foot `first_swing` when i is even, the other foot when odd. Standing is
double support without end. The preview samples' supports (eq. 11) follow Herdt et al.: a
sample belongs to the foothold that carries the robot at the sample's time, and a double
support between steps belongs to the foot that has just landed (the next stance foot), so that
the CoP moves onto it during the double support; while standing, to both feet together.

Support indices: 0 is the current foothold (the stance foot; both feet while standing), j >= 1
the j-th next footstep (the decision variables P_j of eq. 12).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

FEET = ("left_foot", "right_foot")


def other_foot(foot: str) -> str:
    return FEET[1 - FEET.index(foot)]


@dataclass(frozen=True)
class SchedulePhase:
    """The phase at a time: `swing` the foot in the air (None: double support), `stance` the
    foot that carries the robot in single support or will carry it next (None while
    standing), `step` the step's index (-1 while standing), `touchdown_s` the swing's
    touchdown time [s] (None in double support), `remaining_s` the time left in the phase."""

    swing: str | None
    stance: str | None
    step: int
    touchdown_s: float | None
    remaining_s: float


class StepSchedule:
    """Fixed step timing; `start(t, first_swing, steps)` begins a walk at t [s] (steps None:
    without end), `stop(t)` ends it at the next double support."""

    def __init__(self, single_s: float = 0.7, double_s: float = 0.1) -> None:
        if single_s <= 0 or double_s < 0:
            raise ValueError(f"step timing must be positive, got {single_s} s, {double_s} s")
        self.single_s, self.double_s = single_s, double_s
        self.period_s = single_s + double_s
        self.walk_start: float | None = None
        self.first_swing = FEET[1]
        self.steps: int | None = None

    @property
    def walking(self) -> bool:
        return self.walk_start is not None

    def starting(self, t: float) -> bool:
        """A walk is scheduled to start after t (the double support before its first step)."""
        return self.walk_start is not None and t < self.walk_start - 1e-12

    def start(self, t: float, first_swing: str, steps: int | None = None) -> None:
        if first_swing not in FEET:
            raise ValueError(f"first swing foot must be one of {FEET}, got {first_swing!r}")
        self.walk_start, self.first_swing, self.steps = t, first_swing, steps

    def stop_after(self, step: int) -> None:
        """End the walk with step `step` (standing after its double support)."""
        self.steps = step + 1

    def swing_of(self, step: int) -> str:
        return self.first_swing if step % 2 == 0 else other_foot(self.first_swing)

    def _step_at(self, t: float) -> tuple[int, float] | None:
        """(step index, time into it) at t, None if standing."""
        if self.walk_start is None or t < self.walk_start - 1e-12:
            return None
        step = math.floor((t - self.walk_start) / self.period_s + 1e-9)
        if self.steps is not None and step >= self.steps:
            return None
        return step, t - self.walk_start - step * self.period_s

    def phase(self, t: float) -> SchedulePhase:
        at = self._step_at(t)
        if at is None:
            return SchedulePhase(None, None, -1, None, math.inf)
        step, into = at
        swing = self.swing_of(step)
        if into < self.single_s - 1e-9:
            touchdown = self.walk_start + step * self.period_s + self.single_s
            return SchedulePhase(swing, other_foot(swing), step, touchdown, self.single_s - into)
        return SchedulePhase(None, swing, step, None, self.period_s - into)

    def first_interval(self, t: float, period_s: float) -> float:
        """[s] the preview's first interval at t, T_0 in (0, period_s]: up to the next point of
        the walk's grid (its start plus multiples of period_s), so that the samples
        t + T_0 + k period_s fall on its lift-offs, touchdowns and the ends of its double
        supports when those are multiples of period_s apart (the caller checks), as the
        authors' humoto shortens its first interval to the step grid (module `wpg04`);
        period_s while standing without a walk scheduled."""
        if self.walk_start is None:
            return period_s
        first = (self.walk_start - t) % period_s
        return period_s if first < 1e-9 or first > period_s - 1e-9 else first

    def sample_supports(self, t: float, period_s: float, n: int) -> np.ndarray:
        """(n,) int: the support index (see the module) of preview samples k = 1..n at
        t + T_0 + (k - 1) period_s (T_0: `first_interval`), relative to the phase at t. The
        CoP of eq. 10 is linear between samples, so a sample at a touchdown stays on the foot
        that carried the single support and one in the double support after it (its end
        included) is on the landed foot: the previewed CoP crosses between the feet only
        while both are down (until 2026-12-01 a sample at a touchdown was on the landed foot,
        and on a grid not aligned with the steps the CoP left the stance foot up to one
        interval before the touchdown, over the gap to a foot still in the air)."""
        now = self._step_at(t)
        first_s = self.first_interval(t, period_s)
        supports = np.zeros(n, dtype=int)
        if now is None:
            if self.walk_start is None or t >= self.walk_start:
                return supports
            first = 0  # a walk about to start: its first touchdown is footstep 1
        else:
            step_now, into = now
            # landings counted from now: in single support the swing's touchdown is footstep
            # 1; in the double support after a touchdown, the landed foot is the current one
            first = step_now if into < self.single_s - 1e-9 else step_now + 1
        for k in range(1, n + 1):
            sample = t + first_s + (k - 1) * period_s
            at = self._step_at(sample)
            if at is None and sample < self.walk_start - 1e-12:
                continue  # before the walk starts: on the current foothold (0)
            if at is None:  # the walk has ended by then: its last foothold
                last = (self.steps or 0) - 1
                supports[k - 1] = max(0, last - first + 1)
                continue
            step, into_k = at
            landed = step if into_k > self.single_s + 1e-9 else step - 1
            supports[k - 1] = max(0, landed - first + 1)
        return supports

    def samples_after_walk(self, t: float, period_s: float, n: int) -> np.ndarray:
        """(n,) bool: the preview samples (times as in `sample_supports`) at or after the end
        of a walk of given length (its last double support's end), when the robot stands on
        both feet again; all False for a walk without end or while standing."""
        after = np.zeros(n, dtype=bool)
        if self.walk_start is None or self.steps is None:
            return after
        end = self.walk_start + self.steps * self.period_s
        if t >= end - 1e-9:
            return after  # standing again: every sample is on the current support
        times = t + self.first_interval(t, period_s) + period_s * np.arange(n)
        after[:] = times >= end - 1e-9
        return after
