"""Ficht & Behnke's stabilizer: the CoM controller's eqs. 8-9 for a period; the inertia
controller's ZMP (eq. 13: eq. 7's estimate is the CMP of the flywheel model; `flywheel_zmp`
recovers the ZMP from it and the flywheel's acceleration) and its loop."""

import math

import numpy as np
import pytest

from stabilizers.direct_centroidal import GRAVITY, flywheel_zmp


def test_the_flywheel_zmp_of_a_simulated_pendulum_plus_flywheel_is_its_zmp():
    """Integrate x'' = omega^2 (x - p) - s theta'' (eq. 13 with the ZMP p held) for a flywheel
    swung as theta = A sin(w t): eq. 7's x - x''/omega^2 is off p by s theta'' / omega^2 (the
    CMP), and `flywheel_zmp` of it is p again; the augmented CoM obeys eq. 13's LIPM form."""
    height, scale, zmp = 0.8, 0.12, 0.01  # [m], I/(m h) [m/rad], [m]
    omega2 = GRAVITY / height
    dt, amplitude, rate = 1e-4, 0.05, 2 * math.pi * 2.0
    x, v = 0.0, 0.0
    worst_cmp, worst_zmp, worst_lipm = 0.0, 0.0, 0.0
    for k in range(5000):
        t = k * dt
        theta_dd = -amplitude * rate**2 * math.sin(rate * t)
        acceleration = omega2 * (x - zmp) - scale * theta_dd
        cmp = x - acceleration / omega2  # eq. 7
        recovered = flywheel_zmp(np.array([cmp]), np.array([scale]), np.array([theta_dd]), height)
        worst_cmp = max(worst_cmp, abs(cmp - zmp))
        worst_zmp = max(worst_zmp, abs(recovered[0] - zmp))
        theta = amplitude * math.sin(rate * t)
        x_aug, p_aug = x + scale * theta, recovered[0] + scale * theta
        aug_acceleration = acceleration + scale * theta_dd
        worst_lipm = max(worst_lipm, abs(aug_acceleration - omega2 * (x_aug - p_aug)))
        v += acceleration * dt
        x += v * dt
    assert worst_cmp > 0.01  # the CMP is centimetres off while the flywheel swings
    assert worst_zmp < 1e-12
    assert worst_lipm < 1e-9


def test_without_a_flywheel_acceleration_the_estimate_is_kept():
    cmp = np.array([0.02, -0.01])
    assert np.array_equal(flywheel_zmp(cmp, np.array([0.12, 0.1]), None, 0.8), cmp)


def test_without_a_measured_zmp_the_zmp_term_of_eq_8_is_dropped():
    """A force-sensor ZMP is NaN when the feet carry no vertical force: p = p_ref then, so that
    K_zmp (p_ref - p) is zero; a measured ZMP is used as it is."""
    from stabilizers.direct_centroidal import measured_or_reference_zmp

    reference = np.array([0.03, -0.09])
    dropped = measured_or_reference_zmp(np.array([math.nan, 0.01]), reference)
    assert np.array_equal(reference - dropped, np.zeros(2))
    measured = np.array([0.05, -0.08])
    assert np.array_equal(measured_or_reference_zmp(measured, reference), measured)


