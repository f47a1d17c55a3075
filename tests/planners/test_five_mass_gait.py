"""Ficht & Behnke's reference generation and stepping controller (paper 003, eqs. 2-5, 16-17)
on the planner alone, with a state that follows the reference exactly unless a test moves it."""

from dataclasses import replace

import numpy as np
import pytest

from bench.scenarios import make_scenario, walk
from centroidal.lipm import gait_frequency, timing_gain
from planners.five_mass_gait import (
    GAIT_ACCELERATION_MPS2,
    FiveMassGaitPlanner,
    SteppingOptions,
    commanded_strides,
    foothold_adjustment_limit,
    timed_gait_frequency,
)
from robots.gait import GaitCommand
from robots.humanoid import humanoid
from robots.model import RobotModel

DT = 0.002


@pytest.fixture(scope="module")
def model():
    return RobotModel(humanoid())


def _start(model, scenario, options=None):
    planner = FiveMassGaitPlanner(DT, options)
    state = model.standing_state()
    state = replace(
        state, com_position_world=model.com_position_world(state), com_velocity_world=np.zeros(3)
    )
    planner.reset(model, scenario, state)
    return planner, state


def _follow(planner, state, t):
    plan = planner.plan(t, state)
    return plan, replace(
        state,
        com_position_world=plan.com_planned_world,
        com_velocity_world=plan.com_velocity_planned_world,
    )


def test_eq_3_steps_wide_then_trailing_toward_the_lateral_command(model):
    """Moving left, the left foot (support right) steps s_w + 2 v_y / f_g and the right one
    trails back to s_w; moving right, the mirror image."""
    for lateral in (0.05, -0.05):
        scenario = walk(model, gait=GaitCommand(step_length=0.0, lateral_step=lateral))
        planner, _ = _start(model, scenario)
        width, v_y = planner.step_width, planner.velocity_command[1]
        right = planner.feet["right_foot"]
        left = planner.feet["left_foot"]
        wide = planner._nominal_after(right, "right_foot", closing=False)
        trailing = planner._nominal_after(left, "left_foot", closing=False)
        if lateral > 0:
            assert wide.position[1] - right.position[1] == pytest.approx(
                width + 2 * v_y / planner.f_g
            )
            assert trailing.position[1] - left.position[1] == pytest.approx(-width)
        else:
            assert wide.position[1] - right.position[1] == pytest.approx(width)
            assert trailing.position[1] - left.position[1] == pytest.approx(
                -width + 2 * v_y / planner.f_g
            )


def test_the_reference_walks_the_command_with_its_zmp_on_the_support_foot(model):
    scenario = make_scenario("walk", model)
    planner, state = _start(model, scenario)
    com, zmps = [], []
    for k in range(round(scenario.duration / DT)):
        plan, state = _follow(planner, state, k * DT)
        com.append(plan.com_planned_world[:2])
        if plan.contact_limbs in (("left_foot",), ("right_foot",)):
            index = model.robot.limb_names.index(plan.contact_limbs[0])
            zmps.append(plan.zmp_planned_world[:2] - plan.limb_target_position_world[index, :2])
    com = np.array(com)
    assert np.abs(zmps).max() < 1e-12  # eq. 1 about the support foot, in single support
    assert np.abs(np.diff(com, axis=0)).max() < 0.5 * DT  # continuous, below 0.5 m/s
    assert planner.steps_done == planner.n_steps
    walked = com[-1, 0] - com[0, 0]
    goal = scenario.goal_offset_world[0]
    assert walked == pytest.approx(goal, rel=0.15)  # same speed, same time: about as far


def _in_single_support(model, options=None):
    scenario = make_scenario("walk", model)
    planner, state = _start(model, scenario, options)
    t = 0.0
    while planner.steps_done < 4 or planner.mu < 0.3:
        _, state = _follow(planner, state, t)
        t += DT
    return planner, state, t


def test_eq_16_lateral_overshoot_toward_the_swing_leg_hurries_the_step(model):
    for toward_swing, faster in ((0.02, True), (-0.02, False)):
        planner, state, t = _in_single_support(model, SteppingOptions(step_size=False))
        swing_side = 1.0 if planner.support == "right_foot" else -1.0
        moved = state.com_position_world + np.array([0.0, swing_side * toward_swing, 0.0])
        planner.plan(t, replace(state, com_position_world=moved))
        assert (planner.f_tilde > planner.f_g) == faster
        assert planner.f_tilde != pytest.approx(planner.f_g)


