"""How much of its joints' torque limits an episode used, from the torques the simulator applied
(`Sensors.joint_torque`: the servo law's output after clipping, at the last physics step of
each control period).

Issue 19 asks for "the torque limits that the motions need": the limits are the robot's
(`robots.humanoid`'s table, JVRC-1's by similarity); an episode reports the largest share of a
limit that any joint used, the joint, and the fraction of control periods in which some joint
was held at its limit (the clipping decided its torque). A share of 1 means that the limit,
not the controller, decided what the robot did.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

AT_LIMIT = 1.0 - 1e-9
"""A joint whose applied |torque| is at least this share of its limit is at it (clipped)."""


class TorqueUse:
    """Accumulates the applied joint torques [N m] of an episode against `limits` [N m]."""

    def __init__(self, joint_names: Sequence[str], limits: np.ndarray) -> None:
        self.joint_names = tuple(joint_names)
        limits = np.asarray(limits, dtype=float)
        self.locked = limits <= 0.0  # a zero limit (torque_scale 0): always at it, share 1
        self.inverse_limits = np.where(self.locked, 0.0, 1.0 / np.where(self.locked, 1.0, limits))
        self.peak = np.zeros(len(self.joint_names))  # per joint: max |tau| / limit
        self.periods = 0
        self.saturated = 0  # periods with some joint at its limit

    def observe(self, joint_torque: np.ndarray) -> None:
        share = np.abs(joint_torque) * self.inverse_limits
        share[self.locked] = 1.0
        np.maximum(self.peak, share, out=self.peak)
        self.periods += 1
        if share.max(initial=0.0) >= AT_LIMIT:
            self.saturated += 1

    def summary(self) -> dict[str, float | str | None]:
        """`torque_share_max` (the largest |tau| / limit of any joint), `torque_share_joint`
        (that joint), `torque_saturated_fraction` (periods with some joint at its limit); None
        before the first period."""
        if self.periods == 0 or not len(self.peak):
            return {
                "torque_share_max": None,
                "torque_share_joint": None,
                "torque_saturated_fraction": None,
            }
        k = int(np.argmax(self.peak))
        return {
            "torque_share_max": float(self.peak[k]),
            "torque_share_joint": self.joint_names[k],
            "torque_saturated_fraction": self.saturated / self.periods,
        }