def _flywheel_loop(
    tilt_lag: bool,
    periods: int = 2000,
    dt: float = 0.002,
    hidden: bool = False,
    tilt_limit: float | None = None,
) -> np.ndarray:
    """The inertia controller (eqs. 13-15) closed over eq. 13's flywheel alone: the IK's CoM
    held still (the real robot's CoM moves with a tilt: docs/ficht-behnke.md) and a constant
    1 cm offset of eq. 7's estimate from the reference ZMP as the forcing input; each
    period's set tilt realised by the next period (stiff servos) and its theta'' the second
    difference of the realised tilts (a perfect estimator), so that `flywheel_zmp` sees the
    ZMP move by -I theta'' / (m g); with `hidden`, theta'' is not given (the paper's "hidden"
    term) and that path is absent; `tilt_limit` bounds the set tilt. Our humanoid's numbers:
    58.4 kg, 0.82 m, I / (m h) = 0.12 m/rad. Returns the realised tilts theta_x [rad], cut
    short once one exceeds 1 rad."""
    from centroidal.tilt import angles_of_axis
    from stabilizers.direct_centroidal import (
        DirectCentroidalStabilizer,
        FeedbackOptions,
        choi_gains,
    )

    mass, height, scale = 58.4, 0.82, 0.12
    inertia = scale * mass * height
    omega = math.sqrt(GRAVITY / height)
    k_com, k_zmp = choi_gains(omega)
    options = FeedbackOptions(tilt_lag=tilt_lag, tilt_limit=tilt_limit)
    stabilizer = DirectCentroidalStabilizer(dt, options)
    stabilizer.mass, stabilizer.moments = mass, np.array([inertia, inertia, 0.3 * inertia])
    stabilizer.x_aug_i, stabilizer.theta_lagged = np.zeros(2), np.zeros(2)
    zeros, cmp = np.zeros(2), np.array([0.01, 0.0])
    realised = [zeros, zeros, zeros]
    for _ in range(periods):
        acceleration = (realised[-1] - 2 * realised[-2] + realised[-3]) / dt**2
        axes = stabilizer._inertia(
            zeros,
            zeros,
            zeros,
            cmp,
            realised[-1],
            None if hidden else acceleration,
            np.eye(3),
            height,
            k_com,
            k_zmp,
            omega,
        )
        realised.append(angles_of_axis(axes[:, 2]))
        if not abs(realised[-1][0]) < 1.0:
            break
    return np.array([theta[0] for theta in realised[3:]])


def _settles(tilts: np.ndarray) -> bool:
    """All 2000 periods run, the tilt within 0.1 rad and still over the last second."""
    return len(tilts) == 2000 and np.abs(tilts).max() < 0.1 and abs(tilts[-1] - tilts[-500]) < 1e-4


def test_with_the_tilt_realised_the_next_period_the_flywheel_loop_diverges_within_periods():
    """The ZMP term's path through the flywheel's reaction (`flywheel_zmp`'s theta'' term)
    with a one-period delay: its dominant root is about -(1 + K_zmp / (omega^2 dt)) = -73, so
    the tilt alternates in sign and passes 1 rad within ten periods."""
    tilts = _flywheel_loop(tilt_lag=False)
    assert len(tilts) < 10
    assert abs(tilts[-1]) >= 1.0
    assert tilts[-1] * tilts[-2] < 0  # the period-to-period alternation of a negative root


def test_with_the_papers_hidden_theta_dd_the_same_loop_settles_without_a_lag():
    """The divergence above runs through the theta'' term only: without it (eq. 7's CMP used
    as p, the paper's "hidden" theta'') the same loop settles."""
    assert _settles(_flywheel_loop(tilt_lag=False, hidden=True))


def test_through_the_lag_the_flywheel_loop_settles():
    """With the set tilt through the lag of `tilt_lag_time_constant` (twice the bound K_zmp /
    omega^2) the same loop settles, at a lean of a few hundredths of a radian."""
    assert _settles(_flywheel_loop(tilt_lag=True))


@pytest.mark.parametrize(("factor", "settles"), [(0.8, False), (1.2, True)])
def test_the_lags_bound_is_where_the_loop_turns_stable(monkeypatch, factor, settles):
    """The bound tau > K_zmp / omega^2 (the path's gain below 1 at every frequency): a lag of
    0.8 times it still diverges, 1.2 times it settles."""
    import stabilizers.direct_centroidal as module

    monkeypatch.setattr(module, "tilt_lag_time_constant", lambda w, k: factor * k / w**2)
    assert _settles(_flywheel_loop(tilt_lag=True)) == settles


def test_through_the_lag_and_a_bound_the_set_tilt_settles_at_the_bound():
    """The lagged loop above settles at a lean beyond 0.01 rad; with `tilt_limit` 0.01 rad the
    realised tilt never passes the bound and settles on it (through the lag, exponentially)."""
    free = _flywheel_loop(tilt_lag=True)
    assert abs(free[-1]) > 0.012
    bounded = _flywheel_loop(tilt_lag=True, tilt_limit=0.01)
    assert _settles(bounded)
    assert np.abs(bounded).max() <= 0.01 + 1e-12
    assert abs(bounded[-1]) == pytest.approx(0.01, rel=1e-3)  # the lag approaches it


