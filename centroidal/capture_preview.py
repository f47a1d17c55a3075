"""Linear building blocks of the long-term balance constraints of Sherikov, Dimitrov & Wieber,
"Whole body motion controller with long-term balance constraints", Humanoids 2014 (paper 004,
Sec. III and IV).

Everything here is per horizontal axis and identical for x and y. The third-order point-mass
model (eq. 10) has the state s = (c, c', c'') [m, m/s, m/s^2], the input the CoP velocity z'
[m/s] held constant over each preview interval, and the CoP z = c - (h / g) c'':

    c''' = omega^2 (c' - z'),   omega = sqrt(g / h)                                  (eq. 10)

This module only builds matrices; a caller (a hierarchical least-squares problem, Sec. VI)
stacks them. The decision variables of the preview (Sec. III-A, Sec. VI) are the current CoM
acceleration c''_0 (coupled to the whole body by eq. 15) and the CoP positions
Z = (z_1, ..., z_N) at the ends of the N intervals; c_0, c'_0 are measured. Which footstep
bounds each CoP sample (eq. 11) and which footstep the swing foot goes to stays with the
caller; `footstep_bounds` only gives the rectangle of eq. 12 for one step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from centroidal.gravity import GRAVITY

SWING_TIME_FLOOR_S = 0.002  # one control period at 500 Hz; see swing_cubic


def _check_positive(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} must be a positive finite number, got {value}")
    return value


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


def omega(height_m: float) -> float:
    """omega = sqrt(g / h) [1/s] of eq. 10 for a constant CoM height h [m]."""
    return math.sqrt(GRAVITY / _check_positive("height_m", height_m))


def discretize(height_m: float, period_s: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact discretisation of eq. 10 over one interval of T = `period_s` [s] with z' constant:
    s_{k+1} = A s_k + B z'_k with s = (c, c', c''), for CoM height h = `height_m` [m].

    Closed form, with w = omega, ch = cosh(w T), sh = sinh(w T):

        A = [[1, sh / w, (ch - 1) / w^2],      B = [T - sh / w,
             [0, ch,     sh / w        ],           1 - ch,
             [0, w sh,   ch            ]]           -w sh]

    (c' obeys v'' = w^2 (v - z'), a shifted hyperbolic oscillator). It keeps the CoP of eq. 10
    exactly linear in time, z_{k+1} = z_k + T z'_k. Returns (A (3, 3), B (3,)).
    """
    w = omega(height_m)
    t = _check_positive("period_s", period_s)
    ch, sh = math.cosh(w * t), math.sinh(w * t)
    a = np.array(
        [
            [1.0, sh / w, (ch - 1.0) / w**2],
            [0.0, ch, sh / w],
            [0.0, w * sh, ch],
        ]
    )
    b = np.array([t - sh / w, 1.0 - ch, -w * sh])
    return a, b


@dataclass(frozen=True)
class Preview:
    """The preview of eq. 10 over `n` intervals of `period_s` [s], linear in the decision
    variables c''_0 [m/s^2] and Z = (z_1, ..., z_N) [m] (Sec. III-A), given (c_0, c'_0).

    For k = 1..N (array index k - 1):

        s_k = s_known[k-1] @ (c_0, c'_0) + s_acc[k-1] * c''_0 + s_cop[k-1] @ Z

    with s_k = (c_k, c'_k, c''_k) the state at the end of interval k; shapes (N, 3, 2), (N, 3),
    (N, 3, N). The CoP velocities Z' = (z'_0, ..., z'_{N-1}) [m/s] of objective eq. 22 are

        Z' = d_known @ (c_0, c'_0) + d_acc * c''_0 + d_cop @ Z

    with z'_k = (z_{k+1} - z_k) / T_k and z_0 = c_0 - c''_0 / omega^2 the CoP now (eq. 10);
    shapes (N, 2), (N,), (N, N). The first interval lasts `first_s` [s] (T_0; `period_s`
    unless the preview is aligned with a step schedule), the others `period_s` (T). `a`, `b`
    are the one-interval matrices of `discretize` for `period_s`. All arrays are read-only.
    """

    height_m: float
    period_s: float
    n: int
    omega: float
    a: np.ndarray
    b: np.ndarray
    s_known: np.ndarray
    s_acc: np.ndarray
    s_cop: np.ndarray
    d_known: np.ndarray
    d_acc: np.ndarray
    d_cop: np.ndarray
    first_s: float