def test_eq_17_a_sagittal_lead_lengthens_the_step(model):
    planner, state, t = _in_single_support(model)
    nominal = planner.next_nominal.position.copy()
    moved = state.com_position_world + np.array([0.01, 0.0, 0.0])
    plan = planner.plan(t, replace(state, com_position_world=moved))
    lead = planner.next.position - nominal
    assert lead[0] > 0.0
    assert lead[1] == pytest.approx(0.0, abs=1e-12)
    assert plan.footsteps[0].position_world[0] == pytest.approx(planner.next.position[0])
    # ... and not without step size feedback
    planner, state, t = _in_single_support(model, SteppingOptions(step_size=False))
    nominal = planner.next_nominal.position.copy()
    planner.plan(
        t, replace(state, com_position_world=state.com_position_world + np.array([0.01, 0, 0]))
    )
    np.testing.assert_array_equal(planner.next.position, nominal)


def _landings(model, lead_m: float, during_step: int) -> list[np.ndarray]:
    """The support footholds of `walk` (the state following the reference, but `lead_m`
    ahead of it during step `during_step`), one per support exchange."""
    planner, state = _start(model, make_scenario("walk", model))
    landed, last, t = [], None, 0.0
    while planner.mode != "stop":
        plan = planner.plan(t, state)
        ahead = lead_m if planner.mode == "walk" and planner.steps_done == during_step else 0.0
        state = replace(
            state,
            com_position_world=plan.com_planned_world + np.array([ahead, 0.0, 0.0]),
            com_velocity_world=plan.com_velocity_planned_world,
        )
        if planner.mode == "walk" and planner.steps_done != last:
            last = planner.steps_done
            landed.append(planner.feet[planner.support].position[:2].copy())
        t += DT
    landed.append(planner.feet[planner.support].position[:2].copy())
    return landed


def test_eq_17_sets_the_steps_distance_from_where_the_support_foot_is(model):
    """Eq. 17 gives the next foothold's distance from the support foot: a lead of 1 cm during
    step 6 lengthens that step, and every later step is as long as without it, from where the
    adjusted foot landed (the reference moves with the support, in whose frame the LIPM is);
    the walk ends further by the adjustment. (Until 2026-11-29 the next step was planned from
    the unadjusted path and the reference ran about the adjusted foot: the step after a 1 cm
    adjustment was 0.6 cm long instead of 7, and the walk zig-zagged back to the old path.)"""
    nominal = np.array(_landings(model, 0.0, 6))
    pushed = np.array(_landings(model, 0.01, 6))
    assert len(nominal) == len(pushed)
    adjustment = pushed[7, 0] - nominal[7, 0]  # step 7 was planned during step 6
    # eq. 17 with K_s = 1: the lead held to the exchange, where t_r -> 0 and eq. 1's end-of-step
    # error is the lead itself, lengthens the step by K_s x 1 cm
    assert adjustment == pytest.approx(1.0 * 0.01, abs=1e-4)  # K_s = 1, the paper's (Sec. 4)
    np.testing.assert_allclose(pushed[:7], nominal[:7], atol=1e-12)
    lengths, pushed_lengths = np.diff(nominal[:, 0]), np.diff(pushed[:, 0])
    np.testing.assert_allclose(pushed_lengths[7:], lengths[7:], atol=1e-3)
    assert pushed[-1, 0] - nominal[-1, 0] == pytest.approx(adjustment, abs=1e-3)


