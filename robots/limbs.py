"""Limb contact surfaces and limb targets, shared by the centroidal planners and the
stabilizers that distribute wrenches."""

from __future__ import annotations

import numpy as np

from centroidal.contacts import ContactSurface
from robots.scene import Scenario
from robots.spec import RobotDescription

CONTACT_MARGIN = 0.01
"""[m] inner margin of the contact polygons (Murooka: "contact polygon vertices with inner
margins", Fig. 3, without a number), scaled with the robot."""


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
