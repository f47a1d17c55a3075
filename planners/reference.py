"""Reference trajectories from a scenario's contact sequence (Murooka et al. 2022, Sec. V-B,
V-C): piecewise constant and synchronised with the contact switches.

- Horizontal CoM: the centre of the supporting feet (the supporting foot in single support,
  the middle of both in double support); the centre of all contacts when no foot is in contact;
  during a phase without any contact (a flight), the last supported phase's centre.
- Vertical CoM: the mean height of the supporting feet plus a constant offset (the initial CoM
  height above the soles).
- Base orientation: zero (level, yaw 0). Reference resultant force and moment: zero.
"""

from __future__ import annotations

import numpy as np

from robots.scene import Scenario


def support_centre(scenario: Scenario, time: float) -> tuple[np.ndarray, float]:
    """Horizontal support centre (2,) [m] and mean support height [m] at `time`."""
    phase = scenario.phase_at(time)
    if not phase.contacts:  # flight: hold the last supported phase's centre
        earlier = [p for p in scenario.phases if p.end <= phase.start and p.contacts]
        if not earlier:
            raise ValueError(f"no contact at or before t = {time} s: no support reference")
        return support_centre(scenario, earlier[-1].start)
    contacts = phase.contacts
    feet = [c.position_world for c in contacts if c.limb.endswith("foot")] or [
        c.position_world for c in contacts
    ]
    points = np.asarray(feet, dtype=float)
    return points[:, :2].mean(axis=0), float(points[:, 2].mean())


def com_reference(
    scenario: Scenario, dtau: float, n_samples: int, height_offset: float
) -> np.ndarray:
    """CoM reference (n_samples, 3) [m] at times 0, dtau, 2 dtau, ... (the last phase holds
    beyond the scenario's end)."""
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
