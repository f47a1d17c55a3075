"""Stabilizer `direct_centroidal`: Ficht & Behnke's CoM controller (paper 003, Sec. 3.3,
eqs. 8-11) and inertia controller (Sec. 3.4, eqs. 12-15), per horizontal axis.

CoM controller. After Choi et al. ([5]), a CoM velocity that steers the CoM x back to the
reference x_ref and the ZMP p to p_ref,

    x'_zmp = -K_zmp (p_ref - p),   x'_com = K_com (x_ref - x)                         (8)
    x'_vel = K_vel (x'_ref - x'),  x'_eos = K_eos (x_eos^ref - x_eos)                 (10)
    x'_ctrl = x'_com + x'_zmp [+ x'_vel + x'_eos]                                     (11)
    x_i[n] = x'_ctrl[n] dt + (1 - alpha) x_i[n-1],   x_set = x_ref + x_i              (9)

The ZMP term carries Choi's sign (his u = x'_d - k_p (p_d - p) + k_x (x_d - x)); eq. 8 is
printed with +K_zmp. With the CoM following x'_ctrl and the LIPM p = x - x''/omega^2, the error
e = x_ref - x obeys (K_zmp / omega^2) e'' + e' + (K_com - K_zmp) e = 0: stable only for
K_com > K_zmp > 0, and Choi's input-to-state stability condition is K_com > omega > K_zmp > 0
(`choi_gains`). x_eos are end-of-step positions by eq. 1 over the remaining step time
t_r (the plan's `step_remaining_s`) with the ZMP at the reference ZMP (the support foot):
the reference's from (x_ref, x'_ref) and the expected from the estimated (x, x').

Inertia controller. The augmented CoM and ZMP of the flywheel model (eq. 13),
x~ = x + I theta_f / (m h), p~ = p + I theta_f / (m h), where theta_f is the tilt of the
principal z axis from its reference (projected angles: toward +x about the y moment, toward
+y about the x moment), are driven by the same law toward x~_ref = x_set and p~_ref = p_ref
(eq. 14); the leaky integral x~_i of eq. 9 holds the set tilt theta_set = x~_i m h / I (eq. 15),
the complementary rotation R_c, and R_I^set = R_c R_I^ref (eq. 12).

The ZMP in p~ (`flywheel_zmp`, ours): eq. 13's p is the ZMP, x'' = omega^2 (x - p) -
I theta_f'' / (m h), but eq. 7's estimate x - x''/omega^2 is then the CMP, p + I theta_f'' /
(m g). We take p = CMP - I theta_f'' / (m g), theta_f'' from the estimator's tilt filter
(`RobotState.inertia_tilt_acceleration`), so that p~ = x~ - x~''/omega^2 with x~'' = x'' +
I theta_f'' / (m h), eq. 13's own LIPM form. The paper says the theta'' term "gets hidden within
x~''" and does not use it in eqs. 13-15 (its second Kalman filter, Sec. 3.2, does estimate
theta''). Measured (MuJoCo, `stand`, Choi's gains, bent knees): the full
method falls after 0.18 s with the CMP and 0.6 s with the ZMP (0.66 / 0.39 s MuJoCo / PyBullet
with the straight-leg layer); it stood 3 s only with the bent-knee layer and the inertia loop's
gains at 0.1 K_zmp and 0.3 K_com (issue 17's note).

The lagged tilt (`tilt_lag_time_constant`, ours, only in the variant
`direct_centroidal_lagged_inertia`): the set tilt reaches R_c through a first-order lag. Eq.
14's ZMP term closes a loop through the flywheel's own reaction: a tilt accelerated by theta''
moves the ZMP by -I theta'' / (m g) (eq. 13), so this path's loop gain is K_zmp s / omega^2.
Without delay that loop is stable, but its gain grows without bound with frequency, and the
one-period delay of a digital loop and the servos supply the phase near the sampling rate
(with each set tilt realised by the next period the dominant root is about -(1 + K_zmp /
(omega^2 dt)), -73 here). Through the lag 1 / (1 + tau s) the path's gain tends to K_zmp /
(omega^2 tau) instead and stays below 1 at every frequency for tau > K_zmp / omega^2 (0.15 s
on our humanoid at Choi's gains), whatever the delay. The lag does not bound the ZMP term's
other path, p~'s I theta / (m h), which the K_com term holds at low frequencies. Our reading
(the paper says nothing of it): its robot's servos and 100 Hz loop smooth the flywheel's
reaction; ours realise a tilt within one period (docs/ficht-behnke.md).

The bounded tilt (`FeedbackOptions.tilt_limit`, ours, only in the variant
`direct_centroidal_bounded_inertia`): eq. 15's leaky integral x~_i is held within
+-I theta_max / (m h) (anti-windup saturation), so the set tilt stays within theta_max [rad]
about each axis. Through the lag alone the tilt settles standing, but a push or a step makes
eq. 14 ask for tenths of a radian (its K_com term: x~ = x_set needs theta = (m h / I)(x_set
- x), 8 rad per metre of CoM error on our humanoid), and the robot falls. The bound does not
replace the lag: without it the bounded loop still alternates period by period.

A state without a ZMP (an estimator with force sensors and no loaded limb gives NaN) drops the
ZMP term for that period. The ablation modes of the paper's Table 1 are `FeedbackOptions`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from centroidal.gravity import GRAVITY
from centroidal.lipm import leaky_alpha, lipm_state
from centroidal.tilt import axis_from_angles, flywheel_angles, tilt_rotation
from robots.five_mass import FiveMassModel
from robots.model import RobotModel
from robots.scene import Scenario
from robots.types import CentroidalPlan, RobotState, WholeBodyTargets
from stabilizers.base import StabilizerSpec, register

VELOCITY_GAIN = 0.5  # K_vel (Sec. 4)
EOS_GAIN_RATIO = 0.5  # K_eos = 0.5 K_com (Sec. 4)


K_COM_PER_OMEGA = 2.0  # ours: K_com / omega (`choi_gains`)
K_ZMP_PER_OMEGA = 0.5  # ours: K_zmp / omega


def choi_gains(
    omega: float, k_com_per_omega: float = K_COM_PER_OMEGA, k_zmp_per_omega: float = K_ZMP_PER_OMEGA
) -> tuple[float, float]:
    """(K_com, K_zmp) [1/s] inside Choi et al.'s condition K_com > omega > K_zmp > 0: the
        paper sets them "according to [5], but with quite high gains due to the leaky integration"
        without numbers, tuned as its Table 1 says "to achieve the best possible performance". By
        default we take K_com = 2 omega and K_zmp = omega / 2 (the middle of each range on a log
        scale between omega / 4 and 4 omega), for the augmented CoM too (ours: the paper names
    K_zmp^aug and K_com^aug apart, Sec. 4, without numbers), whose eq. 14 takes Choi's sign
    -K_zmp^aug as eq. 8 does (printed +K_zmp^aug; the module). Other ratios inside the
        condition are `FeedbackOptions`'. Measured at 1.5 omega and 0.8 omega (2026-12-02,
        docs/ficht-behnke.md, not the default): `no_inertia` survives 20 / 20 of the 20 standing
        pushes at 0.35 m/s in both simulators instead of 13 / 20 (19-20 against 13-14 on another
        seed's), and on JVRC-1 with a perfect state `bent_no_inertia` walks; but on JVRC-1 with its
        own filter it no longer stands (falls at 3.10 / 1.19 s, MuJoCo / PyBullet; it stands 10 s
        at the default). ValueError outside the condition."""
    if not k_com_per_omega > 1.0 > k_zmp_per_omega > 0.0:
        raise ValueError(
            "Choi's condition K_com > omega > K_zmp > 0 needs k_com_per_omega > 1 > "
            f"k_zmp_per_omega > 0, got {k_com_per_omega!r} and {k_zmp_per_omega!r}"
        )
    return k_com_per_omega * omega, k_zmp_per_omega * omega


@dataclass(frozen=True)
class FeedbackOptions:
    """The CoM and inertia controllers' parts (Table 1's rows): `closed_loop` False is the
    open loop (x_set = x_ref); `leaky` False integrates with alpha = 0; `extended` adds
    x'_vel and x'_eos; `inertia` runs the inertia controller; `tilt_lag` (ours) passes its set
    tilt through the lag of `tilt_lag_time_constant`; `tilt_limit` [rad] (ours, None: none)
    bounds the set tilt about each axis (see the module); `k_com_per_omega`, `k_zmp_per_omega`:
    the gains of `choi_gains` (both controllers)."""

    closed_loop: bool = True
    leaky: bool = True
    extended: bool = True
    inertia: bool = True
    tilt_lag: bool = False
    tilt_limit: float | None = None
    k_com_per_omega: float = K_COM_PER_OMEGA
    k_zmp_per_omega: float = K_ZMP_PER_OMEGA

    def __post_init__(self) -> None:
        if self.tilt_lag and not self.inertia:
            raise ValueError("tilt_lag lags the inertia controller's tilt: it needs inertia=True")
        if self.tilt_limit is not None:
            if not self.inertia:
                raise ValueError(
                    "tilt_limit bounds the inertia controller's tilt: it needs inertia=True"
                )
            if not 0.0 < self.tilt_limit < math.pi / 2:
                raise ValueError(f"tilt_limit must be in (0, pi/2) rad, got {self.tilt_limit!r}")
        choi_gains(1.0, self.k_com_per_omega, self.k_zmp_per_omega)  # Choi's condition


TILT_LIMIT_RAD = 0.02
"""[rad] ours: the bound of `direct_centroidal_bounded_inertia`'s set tilt (with the lag): one
at which the inertia controller still acts (its set tilt at the bound in 56-73 % of the
periods of `walk`, MuJoCo) and the full method walks `walk` in both simulators (it does at
0.01-0.03 rad, falls at 0.05 and 0.10). No bound makes it better than `no_inertia`: of the
20 standing pushes at 0.35 m/s on two seeds (40 a simulator, MuJoCo / PyBullet), 0.01 rad
survives 26 / 27 as `no_inertia` does, 0.02 26 / 25, 0.03 22 / 22; on one seed 0.05 12 / 11
and 0.10 9 / 9 of 20 (2026-12-02, docs/ficht-behnke.md, "The inertia controller bounded")."""
NO_TILT = (
    "direct_centroidal's inertia control (eqs. 12-15) needs the estimator's inertia tilt "
    "(RobotState.inertia_tilt), which this estimator does not give (`centrobench list` names "
    "the estimators that give it)"
)
"""The error of an inertia-controlled episode run with an estimator that gives no tilt (e.g.
`ground_truth`): the controller would otherwise run without its inertia control, unseen.
Sweeps and `run` refuse such a pair before it starts (the variants' `needs_state`,
`bench.controllers.estimator_refusal`); this is the guard for an episode started otherwise."""


def tilt_lag_time_constant(omega: float, k_zmp: float) -> float:
    """tau [s] of the lagged tilt (ours, see the module): twice the bound K_zmp / omega^2 [1/s
    over 1/s^2] above which the ZMP term's path through the flywheel's reaction has a gain
    below 1 at every frequency, so a gain of 1/2 at high frequencies; omega = sqrt(g / h)
    [1/s], K_zmp [1/s]. 0.29 s on our humanoid at Choi's gains (K_zmp = omega / 2: tau = 1 /
    omega). Measured (MuJoCo / PyBullet, `stand`, 10 s): a lag of 0.08 s falls (7.1 / 1.9 s),
    0.10 s stands / falls (4.0 s), 0.12 s and more stand in both; at 1.6 K_zmp the boundary
    moves to 0.12-0.15 s (MuJoCo)."""
    return 2.0 * k_zmp / omega**2


class DirectCentroidalStabilizer:
    name = "direct_centroidal"

    def __init__(self, dt: float, options: FeedbackOptions | None = None) -> None:
        self.dt = dt
        self.options = options or FeedbackOptions()
        self.alpha = leaky_alpha(1.0 / dt) if self.options.leaky else 0.0

    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None:
        self.limb_names = robot.robot.limb_names
        self.feet = [k for k, name in enumerate(self.limb_names) if name.endswith("foot")]
        self.mass = robot.total_mass
        five = FiveMassModel(robot).evaluate(robot.configuration(state))
        self.moments = five.moments  # I_PA in the standing pose (Sec. 3.1: kept constant)
        self.x_i = np.zeros(2)
        self.x_aug_i = np.zeros(2)
        self.theta_lagged = np.zeros(2)  # [rad] the set tilt through the lag (tilt_lag)

    def stabilize(self, t: float, plan: CentroidalPlan, state: RobotState) -> WholeBodyTargets:
        start = time.perf_counter_ns()
        options = self.options
        ground = plan.zmp_planned_world[2]
        height = plan.com_planned_world[2] - ground
        omega = math.sqrt(GRAVITY / height)
        k_com, k_zmp = choi_gains(omega, options.k_com_per_omega, options.k_zmp_per_omega)
        x_ref = plan.com_planned_world[:2]
        v_ref = plan.com_velocity_planned_world[:2]
        p_ref = plan.zmp_planned_world[:2]
        x = state.com_position_world[:2]
        v = state.com_velocity_world[:2]
        p = measured_or_reference_zmp(state.zmp_world[:2], p_ref)
        com_target = plan.com_planned_world.copy()
        axes = plan.inertia_axes_reference_world
        if options.closed_loop:
            control = -k_zmp * (p_ref - p) + k_com * (x_ref - x)  # eq. 8
            if options.extended:
                control += VELOCITY_GAIN * (v_ref - v)  # eq. 10
                remaining = plan.step_remaining_s
                if remaining is not None:  # else `end_of_step_term`: none
                    control += end_of_step_term(x_ref, v_ref, x, v, p_ref, omega, remaining, k_com)
            self.x_i = control * self.dt + (1.0 - self.alpha) * self.x_i  # eq. 9
            com_target[:2] = x_ref + self.x_i
            if axes is not None:
                feet = plan.limb_target_position_world[self.feet].mean(axis=0)
                reference = _unit(plan.com_planned_world - feet)
                axes_set = axes_for_set_com(axes, reference, _unit(com_target - feet))
                if options.inertia:
                    if state.inertia_tilt is None:
                        raise ValueError(NO_TILT)
                    neutral = flywheel_angles(axes[:, 2], reference)
                    axes_set = self._inertia(
                        com_target[:2],
                        p_ref,
                        x,
                        p,
                        state.inertia_tilt - neutral,
                        state.inertia_tilt_acceleration,
                        axes_set,
                        height,
                        k_com,
                        k_zmp,
                        omega,
                    )
                axes = axes_set
        in_contact = np.array([name in plan.contact_limbs for name in self.limb_names])
        return WholeBodyTargets(
            com_position_world=com_target,
            base_orientation_world=plan.base_orientation_planned_world,
            limb_position_world=plan.limb_target_position_world,
            limb_orientation_world=plan.limb_target_orientation_world,
            limb_in_contact=in_contact,
            com_desired_world=com_target,
            zmp_desired_world=plan.zmp_planned_world,
            timings_ns={"feedback": time.perf_counter_ns() - start},
            limb_tracked=plan.limb_tracked,
            inertia_axes_world=axes,
        )

    def _inertia(
        self,
        x_set,
        p_ref,
        x,
        p,
        theta_f,
        theta_f_acceleration,
        axes_ref,
        height,
        k_com,
        k_zmp,
        omega,
    ) -> np.ndarray:
        """Eqs. 12-15: R_I^set = R_c R_I^ref; theta_f (2,) [rad] the flywheel angle (the
        estimator's, less the reference's neutral lean), theta_f_acceleration (2,) [rad/s^2]
        (None: taken as 0); with `tilt_limit`, eq. 15's integral held within the bound; with
        `tilt_lag`, R_c from the set tilt through the lag."""
        # moments about the axes the tilts turn about: a tilt toward +x turns about y
        inertia = np.array([self.moments[1], self.moments[0]])
        scale = inertia / (self.mass * height)
        x_aug = x + scale * theta_f  # eq. 13
        p_aug = flywheel_zmp(p, scale, theta_f_acceleration, height) + scale * theta_f
        control = -k_zmp * (p_ref - p_aug) + k_com * (x_set - x_aug)  # eq. 14
        self.x_aug_i = control * self.dt + (1.0 - self.alpha) * self.x_aug_i
        if self.options.tilt_limit is not None:  # ours: anti-windup bound of the set tilt
            bound = scale * self.options.tilt_limit
            self.x_aug_i = np.clip(self.x_aug_i, -bound, bound)
        theta_set = self.x_aug_i / scale  # eq. 15
        if self.options.tilt_lag:
            tau = tilt_lag_time_constant(omega, k_zmp)
            self.theta_lagged += -math.expm1(-self.dt / tau) * (theta_set - self.theta_lagged)
            theta_set = self.theta_lagged
        rotation = tilt_rotation(axis_from_angles(theta_set[0], theta_set[1]))
        return rotation @ axes_ref  # eq. 12


def end_of_step_term(
    x_ref: np.ndarray,
    v_ref: np.ndarray,
    x: np.ndarray,
    v: np.ndarray,
    p_ref: np.ndarray,
    omega: float,
    remaining_s: float,
    k_com: float,
) -> np.ndarray:
    """Eq. 10's x'_eos = K_eos (x_eos^ref - x_eos) [m/s], K_eos = 0.5 K_com (Sec. 4): the
    end-of-step CoM positions by eq. 1 over the remaining step time t_r [s] with the ZMP at the
    reference ZMP, the reference's from (x_ref, v_ref) and the expected one from the estimate
    (x, v). Ours: while no step is under way (standing, the start's weight shift, after the
    closing step: the plan's `step_remaining_s` is None) the term is left out, as the paper
    defines t_r = (1 - mu) / f_g only for a step."""
    eos_ref = lipm_state(x_ref, v_ref, p_ref, omega, remaining_s)[0]
    eos = lipm_state(x, v, p_ref, omega, remaining_s)[0]
    return EOS_GAIN_RATIO * k_com * (eos_ref - eos)


def axes_for_set_com(
    axes_reference_world: np.ndarray, pendulum_reference: np.ndarray, pendulum_set: np.ndarray
) -> np.ndarray:
    """R_I^ref of eq. 12 for the set CoM [3x3]: eq. 5 places z_I along the line from the
    feet's midpoint to the CoM, and the pose generator's feet are relative to the CoM it is
    given, so the reference axes are turned with that line from the reference CoM's direction
    to the set CoM's (unit vectors, world frame). Ours: the paper writes eq. 5 for the
    reference CoM and R_I^set = R_c R_I^ref (eq. 12) without saying which CoM the neutral tilt
    follows once eq. 9 moves it; this applies in every closed-loop row with inertia axes, also
    those without the inertia controller (R_c = I)."""
    return tilt_rotation(pendulum_set) @ tilt_rotation(pendulum_reference).T @ axes_reference_world


def measured_or_reference_zmp(zmp: np.ndarray, zmp_reference: np.ndarray) -> np.ndarray:
    """p [m] (2,) for eqs. 8 and 14: the estimator's ZMP, or the reference p_ref when it has
    none (NaN: a force-sensor ZMP with no vertical force, the feet unloaded; eq. 7's estimate
    of `five_mass_kalman` is always finite). Ours: the paper does not say. With p = p_ref, eq.
    8's ZMP term K_zmp (p_ref - p) is zero for that period and its CoM term still acts; in eq.
    14 the augmented ZMP keeps its flywheel terms (p~ = p_ref + I theta / (m h) less the
    theta'' term of `flywheel_zmp`)."""
    if math.isfinite(zmp[0] + zmp[1]):
        return zmp
    return zmp_reference


def flywheel_zmp(
    cmp: np.ndarray, scale: np.ndarray, theta_acceleration: np.ndarray | None, height: float
) -> np.ndarray:
    """The flywheel model's ZMP [m] from eq. 7's estimate, which is its CMP (see the module):
    p = CMP - I theta'' / (m g) = CMP - scale theta'' h / g, scale = I / (m h) [m/rad],
    theta'' [rad/s^2], h [m]. Ours: the paper leaves the theta'' term "hidden". `cmp` must be
    a CMP, as eq. 7's estimate of both estimators that give the tilt is: a force sensors' ZMP
    already holds the flywheel's reaction, and through this it would be counted twice (as
    the fifth session's simulator-state runs of 2026-12-02 did; docs/ficht-behnke.md, "Where
    the inertia controller's loop closes")."""
    if theta_acceleration is None:
        return cmp
    return cmp - scale * theta_acceleration * (height / GRAVITY)


def _unit(vector: np.ndarray) -> np.ndarray:
    return vector / math.sqrt(vector @ vector)


def _make(options: FeedbackOptions):
    def factory(dt: float) -> DirectCentroidalStabilizer:
        return DirectCentroidalStabilizer(dt, options)

    return factory


VARIANTS = {
    "direct_centroidal": (
        FeedbackOptions(),
        "Ficht & Behnke 2021: CoM-ZMP, extended and inertia control",
    ),
    "direct_centroidal_no_inertia": (
        FeedbackOptions(inertia=False),
        "direct_centroidal without the inertia controller (Table 1 ablation)",
    ),
    "direct_centroidal_lagged_inertia": (
        FeedbackOptions(tilt_lag=True),
        "direct_centroidal with the inertia controller's set tilt through a first-order lag "
        "(ours: tilt_lag_time_constant)",
    ),
    "direct_centroidal_bounded_inertia": (
        FeedbackOptions(tilt_lag=True, tilt_limit=TILT_LIMIT_RAD),
        "direct_centroidal with the inertia controller's set tilt through the lag and within "
        "TILT_LIMIT_RAD (ours)",
    ),
    "direct_centroidal_no_inertia_near_omega": (
        FeedbackOptions(inertia=False, k_com_per_omega=1.5, k_zmp_per_omega=0.8),
        "direct_centroidal without the inertia controller, K_com = 1.5 omega and K_zmp = 0.8 "
        "omega (ours: other gains inside Choi's condition)",
    ),
    "direct_centroidal_leaky": (
        FeedbackOptions(extended=False, inertia=False),
        "CoM-ZMP control with leaky integration only (eq. 8-9; Table 1 ablation)",
    ),
    "direct_centroidal_integrator": (
        FeedbackOptions(leaky=False, extended=False, inertia=False),
        "CoM-ZMP control with a plain integrator (alpha = 0; Table 1 ablation)",
    ),
    "direct_centroidal_open_loop": (
        FeedbackOptions(closed_loop=False, extended=False, inertia=False),
        "the references without feedback (Table 1 ablation)",
    ),
}
for _name, (_options, _description) in VARIANTS.items():
    _reads = _options.inertia and _options.closed_loop  # eqs. 12-15 read the tilt
    register(
        StabilizerSpec(
            _name,
            _make(_options),
            _description,
            needs_state=frozenset({"inertia_tilt"}) if _reads else frozenset(),
        )
    )
