"""Limb contact surfaces and limb targets, shared by the centroidal planners and the
stabilizers that distribute wrenches."""

from __future__ import annotations

import bisect
from dataclasses import replace

import numpy as np

from centroidal.contacts import ContactSet, ContactSurface, contact_set
from centroidal.rotations import to_matrix, yaw_of
from robots.scene import Contact, ContactPhase, Scenario
from robots.spec import RobotDescription
from robots.types import Footstep

CONTACT_MARGIN = 0.01
"""[m] inner margin of the contact polygons (Murooka: "contact polygon vertices with inner
margins", Fig. 3, without a number), scaled with the robot."""


class PhaseContacts:
    """The contact set (G of eq. 8) of a contact phase and its mean contact height [m] (0 for
    a phase without contacts), built once per phase object and kept while it is in use."""

    def __init__(self, surfaces: dict[str, ContactSurface]) -> None:
        self.surfaces = surfaces
        self.grasping = grasp_surfaces(surfaces)
        self._built: dict[int, tuple[ContactPhase, ContactSet, float]] = {}
        self._grasps: dict[int, tuple[ContactPhase, tuple[str, ...]]] = {}
        self._phase_surfaces: dict[int, tuple[ContactPhase, tuple[ContactSurface, ...]]] = {}

    def surface_of(self, contact: Contact) -> ContactSurface:
        """The contact's surface: the limb's (as a grasp if it grasps), or its own polygon
        (`Contact.support_in_frame`) with the limb's friction, in its own frame when it has one
        (`Contact.surface_pose_world`)."""
        surface = (self.grasping if contact.grasp else self.surfaces)[contact.limb]
        if contact.support_in_frame is not None:
            surface = replace(
                surface, vertices_in_frame=np.array(contact.support_in_frame, dtype=float)
            )
        if contact.surface_pose_world is not None:  # the surface's frame in the contact frame
            origin, orientation = contact.surface_pose_world
            frame = to_matrix(contact.orientation_world)
            surface = replace(
                surface,
                rotation_in_frame=frame.T @ to_matrix(orientation),
                origin_in_frame=frame.T
                @ (
                    np.asarray(origin, dtype=float)
                    - np.asarray(contact.position_world, dtype=float)
                ),
            )
        return surface

    def phase_surfaces(self, phase: ContactPhase) -> tuple[ContactSurface, ...]:
        """The surfaces of `phase`'s contacts in their order (cached per phase object: the
        same tuple while the phase lasts)."""
        known = self._phase_surfaces.get(id(phase))
        if known is None or known[0] is not phase:
            surfaces = tuple(self.surface_of(c) for c in phase.contacts)
            known = self._phase_surfaces[id(phase)] = (phase, surfaces)
        return known[1]

    def grasps(self, phase: ContactPhase) -> tuple[str, ...]:
        """The limbs of `phase` that grasp (cached per phase object)."""
        known = self._grasps.get(id(phase))
        if known is None or known[0] is not phase:
            limbs = tuple(c.limb for c in phase.contacts if c.grasp)
            known = self._grasps[id(phase)] = (phase, limbs)
        return known[1]

    def __call__(self, phase: ContactPhase) -> tuple[ContactSet, float]:
        built = self._built.get(id(phase))
        if built is None or built[0] is not phase:
            contacts = contact_set(
                [c.limb for c in phase.contacts],
                self.phase_surfaces(phase),
                [np.asarray(c.position_world, dtype=float) for c in phase.contacts],
                [to_matrix(c.orientation_world) for c in phase.contacts],
            )
            heights = [c.position_world[2] for c in phase.contacts]
            height = float(np.mean(heights)) if heights else 0.0
            built = self._built[id(phase)] = (phase, contacts, height)
        return built[1], built[2]


def grasp_surfaces(surfaces: dict[str, ContactSurface]) -> dict[str, ContactSurface]:
    """Each limb's surface as a grasp: the same polygon with the opposing pyramids."""
    return {name: replace(surface, grasp=True) for name, surface in surfaces.items()}


def limb_surfaces(robot: RobotDescription, friction: float) -> dict[str, ContactSurface]:
    """Each limb's rectangular contact surface shrunk by `CONTACT_MARGIN`."""
    return {
        limb.name: ContactSurface.rectangle(
            *limb.half_extents, friction, margin=CONTACT_MARGIN * robot.scale
        )
        for limb in robot.limbs
    }


def limb_targets(scenario: Scenario, limbs, start_pose: dict, t: float):
    """Per limb: target position (n, 3) [m], orientation (n, 4) (w, x, y, z) from the scenario
    (contact pose or swing), and whether it has one; limbs without keep their start pose,
    untracked."""
    positions = np.empty((len(limbs), 3))
    orientations = np.empty((len(limbs), 4))
    tracked = np.zeros(len(limbs), dtype=bool)
    for k, limb in enumerate(limbs):
        pose = scenario.limb_pose(limb.name, t)
        tracked[k] = pose is not None
        positions[k], orientations[k] = pose if pose is not None else start_pose[limb.name]
    return positions, orientations, tracked


def scheduled_footsteps(scenario: Scenario) -> tuple[Footstep, ...]:
    """Every contact the scenario's sequence makes after t = 0, in touchdown order: a limb in
    contact in a phase but not in the one before touches down at the phase's start; it lifted
    off at the end of its last contact (the first phase's limbs are standing, not steps)."""
    steps = []
    last_end: dict[str, float] = {}
    previous: tuple[str, ...] = scenario.phases[0].limbs
    for contact in scenario.phases[0].contacts:
        last_end[contact.limb] = scenario.phases[0].end
    for phase in scenario.phases[1:]:
        for contact in phase.contacts:
            if contact.limb not in previous:
                orientation = np.array(contact.orientation_world, dtype=float)
                steps.append(
                    Footstep(
                        contact.limb,
                        np.array(contact.position_world, dtype=float),
                        yaw_of(orientation),
                        last_end.get(contact.limb, phase.start),
                        phase.start,
                        orientation,
                    )
                )
            last_end[contact.limb] = phase.end
        previous = phase.limbs
    return tuple(sorted(steps, key=lambda s: s.touchdown_time))


class FootstepSchedule:
    """A fixed schedule's upcoming footsteps: `upcoming(t)` is the tuple of those touching down
    after t [s], the same object until the next touchdown passes (cheap to call every period,
    and cheap for the runner to notice a change: by identity)."""

    def __init__(self, footsteps: tuple[Footstep, ...]) -> None:
        self.footsteps = footsteps
        self.touchdowns = [s.touchdown_time for s in footsteps]
        self._index = -1
        self._upcoming: tuple[Footstep, ...] = footsteps

    def upcoming(self, t: float) -> tuple[Footstep, ...]:
        index = bisect.bisect_right(self.touchdowns, t)
        if index != self._index:
            self._index, self._upcoming = index, self.footsteps[index:]
        return self._upcoming