def preview(height_m: float, period_s: float, n: int, first_s: float | None = None) -> Preview:
    """Build the `Preview` of eq. 10 over `n` >= 1 intervals at CoM height `height_m` [m]:
    the first of `first_s` [s] (default `period_s`), the others of `period_s` [s] (the paper:
    N = 16 intervals of 0.1 s, two steps of 0.8 s, Sec. VII; the first shortened to the step
    schedule's grid as the authors' humoto does, `StepSchedule.first_interval`)."""
    if isinstance(n, bool) or int(n) != n or n < 1:
        raise ValueError(f"n must be a positive integer, got {n}")
    n = int(n)
    a, b = discretize(height_m, period_s)
    w = omega(height_m)
    t = float(period_s)
    first = t if first_s is None else _check_positive("first_s", first_s)
    lengths = [first] + [t] * (n - 1)
    steps = [discretize(height_m, first) if first != t else (a, b)] + [(a, b)] * (n - 1)

    # Z' in terms of (c_0, c'_0), c''_0 and Z.
    d_known = np.zeros((n, 2))
    d_acc = np.zeros(n)
    d_cop = np.zeros((n, n))
    d_known[0, 0] = -1.0 / first  # -z_0 / T_0 with z_0 = c_0 - c''_0 / w^2
    d_acc[0] = 1.0 / (first * w**2)
    for k in range(n):
        d_cop[k, k] = 1.0 / lengths[k]
        if k > 0:
            d_cop[k, k - 1] = -1.0 / lengths[k]

    # s_0 = (c_0, c'_0, c''_0), then s_{k+1} = A s_k + B z'_k.
    known = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
    acc = np.array([0.0, 0.0, 1.0])
    cop = np.zeros((3, n))
    s_known = np.empty((n, 3, 2))
    s_acc = np.empty((n, 3))
    s_cop = np.empty((n, 3, n))
    for k in range(n):
        a_k, b_k = steps[k]
        known = a_k @ known + np.outer(b_k, d_known[k])
        acc = a_k @ acc + b_k * d_acc[k]
        cop = a_k @ cop + np.outer(b_k, d_cop[k])
        s_known[k], s_acc[k], s_cop[k] = known, acc, cop

    return Preview(
        height_m=float(height_m),
        period_s=t,
        n=n,
        omega=w,
        a=_read_only(a),
        b=_read_only(b),
        s_known=_read_only(s_known),
        s_acc=_read_only(s_acc),
        s_cop=_read_only(s_cop),
        d_known=_read_only(d_known),
        d_acc=_read_only(d_acc),
        d_cop=_read_only(d_cop),
        first_s=first,
    )


