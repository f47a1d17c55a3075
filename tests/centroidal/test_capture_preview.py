"""Long-term balance building blocks of Sherikov, Dimitrov & Wieber 2014 (paper 004): the
third-order point-mass model (eq. 10), its preview in CoP positions (Sec. III-A), the terminal
capturability constraint (eq. 14), the swing-foot cubic (eqs. 16, 20) and the footstep
rectangle (eq. 12)."""

import math

import numpy as np
import pytest
import scipy.linalg
from scipy.integrate import solve_ivp

from centroidal.capture_preview import (
    SWING_TIME_FLOOR_S,
    capture_point_row,
    capture_velocity_row,
    discretize,
    footstep_bounds,
    preview,
    swing_cubic,
)

G = 9.81
HEIGHT, PERIOD, N = 0.8, 0.1, 16  # the paper's two steps of 0.8 s at 100 ms (Sec. VII)
OMEGA = math.sqrt(G / HEIGHT)


def _continuous_matrix(omega: float) -> np.ndarray:
    """d/dt (c, c', c'') of eq. 10 with z' = 0, written out here from the paper."""
    return np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, omega**2, 0.0]])


def _simulate(a, b, s0, z_dot):
    """States s_1..s_N of s_{k+1} = A s_k + B z'_k, stepped one interval at a time."""
    states, s = [], np.asarray(s0, dtype=float)
    for u in z_dot:
        s = a @ s + b * u
        states.append(s)
    return np.array(states)


def _random_preview_inputs(rng):
    known = rng.uniform([-0.1, -0.5], [0.1, 0.5])  # c_0 [m], c'_0 [m/s]
    acc = rng.uniform(-2.0, 2.0)  # c''_0 [m/s^2]
    cop = rng.uniform(-0.15, 0.15, N)  # z_1..z_N [m]
    return known, acc, cop


def _cop_velocities(known, acc, cop):
    """z'_k = (z_{k+1} - z_k) / T with z_0 = c_0 - c''_0 / omega^2 (eq. 10)."""
    z = np.concatenate([[known[0] - acc / OMEGA**2], cop])
    return np.diff(z) / PERIOD


