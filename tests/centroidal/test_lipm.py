"""The LIPM closed form and Ficht & Behnke's parameter adaptations (paper 003, eqs. 1, 2, 9)."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from centroidal.lipm import (
    PAPER_LEAKY_ALPHA,
    critically_damped,
    gait_frequency,
    half_life_s,
    leaky_alpha,
    lipm_state,
    modified_foot_placement,
    step_primitive,
    stride_factors,
    timing_gain,
)


@pytest.mark.parametrize(
    ("x0", "v0", "zmp"), [(0.03, -0.2, 0.1), (-0.05, 0.4, 0.0), (0.0, 0.0, 0.02)]
)
def test_closed_form_equals_a_numerical_integration_of_eq_1(x0, v0, zmp):
    omega, duration = math.sqrt(9.81 / 0.8), 0.6
    numeric = solve_ivp(
        lambda t, s: [s[1], omega**2 * (s[0] - zmp)],
        (0, duration),
        [x0, v0],
        rtol=1e-12,
        atol=1e-14,
    )
    x, v = lipm_state(x0, v0, zmp, omega, duration)
    assert x == pytest.approx(numeric.y[0, -1], abs=1e-9)
    assert v == pytest.approx(numeric.y[1, -1], abs=1e-9)


@pytest.mark.parametrize(("x0", "v0", "target"), [(0.02, 0.0, 0.0), (-0.01, 0.3, 0.005)])
def test_the_critically_damped_approach_equals_a_numerical_integration(x0, v0, target):
    """x'' = omega^2 (target - x) - 2 omega x', integrated numerically: position, velocity and
    acceleration at 0.1-1.5 s; it starts at (x0, x0') and is at the target after 8 s."""
    omega = math.sqrt(9.81 / 0.8)
    times = np.array([0.1, 0.4, 1.5])
    numeric = solve_ivp(
        lambda t, s: [s[1], omega**2 * (target - s[0]) - 2 * omega * s[1]],
        (0, times[-1]),
        [x0, v0],
        t_eval=times,
        rtol=1e-12,
        atol=1e-14,
    )
    for k, t in enumerate(times):
        x, v, a = critically_damped(x0, v0, target, omega, t)
        assert x == pytest.approx(numeric.y[0, k], abs=1e-9)
        assert v == pytest.approx(numeric.y[1, k], abs=1e-9)
        assert a == pytest.approx(omega**2 * (target - x) - 2 * omega * v, abs=1e-9)
    assert critically_damped(x0, v0, target, omega, 0.0)[:2] == pytest.approx((x0, v0))
    assert critically_damped(x0, v0, target, omega, 8.0)[0] == pytest.approx(target, abs=1e-9)


def test_from_rest_the_approach_s_lip_zmp_starts_mirrored_and_moves_to_the_target():
    """Starting at rest at x0 = target + d, the LIP's ZMP x - x'' / omega^2 of the approach
    starts at target + 2 d (as far beyond the start as the start is from the target: the CoP
    that pushes the CoM toward it) and moves monotonically onto the target."""
    omega = math.sqrt(9.81 / 0.8)
    approach = [critically_damped(-0.02, 0.0, 0.0, omega, t) for t in np.linspace(0, 3, 3001)]
    zmp = np.array([x - a / omega**2 for x, _, a in approach])
    assert zmp[0] == pytest.approx(-0.04, abs=1e-12)
    assert np.all(np.diff(zmp) > 0)
    assert zmp[-1] == pytest.approx(0.0, abs=1e-5)


def test_the_leaky_integrator_keeps_the_papers_half_life_in_seconds():
    paper = half_life_s(PAPER_LEAKY_ALPHA, 100.0)
    assert paper == pytest.approx(math.log(0.5) / math.log(0.97) / 100.0)
    # "roughly half the step time": 0.228 s against half of 1 / 2.6 Hz, 0.19 s, within 25 %
    assert paper == pytest.approx(0.5 / 2.6, rel=0.25)
    assert leaky_alpha(100.0) == pytest.approx(PAPER_LEAKY_ALPHA, rel=1e-12)
    assert half_life_s(leaky_alpha(500.0), 500.0) == pytest.approx(paper, rel=1e-12)
    # iterate the integrator of eq. 9 with no input: half of x_i is left after the half-life
    x_i, alpha = 1.0, leaky_alpha(500.0)
    for _ in range(round(paper * 500)):
        x_i *= 1 - alpha
    assert x_i == pytest.approx(0.5, abs=0.002)


def test_froude_similarity_of_the_gait_frequency_and_the_timing_gain():
    assert gait_frequency(0.9) == pytest.approx(2.6)
    assert gait_frequency(3.6) == pytest.approx(1.3)  # four times as tall: half the frequency
    assert timing_gain(2.6, 0.9) == pytest.approx(10 * 2.6)  # the paper's K_t = 10 f_g
    # a 10 cm error on the paper's robot is a 20 cm one on a robot twice as tall
    assert timing_gain(gait_frequency(1.8), 1.8) * 0.2 == pytest.approx(gait_frequency(1.8))


def test_modified_foot_placement_minimises_kajitas_cost():
    omega, period = 3.4, 0.5
    x_i, v_i, x_d, v_d = 0.02, 0.3, 0.18, 0.25

    def cost(p):
        x, v = lipm_state(x_i, v_i, p, omega, period)
        return 10.0 * (x_d - x) ** 2 + (v_d - v) ** 2

    best = minimize_scalar(cost, bounds=(-1, 1), method="bounded", options={"xatol": 1e-10})
    assert modified_foot_placement(x_i, v_i, x_d, v_d, omega, period) == pytest.approx(
        best.x, abs=1e-7
    )


def test_the_walk_primitive_is_a_lipm_solution():
    """Kajita's primitive: from (-x_bar, v_x) about the support the LIPM reaches (x_bar, v_x)
    after one step, and laterally from (y_bar, -v_y) it returns to (y_bar, v_y)."""
    omega, period = 3.4, 0.5
    x_bar, v_x, y_bar, v_y = step_primitive(0.2, 0.18, omega, period)
    x, v = lipm_state(-x_bar, v_x, 0.0, omega, period)
    assert (x, v) == pytest.approx((x_bar, v_x), abs=1e-12)
    y, w = lipm_state(y_bar, -v_y, 0.0, omega, period)
    assert (y, w) == pytest.approx((y_bar, v_y), abs=1e-12)
    assert np.sign(v_y) == np.sign(y_bar)


@pytest.mark.parametrize(
    ("strides", "speed", "acceleration"),
    [(17, 0.139, 0.1), (20, 0.5, 0.1), (20, 0.6, 0.3), (3, 0.8, 0.05), (5, 0.01, 1.0)],
)
def test_the_start_s_strides_cover_the_commanded_ones_within_the_acceleration(
    strides, speed, acceleration
):
    """A walk starting from rest covers exactly `strides` commanded strides; each step's
    stride (as a speed: fraction x v) rises by at most a / f_g per step (the speed limited
    to the acceleration) and never exceeds the command; the partial strides all come first
    (the walk ends at full speed), no more of them than the steps the ramp needs."""
    f_g = 1.98
    factors = stride_factors(strides, speed, acceleration, f_g)
    assert sum(factors) == pytest.approx(strides, abs=1e-9)
    speeds = np.array([0.0, *factors]) * speed
    assert np.all(np.diff(speeds) >= 0.0)
    assert np.all(np.diff(speeds) <= acceleration / f_g + 1e-12)
    assert max(factors) <= 1.0
    assert min(factors) > 0.0
    ramp = math.ceil(f_g * speed / acceleration - 1e-12)  # steps until a k / f_g >= v
    assert sum(factor < 1.0 for factor in factors) <= ramp
    if len(factors) > ramp:
        assert factors[-1] == 1.0


def test_without_a_speed_or_a_limit_every_stride_is_full():
    assert stride_factors(4, 0.0, 0.1, 1.98) == (1.0,) * 4
    assert stride_factors(4, 0.3, 0.0, 1.98) == (1.0,) * 4
    with pytest.raises(ValueError, match="strides"):
        stride_factors(-1, 0.3, 0.1, 1.98)
    with pytest.raises(ValueError, match="finite"):
        stride_factors(4, math.inf, 0.1, 1.98)
