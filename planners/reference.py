"""Reference trajectories from a scenario's contact sequence (Murooka et al. 2022, Sec. V-B,
V-C): piecewise constant and synchronised with the contact switches.

- Horizontal CoM: the centre of the supporting feet (the supporting foot in single support,
  the middle of both in double support); the centre of all contacts when no foot is in contact;
  during a phase without any contact (a flight), the last supported phase's centre; plus the
  phase's `com_offset_world` (Sec. V-C: the handrail stairs' 50 mm inward offset in single
  support, the ladder's CoM behind the ladder).
- Vertical CoM: the mean height of the supporting feet plus a constant offset (the initial CoM
  height above the soles); in a phase on the hands alone, that of the last phase with a foot
  ("the mean of the foot contact positions", Sec. V-C).
- Base orientation: zero (level, yaw 0); a turning walk's yaw follows the support's heading
  (`yaw_reference`, an adaptation). Reference resultant force and moment: zero.
"""

from __future__ import annotations

import numpy as np

from centroidal.rotations import circular_mean, yaw_of
from robots.scene import Scenario


def support_centre(scenario: Scenario, time: float) -> tuple[np.ndarray, float]:
    """Horizontal support centre (2,) [m] and mean support height [m] at `time`. Beyond Murooka
    Sec. V-B/V-C's feet (ours): in a flight the last supported phase's centre is held, and with
    only the hands in contact ((D)) it is their centre, at the last foot phase's height."""
    phase = scenario.phase_at(time)
    if not phase.contacts:  # flight: hold the last supported phase's centre
        earlier = [p for p in scenario.phases if p.end <= phase.start and p.contacts]
        if not earlier:
            raise ValueError(f"no contact at or before t = {time} s: no support reference")
        return support_centre(scenario, earlier[-1].start)
    contacts = phase.contacts
    feet = [c.position_world for c in contacts if c.limb.endswith("foot")]
    if not feet:  # hands only: their centre; the height of the last phase with a foot
        points = np.asarray([c.position_world for c in contacts], dtype=float)
        earlier = [
            p
            for p in scenario.phases
            if p.end <= phase.start and any(c.limb.endswith("foot") for c in p.contacts)
        ]
        height = support_centre(scenario, earlier[-1].start)[1] if earlier else points[:, 2].mean()
        return points[:, :2].mean(axis=0) + phase.com_offset_world, float(height)
    points = np.asarray(feet, dtype=float)
    centre = points[:, :2].mean(axis=0)
    if phase.com_offset_world != (0.0, 0.0):
        centre = centre + phase.com_offset_world
    return centre, float(points[:, 2].mean())


def height_offset(scenario: Scenario, com_height_world: float) -> float:
    """The CoM reference's constant offset [m] above the mean foot height (Sec. V-C): the
    scenario's `com_height_offset`, else the initial CoM's height above the first support."""
    if scenario.com_height_offset is not None:
        return scenario.com_height_offset
    _, support_height = support_centre(scenario, 0.0)
    return com_height_world - support_height


def com_reference(
    scenario: Scenario, dtau: float, n_samples: int, height_offset: float
) -> np.ndarray:
    """CoM reference (n_samples, 3) [m] at times 0, dtau, 2 dtau, ... (the last phase holds
    beyond the scenario's end).

    Adaptation (Murooka et al. Table IV, "calculate reference", 22 us a period on HRP-5P): the
    planners call this once, at reset, for the whole scenario, so their "reference" stage is
    a slice of this array (about 1 us); the reference is the same as computed period by
    period, since it depends only on the scenario's fixed contact sequence."""
    reference = np.empty((n_samples, 3))
    by_phase: dict[int, tuple[np.ndarray, float]] = {}  # support_centre depends on the phase only
    for i in range(n_samples):
        phase = scenario.phase_at(i * dtau)
        if id(phase) not in by_phase:
            by_phase[id(phase)] = support_centre(scenario, i * dtau)
        centre, height = by_phase[id(phase)]
        reference[i, :2] = centre
        reference[i, 2] = height + height_offset
    return reference


def support_yaw(scenario: Scenario, time: float) -> float:
    """Heading [rad] of the support at `time`: the circular mean of the supporting feet's yaws
    (of all contacts when no foot is in contact; a flight holds the last supported phase's),
    the rule of `support_centre` applied to the heading."""
    phase = scenario.phase_at(time)
    if not phase.contacts:
        earlier = [p for p in scenario.phases if p.end <= phase.start and p.contacts]
        if not earlier:
            raise ValueError(f"no contact at or before t = {time} s: no support reference")
        return support_yaw(scenario, earlier[-1].start)
    contacts = [c for c in phase.contacts if c.limb.endswith("foot")] or list(phase.contacts)
    return circular_mean(np.array([yaw_of(c.orientation_world) for c in contacts]))


def yaw_reference(scenario: Scenario, dtau: float, n_samples: int) -> np.ndarray | None:
    """Base yaw reference (n_samples,) [rad] at times 0, dtau, ...: piecewise constant, the
    support's heading (`support_yaw`), unwrapped; None when it is zero throughout (a walk that
    does not turn: the paper's zero base-orientation reference, Sec. V-B, unchanged).

    Adaptation (not in the paper, whose walks do not turn): a turning walk's base follows the
    support's heading by the same rule as the horizontal CoM reference."""
    yaws = np.empty(n_samples)
    by_phase: dict[int, float] = {}
    for i in range(n_samples):
        phase = scenario.phase_at(i * dtau)
        if id(phase) not in by_phase:
            by_phase[id(phase)] = support_yaw(scenario, i * dtau)
        yaws[i] = by_phase[id(phase)]
    if not yaws.any():
        return None
    return np.unwrap(yaws)


def feet_heading(limbs, orientations_wxyz: np.ndarray) -> float:
    """The circular mean [rad] of the feet's target yaws (`limbs` with their target
    orientations (n, 4)): a smooth base heading for planners that plan no base rotation
    (their swing targets turn smoothly)."""
    yaws = np.array(
        [
            yaw_of(q)
            for limb, q in zip(limbs, orientations_wxyz, strict=True)
            if limb.name.endswith("foot")
        ]
    )
    return circular_mean(yaws) if len(yaws) else 0.0
