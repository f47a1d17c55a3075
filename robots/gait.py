"""The gait command that walking scenarios are built from (issue 15), kept with the scene
types so that an adaptive planner can read it from the scenario (`Scenario.gait`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robots.similarity import froude_time_scale

GAIT_STEPS = 10  # the default number of steps


@dataclass(frozen=True)
class GaitCommand:
    """A walking command, in the units of the centrobench humanoid at scale 1 (lengths scale
    with the robot, times with the square root of its scale: Froude similarity, like the joint
    speed limits). Per step the walking path advances `step_length` forward and
    `lateral_step` to the left [m] in its own frame; the swing foot lands at the path's new
    pose, keeping its standing offset across the path. The first step goes from the standing
    pose, the last brings the feet side by side (so the path makes steps - 1 advances).

    `speed` [m/s] (forward) and `lateral_speed` [m/s] set the step lengths instead:
    step_length = speed x step_period (`step_length_for`). Defaults: today's `walk`, 10 steps
    of 0.125 m (footprints of one foot 0.25 m apart), 0.9 s per step with 15 % double
    support, 0.05 m swing clearance, 1.0 s standing before and 1.5 s after; right foot first
    unless the walk goes left (then the left foot leads, so that the feet never cross).
    Ours (an adaptation): Murooka et al.'s walk gives only a 300 mm stride (Sec. V-B, Fig. 3,
    on HRP-5P, about 1.8 m); the authors' BaselineWalkingController walks 0.8 s steps with
    12.5 % double support, 0.30 m per foot, 0.05 m swing and feet 0.21 m apart, their
    MultiContactController 1.5 s steps with 33 % and 0.1 m."""

    step_length: float = 0.125
    lateral_step: float = 0.0
    speed: float | None = None
    lateral_speed: float | None = None
    turn: float = 0.0
    """[rad] the path's heading change per step (left positive); `yaw_rate` sets it instead."""
    yaw_rate: float | None = None
    """[rad/s] turn = yaw_rate x step_period."""
    step_width: float | None = None
    """[m] lateral distance between the footprints (None: the standing width)."""
    step_period: float = 0.9
    double_support_ratio: float = 0.15
    swing_height: float = 0.05
    steps: int = GAIT_STEPS
    start_double_support: float = 1.0
    end_double_support: float = 1.5

    def step_length_for(self, scale: float) -> tuple[float, float]:
        """(forward, lateral) advance of the path per step [m] at `scale`."""
        period = self.step_period * froude_time_scale(scale)
        forward = self.speed * period if self.speed is not None else self.step_length * scale
        lateral = (
            self.lateral_speed * period
            if self.lateral_speed is not None
            else self.lateral_step * scale
        )
        return forward, lateral

    def turn_per_step(self, scale: float) -> float:
        """The path's heading change per step [rad] at `scale`."""
        if self.yaw_rate is None:
            return self.turn
        return self.yaw_rate * self.step_period * froude_time_scale(scale)

    def path(self, scale: float) -> list[tuple[np.ndarray, float]]:
        """The path's poses after 0, 1, ..., steps - 1 advances: position (x, y) [m] relative
        to where it starts and heading [rad]. Each advance moves (forward, lateral) in the
        frame of the heading halfway through it (a chord of the arc when the path turns),
        then turns by `turn_per_step`."""
        forward, lateral = self.step_length_for(scale)
        turn = self.turn_per_step(scale)
        poses = [(np.zeros(2), 0.0)]
        for _ in range(self.steps - 1):
            position, heading = poses[-1]
            middle = heading + turn / 2
            c, s = np.cos(middle), np.sin(middle)
            poses.append(
                (
                    position + np.array([c * forward - s * lateral, s * forward + c * lateral]),
                    heading + turn,
                )
            )
        return poses

    def goal_offset(self, scale: float) -> np.ndarray:
        """Where the walk ends relative to where it starts [m] (x forward, y left)."""
        if self.turn_per_step(scale) == 0.0:
            forward, lateral = self.step_length_for(scale)
            return (self.steps - 1) * np.array([forward, lateral])
        return self.path(scale)[-1][0]

    def goal_yaw(self, scale: float) -> float:
        """How far the walk turns [rad] (left positive)."""
        return (self.steps - 1) * self.turn_per_step(scale)

    @property
    def straight(self) -> bool:
        """No turn and the standing width: the contact sequence of the straight walk."""
        return self.turn == 0.0 and self.yaw_rate in (None, 0.0) and self.step_width is None
