"""Limb contact surfaces and limb targets, shared by the centroidal planners and the
stabilizers that distribute wrenches."""

from __future__ import annotations

import numpy as np

from centroidal.contacts import ContactSet, ContactSurface, contact_set
from centroidal.rotations import to_matrix
from robots.scene import ContactPhase, Scenario
from robots.spec import RobotDescription

CONTACT_MARGIN = 0.01
"""[m] inner margin of the contact polygons (Murooka: "contact polygon vertices with inner
margins", Fig. 3, without a number), scaled with the robot."""


class PhaseContacts:
    """The contact set (G of eq. 8) of a contact phase and its mean contact height [m] (0 for
    a phase without contacts), built once per phase object and kept while it is in use."""

    def __init__(self, surfaces: dict[str, ContactSurface]) -> None:
        self.surfaces = surfaces
        self._built: dict[int, tuple[ContactPhase, ContactSet, float]] = {}

    def __call__(self, phase: ContactPhase) -> tuple[ContactSet, float]:
        built = self._built.get(id(phase))
        if built is None or built[0] is not phase:
            contacts = contact_set(
                [c.limb for c in phase.contacts],
                [self.surfaces[c.limb] for c in phase.contacts],
                [np.asarray(c.position_world, dtype=float) for c in phase.contacts],
                [to_matrix(c.orientation_world) for c in phase.contacts],
            )
            heights = [c.position_world[2] for c in phase.contacts]
            height = float(np.mean(heights)) if heights else 0.0
            built = self._built[id(phase)] = (phase, contacts, height)
        return built[1], built[2]


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
