"""Murooka et al.'s multi-contact motions (RA-L 2022, Fig. 4 and Sec. V-C) as contact sequences.

Each motion is data: the scene of `robots.multi_contact_scenes`, a sequence of contact phases
built with `ContactSequence` (which limb touches which surface where, with the contact frame's
orientation: its z axis along the surface's normal, into the limb), the waypoints a hand leaves
from when it first reaches out, and the reference rules of Sec. V-C as per-phase CoM offsets
(`ContactPhase.com_offset_world`), with the motion's controller settings of Tables II and III
(`Scenario.hand_contact_kd_linear`, `Scenario.ladder_gains`). Timings, hand heights and
positions on the surfaces are ours (the paper prints none); each is a named constant at scale 1,
lengths x scale and times x sqrt(scale) (Froude similarity, as the walks).

- `moving_contacts` (Fig. 4 E): standing on the two moving floor plates, the hands reach the
  two moving walls one after the other, then the robot balances with four contacts while floors
  and walls move (their motion starts once the hands are on the walls).
- `handrail_stairs` (Fig. 4 B): the hands grasp the rails, the feet climb the four steps one
  tread at a time, the hands moving along the rails after each tread.
- `hand_wall` (Fig. 4 A): stepping over the 25 deg scaffold boards with a palm on the wall,
  switching from the left hand to the right at the top.
- `ladder_motion` (Fig. 4 C): the hands grasp a rung, the feet climb three rungs on their toes
  (`robots.scene.Contact.support_in_frame`), the hands moving one rung up after the feet.
- `hand_supports_motion` (Fig. 4 D): crouched, both palms on the two supports, then the feet
  swing forward together while the hands alone carry the body, and the hands follow one at a
  time.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from scipy.spatial.transform import Rotation

from centroidal.rotations import from_matrix
from robots.limbs import CONTACT_MARGIN
from robots.model import RobotModel
from robots.multi_contact_scenes import (
    BOARD_RUN,
    BOARD_TOP_LENGTH,
    HANDRAIL_HALF_SECTION,
    HANDRAIL_HEIGHT,
    HANDRAIL_RUNOUT,
    HANDRAIL_Y,
    LADDER_RUNG_THICKNESS,
    LADDER_X,
    MOTION_PERIOD_S,
    PAPER_BOARD_INCLINE_RAD,
    PAPER_RUNG_DEPTH_M,
    PAPER_RUNG_SPACING_M,
    PAPER_STEP_COUNT,
    PAPER_STEP_RISE_M,
    PAPER_SUPPORT_HEIGHT_M,
    STEP_RUN,
    SUPPORT_Y,
    WALKWAY_START_X,
    WALL_INNER_FACE_Y,
    WALL_WALK_FACE_Y,
    hand_supports,
    hand_wall,
    handrail_stairs,
    ladder,
    moving_contacts,
)
from robots.scene import Contact, ContactPhase, Grasp, LimbWaypoint, Scenario
from robots.similarity import froude_time_scale

Quaternion = tuple[float, float, float, float]

LEFT_WALL_PALM: Quaternion = (math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0)
"""A palm on the left wall (its face's normal -y): the contact frame turned +90 deg about x,
so that its z axis (into the limb) is -y."""
RIGHT_WALL_PALM: Quaternion = (math.sqrt(0.5), -math.sqrt(0.5), 0.0, 0.0)
"""A palm on the right wall (normal +y): -90 deg about x, z axis +y."""

WALL_PALM_X = 0.05
WALL_PALM_HEIGHT = 1.00
"""[m] at scale 1: where a palm presses a side wall, 0.05 m ahead of the soles' centres and
1.00 m above the soles (0.26 m below the shoulders: the elbow bent, the forearm reaching out
to the wall 0.24 m beyond the shoulder)."""

MOVING_STAND_S = 1.0
MOVING_REACH_S = 1.2
MOVING_SETTLE_S = 0.8
"""[s] at scale 1 of `moving_contacts`: standing before the first hand moves, each hand's move
to its wall, and holding after each placement."""
MOVING_BALANCE_PERIODS = 2.0
"""Balancing on the four moving contacts for two periods of the scene's motion
(`MOTION_PERIOD_S`, 16 s at scale 1; the first half period ramps the amplitude in)."""


LIFT_FRACTION = 0.3
"""A lifted swing (`ContactSequence.move(lift=...)`) rises for this fraction of its time,
moves across for 1 - 2 x it, and comes down for the rest."""

STAIRS_STAND_S = 1.0
STAIRS_REACH_S = 2.0
STAIRS_SWING_S = 1.0
STAIRS_DOUBLE_S = 0.6
STAIRS_HAND_MOVE_S = 2.0
"""[s] at scale 1 of `handrail_stairs`: standing first, each hand's first reach to its rail,
each foot's swing (single support), each double support after a step or a hand's move, and
each hand's move along its rail."""
STAIRS_SETTLE_S = 0.5
"""[s] at scale 1: a hand reaches its grasp pose this long before the grasp is made, and
waits (`ContactSequence.move(settle=...)`): made at once, the grasps were 3-5 cm off their
targets, the position-servoed arm's lag, and the damping control fought the offset."""
STAIRS_LIFT = 0.05
"""[m] at scale 1: a foot's swing rises to this above the higher tread before moving across
(the stair's nosing is 0.19 m ahead of the toes on the ground)."""
STAIRS_APPROACH_X = 0.15
"""[m] at scale 1: the feet first step to 0.15 m ahead (toes 0.04 m short of the first
riser), so that every step up is one tread (0.30 m) long."""
STAIRS_COM_HEIGHT = 0.74
"""[m] at scale 1: (B)'s CoM reference above the feet's mean height (Sec. V-C's constant
offset; 0.826 m, the standing height, is the default). From the kinematic check (`centrobench
check --scenario handrail_stairs`): at the standing height the trailing leg's knee reaches its
limit (straight) in the double support after each step up, a stride of 0.30 m run and 0.15 m
rise, and the IK misses the CoM reference by up to 91 mm there and the swing foot its tread by
70 mm; 0.78 m still straightens it in some phases, 0.75 m on the last step; at 0.74 m no knee
reaches its limit (with the rails lowered with it, `HANDRAIL_HEIGHT`: the CoM within 13 mm of
its reference once both hands hold, the swing foot within 47 mm, the trailing ankle's pitch at
its limit while it swings; 0.72-0.73 m: 14-17 mm)."""
STAIRS_HAND_START = 0.20
"""[m] at scale 1: the hands' first grasps, 0.20 m ahead of the feet."""
STAIRS_HAND_AHEAD = 0.35
"""[m] at scale 1: after both feet are on a tread (or the approach step), each hand in turn
moves along its rail to 0.35 m ahead of the feet (at most to the rail's end): the body then
advances one tread (0.30 m) before the hands move again, so a hand stays 0.05 to 0.35 m ahead
of its shoulder, inside the range where the arm reaches `RAIL_PALM_EULER_DEG`."""
PAPER_COM_INWARD_M = 0.050
"""Sec. V-C, (B): "the CoM lateral position in the single support phase is offset inward by
50 mm so that the hands support part of the robot's weight"."""


class ContactSequence:
    """Builds a motion's contact phases from its start: `hold` keeps the current contacts for a
    while, `move` takes limbs off their contacts (or from free waypoints) for a swing and places
    them on new ones (pressed, or grasping a scene box). `phases`, `waypoints` and `grasps`
    (the scene's `Grasp`s, one per grasp contact, from its touchdown to its lift-off) are the
    result."""

    def __init__(self, contacts: tuple[Contact, ...]) -> None:
        self.contacts: dict[str, Contact] = {c.limb: c for c in contacts}
        self.time = 0.0
        self.phases: list[ContactPhase] = []
        self.waypoints: list[LimbWaypoint] = []
        self.grasps: list[Grasp] = []
        self._holding: dict[str, tuple[str, float]] = {}  # limb -> (box, since)

    def _phase(self, duration: float, com_offset: tuple[float, float]) -> None:
        if not duration > 0:
            raise ValueError(f"a phase needs a positive duration, got {duration}")
        end = self.time + duration
        contacts = tuple(self.contacts.values())
        self.phases.append(ContactPhase(self.time, end, contacts, com_offset))
        self.time = end

    def hold(self, duration: float, com_offset: tuple[float, float] = (0.0, 0.0)) -> None:
        """The current contacts for `duration` [s]."""
        self._phase(duration, com_offset)

    def move(
        self,
        targets: tuple[Contact, ...],
        duration: float,
        start_poses: dict[str, tuple[np.ndarray, np.ndarray]] | None = None,
        com_offset: tuple[float, float] = (0.0, 0.0),
        boxes: dict[str, str] | None = None,
        lift: float | None = None,
        lift_over: bool = True,
        settle: float = 0.0,
        via: dict[str, tuple[tuple[float, tuple[float, float, float]], ...]] | None = None,
    ) -> None:
        """Each target's limb leaves its contact (or, if it has none, the pose `start_poses`
        gives it: position [m], orientation (w, x, y, z), a waypoint at the move's start) and
        is placed on the target after `duration` [s] of swing. A grasping target names its
        scene box in `boxes` (limb -> box). `lift` [m]: the swing rises straight up to `lift`
        above the higher of its two ends, moves across at that height and comes straight down
        (waypoints at `LIFT_FRACTION` of the swing from either end: a foot clears a stair's
        nosing); with `lift_over` False, to `lift` above each end (a hand moving parallel to a
        sloped rail). `settle` [s]: the limb reaches the target this long before the contact
        starts and waits there, free (a grasp is made where the hand is when it starts: the
        servos' lag then has time to go). `via`: per limb, positions [m] its swing passes
        through, each at a fraction of the swing (a foot drawn back from under the next rung
        before it rises), in the origin's orientation before mid-swing and the target's after."""
        start = self.time
        for target in targets:
            if target.limb in self._holding:
                box, since = self._holding.pop(target.limb)
                self.grasps.append(Grasp(target.limb, box, since, start))
            if target.limb in self.contacts:
                origin = self.contacts.pop(target.limb)
            else:
                if start_poses is None or target.limb not in start_poses:
                    raise ValueError(f"{target.limb!r} is in no contact: give its start pose")
                position, orientation = start_poses[target.limb]
                origin = Contact(
                    target.limb,
                    tuple(float(v) for v in position),
                    tuple(float(v) for v in orientation),
                )
                self.waypoints.append(
                    LimbWaypoint(
                        target.limb, start, origin.position_world, origin.orientation_world
                    )
                )
            swing = duration - settle
            if not swing > 0:
                raise ValueError(f"settle {settle} s leaves no swing in {duration} s")
            if settle > 0:
                self.waypoints.append(
                    LimbWaypoint(
                        target.limb,
                        start + swing,
                        target.position_world,
                        target.orientation_world,
                    )
                )
            for fraction, position in (via or {}).get(target.limb, ()):
                if not 0.0 < fraction < 1.0:
                    raise ValueError(f"a via point's fraction must be in (0, 1), got {fraction}")
                pose = origin if fraction < 0.5 else target
                self.waypoints.append(
                    LimbWaypoint(
                        target.limb,
                        start + fraction * swing,
                        tuple(float(v) for v in position),
                        pose.orientation_world,
                    )
                )
            if lift is not None:
                top = max(origin.position_world[2], target.position_world[2]) + lift
                for fraction, pose in ((LIFT_FRACTION, origin), (1 - LIFT_FRACTION, target)):
                    x, y, z = pose.position_world
                    self.waypoints.append(
                        LimbWaypoint(
                            target.limb,
                            start + fraction * swing,
                            (x, y, top if lift_over else z + lift),
                            pose.orientation_world,
                        )
                    )
        self._phase(duration, com_offset)
        for target in targets:
            self.contacts[target.limb] = target
            if target.grasp or target.held:
                if boxes is None or target.limb not in boxes:
                    raise ValueError(f"{target.limb!r} is held: name its box in `boxes`")
                self._holding[target.limb] = (boxes[target.limb], self.time)

    def free(
        self,
        limb: str,
        pose: tuple[np.ndarray, np.ndarray],
        duration: float,
        com_offset: tuple[float, float] = (0.0, 0.0),
    ) -> None:
        """`limb` leaves its contact and moves to `pose` (position [m], orientation (w, x, y,
        z)) over `duration` [s], where it is let go (a `LimbWaypoint` with `release`: the
        whole-body layer's posture task takes it from there)."""
        if limb in self._holding:
            box, since = self._holding.pop(limb)
            self.grasps.append(Grasp(limb, box, since, self.time))
        if limb not in self.contacts:
            raise ValueError(f"{limb!r} is in no contact to leave")
        del self.contacts[limb]
        position, orientation = pose
        self.waypoints.append(
            LimbWaypoint(
                limb,
                self.time + duration,
                tuple(float(v) for v in position),
                tuple(float(v) for v in orientation),
                release=True,
            )
        )
        self._phase(duration, com_offset)

    def carry(self, limb: str, pose: tuple[np.ndarray, np.ndarray]) -> None:
        """A free limb passes through `pose` (position [m], orientation (w, x, y, z)) now (a
        `LimbWaypoint` at the current time): a hand not yet used is carried along with the
        walking body instead of being held where the robot started (before its first
        waypoint a limb's target is that waypoint, `Scenario.limb_pose`)."""
        if limb in self.contacts:
            raise ValueError(f"{limb!r} is in contact: only a free limb is carried")
        position, orientation = pose
        self.waypoints.append(
            LimbWaypoint(
                limb,
                self.time,
                tuple(float(v) for v in position),
                tuple(float(v) for v in orientation),
            )
        )

    def all_grasps(self) -> tuple[Grasp, ...]:
        """The grasps made so far, those still held lasting to the end (`Grasp.end` inf)."""
        held = [Grasp(limb, box, since) for limb, (box, since) in self._holding.items()]
        return tuple(sorted([*self.grasps, *held], key=lambda g: (g.start, g.limb)))


def _begin(model: RobotModel):
    """A motion's start: the robot's scale, its time scale sqrt(scale) (Froude), the limbs'
    standing poses, the feet's contacts there (by limb) and a sequence standing on them."""
    poses = _limb_poses(model)
    feet = {c.limb: c for c in _standing_feet(poses)}
    scale = model.robot.scale
    return scale, froude_time_scale(scale), poses, feet, ContactSequence(tuple(feet.values()))


def _limb_poses(model: RobotModel) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Every limb's contact frame in the standing posture: position [m], (w, x, y, z)."""
    state = model.standing_state()
    poses = {}
    for limb in model.robot.limbs:
        position, rotation = model.frame_pose(state, limb.contact_frame)
        poses[limb.name] = (position, from_matrix(rotation))
    return poses


def _standing_feet(poses: dict[str, tuple[np.ndarray, np.ndarray]]) -> tuple[Contact, ...]:
    """The feet's contacts where they stand (level: orientation identity, as `stand`'s)."""
    return tuple(
        Contact(name, tuple(float(x) for x in position))
        for name, (position, _) in poses.items()
        if name.endswith("foot")
    )


def _wall_palms(
    scale: float, offset_y: float = 0.0, face_y: float = WALL_INNER_FACE_Y
) -> tuple[Contact, Contact]:
    """The left and right palms on side walls whose faces are at y = +-face_y [m at scale 1]."""
    y = face_y * scale + offset_y
    x, z = WALL_PALM_X * scale, WALL_PALM_HEIGHT * scale
    return (
        Contact("left_hand", (x, y, z), LEFT_WALL_PALM),
        Contact("right_hand", (x, -y, z), RIGHT_WALL_PALM),
    )


def moving_contacts_motion(model: RobotModel, duration: float | None = None) -> Scenario:
    """Fig. 4 (E): "balancing on the floors and walls, which move periodically in translation
    and rotation with an amplitude of 20 mm and 2 degrees. Damping control allows feet and
    hands to adapt to floor and wall movements." Standing on the floor plates, the left hand
    reaches the left wall, then the right hand the right wall; the scene's motion (the same as
    `robots.multi_contact_scenes.moving_contacts`, delayed) starts once both hands are on, and
    the robot balances on the four contacts (targets at the surfaces' mean poses: the
    damping control follows their motion). The CoM reference follows the rule of Sec. V-C
    (the feet's centre, constant height above them)."""
    robot = model.robot
    scale, time_scale = robot.scale, froude_time_scale(robot.scale)
    poses = _limb_poses(model)
    left, right = _wall_palms(scale)
    sequence = ContactSequence(_standing_feet(poses))
    sequence.hold(MOVING_STAND_S * time_scale)
    sequence.move((left,), MOVING_REACH_S * time_scale, poses)
    sequence.hold(MOVING_SETTLE_S * time_scale)
    sequence.move((right,), MOVING_REACH_S * time_scale, poses)
    sequence.hold(MOVING_SETTLE_S * time_scale)
    motion_start = sequence.time
    sequence.hold(MOVING_BALANCE_PERIODS * MOTION_PERIOD_S * time_scale)
    scene = moving_contacts(robot)
    scene = replace(
        scene,
        moving_boxes=tuple(replace(box, start_time=motion_start) for box in scene.moving_boxes),
    )
    return _scenario("moving_contacts", scene, sequence, model, duration)


def _scenario(
    name: str,
    scene,
    sequence: ContactSequence,
    model: RobotModel,
    duration: float | None,
    **settings,
) -> Scenario:
    """The motion as a `Scenario` with the sequence's grasps in its scene and `settings` (the
    motion's Scenario fields, e.g. its hand damping); a `duration` [s] cuts it short or holds
    the last phase."""
    phases = list(sequence.phases)
    total = sequence.time if duration is None else duration
    if duration is not None:
        phases = [p for p in phases if p.start < duration]
        phases[-1] = replace(phases[-1], end=duration)
    grasps = sequence.all_grasps()
    if grasps:
        scene = replace(scene, grasps=grasps)
    return Scenario(
        name,
        total,
        scene,
        tuple(phases),
        model.robot.nominal_posture,
        limb_waypoints=tuple(sequence.waypoints),
        **settings,
    )


RAIL_PALM_EULER_DEG = (30.0, 20.0, 30.0)
"""A hand grasping a handrail (left hand; the right one mirrored): its contact frame turned
-90 deg about y (z axis, into the limb, -x: the hand's end face forward along the rail), then
by these yaw, pitch, roll [deg] (world z, y, x: turned inward, tilted down, rolled in). Ours,
from the arm's reach: a search over yaw, pitch, roll in 10 deg steps (and roll +-30) for the
widest range of the palm's distance ahead of the shoulder, along the rail, over which the IK
reaches the pose exactly (to 2 mm and 0.02 rad, the standing robot's left arm alone): -0.05
to 0.40 m with these, 0.10 to 0.40 m without them (the wrist roll or the elbow at a limit
outside), against the 0.30 m the body advances per tread between two moves of a hand.
Turned down onto the rail's top (z up) the elbow would have to rise above the shoulder; out
onto its inner face (as a palm on a wall) the wrist pitch hits its 1.2 rad limit."""


def _rail_palm(side: str) -> Quaternion:
    """`RAIL_PALM_EULER_DEG` as a quaternion (w, x, y, z), mirrored for the right hand."""
    yaw, pitch, roll = RAIL_PALM_EULER_DEG
    if side == "right":
        yaw, roll = -yaw, -roll
    rotation = Rotation.from_euler("zyx", [yaw, pitch, roll], degrees=True) * Rotation.from_euler(
        "y", -90.0, degrees=True
    )
    x, y, z, w = rotation.as_quat()
    return (float(w), float(x), float(y), float(z))


RAIL_REST_HALF_EXTENTS = (0.03, 0.01)
"""[m] at scale 1: where a hand resting on a rail (`handrail_stairs_resting`) touches it, a
rectangle on the rail's top face under the palm, half extents along and across the rail: the
0.04 m bar's width and about the hand's width along it, less the 0.01 m inner margin of every
contact polygon (`robots.limbs.CONTACT_MARGIN`). Ours: the paper draws no hand polygon."""


def _rail_grasp(
    scale: float, side: str, x: float, pad_half_length: float, resting: bool = False
) -> tuple[Contact, str]:
    """A hand grasping the `side` rail of `handrail_stairs` at x [m] (`RAIL_PALM_EULER_DEG`):
    the palm centre over the bar's centre line, `pad_half_length` [m] (half the palm pad's
    length along its x axis, the hand limb's `half_extents[0]`: 0.05 m on the humanoid,
    0.035 m on JVRC-1, where a fixed 0.05 m held JVRC-1's palm 15 mm above the bar until
    2026-12-03) above the bar's top face; and the rail piece (box) that holds it there.
    `resting`: the same pose, but the hand only pushes on the rail's top face (a unilateral
    contact, `RAIL_REST_HALF_EXTENTS`, normal perpendicular to the rail) and the scene holds
    it there (`Contact.held`)."""
    s = scale
    run, rise = STEP_RUN * s, PAPER_STEP_RISE_M * s
    foot_of_slope = WALKWAY_START_X * s - run
    last_nosing = WALKWAY_START_X * s + (PAPER_STEP_COUNT - 1) * run
    if x > last_nosing + HANDRAIL_RUNOUT * s or x < foot_of_slope - HANDRAIL_RUNOUT * s:
        raise ValueError(f"x = {x} m is beyond the rails")
    if x < foot_of_slope:
        piece, height, slope = "bottom", HANDRAIL_HEIGHT * s, 0.0
    elif x <= last_nosing:
        slope = rise / run
        piece, height = "slope", HANDRAIL_HEIGHT * s + (x - foot_of_slope) * slope
    else:
        piece, height, slope = "top", HANDRAIL_HEIGHT * s + PAPER_STEP_COUNT * rise, 0.0
    top = height + HANDRAIL_HALF_SECTION * s * math.hypot(1.0, slope)  # the top face at x
    sign = 1.0 if side == "left" else -1.0
    position = (x, sign * HANDRAIL_Y * s, top + pad_half_length)
    if not resting:
        return Contact(
            f"{side}_hand", position, _rail_palm(side), grasp=True
        ), f"rail_{side}_{piece}"
    half_along, half_across = (RAIL_REST_HALF_EXTENTS[0] * s, RAIL_REST_HALF_EXTENTS[1] * s)
    w, qx, qy, qz = Rotation.from_euler("y", -math.atan(slope)).as_quat(scalar_first=True)
    contact = Contact(
        f"{side}_hand",
        position,
        _rail_palm(side),
        support_in_frame=(
            (half_along, half_across),
            (-half_along, half_across),
            (-half_along, -half_across),
            (half_along, -half_across),
        ),
        surface_pose_world=((x, sign * HANDRAIL_Y * s, top), (w, qx, qy, qz)),
        held=True,
    )
    return contact, f"rail_{side}_{piece}"


def handrail_stairs_motion(
    model: RobotModel, duration: float | None = None, resting: bool = False
) -> Scenario:
    """Fig. 4 (B): "climbing four steps of 150 mm height with handrails" (`robots.
    multi_contact_scenes.handrail_stairs`). Standing at the foot of the stairs, the hands grasp
    the rails 0.20 m ahead (left, then right); the feet step to 0.15 m ahead, then both onto
    each tread in turn, right foot first (treads' centres; the landing 0.15 m past its
    nosing), each swing lifted over the nosing (`STAIRS_LIFT`); after both feet are on a
    tread each hand moves one tread ahead along its rail (released, moved, grasped again).
    The CoM reference follows Sec. V-C: the feet's centre (single support: the supporting
    foot's, offset inward by 50 mm, `PAPER_COM_INWARD_M`), at a constant height above their
    mean; grasps as `Contact.grasp` (the paper's facing pyramids) held by the scene's `Grasp`s.
    Table II's hand K_d is the table's (the paper gives other values only for (A) and (C)).
    `resting` (`handrail_stairs_resting`): the hands rest on the rails' tops instead, unilateral
    contacts in the same poses (`_rail_grasp`), as the paper's (B) most likely had them (its
    Sec. V-G projection errors), held there by the scene as a grasp is."""
    robot = model.robot
    s, time_scale, poses, feet, sequence = _begin(model)
    sequence.hold(STAIRS_STAND_S * time_scale)
    hand_x = STAIRS_HAND_START * s
    pad = {side: robot.limb(f"{side}_hand").half_extents[0] for side in ("left", "right")}
    for side in ("left", "right"):
        grasp, box = _rail_grasp(s, side, hand_x, pad[side], resting)
        sequence.move(
            (grasp,),
            STAIRS_REACH_S * time_scale,
            poses,
            boxes={grasp.limb: box},
            lift=STAIRS_LIFT * s,
            settle=STAIRS_SETTLE_S * time_scale,
        )
        sequence.hold(STAIRS_DOUBLE_S * time_scale)
    run, rise = STEP_RUN * s, PAPER_STEP_RISE_M * s
    treads = [(STAIRS_APPROACH_X * s, 0.0)]
    for k in range(1, PAPER_STEP_COUNT + 1):
        front = WALKWAY_START_X * s + (k - 1) * run
        treads.append((front + 0.5 * run, k * rise))
    inward = PAPER_COM_INWARD_M * s
    for x, z in treads:
        for foot in ("right_foot", "left_foot"):
            y = feet[foot].position_world[1]
            target = Contact(foot, (x, y, z))
            other = "left_foot" if foot == "right_foot" else "right_foot"
            support_y = feet[other].position_world[1]
            offset = (0.0, -math.copysign(inward, support_y))  # towards the middle
            sequence.move(
                (target,), STAIRS_SWING_S * time_scale, com_offset=offset, lift=STAIRS_LIFT * s
            )
            feet[foot] = target
            sequence.hold(STAIRS_DOUBLE_S * time_scale)
        rail_end = WALKWAY_START_X * s + (PAPER_STEP_COUNT - 1) * run + HANDRAIL_RUNOUT * s
        hand_x = min(x + STAIRS_HAND_AHEAD * s, rail_end - 0.05 * s)
        for side in ("left", "right"):
            grasp, box = _rail_grasp(s, side, hand_x, pad[side], resting)
            sequence.move(
                (grasp,),
                STAIRS_HAND_MOVE_S * time_scale,
                boxes={grasp.limb: box},
                lift=STAIRS_LIFT * s,
                lift_over=False,
                settle=STAIRS_SETTLE_S * time_scale,
            )
            sequence.hold(STAIRS_DOUBLE_S * time_scale)
    sequence.hold(STAIRS_STAND_S * time_scale)
    scene = handrail_stairs(robot)
    # every swing is lifted (`STAIRS_LIFT`): no clearance bump on top of it
    name = "handrail_stairs_resting" if resting else "handrail_stairs"
    return _scenario(
        name,
        scene,
        sequence,
        model,
        duration,
        swing_height=0.0,
        com_height_offset=STAIRS_COM_HEIGHT * s,
    )


WALL_WALK_FOOTHOLDS = (0.18, 0.42, 0.56, 0.70, 0.80, 1.05, 1.15, 1.42, 1.56, 1.70, 1.79, 2.05)
"""[m] at scale 1: the x of the soles' centres at each foothold of `hand_wall`, both feet
side by side (each foot steps there in turn, right first): on the ground before the boards,
four times up the ascending board, twice on the flat top board, four times down the
descending one, and on the ground after, every sole on one plane (its centre at least 0.11 m
along the board from a board's end); 0.09-0.14 m apart on a board (with 0.30 m the trailing
leg straightened and its foot left the ground). The fourth foothold down (1.79 m, since
2026-11-27): from 1.70 m the last stride, 0.35 m and down, straightened the swing knee (the
kinematic check). Ours; the paper gives no footholds."""
WALL_WALK_COM_HEIGHT = 0.78
"""[m] at scale 1: the CoM reference's constant offset above the feet (Sec. V-C; 0.826 m, the
standing height, is the default): 5 cm lower, so that the legs keep some bend with one foot
on the slope above the other."""
WALL_WALK_SWING_S = 1.0
WALL_WALK_DOUBLE_S = 0.6
WALL_WALK_HAND_S = 1.5
"""[s] at scale 1 of `hand_wall`: each foot's swing, each double support, each hand's move."""
WALL_WALK_SWITCH = 5
"""The foothold (from 0) at which the right hand takes the right wall and the left lets go
(Fig. 5: "contact forces of the left hand (1-6 s) and right hand (6-10 s)")."""
WALL_WALK_PALM_HEIGHT = 0.90
"""[m] at scale 1: (A)'s palm on the wall is this far above the feet's footholds (the mean
height of the two it lies between, `hand_wall_palm_place`). Ours, from the kinematic check
(`bench.kinematic_check`, the IK alone on the motion). As first built (the palm 0.10 m ahead
of the feet, moved every other foothold, the right hand held at its start pose): at
`WALL_PALM_HEIGHT` (1.00 m, (E)'s) the left wrist pitch sat at its limit and the CoM was up to
94 mm (28 mm on average over the phases) from its reference; at 0.90 m up to 61 mm (13 mm);
0.75, 0.85 and 1.10 m were worse. With the palm moved at every foothold, midway (2026-11-27,
before the fourth foothold down: 70 phases), 0.85 m straightened the elbow in 26 phases and
0.95 / 1.00 m put the CoM up to 56 / 66 mm off, against 36 mm at 0.90 m, in the first phase
only (the reference's start)."""
PAPER_WALL_HAND_KD = 1000.0
"""Table II's note: the hands' linear K_d in contact "1000 for walking with hands on the wall"."""
WALL_WALK_SWING_PROFILE = "cubic_spline_simple"
"""(A)'s swings, feet and palms: Murooka et al.'s own (`robots.swing`)."""


def _walkway(scale: float, x: float) -> tuple[float, Quaternion]:
    """The height [m] of `hand_wall`'s walking surface at x [m] and a sole's orientation there
    (pitched with the board: its x axis along the slope, z along the board's normal)."""
    s = scale
    x0, run, top = WALKWAY_START_X * s, BOARD_RUN * s, BOARD_TOP_LENGTH * s
    slope = math.tan(PAPER_BOARD_INCLINE_RAD)
    rise = run * slope
    half = 0.5 * PAPER_BOARD_INCLINE_RAD
    up = (math.cos(-half), 0.0, math.sin(-half), 0.0)  # toes up: -25 deg about y
    down = (math.cos(half), 0.0, math.sin(half), 0.0)
    if x <= x0 or x >= x0 + 2 * run + top:
        return 0.0, (1.0, 0.0, 0.0, 0.0)
    if x < x0 + run:
        return (x - x0) * slope, up
    if x <= x0 + run + top:
        return rise, (1.0, 0.0, 0.0, 0.0)
    return rise - (x - x0 - run - top) * slope, down


def hand_wall_palm_place(scale: float, k: int) -> tuple[float, float]:
    """Where (A)'s palm goes on the wall while the feet stand on foothold k (-1: where they
    start) and step to foothold k + 1: x [m] midway between the two footholds, z [m]
    `WALL_WALK_PALM_HEIGHT` above their mean height; at the last foothold, above it. Ours: the
    body passes the palm halfway through its stride, so the arm is stretched least at either
    end (the kinematic check, with JVRC-1's ankle and wrist ranges and the ankle at -1.48 rad:
    a palm placed 0.10 m ahead of the foothold the feet stand on, moved every other foothold,
    straightened the elbow or put the wrist at its limit in 36 of 62 phases, the CoM up to 72
    mm from its reference; moved every foothold, midway, with the walls at 0.45 m, the elbow in
    7 of 70, 36 mm in the first phase only)."""
    if not -1 <= k < len(WALL_WALK_FOOTHOLDS):
        raise ValueError(f"foothold {k} is not one of -1 .. {len(WALL_WALK_FOOTHOLDS) - 1}")
    footholds = (0.0, *(x * scale for x in WALL_WALK_FOOTHOLDS))
    x_here, x_next = footholds[k + 1], footholds[min(k + 2, len(footholds) - 1)]
    z_here, z_next = _walkway(scale, x_here)[0], _walkway(scale, x_next)[0]
    return 0.5 * (x_here + x_next), 0.5 * (z_here + z_next) + WALL_WALK_PALM_HEIGHT * scale


def hand_wall_motion(model: RobotModel, duration: float | None = None) -> Scenario:
    """Fig. 4 (A): "stepping on scaffold boards with 25 degree incline while keeping the hand
    on a vertical wall" (`robots.multi_contact_scenes.hand_wall`). The left palm reaches the
    left wall, then the feet step foothold by foothold (`WALL_WALK_FOOTHOLDS`, both feet on
    each in turn, right first, soles pitched with the boards, every swing of a foot or a palm
    the authors' own, `WALL_WALK_SWING_PROFILE`) and after every foothold the palm on the wall
    moves along it
    (`hand_wall_palm_place`: midway to the next foothold; after the last, above it); at
    `WALL_WALK_SWITCH` the right palm takes the right wall and the left hand lets go (Fig. 5's
    switch of hands), the right palm moving along from then on. CoM reference by Sec. V-C's
    walking rule (the supporting feet's centre, constant height above their mean); the
    hands' damping K_d of Table II's note for this motion (`PAPER_WALL_HAND_KD`)."""
    robot = model.robot
    s, time_scale, poses, feet, sequence = _begin(model)
    sequence.carry("right_hand", poses["right_hand"])
    sequence.hold(WALL_WALK_DOUBLE_S * time_scale)
    left, right = _wall_palms(s, face_y=WALL_WALK_FACE_Y)

    def palm(contact: Contact, k: int) -> Contact:
        x, z = hand_wall_palm_place(s, k)
        return Contact(contact.limb, (x, contact.position_world[1], z), contact.orientation_world)

    sequence.move((palm(left, -1),), WALL_WALK_HAND_S * time_scale, poses)
    sequence.hold(WALL_WALK_DOUBLE_S * time_scale)
    hand = left
    for k, x_scaled in enumerate(WALL_WALK_FOOTHOLDS):
        x = x_scaled * s
        z, orientation = _walkway(s, x)
        for foot in ("right_foot", "left_foot"):
            y = feet[foot].position_world[1]
            target = Contact(foot, (x, y, z), orientation)
            sequence.move((target,), WALL_WALK_SWING_S * time_scale)
            feet[foot] = target
            sequence.hold(WALL_WALK_DOUBLE_S * time_scale)
        position, orientation = poses["right_hand"]
        hanging = (position + np.array([x, 0.0, z]), orientation)  # beside the body
        if k < WALL_WALK_SWITCH:
            sequence.carry("right_hand", hanging)
        if k == WALL_WALK_SWITCH:
            sequence.move((palm(right, k),), WALL_WALK_HAND_S * time_scale, {"right_hand": hanging})
            sequence.hold(WALL_WALK_DOUBLE_S * time_scale)
            hanging, orientation_hanging = poses["left_hand"]
            let_go = (hanging + np.array([x, 0.0, z]), orientation_hanging)
            sequence.free("left_hand", let_go, WALL_WALK_HAND_S * time_scale)
            sequence.hold(WALL_WALK_DOUBLE_S * time_scale)
            hand = right
        else:
            sequence.move((palm(hand, k),), WALL_WALK_HAND_S * time_scale)
            sequence.hold(WALL_WALK_DOUBLE_S * time_scale)
    sequence.hold(WALL_WALK_DOUBLE_S * time_scale)
    return _scenario(
        "hand_wall",
        hand_wall(robot),
        sequence,
        model,
        duration,
        hand_contact_kd_linear=PAPER_WALL_HAND_KD,
        com_height_offset=WALL_WALK_COM_HEIGHT * s,
        swing_profile=WALL_WALK_SWING_PROFILE,
        swing_scale=s,
    )


PAPER_LADDER_COM_BEHIND_M = 0.4
PAPER_LADDER_COM_FORWARD_M = 0.1
"""Sec. V-C, (C): "the reference CoM position is set 0.4 m behind the center of the ladder, but
offset forward by 0.1 m to reduce the pitch moment during the hand contact transitions"."""
PAPER_LADDER_HAND_KD = 50000.0
"""Table II's note: the hands' linear K_d in contact "50000 for climbing a vertical ladder"."""

LADDER_TOE_OVERHANG = 0.015
"""[m] at scale 1: a foot on a rung has its toe tip this far beyond the rung's far edge, so
that the whole 75 mm depth lies under the sole even if it touches down a little short."""
LADDER_FOOT_RETREAT = 0.13
"""[m] at scale 1: before it rises, a foot on a rung is drawn back this far, its toe tip then
0.02 m behind the rung's near edge (the next rung is right above the toes)."""
LADDER_CLEARANCE = 0.05
"""[m] at scale 1: a foot rises to this above its next rung before moving in over it."""
LADDER_HAND_Y = 0.18
"""[m] at scale 1: the hands grasp the rungs 0.18 m either side of the centre (the shoulders
are 0.21 m out; the stiles' inner faces 0.25 m)."""
LADDER_HAND_RETREAT = 0.06
"""[m] at scale 1: a hand moving to the next rung is drawn back this far from the rungs' near
faces first, and rises there."""
LADDER_FIRST_HAND_RUNG = 6
"""The rung the hands grasp first, standing on the ground (its top 1.20 m up, its centre 0.075
m below the shoulders); they move one rung up after the feet do (`ladder_motion`)."""
LADDER_CLIMB_RUNGS = 3
"""How many rungs the feet climb (to the third, 0.60 m up)."""
LADDER_STAND_S = 1.0
LADDER_REACH_S = 2.0
LADDER_SWING_S = 2.0
LADDER_DOUBLE_S = 0.8
LADDER_HAND_MOVE_S = 2.0
"""[s] at scale 1 of `ladder_motion`: standing first, each hand's first reach, each foot's
swing to the next rung, each double support after a step or a hand's move, each hand's move
to the next rung (its last `STAIRS_SETTLE_S` at the grasp pose, waiting). No phase moves the
CoM back once both hands grasp: `LADDER_X` less Sec. V-C's 0.3 m offset is 0, so the
ladder's reference is over the standing feet from the start."""


def _rung_top(scale: float, rung: int) -> float:
    """The height [m] of rung `rung`'s top face (`robots.multi_contact_scenes.ladder`)."""
    return rung * PAPER_RUNG_SPACING_M * scale


def _rung_foot(
    scale: float, foot: Contact, rung: int, sole_half_extents: tuple[float, float]
) -> Contact:
    """`foot` standing on its toes on rung `rung`: level, its toe tip `LADDER_TOE_OVERHANG`
    beyond the rung's far edge, the support polygon the part of the sole over the rung
    (`Contact.support_in_frame`, the sole frame at the sole's centre) with the inner margin.
    `sole_half_extents` [m]: the foot limb's (the humanoid's 0.11 x 0.06 m; JVRC-1's
    0.10 x 0.04 m, where the humanoid's fixed numbers put the polygon 13 mm beyond its sole's
    edge until 2026-12-03)."""
    s = scale
    half_length, half_width = sole_half_extents
    far_edge = LADDER_X * s + 0.5 * PAPER_RUNG_DEPTH_M * s
    x = far_edge + LADDER_TOE_OVERHANG * s - half_length
    near_edge = LADDER_X * s - 0.5 * PAPER_RUNG_DEPTH_M * s
    margin = CONTACT_MARGIN * s
    back, front = near_edge - x + margin, far_edge - x - margin
    side = half_width - margin
    return Contact(
        foot.limb,
        (x, foot.position_world[1], _rung_top(s, rung)),
        support_in_frame=((front, side), (back, side), (back, -side), (front, -side)),
    )


def _rung_grasp(scale: float, side: str, rung: int) -> tuple[Contact, str]:
    """A hand grasping rung `rung` (Fig. 4 C, "grasping contacts ... friction pyramids facing
    each other"): the hand's end face on the rung's near face (the contact frame's z axis, into
    the hand, along -x: the frame turned -90 deg about y), at the rung's mid-thickness,
    `LADDER_HAND_Y` out; and the rung box."""
    s = scale
    sign = 1.0 if side == "left" else -1.0
    near_face = LADDER_X * s - 0.5 * PAPER_RUNG_DEPTH_M * s
    z = _rung_top(s, rung) - 0.5 * LADDER_RUNG_THICKNESS * s
    orientation = (math.sqrt(0.5), 0.0, -math.sqrt(0.5), 0.0)
    contact = Contact(
        f"{side}_hand", (near_face, sign * LADDER_HAND_Y * s, z), orientation, grasp=True
    )
    return contact, f"rung_{rung:02d}"


def ladder_motion(model: RobotModel, duration: float | None = None) -> Scenario:
    """Fig. 4 (C): "climbing a vertical ladder with 200 mm steps. The depth of the ladder rungs
    is 75 mm, which is less than half the depth of the robot's sole" (`robots.
    multi_contact_scenes.ladder`). Standing before the ladder, the hands grasp rung
    `LADDER_FIRST_HAND_RUNG` (left, then right); then, `LADDER_CLIMB_RUNGS` times, the right
    foot and then the left step up to the next rung (on their toes: `_rung_foot`; from a rung
    drawn back first, `LADDER_FOOT_RETREAT`, to rise clear of the one above) and the left hand
    and then the right move one rung up. The CoM reference is Sec. V-C's: "0.4 m behind the
    center of the ladder, but offset forward by 0.1 m" horizontally (on the ladder's centre
    line), the constant offset above the feet's mean height vertically; Table III's ladder
    gains and Table II's hand K_d for the ladder.

    On the centrobench humanoid this rule puts the knee of a leg stepping up into the rungs
    above (its shank and ankle, 0.44 m, are two rung spacings): both simulators stop it at the
    first step (the thigh touches a rung, docs/multi-contact.md)."""
    robot = model.robot
    s, time_scale, poses, feet, sequence = _begin(model)
    com_x = LADDER_X * s - (PAPER_LADDER_COM_BEHIND_M - PAPER_LADDER_COM_FORWARD_M) * s

    def com_offset() -> tuple[float, float]:
        """From the rule's support centre (the feet in contact after the phase's moves start:
        `planners.reference.support_centre`) to the ladder's CoM reference."""
        standing = [c for c in sequence.contacts.values() if c.limb.endswith("foot")]
        centre = np.mean([c.position_world[:2] for c in standing], axis=0)
        return (float(com_x - centre[0]), float(-centre[1]))

    sequence.hold(LADDER_STAND_S * time_scale)
    hand_rung = LADDER_FIRST_HAND_RUNG
    settle = STAIRS_SETTLE_S * time_scale
    for side in ("left", "right"):
        grasp, box = _rung_grasp(s, side, hand_rung)
        sequence.move(
            (grasp,), LADDER_REACH_S * time_scale, poses, boxes={grasp.limb: box}, settle=settle
        )
        sequence.hold(LADDER_DOUBLE_S * time_scale)
    retreat, clearance = LADDER_FOOT_RETREAT * s, LADDER_CLEARANCE * s
    for rung in range(1, LADDER_CLIMB_RUNGS + 1):
        for foot in ("right_foot", "left_foot"):
            sole = robot.limb(foot).half_extents
            origin, target = feet[foot], _rung_foot(s, feet[foot], rung, sole)
            x0, y, z0 = origin.position_world
            back = x0 - (retreat if z0 > 0 else 0.0)
            high = target.position_world[2] + clearance
            via = {
                foot: (
                    (0.15, (back, y, z0 + 0.5 * clearance)),
                    (0.5, (back, y, high)),
                    (0.8, (target.position_world[0], y, high)),
                )
            }
            del sequence.contacts[foot]  # the support centre of the swing: the other foot
            offset = com_offset()
            sequence.contacts[foot] = origin
            sequence.move((target,), LADDER_SWING_S * time_scale, com_offset=offset, via=via)
            feet[foot] = target
            sequence.hold(LADDER_DOUBLE_S * time_scale, com_offset())
        hand_rung += 1
        for side in ("left", "right"):
            grasp, box = _rung_grasp(s, side, hand_rung)
            x, y, z = sequence.contacts[grasp.limb].position_world
            back = x - LADDER_HAND_RETREAT * s
            via = {
                grasp.limb: (
                    (0.25, (back, y, z)),
                    (0.75, (back, y, grasp.position_world[2])),
                )
            }
            sequence.move(
                (grasp,),
                LADDER_HAND_MOVE_S * time_scale,
                com_offset=com_offset(),
                boxes={grasp.limb: box},
                settle=settle,
                via=via,
            )
            sequence.hold(LADDER_DOUBLE_S * time_scale, com_offset())
    sequence.hold(LADDER_STAND_S * time_scale, com_offset())
    return _scenario(
        "ladder",
        ladder(robot),
        sequence,
        model,
        duration,
        swing_height=0.0,
        hand_contact_kd_linear=PAPER_LADDER_HAND_KD,
        ladder_gains=True,
    )


SUPPORTS_COM_HEIGHT = 0.60
"""(D): the CoM reference's constant height [m] above the soles (ours; 0.826 m standing). The
crouch that brings the palms down to the 0.5 m supports with the elbows straight: by the
kinematic check (`centrobench check --scenario hand_supports`), 0.60 m gives CoM errors of
8-10 mm in every phase; 0.63 m gives 35-47 mm and 0.66 m 63-78 mm (the palms pull the CoM
down), 0.57 m puts the ankles at their pitch limit in double support."""
SUPPORTS_FEET_AHEAD = 0.10
"""(D): the feet land this far [m] ahead of the hands (ours), and the hands then move to
above the feet: each cycle moves the robot forward by this much. The hands are never ahead
of the feet when the feet take off, so that the CoM is above the hands already (the
flight's CoM reference, `planners.reference.support_centre`, is the hands' centre): with
the hands 0.05-0.10 m ahead, the ankles' pitch limit keeps the CoM 24-52 mm short of them
(kinematic check), and in MuJoCo releasing the feet then kicked the body off the supports."""
SUPPORTS_CYCLES = 3
SUPPORTS_STAND_S = 1.0
SUPPORTS_REACH_S = 2.0
SUPPORTS_SETTLE_S = 0.5
"""(D): the palms reach the supports this long before their contact starts (as the grasps'
`STAIRS_SETTLE_S`)."""
SUPPORTS_DOUBLE_S = 1.0
SUPPORTS_SWING_S = 1.0
"""(D): both feet swing together over this time [s], the hands alone carrying the body."""
SUPPORTS_LAND_S = 0.8
SUPPORTS_HAND_MOVE_S = 1.5
SUPPORTS_FOOT_LIFT = 0.03
SUPPORTS_HAND_LIFT = 0.05


def _support_palm(scale: float, side: str, x: float) -> Contact:
    """A palm flat on top of the support on `side` at x [m]: the contact frame level (z up,
    into the palm), on the support's centre line."""
    sign = 1.0 if side == "left" else -1.0
    return Contact(f"{side}_hand", (x, sign * SUPPORT_Y * scale, PAPER_SUPPORT_HEIGHT_M * scale))


def hand_supports_motion(model: RobotModel, duration: float | None = None) -> Scenario:
    """Fig. 4 (D): "with both hands on the support surfaces at the height of 500 mm, moving
    forward by swinging both feet simultaneously" (`robots.multi_contact_scenes.
    hand_supports`). The robot crouches (`SUPPORTS_COM_HEIGHT`) while both palms reach the
    supports beside its feet; then, `SUPPORTS_CYCLES` times, both feet swing together to
    `SUPPORTS_FEET_AHEAD` ahead of the hands (a phase on the two palms alone), and the left
    palm and then the right move to above the feet. CoM reference by Sec. V-C's rules (the
    feet's centre, constant height above their mean; on the hands alone, their centre at the
    last feet's height); Table II's contact-phase K_d (the paper names no other value for this
    motion)."""
    robot = model.robot
    s, time_scale, poses, feet, sequence = _begin(model)
    sequence.hold(SUPPORTS_STAND_S * time_scale)
    x_hands = 0.0
    sequence.move(
        (_support_palm(s, "left", x_hands), _support_palm(s, "right", x_hands)),
        SUPPORTS_REACH_S * time_scale,
        poses,
        lift=SUPPORTS_HAND_LIFT * s,
        settle=SUPPORTS_SETTLE_S * time_scale,
    )
    sequence.hold(SUPPORTS_DOUBLE_S * time_scale)
    for _ in range(SUPPORTS_CYCLES):
        x_feet = x_hands + SUPPORTS_FEET_AHEAD * s
        targets = tuple(
            Contact(foot, (x_feet, feet[foot].position_world[1], 0.0))
            for foot in ("left_foot", "right_foot")
        )
        sequence.move(targets, SUPPORTS_SWING_S * time_scale, lift=SUPPORTS_FOOT_LIFT * s)
        feet.update({target.limb: target for target in targets})
        sequence.hold(SUPPORTS_LAND_S * time_scale)
        x_hands = x_feet
        for side in ("left", "right"):
            sequence.move(
                (_support_palm(s, side, x_hands),),
                SUPPORTS_HAND_MOVE_S * time_scale,
                lift=SUPPORTS_HAND_LIFT * s,
            )
            sequence.hold(SUPPORTS_LAND_S * time_scale)
    sequence.hold(SUPPORTS_DOUBLE_S * time_scale)
    return _scenario(
        "hand_supports",
        hand_supports(robot),
        sequence,
        model,
        duration,
        com_height_offset=SUPPORTS_COM_HEIGHT * s,
        swing_height=0.0,
    )
