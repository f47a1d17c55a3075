"""The swing of a limb from one contact to the next as Murooka et al.'s own implementation
draws it: `SwingTrajCubicSplineSimple` of MultiContactController (isri-aist, the code of the
paper's Fig. 4 motions; the paper itself gives no swing trajectory).

Over a swing from pose (p0, R0) at t0 to (p1, R1) at t1, T = t1 - t0 (MCC's defaults,
`etc/MultiContactController.in.yaml`, used as printed: its sample runs JVRC-1, of our
humanoid's size at scale 1; every offset x the robot's scale):

- withdraw, [t0, t0 + 0.2 T]: from p0 to w = p0 + R0 (0, 0, 0.03) (3 cm along the contact
  normal, out of the surface), a cubic with zero velocity at t0 and zero acceleration at its
  end: p0 + (w - p0) (1.5 s^2 - 0.5 s^3);
- swing, [t0 + 0.2 T, t1 - 0.2 T]: a clamped cubic spline through w, the midpoint
  m = (p0 + p1) / 2 + R_m (0, 0, 0.1) at (t0 + t1) / 2 (R_m halfway between R0 and R1, by
  slerp) and a, with the withdraw's end velocity and the approach's start velocity at its ends;
- approach, [t1 - 0.2 T, t1]: from a = p1 + R1 (0, 0, 0.03) down to p1, zero acceleration at
  its start and zero velocity at t1;
- orientation: R0 until the withdraw ends, R1 from the approach on, and between them a cubic
  blend (3 s^2 - 2 s^3) of the spherical interpolation (MCC: a cubic interpolator
  through R0, R0, R1, R1 at those four times).

Where this differs from MCC (checked against its source, session 25): a limb that starts
free (from a waypoint, not a contact) keeps our quintic, where MCC draws one spline from the
start pose to the approach point; the swing starts from the planned contact pose, where MCC
starts from the IK's last result (`swingStartPolicy: ControlRobot`); the limb's IK task gets
the pose only, not MCC's velocity and acceleration feed-forward; a limb let go (MCC's Remove
command: withdraw, hold, stiffness ramped to zero) is handed to the posture task
(`LimbWaypoint.release`); and MCC's stop of the swing at an early touchdown is not modelled
(tried in the stabilizer, docs/multi-contact.md "(A)": no change).

Unlike our lifted swing (`bench.motions.ContactSequence.move(lift=...)`: quintic pieces
between waypoints, stopping at each), the foot never stops between lift-off and touchdown:
the across motion is spread over the middle 0.6 T instead of being packed between two stops.
"""

from __future__ import annotations

import functools

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.spatial.transform import Rotation, Slerp

WITHDRAW_DURATION_RATIO = 0.2
APPROACH_DURATION_RATIO = 0.2
WITHDRAW_OFFSET_M = 0.03
APPROACH_OFFSET_M = 0.03
SWING_OFFSET_M = 0.1
"""MultiContactController's `SwingTraj: CubicSplineSimple` defaults: the fractions of the
swing spent withdrawing from and approaching a contact, and the offsets [m] along the contact
frames' z axes (withdraw, approach) and along the mid-swing frame's z axis (swing)."""

Pose = tuple[tuple[float, float, float], tuple[float, float, float, float]]


def _z_axis(rotation: Rotation) -> np.ndarray:
    """The rotated frame's z axis in the world."""
    return rotation.apply([0.0, 0.0, 1.0])


def _rotation(q: np.ndarray) -> Rotation:
    """The rotation of the unit quaternion (w, x, y, z)."""
    return Rotation.from_quat([q[1], q[2], q[3], q[0]])


class CubicSplineSimpleSwing:
    """One swing (module docstring) from `start` at `t0` to `end` at `t1` [s]; poses as
    (position [m], orientation (w, x, y, z)) of the limb's contact frame; `scale` multiplies
    the offsets (the robot's scale)."""

    def __init__(self, t0: float, t1: float, start: Pose, end: Pose, scale: float = 1.0) -> None:
        if not t1 > t0:
            raise ValueError(f"a swing needs t1 > t0, got {t0} and {t1}")
        self.t0, self.t1 = t0, t1
        duration = t1 - t0
        self.withdraw_s = WITHDRAW_DURATION_RATIO * duration
        self.approach_s = APPROACH_DURATION_RATIO * duration
        self.p0, self.p1 = np.array(start[0], float), np.array(end[0], float)
        start_end = Rotation.concatenate([_rotation(start[1]), _rotation(end[1])])
        self._slerp = Slerp([0.0, 1.0], start_end)
        self.withdrawn = self.p0 + scale * WITHDRAW_OFFSET_M * _z_axis(start_end[0])
        self.approached = self.p1 + scale * APPROACH_OFFSET_M * _z_axis(start_end[1])
        middle = 0.5 * (self.p0 + self.p1) + scale * SWING_OFFSET_M * _z_axis(self._slerp(0.5))
        # the withdraw's end velocity and the approach's start velocity: 1.5 x distance / time
        velocity_out = 1.5 * (self.withdrawn - self.p0) / self.withdraw_s
        velocity_in = 1.5 * (self.p1 - self.approached) / self.approach_s
        self.middle = CubicSpline(
            [t0 + self.withdraw_s, 0.5 * (t0 + t1), t1 - self.approach_s],
            np.stack([self.withdrawn, middle, self.approached]),
            bc_type=((1, velocity_out), (1, velocity_in)),
        )

    def position(self, time: float) -> np.ndarray:
        """[m] the contact frame's position at `time` [s] (clamped to the swing)."""
        t = min(max(time, self.t0), self.t1)
        if t <= self.t0 + self.withdraw_s:
            s = (t - self.t0) / self.withdraw_s
            return self.p0 + (self.withdrawn - self.p0) * (1.5 * s * s - 0.5 * s**3)
        if t >= self.t1 - self.approach_s:
            u = (self.t1 - t) / self.approach_s
            return self.p1 + (self.approached - self.p1) * (1.5 * u * u - 0.5 * u**3)
        return np.asarray(self.middle(t), dtype=float)

    def orientation(self, time: float) -> np.ndarray:
        """The contact frame's orientation (w, x, y, z) at `time` [s]."""
        start, end = self.t0 + self.withdraw_s, self.t1 - self.approach_s
        s = min(max((time - start) / (end - start), 0.0), 1.0)
        x, y, z, w = self._slerp(s * s * (3.0 - 2.0 * s)).as_quat()
        return np.array([w, x, y, z])


@functools.lru_cache(maxsize=256)
def cubic_spline_simple_swing(
    t0: float, t1: float, start: Pose, end: Pose, scale: float = 1.0
) -> CubicSplineSimpleSwing:
    """The swing, built once per (times, poses, scale): `Scenario.limb_pose` asks every
    period."""
    return CubicSplineSimpleSwing(t0, t1, start, end, scale)