def test_a_bound_without_the_lag_does_not_settle_the_flywheel_loop():
    """The bound caps the tilt but does not remove the fast loop: realised the next period,
    the bounded tilt keeps alternating between near its two bounds, period by period."""
    tilts = _flywheel_loop(tilt_lag=False, tilt_limit=0.01)
    assert len(tilts) == 2000
    last = tilts[-100:]
    assert np.all(last[1:] * last[:-1] < 0)
    assert np.abs(last).min() > 0.005


@pytest.mark.parametrize("limit", [0.0, -0.01, math.nan, 1.6])
def test_a_tilt_limit_outside_0_to_pi_over_2_is_refused(limit):
    from stabilizers.direct_centroidal import FeedbackOptions

    with pytest.raises(ValueError, match="tilt_limit must be in"):
        FeedbackOptions(tilt_limit=limit)


def test_a_tilt_limit_without_the_inertia_controller_is_refused():
    from stabilizers.direct_centroidal import FeedbackOptions

    with pytest.raises(ValueError, match="inertia"):
        FeedbackOptions(inertia=False, tilt_limit=0.02)


def test_a_tilt_lag_without_the_inertia_controller_is_refused():
    from stabilizers.direct_centroidal import FeedbackOptions

    with pytest.raises(ValueError, match="inertia"):
        FeedbackOptions(inertia=False, tilt_lag=True)


@pytest.mark.parametrize(
    ("k_com", "k_zmp"),
    [(1.0, 0.5), (0.9, 0.5), (2.0, 1.0), (2.0, 1.2), (2.0, 0.0), (2.0, -0.5), (math.nan, 0.5)],
)
def test_gains_outside_chois_condition_are_refused(k_com, k_zmp):
    """K_com > omega > K_zmp > 0 (Choi et al.'s input-to-state stability condition, which the
    paper follows): a ratio on its boundary or outside it, or NaN, is a one-line ValueError."""
    from stabilizers.direct_centroidal import FeedbackOptions

    with pytest.raises(ValueError, match="Choi's condition"):
        FeedbackOptions(k_com_per_omega=k_com, k_zmp_per_omega=k_zmp)


def test_the_gain_ratios_set_both_controllers_gains():
    """The CoM controller's gains are the ratios times omega = sqrt(g / h): the default ones
    are 2 omega and omega / 2, and other ratios inside the condition give other gains."""
    from stabilizers.direct_centroidal import choi_gains

    omega = math.sqrt(GRAVITY / 0.8)
    assert choi_gains(omega) == pytest.approx((2.0 * omega, 0.5 * omega), rel=1e-12)
    assert choi_gains(omega, 1.5, 0.8) == pytest.approx((1.5 * omega, 0.8 * omega), rel=1e-12)


def _standing(options):
    """A standing plan of `five_mass_gait` on the humanoid, the stabilizer reset on it, and a
    state on the plan's reference (CoM, its velocity and the ZMP)."""
    from dataclasses import replace

    from bench.scenarios import make_scenario
    from planners.five_mass_gait import FiveMassGaitPlanner
    from robots.humanoid import humanoid
    from robots.model import RobotModel
    from stabilizers.direct_centroidal import DirectCentroidalStabilizer

    model = RobotModel(humanoid())
    scenario = make_scenario("stand", model)
    state = model.standing_state()
    state = replace(
        state, com_position_world=model.com_position_world(state), com_velocity_world=np.zeros(3)
    )
    planner = FiveMassGaitPlanner(0.002)
    planner.reset(model, scenario, state)
    plan = planner.plan(0.0, state)
    stabilizer = DirectCentroidalStabilizer(0.002, options)
    stabilizer.reset(model, scenario, state)
    on_plan = replace(
        state,
        com_position_world=plan.com_planned_world.copy(),
        com_velocity_world=plan.com_velocity_planned_world.copy(),
        zmp_world=plan.zmp_planned_world.copy(),
    )
    return plan, stabilizer, on_plan


