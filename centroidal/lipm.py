"""The linear inverted pendulum in closed form, and the parameter adaptations of Ficht &
Behnke's controller to another robot and control rate (paper 003, Sec. 3 and Sec. 4).

Per horizontal axis, with the ZMP p held constant (eq. 1 written about p):

    x'' = omega^2 (x - p),   omega = sqrt(g / h)
    x(t) - p = (x0 - p) cosh(omega t) + x0' / omega sinh(omega t)
    x'(t)    = (x0 - p) omega sinh(omega t) + x0' cosh(omega t)

(the paper prints the solution for p = 0).
"""

from __future__ import annotations

import math

import numpy as np

PAPER_CONTROL_RATE_HZ = 100.0  # Sec. 4: "the control rate is limited to 100 Hz"
PAPER_LEAKY_ALPHA = 0.03  # Sec. 4: alpha of every integrator, at 100 Hz
PAPER_GAIT_FREQUENCY_HZ = 2.6  # Sec. 4: f_g
PAPER_ROBOT_HEIGHT_M = 0.9  # Sec. 4: "a 90 cm tall igus Humanoid Open Platform"
PAPER_TIMING_ERROR_M = 0.1  # Sec. 4: K_t = 10 f_g, "a 10 cm EOS error ... fully slow down"


def lipm_state(
    x0: np.ndarray | float,
    velocity0: np.ndarray | float,
    zmp: np.ndarray | float,
    omega: float,
    t: float,
) -> tuple[np.ndarray | float, np.ndarray | float]:
    """(x(t), x'(t)) of eq. 1 from (x0 [m], x0' [m/s]) with the ZMP fixed at `zmp` [m]; works
    per axis on arrays."""
    c, s = math.cosh(omega * t), math.sinh(omega * t)
    offset = x0 - zmp
    return zmp + offset * c + velocity0 / omega * s, offset * omega * s + velocity0 * c


def critically_damped(
    x0: np.ndarray | float,
    velocity0: np.ndarray | float,
    target: np.ndarray | float,
    omega: float,
    t: float,
) -> tuple[np.ndarray | float, np.ndarray | float, np.ndarray | float]:
    """(x(t) [m], x'(t) [m/s], x''(t) [m/s^2]) of the critically damped approach x'' = omega^2
    (target - x) - 2 omega x' to `target` [m] at rate omega [1/s], from (x0 [m], x0' [m/s]) at
    t = 0, t [s], in closed form:

        x(t) = target + (d + (x0' + omega d) t) e^(-omega t),   d = x0 - target;

    works per axis on arrays. Not a paper's equation: the framework's planners use it to bring
    a reference CoM that starts at the robot's own CoM onto their nominal point. With omega
    the LIP's and x0' = 0, the ZMP x - x'' / omega^2 it implies starts at x0 + d (as far beyond
    the start as the start is from the target) and moves monotonically onto the target."""
    decay = math.exp(-omega * t)
    offset = x0 - target
    slope = velocity0 + omega * offset
    position = target + (offset + slope * t) * decay
    velocity = (slope - omega * (offset + slope * t)) * decay
    acceleration = (-2 * omega * slope + omega**2 * (offset + slope * t)) * decay
    return position, velocity, acceleration


def leaky_alpha(rate_hz: float) -> float:
    """The decay factor alpha of eq. 9 at `rate_hz` that keeps the paper's half-life in
    seconds: the paper's 0.03 per period at 100 Hz halves x_i in ln 2 / -ln(1 - 0.03) = 22.8
    periods = 0.228 s ("roughly half the step time", Sec. 4); at rate r the same half-life
    needs 1 - alpha_r = (1 - 0.03)^(100 / r) (0.00607 at 500 Hz)."""
    if not rate_hz > 0:
        raise ValueError(f"control rate must be positive, got {rate_hz} Hz")
    return 1.0 - (1.0 - PAPER_LEAKY_ALPHA) ** (PAPER_CONTROL_RATE_HZ / rate_hz)


def half_life_s(alpha: float, rate_hz: float) -> float:
    """The time [s] in which (1 - alpha)^n halves, at `rate_hz` periods per second."""
    return math.log(0.5) / math.log(1.0 - alpha) / rate_hz


def gait_frequency(robot_height_m: float) -> float:
    """f_g [Hz] for a robot `robot_height_m` tall, by Froude similarity (equal g t^2 / L for
    the same motion, so f ~ sqrt(g / L)) with the leg length taken proportional to the height:
    f_g = 2.6 Hz sqrt(0.9 m / H). The paper gives the igus robot's height (0.9 m), not its leg
    length; the proportionality assumes geometric similarity. 1.98 Hz for our 1.56 m humanoid."""
    if not robot_height_m > 0:
        raise ValueError(f"robot height must be positive, got {robot_height_m} m")
    return PAPER_GAIT_FREQUENCY_HZ * math.sqrt(PAPER_ROBOT_HEIGHT_M / robot_height_m)