def test_standing_the_reference_starts_at_the_robots_com_and_settles_on_the_feet(model):
    """JVRC-1's half-sitting has its CoM 19.8 mm behind the feet's midpoint: the reference CoM
    starts at the robot's own (no step at t = 0, which threw the robot forward), is continuous,
    settles on the midpoint (critically damped at omega), and its ZMP, p = x - x''/omega^2
    (behind the CoM by the whole offset at first, to set it moving), stays on the soles."""
    from robots.jvrc1 import jvrc1

    jvrc = RobotModel(jvrc1())
    planner, state = _start(jvrc, make_scenario("stand", jvrc))
    feet = [jvrc.robot.limb_names.index(f"{side}_foot") for side in ("left", "right")]
    start = state.com_position_world[:2]
    com, zmp = [], []
    for k in range(round(3.0 / DT)):
        plan, state = _follow(planner, state, k * DT)
        com.append(plan.com_planned_world[:2])
        zmp.append(plan.zmp_planned_world[:2])
    middle = plan.limb_target_position_world[feet, :2].mean(axis=0)
    com, zmp = np.array(com), np.array(zmp)
    assert np.linalg.norm(middle - start) > 0.015  # the case this test is about
    assert np.linalg.norm(com[0] - start) < 0.02 * np.linalg.norm(middle - start)  # one period
    assert np.abs(np.diff(com, axis=0)).max() < 0.1 * DT  # below 0.1 m/s
    assert np.linalg.norm(com[-1] - middle) < 1e-4
    # the soles side by side and level, yawed by under 0.02 rad: the axis-aligned box of their
    # rectangles overstates their hull by under 1.5 mm, against a ZMP 60 mm inside it
    soles = plan.limb_target_position_world[feet, :2]
    half = np.array(jvrc.robot.limbs[feet[0]].half_extents)
    assert np.all(zmp >= soles.min(axis=0) - half)
    assert np.all(zmp <= soles.max(axis=0) + half)
    assert zmp[0] @ (middle - start) < start @ (middle - start)  # first behind the CoM


@pytest.mark.parametrize("speed", [0.2, 0.5])
def test_from_rest_the_reference_speeds_up_and_never_falls_back(model, speed):
    """A walk commanded at `speed` from rest: the reference CoM (eq. 1 about footholds refined
    after Kajita) moves forward until the closing step, at most about the command's speed, and
    goes as far as the fixed schedule's walk. Without the start's acceleration limit the footholds,
    refined toward a path that starts at full stride, run ahead of a CoM at rest and the
    reference falls back from its support (in MuJoCo 0.19 m behind by 2.6 s at 0.2 m/s)."""
    scenario = make_scenario("walk", model, speed=speed, steps=12)
    planner, state = _start(model, scenario)
    assert planner.stride_factors[0] < 1.0
    velocity, com = [], []
    for k in range(round((scenario.duration + speed / GAIT_ACCELERATION_MPS2) / DT)):
        plan, state = _follow(planner, state, k * DT)
        if planner.steps_done < planner.n_steps - 1:  # the closing step stops it in one step
            velocity.append(plan.com_velocity_planned_world[0])
        com.append(plan.com_planned_world[0])
    assert planner.steps_done == planner.n_steps
    assert min(velocity) > -0.01
    assert max(velocity) < 1.5 * speed
    assert com[-1] - com[0] == pytest.approx(scenario.goal_offset_world[0], rel=0.05)


def test_with_the_start_s_ramp_a_sideways_walk_still_goes_its_strides_sideways(model):
    """`walk_side` (eq. 3's wide leading step and trailing step) started at a limited
    acceleration: its path's sideways offset is its strides' (the sum of the stride factors
    x v_y / f_g, no more), within 0.5 mm of the fixed schedule's 0.45 m."""
    scenario = make_scenario("walk_side", model)
    planner, state = _start(model, scenario)
    assert planner.stride_factors[0] < 1.0
    start = (planner.path["left_foot"].position + planner.path["right_foot"].position) / 2
    for k in range(round(2 * scenario.duration / DT)):  # bounded: a planner that never stops
        if planner.mode == "stop":
            break
        _, state = _follow(planner, state, k * DT)
    assert planner.mode == "stop"
    end = (planner.path["left_foot"].position + planner.path["right_foot"].position) / 2
    strides = sum(planner.stride_factors)
    expected = strides * planner.velocity_command[1] / planner.f_g
    assert end[1] - start[1] == pytest.approx(expected, abs=1e-9)
    assert end[1] - start[1] == pytest.approx(scenario.goal_offset_world[1], abs=5e-4)


