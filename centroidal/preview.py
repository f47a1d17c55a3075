"""Preview control of a triple integrator with one output weighting (Murooka et al. 2022,
eqs. 3-5 and 7; Katayama et al. 1985; Kajita et al. 2003).

Per axis the state is x = [p, p', p''] (position, velocity, acceleration), the input the jerk
u = p''', and the output y = C x: for the linear part (eq. 3b) y = [c, m c''] (CoM and resultant
force), for the angular part (eq. 7b) y = [alpha, I alpha''] (base angle and resultant moment).
Discretised with period dtau (zero-order hold on the jerk), the cost

    J = sum_i ||y[i] - y_ref[i]||^2_Q + ||u[i]||^2_R                     (eq. 4)

is minimised by

    u[k] = -K_fb x[k] + sum_{i=1..Nh} K_ff[i] y_ref[k+i]                (eq. 5)

with P the solution of the discrete algebraic Riccati equation (scipy), K_fb =
(R + B'PB)^-1 B'PA and K_ff[i] = (R + B'PB)^-1 B' (A_c')^(i-1) C'Q, A_c = A - B K_fb.

Steady-state offset and its correction: eq. 5 truncates an infinite sum. With Table I's weights
and Nh = 400 (2 s at 5 ms) the truncated gains settle 1.02 % beyond a step reference (the
neglected tail of the gains is negative; tests/centroidal/test_preview.py measures it).
`tail_correction=True` (the default) adds the whole remaining sum sum_{i>Nh} K_ff[i] to
K_ff[Nh], which is the exact optimum when the reference is held at its last previewed value
beyond the horizon -- the natural assumption for a piecewise-constant reference -- and removes
the offset; the gains K_ff[1..Nh-1] and K_fb are untouched.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg
from numba import njit


def discrete_triple_integrator(dt: float) -> tuple[np.ndarray, np.ndarray]:
    """A (3x3), B (3,) of x = [p, p', p''] with constant jerk over dt [s]."""
    a = np.array([[1.0, dt, dt * dt / 2.0], [0.0, 1.0, dt], [0.0, 0.0, 1.0]])
    b = np.array([dt**3 / 6.0, dt * dt / 2.0, dt])
    return a, b


@dataclass(frozen=True)
class PreviewGains:
    """K_fb (3,), K_ff (Nh, n_outputs), and the model they came from."""

    feedback: np.ndarray
    feedforward: np.ndarray
    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    riccati: np.ndarray


@functools.lru_cache(maxsize=64)
def preview_gains(
    output_scale: float,
    q_position: float,
    q_second: float,
    r_jerk: float,
    dtau: float,
    horizon: int,
    tail_correction: bool = True,
) -> PreviewGains:
    """Gains of eq. 5 for output y = [p, output_scale * p''] (output_scale = m for the linear
    part, I_* for the angular part), weights Q = diag(q_position, q_second), R = r_jerk,
    sample period dtau [s] and Nh = horizon samples. Cached per argument set (the gains depend
    only on mass / inertia, Sec. III-A3)."""
    output = ((1.0, 0.0, 0.0), (0.0, 0.0, output_scale))
    return output_preview_gains(
        output, (q_position, q_second), r_jerk, dtau, horizon, tail_correction
    )


@functools.lru_cache(maxsize=64)
def output_preview_gains(
    output: tuple[tuple[float, float, float], ...],
    q_diagonal: tuple[float, ...],
    r_jerk: float,
    dtau: float,
    horizon: int,
    tail_correction: bool = True,
) -> PreviewGains:
    """Preview gains for any output y = C x of the triple integrator (C given row by row, e.g.
    Kajita's ZMP ((1, 0, -h/g),)), weights Q = diag(q_diagonal), R = r_jerk."""
    a, b = discrete_triple_integrator(dtau)
    c = np.array(output, dtype=float)
    q = np.diag(q_diagonal)
    b_col = b[:, None]
    riccati = scipy.linalg.solve_discrete_are(a, b_col, c.T @ q @ c, np.array([[r_jerk]]))
    gain_den = float(r_jerk + b @ riccati @ b)
    feedback = (b @ riccati @ a) / gain_den
    closed = a - np.outer(b, feedback)
    feedforward = np.zeros((horizon, len(c)))
    power = c.T @ q  # (A_c')^(i-1) C'Q, i = 1
    for i in range(horizon):
        feedforward[i] = (b @ power) / gain_den
        power = closed.T @ power
    if tail_correction:
        # sum_{i > Nh} (A_c')^(i-1) C'Q = (A_c')^Nh (I - A_c')^-1 C'Q; `power` is (A_c')^Nh C'Q.
        tail = np.linalg.solve(np.eye(3) - closed.T, power)
        feedforward[-1] += (b @ tail) / gain_den
    return PreviewGains(feedback, feedforward, a, b, c, riccati)


@njit(cache=True)
def _preview_period(
    state: np.ndarray,
    feedback: np.ndarray,
    position_feedforward: np.ndarray,
    positions: np.ndarray,
    a_dt: np.ndarray,
    b_dt: np.ndarray,
) -> np.ndarray:
    """`TripleIntegratorPreview.jerk_from_positions` and the state one period later with that
    jerk (`advance`), without changing `state` (compiled: one call)."""
    n_axes, horizon, k = state.shape[0], positions.shape[0], positions.shape[1]
    planned = np.empty((n_axes, 3))
    for a in range(n_axes):
        jerk = -(state[a, 0] * feedback[a, 0] + state[a, 1] * feedback[a, 1])
        jerk -= state[a, 2] * feedback[a, 2]
        if a < k:
            total = 0.0
            for h in range(horizon):
                total += position_feedforward[a, h] * positions[h, a]
            jerk += total
        for i in range(3):
            planned[a, i] = (
                state[a, 0] * a_dt[i, 0] + state[a, 1] * a_dt[i, 1] + state[a, 2] * a_dt[i, 2]
            ) + jerk * b_dt[i]
    return planned


class TripleIntegratorPreview:
    """Preview control of several independent axes: states (axes, 3) [p, p', p''].

    `gains` is one `PreviewGains` shared by `n_axes` axes, or a sequence with one per axis
    (e.g. Murooka's six: three linear axes sharing the mass, three angular axes with their own
    inertia). The gains are stacked once, so one period is a few array operations."""

    def __init__(
        self, gains: PreviewGains | Sequence[PreviewGains], control_dt: float, n_axes: int = 1
    ) -> None:
        per_axis = list(gains) if isinstance(gains, Sequence) else [gains] * n_axes
        self.feedback = np.array([g.feedback for g in per_axis])  # (axes, 3)
        self.feedforward = np.array([g.feedforward for g in per_axis])  # (axes, Nh, outputs)
        self._position_feedforward = np.ascontiguousarray(self.feedforward[:, :, 0])
        self.a_dt, self.b_dt = discrete_triple_integrator(control_dt)
        self.state = np.zeros((len(per_axis), 3))

    def jerk(self, reference_window: np.ndarray) -> np.ndarray:
        """Optimal jerk per axis (eq. 5) for references (Nh, axes, n_outputs) at samples
        k+1..k+Nh."""
        return -(self.state * self.feedback).sum(axis=1) + np.einsum(
            "aho,hao->a", self.feedforward, reference_window
        )

    def jerk_from_positions(self, positions: np.ndarray) -> np.ndarray:
        """Eq. 5 when only the first output (the position) has a non-zero reference, on the
        first k axes: `positions` (Nh, k) at samples k+1..k+Nh; the other axes' references
        are zero (Murooka Sec. V-B: reference force, moment and base angle are zero)."""
        jerk = -(self.state * self.feedback).sum(axis=1)
        k = positions.shape[1]
        jerk[:k] += np.einsum("ah,ha->a", self._position_feedforward[:k], positions)
        return jerk

    def planned_from_positions(self, positions: np.ndarray) -> np.ndarray:
        """The state (axes, 3) one period after the current one under the jerk of
        `jerk_from_positions(positions)` (eq. 5), the current state unchanged."""
        return _preview_period(
            self.state,
            self.feedback,
            self._position_feedforward,
            positions,
            self.a_dt,
            self.b_dt,
        )

    def advance(self, jerk: np.ndarray) -> None:
        """Integrate every axis over one control period with constant jerk."""
        self.state = self.state @ self.a_dt.T + np.outer(jerk, self.b_dt)