def test_eqs_8_9_move_the_set_com_toward_the_zmp_and_the_reference_by_chois_gains():
    """Eqs. 8-9 for one period from x_i = 0: the ZMP 1 cm ahead of p_ref moves the set CoM
    forward by K_zmp x 1 cm x dt (Choi's sign, the module; the paper prints +K_zmp, which
    would move it back), the CoM 1 cm behind x_ref moves it forward by K_com x 1 cm x dt,
    with (K_com, K_zmp) = (2 omega, omega / 2); on the reference it stays."""
    from dataclasses import replace

    from stabilizers.direct_centroidal import FeedbackOptions

    options = FeedbackOptions(extended=False, inertia=False)
    plan, _, on_plan = _standing(options)
    height = plan.com_planned_world[2] - plan.zmp_planned_world[2]
    omega = math.sqrt(GRAVITY / height)
    dt, step = 0.002, np.array([0.01, 0.0, 0.0])
    zmp_ahead = replace(on_plan, zmp_world=on_plan.zmp_world + step)
    com_behind = replace(on_plan, com_position_world=on_plan.com_position_world - step)
    cases = [
        (on_plan, 0.0),
        (zmp_ahead, 0.5 * omega * 0.01 * dt),
        (com_behind, 2 * omega * 0.01 * dt),
    ]
    for state, forward in cases:
        _, stabilizer, _ = _standing(options)
        target = stabilizer.stabilize(0.0, plan, state).com_position_world
        moved = target[:2] - plan.com_planned_world[:2]
        assert moved == pytest.approx([forward, 0.0], abs=1e-12)


def test_eq_9_leaks_the_integral_at_the_papers_half_life():
    """Eq. 9 with no error after a 1 cm ZMP offset for one period: x_i decays by (1 - alpha)
    per period, to half in 0.228 s (the paper's alpha = 0.03 at 100 Hz, `leaky_alpha`)."""
    from dataclasses import replace

    from stabilizers.direct_centroidal import FeedbackOptions

    plan, stabilizer, on_plan = _standing(FeedbackOptions(extended=False, inertia=False))
    pushed = replace(on_plan, zmp_world=on_plan.zmp_world + np.array([0.01, 0.0, 0.0]))
    first = stabilizer.stabilize(0.0, plan, pushed).com_position_world[0]
    first -= plan.com_planned_world[0]
    half_life = math.log(0.5) / (100 * math.log(0.97))  # [s] the paper's alpha at 100 Hz
    periods = round(half_life / 0.002)
    for _ in range(periods):
        last = stabilizer.stabilize(0.0, plan, on_plan).com_position_world[0]
    assert (last - plan.com_planned_world[0]) / first == pytest.approx(0.5, abs=0.01)


def test_eq_10s_end_of_step_term_is_k_eos_times_the_lipm_offset_at_the_step_end():
    """x'_eos = 0.5 K_com (x_eos^ref - x_eos) (eq. 10, K_eos of Sec. 4): eq. 1 carries a CoM
    offset d of the estimate at equal velocity to d cosh(omega t_r) at the step's end, so a
    CoM 1 cm behind the reference asks 0.5 K_com x 1 cm x cosh(omega t_r) forward; on the
    reference, nothing."""
    from stabilizers.direct_centroidal import end_of_step_term

    omega, k_com, t_r = 3.5, 7.0, 0.2
    x_ref, v_ref, p_ref = np.array([0.0, 0.05]), np.array([0.1, -0.02]), np.array([0.02, 0.09])
    term = end_of_step_term(x_ref, v_ref, x_ref - [0.01, 0.0], v_ref, p_ref, omega, t_r, k_com)
    expected = 0.5 * k_com * 0.01 * math.cosh(omega * t_r)
    assert term == pytest.approx([expected, 0.0], abs=1e-12)
    on = end_of_step_term(x_ref, v_ref, x_ref, v_ref, p_ref, omega, t_r, k_com)
    assert on == pytest.approx([0.0, 0.0], abs=1e-15)


def test_the_reference_axes_follow_the_pendulum_to_the_set_com():
    """`axes_for_set_com`: reference axes whose z lies along the reference pendulum are turned
    onto the set CoM's pendulum and stay a rotation; with the set CoM on the reference they are
    unchanged."""
    from centroidal.tilt import axis_from_angles, tilt_rotation
    from stabilizers.direct_centroidal import axes_for_set_com

    reference = axis_from_angles(0.05, 0.01)
    axes = tilt_rotation(reference) @ tilt_rotation(np.array([0.0, 0.0, 1.0]))
    moved = axis_from_angles(0.08, -0.02)
    turned = axes_for_set_com(axes, reference, moved)
    np.testing.assert_allclose(turned[:, 2], moved, atol=1e-12)
    np.testing.assert_allclose(turned.T @ turned, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(axes_for_set_com(axes, reference, reference), axes, atol=1e-12)