def stride_factors(
    strides: int, speed_mps: float, acceleration_mps2: float, gait_frequency_hz: float
) -> tuple[float, ...]:
    """The fraction of the commanded stride (eq. 3's v_g^ref / f_g) of each step of a walk
    that starts from rest with its gait command's speed limited to `acceleration_mps2`: step
    k (1, 2, ...) takes min(1, a k / (f_g v)) of it, until the fractions add up to `strides`
    full strides, so that the walk covers the distance, turn and sideways offset of `strides`
    commanded strides. The part of a stride that this leaves over is taken among the ramp's
    steps (the fractions sorted: no step then grows by more than a / (f_g v)), so that the
    walk ends at its full speed. Not in the paper, which does not say how its walks start
    (`GAIT_ACCELERATION_MPS2` in `planners.five_mass_gait`); zero `speed_mps` or
    `acceleration_mps2` <= 0 gives full strides from the first step."""
    if strides < 0:
        raise ValueError(f"strides must be non-negative, got {strides}")
    if not gait_frequency_hz > 0:
        raise ValueError(f"gait frequency must be positive, got {gait_frequency_hz} Hz")
    if not (math.isfinite(speed_mps) and math.isfinite(acceleration_mps2)):
        raise ValueError(
            f"speed and acceleration must be finite, got {speed_mps}, {acceleration_mps2}"
        )
    if speed_mps <= 0 or acceleration_mps2 <= 0:
        return (1.0,) * strides
    factors: list[float] = []
    covered = 0.0
    while covered < strides - 1e-9:
        k = len(factors) + 1
        factor = min(1.0, acceleration_mps2 * k / (gait_frequency_hz * speed_mps))
        factor = min(factor, strides - covered)
        factors.append(factor)
        covered += factor
    return tuple(sorted(factors))


def timing_gain(gait_frequency_hz: float, robot_height_m: float) -> float:
    """K_t [Hz/m] of eq. 16: the paper's K_t = 10 f_g [1/m] makes a 0.1 m lateral EOS error
    change the step frequency by f_g; on a robot H tall the same relative error is
    0.1 m x H / 0.9 m (Froude similarity: lengths scale with the robot), so
    K_t = f_g / (0.1 m x H / 0.9 m)."""
    return gait_frequency_hz / (PAPER_TIMING_ERROR_M * robot_height_m / PAPER_ROBOT_HEIGHT_M)


def step_primitive(
    step_length: float, step_width_or_zero: float, omega: float, period: float
) -> tuple[float, float, float, float]:
    """Kajita's walk primitive (Introduction to Humanoid Robotics, Sec. 4.2, the paper's
    [14]) for steps of `period` [s]: the CoM's end-of-step offset from the support foot and
    velocity, sagittal (x_bar = s_x / 2, v_x = x_bar (C + 1) / (T_c S)) and lateral
    (y_bar = s_y / 2, v_y = y_bar (C - 1) / (T_c S)), with C = cosh(T / T_c), S = sinh(T / T_c)
    and T_c = 1 / omega. `step_width_or_zero` is the signed lateral distance to the next
    support foot [m] (+ to the left). Returns (x_bar, v_x, y_bar, v_y)."""
    c, s = math.cosh(omega * period), math.sinh(omega * period)
    x_bar = step_length / 2
    y_bar = step_width_or_zero / 2
    return x_bar, x_bar * omega * (c + 1) / s, y_bar, y_bar * omega * (c - 1) / s


def modified_foot_placement(
    x_initial: float,
    velocity_initial: float,
    x_target: float,
    velocity_target: float,
    omega: float,
    period: float,
    weight_position: float = 10.0,
    weight_velocity: float = 1.0,
) -> float:
    """Kajita's modified foot placement (the paper's [14], Sec. 4.2.3): the support point p
    [m] for the next step that minimises a (x_d - x(T))^2 + b (v_d - x'(T))^2 for the CoM
    starting at (x_initial, velocity_initial) and the LIPM (eq. 1) over `period` [s]; a = 10,
    b = 1 as in Kajita's example. Closed form:
    p = -a (C - 1)/D (x_d - C x_i - T_c S v_i) - b S/(T_c D) (v_d - S/T_c x_i - C v_i),
    D = a (C - 1)^2 + b (S / T_c)^2."""
    c, s = math.cosh(omega * period), math.sinh(omega * period)
    tc = 1.0 / omega
    a, b = weight_position, weight_velocity
    d = a * (c - 1) ** 2 + b * (s / tc) ** 2
    return -a * (c - 1) / d * (x_target - c * x_initial - tc * s * velocity_initial) - b * s / (
        tc * d
    ) * (velocity_target - s / tc * x_initial - c * velocity_initial)


__all__ = [
    "gait_frequency",
    "half_life_s",
    "leaky_alpha",
    "lipm_state",
    "modified_foot_placement",
    "step_primitive",
    "timing_gain",
]
