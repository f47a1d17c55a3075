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
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from robots.model import RobotModel
from robots.multi_contact_scenes import MOTION_PERIOD_S, WALL_INNER_FACE_Y, moving_contacts
from robots.scene import Contact, ContactPhase, LimbWaypoint, Scenario

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


class ContactSequence:
    """Builds a motion's contact phases from its start: `hold` keeps the current contacts for a
    while, `move` takes limbs off their contacts (or from free waypoints) for a swing and places
    them on new ones. `phases` and `waypoints` are the result."""

    def __init__(self, contacts: tuple[Contact, ...]) -> None:
        self.contacts: dict[str, Contact] = {c.limb: c for c in contacts}
        self.time = 0.0
        self.phases: list[ContactPhase] = []
        self.waypoints: list[LimbWaypoint] = []

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
    ) -> None:
        """Each target's limb leaves its contact (or, if it has none, the pose `start_poses`
        gives it: position [m], orientation (w, x, y, z), a waypoint at the move's start) and
        is placed on the target after `duration` [s] of swing."""
        for target in targets:
            if target.limb in self.contacts:
                del self.contacts[target.limb]
            else:
                if start_poses is None or target.limb not in start_poses:
                    raise ValueError(f"{target.limb!r} is in no contact: give its start pose")
                position, orientation = start_poses[target.limb]
                self.waypoints.append(
                    LimbWaypoint(
                        target.limb,
                        self.time,
                        tuple(float(v) for v in position),
                        tuple(float(v) for v in orientation),
                    )
                )
        self._phase(duration, com_offset)
        for target in targets:
            self.contacts[target.limb] = target


def _limb_poses(model: RobotModel) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Every limb's contact frame in the standing posture: position [m], (w, x, y, z)."""
    from centroidal.rotations import from_matrix

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


def _wall_palms(scale: float, offset_y: float = 0.0) -> tuple[Contact, Contact]:
    """The left and right palms on side walls whose faces are at y = +-WALL_INNER_FACE_Y."""
    y = WALL_INNER_FACE_Y * scale + offset_y
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
    scale, time_scale = robot.scale, math.sqrt(robot.scale)
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
    name: str, scene, sequence: ContactSequence, model: RobotModel, duration: float | None
) -> Scenario:
    """The motion as a `Scenario`; a `duration` [s] cuts it short or holds the last phase."""
    phases = list(sequence.phases)
    total = sequence.time if duration is None else duration
    if duration is not None:
        phases = [p for p in phases if p.start < duration]
        last = phases[-1]
        phases[-1] = ContactPhase(last.start, duration, last.contacts, last.com_offset_world)
    return Scenario(
        name,
        total,
        scene,
        tuple(phases),
        model.robot.nominal_posture,
        limb_waypoints=tuple(sequence.waypoints),
    )