def _terminal_row(p: Preview, weights: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
    """weights @ s_N as (row_known (2,), row_acc, row_cop (N,))."""
    return weights @ p.s_known[-1], float(weights @ p.s_acc[-1]), weights @ p.s_cop[-1]


def capture_velocity_row(p: Preview) -> tuple[np.ndarray, float, np.ndarray]:
    """The terminal capturability constraint, eq. 14, xi'_N = c'_N + c''_N / omega = 0, as one
    row per axis: xi'_N [m/s] = row_known @ (c_0, c'_0) + row_acc * c''_0 + row_cop @ Z.

    Returns (row_known (2,), row_acc, row_cop (N,)); the caller imposes the row = 0 (the
    second level of the hierarchy, Sec. VI). When it holds, xi_N = z_N (Sec. III-D) and with
    z' = 0 afterwards the CoM comes to rest over z_N.
    """
    return _terminal_row(p, np.array([0.0, 1.0, 1.0 / p.omega]))


def capture_point_row(p: Preview) -> tuple[np.ndarray, float, np.ndarray]:
    """The capture point at the end of the preview, eq. 13, xi_N = c_N + c'_N / omega [m], as
    (row_known (2,), row_acc, row_cop (N,)) in the variables of `Preview`."""
    return _terminal_row(p, np.array([1.0, 1.0 / p.omega, 0.0]))


@dataclass(frozen=True)
class SwingRows:
    """Coefficients of the swing-foot acceleration now and of its constant jerk, per axis
    (eq. 16 and eq. 20), for the cubic of `swing_cubic`:

        s''(0) = acc_p * P + acc_s0 * s_0 + acc_ds0 * s'_0      [m/s^2]
        s'''   = jerk_p * P + jerk_s0 * s_0 + jerk_ds0 * s'_0   [m/s^3]

    with P the footstep position [m], (s_0 [m], s'_0 [m/s]) the current swing-foot state.
    `remaining_s` is the touchdown time actually used (after clamping to the floor).
    """

    remaining_s: float
    acc_p: float
    acc_s0: float
    acc_ds0: float
    jerk_p: float
    jerk_s0: float
    jerk_ds0: float


def swing_cubic(remaining_s: float, floor_s: float = SWING_TIME_FLOOR_S) -> SwingRows:
    """Rows of the swing-foot cubic of Sec. IV-B (after the paper's [6]): per axis
    s(t) = a0 + a1 t + a2 t^2 + a3 t^3 with s(0) = s_0, s'(0) = s'_0, s(t_f) = P, s'(t_f) = 0,
    t_f = `remaining_s` [s] the time left to touchdown. Solving the four conditions:

        a2 = 3 (P - s_0) / t_f^2 - 2 s'_0 / t_f,   a3 = -2 (P - s_0) / t_f^3 + s'_0 / t_f^2
        s''(0) = 2 a2 = 6 (P - s_0) / t_f^2 - 4 s'_0 / t_f                          (eq. 16)
        s'''   = 6 a3 = -12 (P - s_0) / t_f^3 + 6 s'_0 / t_f^2                      (eq. 20)

    Near touchdown the rows grow like 1 / t_f^2 and 1 / t_f^3, so t_f is clamped to
    `floor_s` (default 0.002 s, one control period at 500 Hz): any t_f below the floor --
    including zero or a negative value from a late touchdown -- is replaced by the floor.
    Non-finite t_f or a non-positive floor raise ValueError.
    """
    floor_s = _check_positive("floor_s", floor_s)
    remaining_s = float(remaining_s)
    if not math.isfinite(remaining_s):
        raise ValueError(f"remaining_s must be finite, got {remaining_s}")
    tf = max(remaining_s, floor_s)
    return SwingRows(
        remaining_s=tf,
        acc_p=6.0 / tf**2,
        acc_s0=-6.0 / tf**2,
        acc_ds0=-4.0 / tf,
        jerk_p=-12.0 / tf**3,
        jerk_s0=12.0 / tf**3,
        jerk_ds0=6.0 / tf**2,
    )


def footstep_bounds(
    side: str, step_length_max: float, step_width_min: float, step_width_max: float
) -> tuple[np.ndarray, np.ndarray]:
    """Simple bounds of eq. 12 on the (x, y) displacement [m] of a footstep from the previous
    foothold, in that foothold's frame (rectangular feasible area, Sec. III-C).

    `side` is the foot that steps: "left" steps to +y with y in [w_min, w_max], "right" to -y
    with y in [-w_max, -w_min]; x in [-L, L] for both, L = `step_length_max`. The numbers
    (e.g. those of Herdt et al., the paper's [3]) are the caller's. Returns (lower (2,),
    upper (2,)); raises ValueError for an unknown side, a negative or non-finite L, or
    w_min > w_max.
    """
    values = (step_length_max, step_width_min, step_width_max)
    if not all(math.isfinite(float(v)) for v in values):
        raise ValueError(f"footstep bounds must be finite, got {values}")
    length, w_min, w_max = (float(v) for v in values)
    if length < 0.0:
        raise ValueError(f"step_length_max must be >= 0, got {length}")
    if w_min > w_max:
        raise ValueError(f"step_width_min {w_min} exceeds step_width_max {w_max}")
    if side == "left":
        return np.array([-length, w_min]), np.array([length, w_max])
    if side == "right":
        return np.array([-length, -w_max]), np.array([length, -w_min])
    raise ValueError(f"side must be 'left' or 'right', got {side!r}")
