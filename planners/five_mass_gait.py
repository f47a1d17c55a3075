"""Planner `five_mass_gait`: Ficht & Behnke's reference generation (paper 003, Sec. 3.1,
eqs. 1-5) and stepping controller (Sec. 3.5, eqs. 16-17). It chooses its own footsteps and
step timing and publishes them in the plan (DESIGN.md, adaptive controllers).

- Gait phase (eq. 2): mu advances by f~_g dt each period and wraps at 1, which exchanges the
  support leg (no double support, as in the paper). f_g is the paper's 2.6 Hz adapted by
  Froude similarity to our robot's height (`centroidal.lipm.gait_frequency`).
- Footsteps (eq. 3): the next foothold relative to the support foot's frame is
  (v_x / f_g, iota s_w + s_y, v_psi / f_g) with s_y = 2 v_y / f_g on the side the walk goes and
  0 on the trailing step (iota: +1 right support, -1 left, as the paper's). Each is refined by
  Kajita's modified foot placement ([14], `centroidal.lipm.modified_foot_placement`) so that the
  reference CoM is one continuous LIPM trajectory. Three footholds are kept: s[k-1], s[k] (the
  support), s[k+1].
- Reference CoM (eq. 1): the LIPM about the support foot in closed form, advanced by the gait
  phase's own clock (dt f~_g / f_g, `reference_time_step`, ours), so that step timing
  feedback slows or hurries the reference with the steps.
- Swing foot (eq. 4): (1 - mu) s[k-1] + mu s[k+1] in x, y and yaw, height s_h sin(mu pi).
- Inertia reference (eq. 5): z_I along the vector from the feet's midpoint to the CoM, yaw
  along the step progression (1 - mu) s_psi[k] + mu s_psi[k+1].
- Step timing (eq. 16): f~_g = f_g + K_t (y_eos - y_eos^ref), the lateral end-of-step errors
  counted positive toward the swing leg (the sign of the paper's text, `timed_gait_frequency`:
  an overshoot toward the swing leg hurries the exchange, one toward the support leg slows
  it; eq. 16 as printed has it on the left support only), limited to [0, 2 f_g] (the paper:
  a 10 cm error "fully slow[s] down, or double[s] the gait progression").
- Step size (eq. 17): the next foothold's forward distance is recomputed every period as
  v_x / f_g - K_s (x_eos^ref - x_eos), K_s = 1, in the walk's frame; at the exchange the
  swing path and the reference CoM move with the step's adjustment (`carried_step_adjustment`,
  ours).
The end-of-step states come from eq. 1 over the remaining step time t_r = (1 - mu) / f_g with
the ZMP at the support foot (the paper's "confining the ZMP to the support polygon"): the
reference's from the reference state, the expected from the estimated CoM state.

Starting and stopping, which the paper does not describe: before the first step the reference
ZMP moves to the first swing foot for half a step period (a weight shift: the LIPM moves the
reference CoM toward the support foot); the gait command's speed then rises at
`GAIT_ACCELERATION_MPS2` (the first strides are fractions of eq. 3's, `stride_factors`, the
walk takes as many steps as the commanded strides add up to, and a sideways walk's wide leading
step takes its own and the trailing step's shares); after the last step, which closes
the feet side by side (`closing_foothold`, without eq. 17), the reference CoM returns to the
feet's midpoint critically damped with rate omega.
Standing, before the walk, the reference CoM starts at the robot's own CoM and returns to the
midpoint the same way (a robot's nominal CoM need not be above the midpoint: JVRC-1's is
19.8 mm behind it). The number of commanded strides is the time of the fixed schedule's
steps - 1 advances ((steps - 1) x its step period) times f_g, so that a walk goes as far as the
fixed schedule's (until 2026-11-27 it was steps x its step period x f_g, less the closing step:
one stride, 7 cm, further at the default speed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from centroidal.gravity import GRAVITY
from centroidal.lipm import (
    critically_damped,
    gait_frequency,
    lipm_state,
    modified_foot_placement,
    step_primitive,
    stride_factors,
    timing_gain,
)
from centroidal.rotations import from_matrix, heading_quaternion, yaw_of
from centroidal.tilt import tilt_and_yaw, yaw_rotation
from planners.base import PlannerSpec, register
from robots.five_mass import FiveMassModel
from robots.model import RobotModel
from robots.scene import Scenario
from robots.similarity import froude_time_scale
from robots.types import CentroidalPlan, Footstep, RobotState

STEP_SIZE_GAIN = 1.0  # K_s (Sec. 4)
# The walk's start from rest (ours, not in the paper): the gait command's speed rises at this
# acceleration [m/s^2] (`centroidal.lipm.stride_factors`). The authors' lab's gait (the
# paper's [3], AIS-Bonn/humanoid_op_ros) slope-limits its gait command in the same way
# (`gcvAccLimits`, in units of its normalised command). An acceleration is the same for
# robots of every size under Froude similarity (lengths ~ L, times ~ sqrt(L)). Measured on
# `walk` with `bent_no_inertia` (2026-11-27, MuJoCo): without a limit the walk falls in its
# first steps from 0.2 m/s up (its footholds, refined toward a path that starts at full
# stride, run ahead of a CoM at rest); at 0.2 / 0.3 m/s^2 it falls at 0.5 m/s, at 0.1 walks.
GAIT_ACCELERATION_MPS2 = 0.1


def commanded_strides(steps: int, step_period_s: float, f_g_hz: float) -> int:
    """The number of eq. 3 strides a walk of the fixed schedule's `steps` steps commands
    (ours: the paper walks on a velocity command without an end). The fixed schedule advances
    `steps` - 1 times in (`steps` - 1) x `step_period_s` [s]; at the gait frequency f_g [Hz]
    (eq. 2: one stride per 1 / f_g) that time holds (steps - 1) T f_g strides, rounded, at
    least 1; the closing step is added to them. Until 2026-11-27 steps x T x f_g, less the
    closing step: one stride further."""
    return max(1, round((steps - 1) * step_period_s * f_g_hz))


def timed_gait_frequency(f_g_hz: float, k_t_hz_per_m: float, error_to_swing_m: float) -> float:
    """Eq. 16: f~_g = f_g + K_t e [Hz], e [m] the lateral end-of-step error counted positive
    toward the swing leg (ours: eq. 16 is printed with e = y_eos^ref - y_eos for either support,
    which is this on the left support and its opposite on the right; the sign here follows the
    paper's text, "overshooting towards the swing leg will speed-up the step exchange"),
    limited to [0, 2 f_g]: the paper's "a 10 cm error fully slow[s]
    down, or double[s] the gait progression" (K_t = 10 f_g per 0.1 m) read as the bounds of
    the phase rate (ours: the paper states the gain, not a limit)."""
    return min(max(f_g_hz + k_t_hz_per_m * error_to_swing_m, 0.0), 2 * f_g_hz)


def reference_time_step(dt_s: float, f_tilde_hz: float, f_g_hz: float) -> float:
    """The time [s] over which eq. 1's reference CoM advances in a period dt [s]: dt f~_g /
    f_g, the reference on the gait phase's clock (ours: eq. 16's timing changes the phase rate
    of eq. 2, "the rate of step progression", and the paper writes eq. 1 in elapsed time; on
    the phase's clock the reference stays in step with the footholds when the timing feedback
    slows or hurries a step)."""
    return dt_s * f_tilde_hz / f_g_hz


def closing_foothold(iota: float, step_width_m: float) -> tuple[float, float, float]:
    """(x_s [m], y_s [m], psi_s [rad]) of the walk's closing step in the support's frame: beside
    the support foot at the step width, no stride, no turn, and eq. 17's step size feedback off
    for it (ours: the paper walks on a velocity command without an end; a closing step that eq.
    17 moved would end the walk in a stride)."""
    return 0.0, iota * step_width_m, 0.0


def carried_step_adjustment(foothold_xy: np.ndarray, nominal_xy: np.ndarray) -> np.ndarray:
    """The shift [m] (2,) that eq. 17 gave the step just taken (its foothold less eq. 3's
    nominal one), by which the swing path and the reference CoM move at the exchange. Ours: eq.
    17 sets only x_s[k+1]; the reference is eq. 1's LIPM in the support's frame, so it moves
    with the step, and the path goes on from where the step was put (Kajita's refinement is
    not carried: `next_path`). Measured in docs/ficht-behnke.md ("Eq. 17 from where the support
    foot landed")."""
    return foothold_xy - nominal_xy


def foothold_adjustment_limit(step_width_m: float) -> float:
    """How far [m, per horizontal axis] Kajita's modified foot placement ([14]) may move a
    foothold from eq. 3's nominal one: half the step width, so that the feet never cross
    (ours: the paper calls the refinement a "slight position adjustment", Sec. 3.1, and gives
    no bound)."""
    return step_width_m / 2


@dataclass(frozen=True)
class SteppingOptions:
    """Which parts of the stepping controller run (the Table 1 ablation)."""

    step_timing: bool = True  # eq. 16
    step_size: bool = True  # eq. 17


@dataclass
class _Foothold:
    position: np.ndarray  # (3,) [m] contact frame (sole centre)
    yaw: float  # [rad]


class FiveMassGaitPlanner:
    name = "five_mass_gait"
    projects_wrench = False
    tracks_hand_targets = False
    plans_com_trajectory = True

    def __init__(self, dt: float, options: SteppingOptions | None = None) -> None:
        self.dt = dt
        self.options = options or SteppingOptions()

    # ---- set-up -----------------------------------------------------------------------------
    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None:
        description = robot.robot
        limbs = description.limbs
        self.limb_index = {limb.name: k for k, limb in enumerate(limbs)}
        poses = [robot.frame_pose(state, limb.contact_frame) for limb in limbs]
        self.start_position = np.array([p for p, _ in poses])
        self.start_orientation = np.array([from_matrix(r) for _, r in poses])
        self.feet = {
            name: _Foothold(
                self.start_position[self.limb_index[name]].copy(),
                yaw_of(self.start_orientation[self.limb_index[name]]),
            )
            for name in ("left_foot", "right_foot")
        }
        self.mass = robot.total_mass
        com = robot.com_position_world(state)
        self.ground = float(np.mean([f.position[2] for f in self.feet.values()]))
        self.height = float(com[2]) - self.ground  # h of eq. 1
        self.omega = math.sqrt(GRAVITY / self.height)
        robot_height = robot.standing_height()
        self.f_g = gait_frequency(robot_height)
        self.k_t = timing_gain(self.f_g, robot_height)
        self.period = 1.0 / self.f_g
        left, right = self.feet["left_foot"].position, self.feet["right_foot"].position
        self.step_width = float(np.linalg.norm((left - right)[:2]))
        # eq. 5's tilt is the feet-to-CoM vector; our standing pose's principal axis leans by
        # a constant angle from it (the torso's mass sits behind the legs'), kept as the
        # neutral (`_neutral_offset`; the adaptation is listed in the README)
        five = FiveMassModel(robot).evaluate(robot.configuration(state))
        middle = (left + right) / 2
        self.neutral = _neutral_offset(five.axes_world, com - middle)
        # standing: the reference CoM starts at the robot's own and settles onto the feet's
        # midpoint (`_return_to_middle`; a robot whose nominal posture has its CoM off the
        # midpoint, as JVRC-1's half-sitting 19.8 mm behind it, is not asked to jump there)
        self.com_ref = np.array([com[0], com[1]])
        self.velocity_ref = np.zeros(2)
        self.zmp_ref = self.com_ref.copy()
        self.mode, self.mode_start = "stand", 0.0
        self.stop_from = (self.com_ref.copy(), self.velocity_ref.copy())
        self.mu = 0.0
        self.f_tilde = self.f_g
        self.steps_done = 0
        self.support = "right_foot"
        self.path = {name: self._copy(f) for name, f in self.feet.items()}  # unrefined
        self.next_path: _Foothold | None = None
        self.previous: _Foothold | None = None
        self.next: _Foothold | None = None
        self.next_nominal: _Foothold | None = None
        self.step_start_time = 0.0
        gait = scenario.gait
        if gait is None:  # no walk: stand
            self.start_time = math.inf
            return
        scale = description.scale
        forward, lateral = gait.step_length_for(scale)
        step_period = gait.step_period * froude_time_scale(scale)
        self.velocity_command = np.array([forward, lateral]) / step_period  # v_g^ref [m/s]
        self.yaw_rate_command = gait.turn_per_step(scale) / step_period  # [rad/s]
        self.swing_height = gait.swing_height * scale
        if gait.step_width is not None:
            self.step_width = gait.step_width * scale
        self.start_time = gait.start_double_support
        # the commanded strides: as many as cover the fixed schedule's steps - 1 advances
        # (steps - 1 step periods at the speed), each a fraction of a full one while the speed
        # ramps up; then the closing step
        self.stride_factors = stride_factors(
            commanded_strides(gait.steps, step_period, self.f_g),
            float(np.linalg.norm(self.velocity_command)),
            GAIT_ACCELERATION_MPS2,
            self.f_g,
        )
        self.n_steps = len(self.stride_factors) + 1
        leftward = lateral > 0 or (lateral == 0 and self.yaw_rate_command > 0)
        self.first_swing = "left_foot" if leftward else "right_foot"

    # ---- the period -------------------------------------------------------------------------
    def plan(self, t: float, state: RobotState) -> CentroidalPlan:
        dt = self.dt
        if self.mode == "stand" and t >= self.start_time:
            self.mode, self.mode_start = "shift", t
            self.zmp_ref = self._weight_shift_zmp()
        if self.mode == "stand":
            self._return_to_middle(t)
        elif self.mode == "shift":
            self.com_ref, self.velocity_ref = lipm_state(
                self.com_ref, self.velocity_ref, self.zmp_ref, self.omega, dt
            )
            if t - self.mode_start >= self.period / 2 - dt / 2:
                self._begin_walking(t)
        elif self.mode == "walk":
            self._walk_period(t, state)
        elif self.mode == "stop":
            self._return_to_middle(t)
        return self._output(t)

    def _weight_shift_zmp(self) -> np.ndarray:
        """The reference ZMP [m] of the weight shift before the first step: on the line from
        the CoM toward the first swing foot, at the fraction beta of the way that leaves the
        reference CoM, after half a step period, with the lateral orbital energy
        v^2 - omega^2 d^2 about the first support that Kajita's walk primitive has at the start
        of a step (so that the LIPM turns back before the support foot, as in steady walking).
        The shift starts from the reference's state, which need not be at rest (a standing
        return not yet settled)."""
        support_name = "right_foot" if self.first_swing == "left_foot" else "left_foot"
        support = self.feet[support_name].position[:2]
        swing = self.feet[self.first_swing].position[:2]
        _, _, y_bar, v_y = step_primitive(0.0, self.step_width, self.omega, self.period)
        target = v_y**2 - self.omega**2 * y_bar**2

        def energy(beta: float) -> float:
            zmp = self.com_ref + beta * (swing - self.com_ref)
            x, v = lipm_state(self.com_ref, self.velocity_ref, zmp, self.omega, self.period / 2)
            lateral = (support - swing) / np.linalg.norm(support - swing)
            d = (x - support) @ lateral
            return float((v @ lateral) ** 2 - self.omega**2 * d**2 - target)

        beta = brentq(energy, 0.0, 1.0) if energy(0.0) * energy(1.0) < 0 else 1.0
        return self.com_ref + beta * (swing - self.com_ref)

    def _standing_heading(self) -> float:
        """[rad] the heading on two feet: the mean of their yaws."""
        return (self.feet["left_foot"].yaw + self.feet["right_foot"].yaw) / 2

    def _begin_walking(self, t: float) -> None:
        self.mode = "walk"
        self.support = "right_foot" if self.first_swing == "left_foot" else "left_foot"
        self.previous = self._copy(self.feet[self.first_swing])
        # eq. 5's yaw starts from the standing heading, not the support foot's, which can
        # differ (JVRC-1's half-sitting soles: 0.014 and -0.007 rad; a jump of 0.01 rad in
        # one period turned both hip yaws at once)
        self.heading_from = self._standing_heading()
        self.mu = 0.0
        self.steps_done = 0
        self.step_start_time = t
        self.zmp_ref = self.feet[self.support].position[:2].copy()
        self._plan_next_foothold()

    def _walk_period(self, t: float, state: RobotState) -> None:
        support = self.feet[self.support].position[:2]
        remaining = (1.0 - self.mu) / self.f_g  # t_r of eq. 10, nominal
        eos_ref = lipm_state(self.com_ref, self.velocity_ref, support, self.omega, remaining)[0]
        eos = lipm_state(
            state.com_position_world[:2],
            state.com_velocity_world[:2],
            support,
            self.omega,
            remaining,
        )[0]
        rotation = yaw_rotation(self.feet[self.support].yaw)[:2, :2]
        error_path = rotation.T @ (eos - eos_ref)  # (forward, left) in the support's frame
        swing_side = -1.0 if self.support == "left_foot" else 1.0  # +y when the left swings
        if self.options.step_timing:  # eq. 16
            self.f_tilde = timed_gait_frequency(self.f_g, self.k_t, swing_side * error_path[1])
        else:
            self.f_tilde = self.f_g
        closing = self.steps_done >= self.n_steps - 1  # `closing_foothold`: eq. 17 off
        if self.options.step_size and not closing:  # eq. 17
            forward = rotation @ np.array([STEP_SIZE_GAIN * error_path[0], 0.0])
            self.next.position[:2] = self.next_nominal.position[:2] + forward
        self.mu += self.f_tilde * self.dt
        # the reference advances on the gait phase's clock
        self.com_ref, self.velocity_ref = lipm_state(
            self.com_ref,
            self.velocity_ref,
            support,
            self.omega,
            reference_time_step(self.dt, self.f_tilde, self.f_g),
        )
        if self.mu >= 1.0:
            self._exchange(t)

    def _exchange(self, t: float) -> None:
        """mu wrapped: the swing foot lands on s[k+1] and becomes the support."""
        self.mu -= 1.0
        self.steps_done += 1
        swing = self._swing()
        self.previous = self._copy(self.feet[self.support])
        self.feet[swing] = self._copy(self.next)
        adjustment = carried_step_adjustment(self.next.position[:2], self.next_nominal.position[:2])
        self.path[swing] = self._copy(self.next_path)
        self.path[swing].position[:2] += adjustment
        self.com_ref = self.com_ref + adjustment
        self.support = swing
        self.heading_from = self.feet[swing].yaw  # eq. 5: s_psi[k]
        self.step_start_time = t
        self.zmp_ref = self.feet[self.support].position[:2].copy()
        if self.steps_done >= self.n_steps:
            # the reference is already at t + dt (`_walk_period` advanced it): its time
            self.mode, self.mode_start = "stop", t + self.dt
            self.stop_from = (self.com_ref.copy(), self.velocity_ref.copy())
            self.next = self.next_nominal = None
            return
        self._plan_next_foothold()

    def _return_to_middle(self, t: float) -> None:
        """Critically damped return (rate omega) of the reference CoM to the feet's midpoint
        from `stop_from` (its position and velocity at `mode_start`): after the closing step,
        and while standing from the initial CoM (neither is in the paper)."""
        middle = (self.feet["left_foot"].position[:2] + self.feet["right_foot"].position[:2]) / 2
        x0, v0 = self.stop_from
        tau = t + self.dt - self.mode_start
        self.com_ref, self.velocity_ref, acceleration = critically_damped(
            x0, v0, middle, self.omega, tau
        )
        self.zmp_ref = self.com_ref - acceleration / self.omega**2

    # ---- footsteps --------------------------------------------------------------------------
    def _swing(self) -> str:
        return "left_foot" if self.support == "right_foot" else "right_foot"

    @staticmethod
    def _copy(foothold: _Foothold) -> _Foothold:
        return _Foothold(foothold.position.copy(), foothold.yaw)

    def _nominal_after(
        self, support: _Foothold, support_name: str, closing: bool, index: int | None = None
    ) -> _Foothold:
        """Eq. 3: the foothold after `support`, in its frame; as step `index` (1, 2, ...) of
        the walk, with the gait command scaled by that step's stride factor (the start's
        ramp; None: the full command)."""
        iota = 1.0 if support_name == "right_foot" else -1.0
        factor = self._stride_factor(index)
        v_x, v_y = factor * self.velocity_command
        yaw_rate = factor * self.yaw_rate_command
        if closing:
            x_s, y_s, psi_s = closing_foothold(iota, self.step_width)
        else:
            # the sideways step covers its own and the trailing step's share of the command
            # (2 v_y / f_g at full stride; the closing step has none), so that the walk's
            # sideways offset is its strides' (with the start's ramp too)
            if index is None:
                trailing = factor
            elif index < len(self.stride_factors):
                trailing = self.stride_factors[index]  # step index + 1's
            else:
                trailing = 0.0
            shares = factor + trailing
            leading = iota == math.copysign(1.0, v_y) and v_y != 0
            s_y = shares * self.velocity_command[1] / self.f_g if leading else 0.0
            x_s, y_s, psi_s = (
                v_x / self.f_g,
                iota * self.step_width + s_y,
                yaw_rate / self.f_g,
            )
        offset = yaw_rotation(support.yaw) @ np.array([x_s, y_s, 0.0])
        return _Foothold(support.position + offset, support.yaw + psi_s)

    def _stride_factor(self, index: int | None) -> float:
        """The fraction of eq. 3's stride that step `index` (1, 2, ...) takes: the start's
        ramp (`stride_factors`); 1 after it, for the closing step, or for None."""
        if index is None or index > len(self.stride_factors):
            return 1.0
        return self.stride_factors[index - 1]

    def _plan_next_foothold(self) -> None:
        """s[k+1]: eq. 3 from the support's nominal foothold (the walk's path, without the
        refinements, as Kajita's p_n = p_(n-1) + s_n), refined by his modified foot placement
        toward the walk primitive of the step after it."""
        support = self.path[self.support]
        closing = self.steps_done == self.n_steps - 1
        nominal = self._nominal_after(support, self.support, closing, self.steps_done + 1)
        self.next_path = self._copy(nominal)
        if not closing:
            swing = self._swing()
            after = self._nominal_after(
                nominal, swing, self.steps_done + 1 == self.n_steps - 1, self.steps_done + 2
            )
            frame = yaw_rotation(nominal.yaw)[:2, :2]
            step = frame.T @ (after.position[:2] - nominal.position[:2])
            x_bar, v_x, y_bar, v_y = step_primitive(step[0], step[1], self.omega, self.period)
            target = nominal.position[:2] + frame @ np.array([x_bar, y_bar])
            target_velocity = frame @ np.array([v_x, v_y])
            end, end_velocity = lipm_state(
                self.com_ref,
                self.velocity_ref,
                self.feet[self.support].position[:2],
                self.omega,
                self.period,
            )
            refined = np.array(
                [
                    modified_foot_placement(
                        end[i],
                        end_velocity[i],
                        target[i],
                        target_velocity[i],
                        self.omega,
                        self.period,
                    )
                    for i in range(2)
                ]
            )
            # a "slight position adjustment" (Sec. 3.1): within half the step width of the
            # nominal foothold, so that the feet never cross
            limit = foothold_adjustment_limit(self.step_width)
            nominal.position[:2] += np.clip(refined - nominal.position[:2], -limit, limit)
        else:  # the closing step lands beside the actual support
            nominal = self._nominal_after(
                self.feet[self.support], self.support, True, self.steps_done + 1
            )
        self.next_nominal = nominal
        self.next = self._copy(nominal)

    # ---- output -----------------------------------------------------------------------------
    def _output(self, t: float) -> CentroidalPlan:
        positions = self.start_position.copy()
        orientations = self.start_orientation.copy()
        tracked = np.zeros(len(positions), dtype=bool)
        footsteps: tuple[Footstep, ...] = ()
        remaining = None
        for name, foothold in self.feet.items():
            k = self.limb_index[name]
            positions[k] = foothold.position
            orientations[k] = heading_quaternion(foothold.yaw)
            tracked[k] = True
        if self.mode == "walk":
            swing = self._swing()
            k = self.limb_index[swing]
            mu = self.mu
            previous, target = self.previous, self.next
            positions[k, :2] = (1 - mu) * previous.position[:2] + mu * target.position[:2]
            positions[k, 2] = (1 - mu) * previous.position[2] + mu * target.position[2]
            positions[k, 2] += self.swing_height * math.sin(mu * math.pi)
            yaw = (1 - mu) * previous.yaw + mu * target.yaw
            orientations[k] = heading_quaternion(yaw)
            contacts: tuple[str, ...] = (self.support,)
            remaining = (1.0 - mu) / self.f_g
            touchdown = t + (1.0 - mu) / max(self.f_tilde, 1e-3)
            footsteps = (
                Footstep(
                    swing,
                    target.position.copy(),
                    target.yaw,
                    self.step_start_time,
                    touchdown,
                    heading_quaternion(target.yaw),
                ),
            )
            heading = (1 - mu) * self.heading_from + mu * target.yaw
        else:
            contacts = ("left_foot", "right_foot")
            heading = self._standing_heading()
        com = np.array([self.com_ref[0], self.com_ref[1], self.ground + self.height])
        velocity = np.array([self.velocity_ref[0], self.velocity_ref[1], 0.0])
        acceleration = np.zeros(3)
        acceleration[:2] = self.omega**2 * (self.com_ref - self.zmp_ref)
        zmp = np.array([self.zmp_ref[0], self.zmp_ref[1], self.ground])
        feet_middle = (
            positions[self.limb_index["left_foot"]] + positions[self.limb_index["right_foot"]]
        ) / 2
        tilt = com - feet_middle
        axes = tilt_and_yaw(tilt / np.linalg.norm(tilt), heading) @ self.neutral
        wrench = np.zeros(6)
        wrench[:3] = self.mass * acceleration  # the resultant w-bar = m c'' (gravity apart)
        return CentroidalPlan(
            com_reference_world=com,
            com_planned_world=com,
            com_velocity_planned_world=velocity,
            com_acceleration_planned_world=acceleration,
            base_orientation_planned_world=heading_quaternion(heading),
            base_angular_velocity_planned_world=np.zeros(3),
            wrench_planned_world=wrench,
            wrench_projected_world=wrench,
            zmp_planned_world=zmp,
            contact_limbs=contacts,
            limb_target_position_world=positions,
            limb_target_orientation_world=orientations,
            # no sub-stages: the runner's planner stage is the whole plan (it has none of
            # Murooka Table IV's, whose "calculate reference" row it was once shown as)
            timings_ns={},
            limb_tracked=tracked,
            footsteps=footsteps,
            inertia_axes_reference_world=axes,
            step_remaining_s=remaining,
        )


def _neutral_offset(axes_world: np.ndarray, com_from_feet: np.ndarray) -> np.ndarray:
    """The constant rotation N with R_I = tilt_and_yaw(feet-to-CoM, 0) N in the standing pose
    (level heading 0): how far our robot's principal axes lean from eq. 5's neutral tilt."""
    tilt = tilt_and_yaw(com_from_feet / np.linalg.norm(com_from_feet), 0.0)
    return tilt.T @ axes_world


def _make(options: SteppingOptions):
    def factory(dt: float) -> FiveMassGaitPlanner:
        return FiveMassGaitPlanner(dt, options)

    return factory


register(
    PlannerSpec(
        "five_mass_gait",
        _make(SteppingOptions()),
        "Ficht & Behnke 2021: LIPM references, gait phase, step timing and size feedback",
    )
)
register(
    PlannerSpec(
        "five_mass_gait_timing",
        _make(SteppingOptions(step_size=False)),
        "five_mass_gait with step timing feedback only (eq. 16; Table 1 ablation)",
    )
)
register(
    PlannerSpec(
        "five_mass_gait_fixed",
        _make(SteppingOptions(step_timing=False, step_size=False)),
        "five_mass_gait without step timing or size feedback (Table 1 ablation)",
    )
)
