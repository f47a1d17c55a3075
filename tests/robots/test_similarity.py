"""Froude similarity (`robots.similarity`): the time factor is the one a pendulum obeys."""

from __future__ import annotations

import math

import pytest
from scipy.integrate import solve_ivp

from centroidal.gravity import GRAVITY
from robots.similarity import froude_time_scale


def _quarter_period_s(length_m: float, amplitude_rad: float = 0.5) -> float:
    """Time [s] for a simple pendulum of `length_m` released at rest from `amplitude_rad` to
    reach the vertical, integrated numerically (theta'' = -g / L sin theta, large swing)."""

    def vertical(_t, y):
        return y[0]

    vertical.terminal, vertical.direction = True, -1
    solution = solve_ivp(
        lambda _t, y: [y[1], -GRAVITY / length_m * math.sin(y[0])],
        (0.0, 10.0),
        [amplitude_rad, 0.0],
        events=vertical,
        rtol=1e-11,
        atol=1e-12,
    )
    return float(solution.t_events[0][0])


@pytest.mark.parametrize("scale", [0.5, 0.58, 1.0, 2.0])
def test_a_pendulum_scaled_in_length_swings_in_the_froude_time_scale(scale: float) -> None:
    """The same swing (same amplitude) of a pendulum s times longer takes froude_time_scale(s)
    times as long: the relation every scaled time of centrobench rests on."""
    ratio = _quarter_period_s(0.8 * scale) / _quarter_period_s(0.8)
    assert ratio == pytest.approx(froude_time_scale(scale), rel=1e-7)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf])
def test_a_scale_that_is_not_a_positive_number_is_refused(bad: float) -> None:
    with pytest.raises(ValueError, match="length scale must be a positive number"):
        froude_time_scale(bad)
