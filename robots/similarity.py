"""Froude similarity: how a motion's times change with the size of the robot that makes it.

Two geometrically similar robots, lengths in the ratio s, make dynamically similar motions
(the same Froude number v^2 / (g L), g being the same for both) when every time is scaled by
sqrt(s) and every speed by sqrt(s). A linear inverted pendulum shows it: its time constant
1 / omega = sqrt(z_c / g) grows as sqrt(s) with its height z_c. centrobench scales each
method's printed times (step periods, preview periods, scene periods) by this factor when it
runs on a robot of another size (`RobotDescription.scale`), and its lengths by s."""

from __future__ import annotations

import math


def froude_time_scale(length_scale: float) -> float:
    """The factor sqrt(s) [-] by which a time printed for a robot of size 1 is multiplied on a
    geometrically similar robot of size `length_scale` = s (equal Froude number v^2 / (g L)).
    Raises ValueError unless s is a positive finite number."""
    if not (math.isfinite(length_scale) and length_scale > 0):
        raise ValueError(f"length scale must be a positive number, got {length_scale}")
    return math.sqrt(length_scale)