def test_the_heading_is_continuous_when_the_feet_are_yawed_apart():
    """JVRC-1's half-sitting soles are yawed 0.014 and -0.007 rad. Eq. 5's yaw
    (1 - mu) s_psi[k] + mu s_psi[k+1] from the support foot's yaw would turn the planned base
    and inertia axes by 0.010 rad in the period the walk starts (both hip yaws then stepped at
    once); it starts from the standing heading, the feet's mean yaw, and over the whole of
    `walk`, through the stop, no period's planned heading moves by 1 mrad."""
    from centroidal.rotations import yaw_of
    from robots.jvrc1 import jvrc1

    jvrc = RobotModel(jvrc1())
    scenario = make_scenario("walk", jvrc)
    planner, state = _start(jvrc, scenario)
    yaws = [planner.feet[f"{side}_foot"].yaw for side in ("left", "right")]
    assert abs(yaws[0] - yaws[1]) > 0.015  # the case this test is about
    heading = []
    stopped_at = None
    for k in range(round(2 * scenario.duration / DT)):  # bounded: a planner that never stops
        plan, state = _follow(planner, state, k * DT)
        heading.append(yaw_of(plan.base_orientation_planned_world))
        if planner.mode == "stop" and stopped_at is None:
            stopped_at = k
        if stopped_at is not None and k > stopped_at + round(0.5 / DT):
            break
    assert stopped_at is not None
    assert np.abs(np.diff(heading)).max() < 1e-3


@pytest.mark.parametrize("height", [0.9, 1.56])
def test_eq_16_a_10_cm_lateral_error_fully_slows_or_doubles_the_gait_at_the_papers_gain(height):
    """Sec. 4: K_t = 10 f_g makes "a 10 cm EOS error in the lateral plane fully slow down, or
    double the gait progression": on the paper's 0.9 m robot at its 2.6 Hz, and on our 1.56 m
    humanoid at its Froude-similar f_g and K_t (`timing_gain`), where the same relative error
    is 0.1 m x 1.56 / 0.9; larger errors change it no further (the bounds, ours)."""
    f_g = gait_frequency(height)
    k_t = timing_gain(f_g, height)
    full = 0.1 * height / 0.9  # [m] the error that doubles or stops the progression
    assert timed_gait_frequency(f_g, k_t, 0.0) == f_g
    assert timed_gait_frequency(f_g, k_t, full) == pytest.approx(2 * f_g, rel=1e-12)
    assert timed_gait_frequency(f_g, k_t, -full) == pytest.approx(0.0, abs=1e-12)
    assert timed_gait_frequency(f_g, k_t, 5 * full) == 2 * f_g
    assert timed_gait_frequency(f_g, k_t, -5 * full) == 0.0
    assert timed_gait_frequency(f_g, k_t, full / 2) == pytest.approx(1.5 * f_g, rel=1e-12)


def test_a_walk_commands_one_stride_per_step_period_of_the_fixed_schedule():
    """A walk of n steps of period T advances n - 1 times in (n - 1) T; at f_g = 1 / T that is
    n - 1 strides, at 2 / T twice as many; never fewer than one."""
    assert commanded_strides(10, 0.9, 1 / 0.9) == 9
    assert commanded_strides(10, 0.9, 2 / 0.9) == 18
    assert commanded_strides(1, 0.9, 1.98) == 1
    assert commanded_strides(2, 0.1, 1.0) == 1


def test_a_refined_foothold_moves_at_most_half_the_step_width_so_the_feet_never_cross():
    """Two footholds a step width w apart, each moved toward the other by the limit, meet at
    most: they do not cross, and the limit is the largest for which that holds."""
    for width in (0.18, 0.2):
        limit = foothold_adjustment_limit(width)
        gap = (width / 2 - limit) - (-width / 2 + limit)
        assert gap == pytest.approx(0.0, abs=1e-15)


def test_the_closing_step_lands_beside_the_support_foot_whatever_eq_17_asks(model):
    """`closing_foothold`: the walk's last step closes the feet side by side at the step width
    and eq. 17 does not move it, so a 1 cm lead during that step (which lengthens any other
    step by about 1 cm: the test above) leaves every landing where it was."""
    planner, _ = _start(model, make_scenario("walk", model))
    last = planner.n_steps - 1
    nominal = np.array(_landings(model, 0.0, last))
    pushed = np.array(_landings(model, 0.01, last))
    np.testing.assert_allclose(pushed, nominal, atol=1e-12)
    closing, support = nominal[-1], nominal[-2]
    assert closing[0] == pytest.approx(support[0], abs=1e-9)  # side by side
    assert abs(closing[1] - support[1]) == pytest.approx(planner.step_width, abs=1e-9)