@pytest.mark.parametrize(("height", "period"), [(0.8, 0.1), (0.6, 0.005), (1.0, 0.3)])
def test_discretisation_equals_a_numerical_integration_of_eq_10(height, period):
    rng = np.random.default_rng(10)
    omega = math.sqrt(G / height)
    a, b = discretize(height, period)
    z_dot = rng.uniform(-0.5, 0.5, 6)
    s0 = np.array([0.02, -0.3, 1.2])
    z0 = s0[0] - s0[2] / omega**2

    # Integrate eq. 10 interval by interval, with the CoP z carried as a fourth state z' = u.
    y = np.concatenate([s0, [z0]])
    discrete = _simulate(a, b, s0, z_dot)
    for k, u in enumerate(z_dot):
        y = solve_ivp(
            lambda _t, x, u=u: [x[1], x[2], omega**2 * (x[1] - u), u],
            (0.0, period),
            y,
            rtol=1e-12,
            atol=1e-14,
        ).y[:, -1]
        np.testing.assert_allclose(discrete[k], y[:3], rtol=0, atol=1e-9)
        # Eq. 10's output: the integrated CoP is c - c''/omega^2 of the integrated state ...
        assert y[3] == pytest.approx(y[0] - y[2] / omega**2, abs=1e-9)
        # ... and of the discrete state, which keeps z linear in time.
        assert discrete[k][0] - discrete[k][2] / omega**2 == pytest.approx(y[3], abs=1e-9)

    # The closed form also equals the matrix exponential of the augmented system.
    aug = np.zeros((4, 4))
    aug[:3, :3] = _continuous_matrix(omega)
    aug[2, 3] = -(omega**2)
    expm = scipy.linalg.expm(aug * period)
    np.testing.assert_allclose(a, expm[:3, :3], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(b, expm[:3, 3], rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_preview_reproduces_a_step_by_step_simulation(seed):
    rng = np.random.default_rng(seed)
    pv = preview(HEIGHT, PERIOD, N)
    assert pv.s_known.shape == (N, 3, 2)
    assert pv.s_acc.shape == (N, 3)
    assert pv.s_cop.shape == (N, 3, N)
    assert pv.d_known.shape == (N, 2)
    assert pv.d_acc.shape == (N,)
    assert pv.d_cop.shape == (N, N)
    a, b = discretize(HEIGHT, PERIOD)
    known, acc, cop = _random_preview_inputs(rng)
    z_dot = _cop_velocities(known, acc, cop)
    expected = _simulate(a, b, [known[0], known[1], acc], z_dot)

    states = pv.s_known @ known + pv.s_acc * acc + pv.s_cop @ cop
    np.testing.assert_allclose(states, expected, rtol=0, atol=1e-9)
    np.testing.assert_allclose(
        pv.d_known @ known + pv.d_acc * acc + pv.d_cop @ cop, z_dot, rtol=0, atol=1e-9
    )
    # Each previewed state carries its CoP sample: c_k - c''_k / omega^2 = z_k.
    np.testing.assert_allclose(states[:, 0] - states[:, 2] / OMEGA**2, cop, rtol=0, atol=1e-9)


@pytest.mark.parametrize("first", [0.002, 0.037, 0.1])
def test_a_shortened_first_interval_equals_the_simulation_with_it(first):
    """The preview aligned with a step schedule (its first interval T_0 shorter): the states
    equal interval-by-interval integration of eq. 10 with T_0 first, then T, and the CoP
    velocities are the samples' differences over their own intervals."""
    rng = np.random.default_rng(3)
    pv = preview(HEIGHT, PERIOD, N, first_s=first)
    assert pv.first_s == first
    known, acc, cop = _random_preview_inputs(rng)
    z = np.concatenate([[known[0] - acc / OMEGA**2], cop])
    z_dot = np.diff(z) / np.array([first] + [PERIOD] * (N - 1))
    state = np.array([known[0], known[1], acc])
    expected = []
    for k, u in enumerate(z_dot):
        a, b = discretize(HEIGHT, first if k == 0 else PERIOD)
        state = a @ state + b * u
        expected.append(state)
    states = pv.s_known @ known + pv.s_acc * acc + pv.s_cop @ cop
    np.testing.assert_allclose(states, expected, rtol=0, atol=1e-9)
    np.testing.assert_allclose(
        pv.d_known @ known + pv.d_acc * acc + pv.d_cop @ cop, z_dot, rtol=0, atol=1e-9
    )
    np.testing.assert_allclose(states[:, 0] - states[:, 2] / OMEGA**2, cop, rtol=0, atol=1e-9)


def test_preview_arrays_are_read_only_and_bad_arguments_raise():
    pv = preview(HEIGHT, PERIOD, 4)
    with pytest.raises(ValueError, match="read-only"):
        pv.s_cop[0, 0, 0] = 1.0
    for args in [(HEIGHT, PERIOD, 0), (0.0, PERIOD, 4), (HEIGHT, -0.1, 4), (HEIGHT, PERIOD, 2.5)]:
        with pytest.raises(ValueError, match="must be a positive"):
            preview(*args)


def _capturable_cop(pv, known, acc, variant):
    """A least-norm Z satisfying eq. 14's row, free or with the last four samples equal."""
    row_known, row_acc, row_cop = capture_velocity_row(pv)
    rhs = np.array([-(row_known @ known + row_acc * acc)])
    if variant == "least_norm":
        basis = np.eye(N)
    else:
        basis = np.zeros((N, N - 3))
        basis[: N - 4, : N - 4] = np.eye(N - 4)
        basis[N - 4 :, -1] = 1.0
    free = np.linalg.lstsq((row_cop @ basis)[None, :], rhs, rcond=None)[0]
    return basis @ free


@pytest.mark.parametrize("variant", ["least_norm", "last_four_equal"])
@pytest.mark.parametrize("seed", [3, 4, 5, 6])
def test_capturability_constraint_brings_the_com_to_rest_over_the_last_cop(variant, seed):
    # The continuation lasts 4 s = 14 time constants 1/omega: long enough for the stable mode
    # to decay by e^-14, and short enough that the round-off left in xi'_N (~1e-14 m/s) grows
    # only by e^14. Over the brief's 10 s the unstable mode amplifies any float64 residual by
    # e^35 = 1.6e15, so no double-precision Z can stay within 1e-6 there.
    rng = np.random.default_rng(seed)
    pv = preview(HEIGHT, PERIOD, N)
    a, b = discretize(HEIGHT, PERIOD)
    known, acc, _ = _random_preview_inputs(rng)
    cop = _capturable_cop(pv, known, acc, variant)
    if variant == "last_four_equal":
        assert np.ptp(cop[-4:]) < 1e-15
    end = _simulate(a, b, [known[0], known[1], acc], _cop_velocities(known, acc, cop))[-1]

    # Sec. III-D: xi'_N = 0 implies xi_N = z_N; the capture-point row says the same.
    assert end[1] + end[2] / OMEGA == pytest.approx(0.0, abs=1e-9)
    assert end[0] + end[1] / OMEGA == pytest.approx(cop[-1], abs=1e-9)
    point_known, point_acc, point_cop = capture_point_row(pv)
    assert point_known @ known + point_acc * acc + point_cop @ cop == pytest.approx(
        cop[-1], abs=1e-9
    )

    rest = scipy.linalg.expm(_continuous_matrix(OMEGA) * 4.0) @ end  # z' = 0 from now on
    assert abs(rest[1]) < 1e-6
    assert abs(rest[0] + rest[1] / OMEGA - cop[-1]) < 1e-6
    assert abs(rest[0] - cop[-1]) < 1e-6


@pytest.mark.parametrize("seed", [3, 4])
def test_violating_the_capturability_constraint_diverges(seed):
    rng = np.random.default_rng(seed)
    pv = preview(HEIGHT, PERIOD, N)
    a, b = discretize(HEIGHT, PERIOD)
    known, acc, _ = _random_preview_inputs(rng)
    cop = _capturable_cop(pv, known, acc, "least_norm")
    cop[-1] += 0.01  # move the last CoP sample by 1 cm
    row_known, row_acc, row_cop = capture_velocity_row(pv)
    assert abs(row_known @ known + row_acc * acc + row_cop @ cop) > 1e-3
    end = _simulate(a, b, [known[0], known[1], acc], _cop_velocities(known, acc, cop))[-1]
    after = scipy.linalg.expm(_continuous_matrix(OMEGA) * 10.0) @ end
    assert abs(after[0]) > 1.0


def _cubic_by_boundary_conditions(tf, s0, ds0, target):
    """Coefficients (a0, a1, a2, a3) from the four boundary conditions, by a linear solve."""
    m = np.array(
        [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [1.0, tf, tf**2, tf**3],
            [0.0, 1.0, 2.0 * tf, 3.0 * tf**2],
        ]
    )
    return np.linalg.solve(m, [s0, ds0, target, 0.0])


@pytest.mark.parametrize("tf", [0.05, 0.3, 0.8])
def test_swing_cubic_rows_reach_the_footstep_at_rest_and_match_finite_differences(tf):
    rng = np.random.default_rng(int(tf * 100))
    rows = swing_cubic(tf)
    assert rows.remaining_s == tf
    for _ in range(5):
        s0, ds0, target = rng.uniform(-0.3, 0.3), rng.uniform(-1.0, 1.0), rng.uniform(-0.3, 0.3)
        acc = rows.acc_p * target + rows.acc_s0 * s0 + rows.acc_ds0 * ds0
        jerk = rows.jerk_p * target + rows.jerk_s0 * s0 + rows.jerk_ds0 * ds0

        # The polynomial rebuilt from the rows reaches P with zero velocity at t_f.
        def from_rows(t, s0=s0, ds0=ds0, acc=acc, jerk=jerk):
            return s0 + ds0 * t + acc / 2.0 * t**2 + jerk / 6.0 * t**3

        step = 1e-5 * tf
        assert from_rows(tf) == pytest.approx(target, abs=1e-12)
        velocity_end = (from_rows(tf + step) - from_rows(tf - step)) / (2.0 * step)
        assert velocity_end == pytest.approx(0.0, abs=1e-6)

        # Acceleration now and jerk by finite differences of the independently solved cubic.
        coefficients = _cubic_by_boundary_conditions(tf, s0, ds0, target)

        def trajectory(t, c=coefficients):
            return np.polynomial.polynomial.polyval(t, c)

        h = 1e-3 * tf
        fd_acc = (trajectory(h) - 2.0 * trajectory(0.0) + trajectory(-h)) / h**2
        fd_jerk = (
            trajectory(2 * h) - 2 * trajectory(h) + 2 * trajectory(-h) - trajectory(-2 * h)
        ) / (2 * h**3)
        scale_acc, scale_jerk = 1.0 + abs(acc), 1.0 + abs(jerk)
        assert acc == pytest.approx(fd_acc, abs=1e-5 * scale_acc)
        assert jerk == pytest.approx(fd_jerk, abs=1e-3 * scale_jerk)
        assert acc == pytest.approx(2.0 * coefficients[2], rel=1e-9, abs=1e-9)
        assert jerk == pytest.approx(6.0 * coefficients[3], rel=1e-9, abs=1e-9)


def test_swing_foot_already_at_the_footstep_and_at_rest_does_not_accelerate():
    rows = swing_cubic(0.4)
    target = 0.23
    assert rows.acc_p * target + rows.acc_s0 * target + rows.acc_ds0 * 0.0 == pytest.approx(
        0.0, abs=1e-12
    )
    assert rows.jerk_p * target + rows.jerk_s0 * target + rows.jerk_ds0 * 0.0 == pytest.approx(
        0.0, abs=1e-9
    )
    # A foot behind its footstep accelerates towards it.
    assert rows.acc_p * target + rows.acc_s0 * (target - 0.1) > 0.0


@pytest.mark.parametrize("remaining", [0.0, 1e-6, SWING_TIME_FLOOR_S / 2, -0.01])
def test_swing_cubic_clamps_a_tiny_remaining_time_to_the_floor(remaining):
    clamped = swing_cubic(remaining)
    at_floor = swing_cubic(SWING_TIME_FLOOR_S)
    assert clamped == at_floor
    assert clamped.remaining_s == SWING_TIME_FLOOR_S
    assert math.isfinite(clamped.jerk_p)
    assert swing_cubic(2 * SWING_TIME_FLOOR_S).acc_p < at_floor.acc_p  # above it: no clamp
    with pytest.raises(ValueError, match="finite"):
        swing_cubic(math.nan)


def test_footstep_bounds_of_left_and_right_mirror_each_other():
    lower_l, upper_l = footstep_bounds("left", 0.3, 0.18, 0.4)
    lower_r, upper_r = footstep_bounds("right", 0.3, 0.18, 0.4)
    np.testing.assert_allclose(lower_l, [-0.3, 0.18])
    np.testing.assert_allclose(upper_l, [0.3, 0.4])
    np.testing.assert_allclose(lower_r, [lower_l[0], -upper_l[1]])
    np.testing.assert_allclose(upper_r, [upper_l[0], -lower_l[1]])
    assert np.all(lower_l <= upper_l)
    assert np.all(lower_r <= upper_r)


@pytest.mark.parametrize(
    "args",
    [
        ("left", 0.3, 0.4, 0.18),  # min > max
        ("right", -0.1, 0.18, 0.4),  # negative length
        ("middle", 0.3, 0.18, 0.4),  # unknown side
        ("left", math.nan, 0.18, 0.4),
    ],
)
def test_footstep_bounds_reject_bad_values_with_a_one_line_message(args):
    with pytest.raises(ValueError, match=r"\A[^\n]+\Z") as excinfo:
        footstep_bounds(*args)
    message = str(excinfo.value)
    assert message
    assert "\n" not in message
