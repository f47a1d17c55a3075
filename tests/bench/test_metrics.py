"""Walking quality (Ficht & Behnke eq. 18) on synthetic traces with known errors."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from bench.metrics import walking_quality


def trace(speed: float, offset_y: float, zmp_offset_x: float, duration: float = 2.0):
    time = np.arange(0.0, duration, 0.002)
    frame = pd.DataFrame({"time": time})
    x = speed * time
    for name, value in (("com_planned", 0.0), ("com_actual", offset_y)):
        frame[f"{name}_x"], frame[f"{name}_y"] = x, value
    frame["zmp_planned_x"], frame["zmp_planned_y"] = x, 0.0
    frame["zmp_actual_x"], frame["zmp_actual_y"] = x + zmp_offset_x, 0.0
    for name in ("com_velocity_planned", "com_velocity_actual"):
        frame[f"{name}_x"], frame[f"{name}_y"] = speed, 0.0
    return frame


def test_constant_offsets_give_offset_squared_over_speed():
    # e = 1 / (v t_w) * integral(offset^2) = offset^2 / v
    quality = walking_quality(trace(speed=0.25, offset_y=0.01, zmp_offset_x=0.02))
    assert quality["walk_speed_mps"] == pytest.approx(0.25, rel=1e-3)
    assert quality["e_com"] == pytest.approx(0.01**2 / 0.25, rel=1e-3)
    assert quality["e_zmp"] == pytest.approx(0.02**2 / 0.25, rel=1e-3)
    assert quality["e_velocity"] == pytest.approx(0.0, abs=1e-12)


def test_standing_has_no_walking_quality():
    quality = walking_quality(trace(speed=0.0, offset_y=0.01, zmp_offset_x=0.0))
    assert quality == {"walk_speed_mps": None, "e_com": None, "e_zmp": None, "e_velocity": None}


def test_a_plan_that_is_the_state_has_no_com_terms():
    """A planner whose plan's CoM is its state (`Planner.plans_com_trajectory` False) has
    no e_c or e_v (they would compare the state with itself); its e_z stays."""
    quality = walking_quality(
        trace(speed=0.25, offset_y=0.01, zmp_offset_x=0.02), plans_com_trajectory=False
    )
    assert quality["e_com"] is None
    assert quality["e_velocity"] is None
    assert quality["e_zmp"] == pytest.approx(0.02**2 / 0.25, rel=1e-3)
    assert quality["walk_speed_mps"] == pytest.approx(0.25, rel=1e-3)
