"""The world and the experiment as data: scene geometry and physics settings, grasps, contact
phases, pushes, scenarios. Shared by simulators (which build the scene and make the grasps) and
controllers (which read the contact sequence)."""

from __future__ import annotations

import bisect
import functools
import itertools
import math
from dataclasses import dataclass

import numpy as np

from centroidal.gravity import GRAVITY
from robots.gait import GaitCommand
from robots.swing import cubic_spline_simple_swing


@dataclass(frozen=True)
class Box:
    """A static box: centre [m] and orientation (w, x, y, z) in the world, half extents [m]."""

    name: str
    center_world: tuple[float, float, float]
    half_extents: tuple[float, float, float]
    orientation_world: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True)
class MovingBox:
    """A box moving periodically about a mean pose, the same prescribed motion in every
    simulator (a kinematic body: contacts push the robot, nothing pushes the box).

    Mean pose: `center_world` [m] and `orientation_world` (w, x, y, z); `half_extents` [m].
    With s(t) = e(t) sin(2 pi t / period + phase), where the envelope e(t) = sin^2(pi t /
    (2 ramp_time)) rises smoothly from 0 to 1 over the first `ramp_time` [s] (e = 1 when
    `ramp_time` is 0, and for t >= ramp_time; e(0) = e'(0) = 0, so a box that ramps starts at
    its mean pose at rest):
    - centre(t) = center_world + translation_amplitude_world s(t) [m];
    - orientation(t) = R(rotation_axis_world, rotation_amplitude s(t)) orientation_world: a
      rotation by the angle rotation_amplitude s(t) [rad] about the unit world axis
      `rotation_axis_world` through the box's centre, applied after the mean orientation.
    `pose_at` and `velocity_at` give them and their derivatives (`sims` move the box along
    them every physics step)."""

    name: str
    center_world: tuple[float, float, float]
    half_extents: tuple[float, float, float]
    orientation_world: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    translation_amplitude_world: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotation_axis_world: tuple[float, float, float] = (0.0, 0.0, 1.0)
    rotation_amplitude: float = 0.0
    period: float = 2.0
    phase: float = 0.0
    ramp_time: float = 0.0
    start_time: float = 0.0
    """[s] the motion's clock starts here: the box rests at its mean pose before, and t in the
    formulas above is the time since (a motion's contacts are made before it moves)."""

    def _profile(self, time: float) -> tuple[float, float]:
        """s(t) and ds/dt [1/s] (Python-float arithmetic: the same numbers in every caller)."""
        time = time - self.start_time
        if time < 0.0:
            return 0.0, 0.0
        omega = 2.0 * math.pi / self.period
        angle = omega * time + self.phase
        wave, wave_rate = math.sin(angle), omega * math.cos(angle)
        if self.ramp_time <= 0.0 or time >= self.ramp_time:
            return wave, wave_rate
        if time <= 0.0:
            return 0.0, 0.0
        x = 0.5 * math.pi * time / self.ramp_time
        envelope = math.sin(x) ** 2
        envelope_rate = math.sin(2.0 * x) * 0.5 * math.pi / self.ramp_time
        return envelope * wave, envelope_rate * wave + envelope * wave_rate

    def _axis(self) -> tuple[float, float, float]:
        ax, ay, az = self.rotation_axis_world
        norm = math.sqrt(ax * ax + ay * ay + az * az)
        return ax / norm, ay / norm, az / norm

    def pose_at(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """The box's centre [m] and orientation (w, x, y, z), unit, at `time` [s]."""
        s, _ = self._profile(time)
        cx, cy, cz = self.center_world
        tx, ty, tz = self.translation_amplitude_world
        center = np.array([cx + tx * s, cy + ty * s, cz + tz * s])
        half = 0.5 * self.rotation_amplitude * s
        nx, ny, nz = self._axis()
        aw, sin_half = math.cos(half), math.sin(half)
        ax, ay, az = nx * sin_half, ny * sin_half, nz * sin_half
        bw, bx, by, bz = self.orientation_world
        q = (
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        )
        norm = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
        return center, np.array([q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm])

    def velocity_at(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """The centre's velocity [m/s] and the box's angular velocity [rad/s], both in the
        world frame, at `time` [s]."""
        _, rate = self._profile(time)
        tx, ty, tz = self.translation_amplitude_world
        nx, ny, nz = self._axis()
        spin = self.rotation_amplitude * rate
        return np.array([tx * rate, ty * rate, tz * rate]), np.array(
            [nx * spin, ny * spin, nz * spin]
        )

    def validate(self) -> None:
        if not (math.isfinite(self.period) and self.period > 0):
            raise ValueError(
                f"moving box {self.name!r}: period must be positive, got {self.period}"
            )
        if not (math.isfinite(self.ramp_time) and self.ramp_time >= 0):
            raise ValueError(
                f"moving box {self.name!r}: ramp_time must be >= 0, got {self.ramp_time}"
            )
        if not (math.isfinite(self.start_time) and self.start_time >= 0):
            raise ValueError(
                f"moving box {self.name!r}: start_time must be >= 0, got {self.start_time}"
            )
        if math.hypot(*self.rotation_axis_world) < 1e-12:
            raise ValueError(f"moving box {self.name!r}: rotation_axis_world must not be zero")


@dataclass(frozen=True)
class Grasp:
    """A hand grasping a box (a rail, a rung): from `start` to `end` [s] the link of the robot
    limb `limb` (its `Limb.link`, the hand's) is welded to the scene box `box` (a `Box` or a
    `MovingBox`) at the relative pose the two have when the grasp is made. Unlike a palm pressed
    on a surface (a unilateral contact), a grasp can pull, and holds any wrench: an equality
    constraint in the physics engine, the same in every simulator (`sims.base.SimulatorBase
    .grasp`). The simulator makes it before the first physics step that starts at or after
    `start` (to half a physics step) and releases it before the first one at or after `end`
    (never, for the default `end`). Its force is part of the limb's measured contact wrench
    (`Sensors.contact_wrench_limb`), and the limb counts as in contact while it holds."""

    limb: str
    box: str
    start: float = 0.0
    end: float = math.inf


@dataclass(frozen=True)
class Scene:
    """friction: Coulomb coefficient of every contact (robot-ground and robot-box); gravity
    [m/s^2] (world Z up); physics_dt [s] of one simulator step; control_dt [s] of one
    `Simulator.step` (an integer number of physics steps); `boxes` static, `moving_boxes`
    moved along their prescribed motion at every physics step (`MovingBox`). Box names are
    unique across both. `grasps`: the hands' grasps of boxes, made and released by the
    simulator at their times (`Grasp`); the limbs' names are checked against the robot when
    a simulator is reset."""

    boxes: tuple[Box, ...] = ()
    friction: float = 0.6
    gravity: float = GRAVITY
    physics_dt: float = 0.001
    control_dt: float = 0.002
    ground: bool = True
    max_tilt: float = np.deg2rad(30.0)
    """Base tilt [rad] above which the robot counts as fallen."""
    fall_height: float | None = None
    """Base height [m, world z] below which the robot counts as fallen; None: the robot's own
    `RobotDescription.fall_height`. A scene whose motion crouches on purpose (Fig. 4 D) sets
    its own, lower one."""
    moving_boxes: tuple[MovingBox, ...] = ()
    grasps: tuple[Grasp, ...] = ()

    @property
    def substeps(self) -> int:
        n = round(self.control_dt / self.physics_dt)
        if n < 1 or abs(n * self.physics_dt - self.control_dt) > 1e-12:
            raise ValueError(
                f"control_dt {self.control_dt} s is not a whole number of physics steps "
                f"of {self.physics_dt} s"
            )
        return n

    def validate(self) -> None:
        if self.friction <= 0:
            raise ValueError(f"friction must be positive, got {self.friction}")
        if self.physics_dt <= 0:
            raise ValueError(f"physics_dt must be positive, got {self.physics_dt}")
        _ = self.substeps
        names = [box.name for box in (*self.boxes, *self.moving_boxes)]
        if len(set(names)) != len(names):
            repeated = sorted({name for name in names if names.count(name) > 1})
            raise ValueError(f"box names must be unique, repeated: {', '.join(repeated)}")
        for box in self.moving_boxes:
            box.validate()
        held: dict[str, list[Grasp]] = {}
        for grasp in self.grasps:
            if grasp.box not in names:
                raise ValueError(f"grasp of {grasp.limb!r}: no box named {grasp.box!r}")
            if not (math.isfinite(grasp.start) and grasp.start < grasp.end):
                raise ValueError(
                    f"grasp of {grasp.limb!r} on {grasp.box!r}: needs a finite start before "
                    f"its end, got {grasp.start} to {grasp.end} s"
                )
            held.setdefault(grasp.limb, []).append(grasp)
        for limb, grasps in held.items():
            grasps.sort(key=lambda grasp: grasp.start)
            for a, b in itertools.pairwise(grasps):
                if b.start < a.end:
                    raise ValueError(
                        f"{limb!r} grasps {a.box!r} and {b.box!r} at once "
                        f"({a.start}-{a.end} s and {b.start}-{b.end} s)"
                    )


@dataclass(frozen=True)
class Contact:
    """A limb in contact: its contact frame's pose in the world, position [m] and orientation
    (w, x, y, z). `grasp`: the limb holds (a hand around a rail or rung), so it can pull as
    well as push: its wrench cone has the opposing pyramids too (Murooka Sec. III-B1, "friction
    pyramids facing each other", `centroidal.contacts`), and the scene holds it with a `Grasp`
    over the same time."""

    limb: str
    position_world: tuple[float, float, float]
    orientation_world: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    grasp: bool = False
    support_in_frame: tuple[tuple[float, float], ...] | None = None
    """Where only part of the limb's surface touches (a foot's toes on a ladder rung, Fig. 4 C):
    the vertices (x, y) [m] of the polygon that does, in the contact frame's x-y plane (the
    surface's, with `surface_pose_world`), inner margin included; None: the limb's whole
    surface (`robots.limbs.limb_surfaces`)."""
    surface_pose_world: (
        tuple[tuple[float, float, float], tuple[float, float, float, float]] | None
    ) = None
    """The touching surface's frame when it is not the contact frame: origin [m] and
    orientation (w, x, y, z) in the world, z the normal along which the environment pushes (a
    hand resting on a rail in its grasping pose pushes on the rail's top); `support_in_frame`
    is then required, in that frame's x-y plane. None: the contact frame's."""
    held: bool = False
    """The scene holds the limb where it is for the contact's time with a `Grasp` (a weld),
    though its cone cannot pull (not `grasp`): a hand resting on a rail that it could not keep
    on the rail's top otherwise (`handrail_stairs_resting`). A grasp is always held."""

    def __post_init__(self) -> None:
        if self.surface_pose_world is not None and self.support_in_frame is None:
            raise ValueError(f"{self.limb!r}: a surface_pose_world needs its support_in_frame")


@dataclass(frozen=True)
class ContactPhase:
    """The contacts that hold from `start` to `end` [s]. `com_offset_world` [m] (x, y) moves
    the horizontal CoM reference of the phase from the rule's support centre (Murooka Sec.
    V-C: 50 mm inward in the single support of the handrail stairs; the ladder's CoM 0.4 m
    behind its centre, 0.1 m forward; `planners.reference.support_centre`)."""

    start: float
    end: float
    contacts: tuple[Contact, ...]
    com_offset_world: tuple[float, float] = (0.0, 0.0)

    @property
    def limbs(self) -> tuple[str, ...]:
        return tuple(c.limb for c in self.contacts)


@dataclass(frozen=True)
class LimbWaypoint:
    """A pose a free limb passes through: `limb`'s contact frame at `position_world` [m] and
    `orientation_world` (w, x, y, z) at `time` [s], while it is in no contact. A limb's target
    moves from contact or waypoint to the next contact or waypoint (`Scenario.limb_pose`):
    a hand leaving its hanging pose for a wall starts from a waypoint there."""

    limb: str
    time: float
    position_world: tuple[float, float, float]
    orientation_world: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    release: bool = False
    """The limb is let go here: with no contact or waypoint after this one it has no target
    from `time` on (the whole-body layer's posture task takes it back), instead of holding
    this pose for ever."""


@dataclass(frozen=True)
class PushEvent:
    """A push: at `time` [s], `impulse_world` [N s] at `link`'s centre of mass, spread over
    `duration` [s]."""

    time: float
    link: str
    impulse_world: tuple[float, float, float]
    duration: float = 0.1


@dataclass(frozen=True)
class HandTarget:
    """A task target for a limb (a hand reaching for an object, Sherikov et al. 2014 eq. 17):
    `limb`'s contact frame (the palm centre) should be at `position_world` [m] from `time`
    [s] on, until the limb's next target. Not a contact: nothing holds the hand there."""

    limb: str
    time: float
    position_world: tuple[float, float, float]


SWING_PROFILES = ("quintic", "cubic_spline_simple")
"""`Scenario.swing_profile`'s choices."""


@dataclass(frozen=True)
class Scenario:
    """One experiment, as data: the scene, the contact sequence (phases cover [0, duration]),
    the pushes, the initial joint posture [rad] (the base is placed so the soles are on the
    ground), the duration [s] and the limbs' task targets (`hand_targets`)."""

    name: str
    duration: float
    scene: Scene
    phases: tuple[ContactPhase, ...]
    initial_posture: tuple[float, ...]
    pushes: tuple[PushEvent, ...] = ()
    swing_height: float = 0.05
    """Clearance [m] of a limb moving between two contacts (peak, at mid-swing)."""
    goal_offset_world: tuple[float, float] | None = None
    """Where a walk's gait command ends, relative to where it starts (x, y) [m]; None: no
    walk."""
    goal_yaw: float | None = None
    """How far a walk's gait command turns [rad] (left positive); None: no walk."""
    gait: GaitCommand | None = None
    """The gait command a walk was built from (`robots.gait`), for planners that choose
    their own footsteps; None: no walk."""
    hand_targets: tuple[HandTarget, ...] = ()
    """Where limbs' contact frames should be, from given times on (`hand_target_at`); empty:
    no task target."""
    limb_waypoints: tuple[LimbWaypoint, ...] = ()
    """Poses free limbs pass through between contacts (`LimbWaypoint`, `limb_pose`)."""
    hand_contact_kd_linear: float | None = None
    """Murooka Table II's note: the linear K_d [N s/m] of the hands' damping control in the
    contact phase for this motion (1000 walking with a hand on the wall, 50000 on the
    ladder); None: the table's 10000."""
    ladder_gains: bool = False
    """Murooka Table III's note: the centroidal feedback gains for climbing the ladder."""
    com_height_offset: float | None = None
    """[m] the constant offset of the CoM reference above the feet's mean height (Murooka Sec.
    V-C); None: the CoM's height above the soles at the start (`planners.reference`)."""
    swing_profile: str = "quintic"
    """How a limb moves from one contact straight to the next (`limb_pose`): "quintic" (ours,
    the default) or "cubic_spline_simple" (Murooka et al.'s own implementation,
    `robots.swing`); to or from a waypoint it is always the quintic."""
    swing_scale: float = 1.0
    """The robot's scale: multiplies the "cubic_spline_simple" swing's offsets."""

    def __post_init__(self) -> None:
        if self.swing_profile not in SWING_PROFILES:
            raise ValueError(
                f"swing_profile must be one of {', '.join(SWING_PROFILES)}, "
                f"got {self.swing_profile!r}"
            )

    @functools.cached_property
    def _hand_timeline(self) -> dict[str, tuple[list[float], list[np.ndarray]]]:
        """Per limb, its targets' times in increasing order and their positions [m] (a stable
        sort: of two targets at the same time, the later listed wins), for bisection."""
        per_limb: dict[str, list[HandTarget]] = {}
        for target in sorted(self.hand_targets, key=lambda target: target.time):
            per_limb.setdefault(target.limb, []).append(target)
        return {
            limb: (
                [target.time for target in targets],
                [np.array(target.position_world, dtype=float) for target in targets],
            )
            for limb, targets in per_limb.items()
        }

    def hand_target_at(self, limb: str, time: float) -> np.ndarray | None:
        """The position [m] `limb`'s contact frame should be at, at `time` [s]: that of its last
        target with `target.time <= time`; None before its first target, or if it has none.
        Returns a fresh array (the caller may modify it)."""
        timeline = self._hand_timeline.get(limb)
        if timeline is None:
            return None
        times, positions = timeline
        i = bisect.bisect_right(times, time) - 1
        return positions[i].copy() if i >= 0 else None

    @functools.cached_property
    def _waypoint_times(self) -> frozenset[tuple[str, float]]:
        """(limb, time) of every waypoint: which of `_neighbours`' poses are not contacts."""
        return frozenset((w.limb, w.time) for w in self.limb_waypoints)

    @functools.cached_property
    def _releases(self) -> frozenset[tuple[str, float]]:
        """(limb, time) of the waypoints that let their limb go (`LimbWaypoint.release`)."""
        return frozenset((w.limb, w.time) for w in self.limb_waypoints if w.release)

    @functools.cached_property
    def _timeline(self) -> tuple[list[float], dict[str, tuple[list[float], list]]] | None:
        """Phase starts, and per limb the (start, end, contact) of each phase it is in with
        their starts, for bisection; None if the phases are not in time order (then
        `phase_at` and `limb_pose` scan them)."""
        phases = self.phases
        if any(a.end > b.start for a, b in itertools.pairwise(phases)):
            return None
        per_limb: dict[str, list] = {}
        for phase in phases:
            for contact in phase.contacts:
                per_limb.setdefault(contact.limb, []).append((phase.start, phase.end, contact))
        for waypoint in self.limb_waypoints:  # a zero-length span: never "in contact"
            spans = per_limb.setdefault(waypoint.limb, [])
            spans.append((waypoint.time, waypoint.time, _waypoint_contact(waypoint)))
            spans.sort(key=lambda span: span[0])
        return [p.start for p in phases], {
            limb: ([start for start, _, _ in spans], spans) for limb, spans in per_limb.items()
        }

    def phase_at(self, time: float) -> ContactPhase:
        """The contact phase holding at `time` [s] (the last one after the end)."""
        timeline = self._timeline
        if timeline is not None:
            i = bisect.bisect_right(timeline[0], time) - 1
            if i >= 0 and time < self.phases[i].end:
                return self.phases[i]
            return self.phases[-1]
        for phase in self.phases:
            if phase.start <= time < phase.end:
                return phase
        return self.phases[-1]

    def _neighbours(self, limb: str, time: float):
        """(end, contact) of `limb`'s last contact ended by `time` and (start, contact) of its
        first one starting after it; the same pair (start, contact) twice if it is in contact
        at `time`."""
        timeline = self._timeline
        if timeline is None:
            previous = following = None
            for phase in self.phases:
                for contact in phase.contacts:
                    if contact.limb != limb:
                        continue
                    if phase.start <= time < phase.end:
                        current = (phase.start, contact)
                        return current, current
                    if phase.end <= time:
                        if previous is None or phase.end >= previous[0]:
                            previous = (phase.end, contact)
                    elif following is None or phase.start < following[0]:
                        following = (phase.start, contact)
            for waypoint in self.limb_waypoints:
                if waypoint.limb != limb:
                    continue
                if waypoint.time <= time and (previous is None or waypoint.time >= previous[0]):
                    previous = (waypoint.time, _waypoint_contact(waypoint))
                elif waypoint.time > time and (following is None or waypoint.time < following[0]):
                    following = (waypoint.time, _waypoint_contact(waypoint))
            return previous, following
        starts, spans = timeline[1].get(limb, ((), ()))
        i = bisect.bisect_right(starts, time) - 1  # the last span starting by `time`
        if i >= 0 and time < spans[i][1]:
            current = (spans[i][0], spans[i][2])
            return current, current
        previous = (spans[i][1], spans[i][2]) if i >= 0 else None
        following = (spans[i + 1][0], spans[i + 1][2]) if i + 1 < len(spans) else None
        return previous, following

    def limb_pose(self, limb: str, time: float) -> tuple[np.ndarray, np.ndarray] | None:
        """Target pose of `limb`'s contact frame at `time` [s]: its contact pose while in
        contact; between two contacts (or `limb_waypoints`), a swing from the last to the
        next (position and orientation along a quintic blend with zero velocity and
        acceleration at both ends, plus a clearance `swing_height` * 64 s^3 (1 - s)^3 along the
        mean of the two contacts' normals (their frames' z axes: vertical for feet on level
        ground, away from the wall for a hand moving on a wall): peak `swing_height` at
        mid-swing, and zero normal velocity and acceleration at lift-off and touchdown, so that
        the foot lands softly; a sin(pi s) bump, used before, landed at 0.2 m/s and made the
        sole chatter on MuJoCo's contact for 0.15 s), or, from one contact straight to the next
        in a scenario whose `swing_profile` is "cubic_spline_simple", Murooka et al.'s own
        swing (`robots.swing`); None if the limb is never in contact
        around `time`. Returns (position [m], orientation (w, x, y, z))."""
        previous, following = self._neighbours(limb, time)
        if following is None and previous is not None and (limb, previous[0]) in self._releases:
            return None
        if previous is following is not None:  # in contact
            contact = previous[1]
            return (
                np.array(contact.position_world, dtype=float),
                np.array(contact.orientation_world, dtype=float),
            )
        if previous is None and following is None:
            return None
        if previous is None or following is None:
            _, contact = previous or following
            return (
                np.array(contact.position_world, dtype=float),
                np.array(contact.orientation_world, dtype=float),
            )
        (t0, start), (t1, end) = previous, following
        if (
            self.swing_profile == "cubic_spline_simple"
            and (limb, t0) not in self._waypoint_times
            and (limb, t1) not in self._waypoint_times
        ):
            swing = cubic_spline_simple_swing(
                t0,
                t1,
                (start.position_world, start.orientation_world),
                (end.position_world, end.orientation_world),
                self.swing_scale,
            )
            return swing.position(time), swing.orientation(time)
        s = (time - t0) / (t1 - t0)
        blend = s**3 * (10 - 15 * s + 6 * s * s)
        p0, p1 = np.array(start.position_world), np.array(end.position_world)
        position = p0 + blend * (p1 - p0)
        clearance = self.swing_height * 64.0 * (s * (1.0 - s)) ** 3
        normal = _mean_normal(start.orientation_world, end.orientation_world)
        if normal is None:  # both level (z up): the vertical, exactly as before
            position[2] += clearance
        else:
            position += clearance * normal
        q0, q1 = np.array(start.orientation_world), np.array(end.orientation_world)
        if q0 @ q1 < 0:
            q1 = -q1
        orientation = q0 + blend * (q1 - q0)  # normalised lerp: exact for equal orientations
        return position, orientation / np.linalg.norm(orientation)


def _waypoint_contact(waypoint: LimbWaypoint) -> Contact:
    """A waypoint as the pose record `limb_pose` blends between (not a contact)."""
    return Contact(waypoint.limb, waypoint.position_world, waypoint.orientation_world)


def contact_normal(orientation_world) -> tuple[float, float, float]:
    """The z axis (third column of the rotation matrix) of the unit quaternion (w, x, y, z): a
    contact frame's normal in the world (into the limb: the direction of a pressing force)."""
    w, x, y, z = orientation_world
    return (2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y))


@functools.lru_cache(maxsize=1024)
def _mean_normal(q0, q1) -> np.ndarray | None:
    """The unit mean of two contact frames' normals; None when both are the world z axis
    (level contacts of any yaw: the clearance is then added to z alone, as it always was).
    Cached per pair of orientations (tuples): `limb_pose` asks every period of a swing; the
    array returned is shared, and read only."""
    n0, n1 = contact_normal(q0), contact_normal(q1)
    if n0[0] == n0[1] == n1[0] == n1[1] == 0.0:
        return None
    mean = np.add(n0, n1)
    norm = float(np.linalg.norm(mean))
    if norm < 1e-9:  # opposite normals: no common direction away from both
        return np.zeros(3)
    return mean / norm
