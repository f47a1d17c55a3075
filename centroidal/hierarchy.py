"""Hierarchical least squares with inequalities (lexicographic priorities), for the whole-body
controller of Sherikov et al. 2014 Sec. VI (three levels; the equalities and inequalities of a
level are satisfied in the least-squares sense, level by level).

Problem (units-free). Variables x in R^n; levels i = 1..L, each a block of rows

    lower_i <= A_i x <= upper_i        (equality: lower == upper; one-sided rows use -inf / +inf)

with violation r_i(x) = A_i x - clip(A_i x, lower_i, upper_i). Lexicographically: minimise
||r_1||; among its minimisers minimise ||r_2||; ...; among the minimisers of every level take the
least-norm x (the least 1/2 x^T H x for a positive definite `regularization` H). Each level's
optimal violation vector is unique, and so is x.

Backends (`SOLVERS`):

* ``"daqp"``, the one the controller uses: DAQP's hierarchical mode (`break_points`). DAQP is a
  maintained dual active-set solver with a hierarchical mode and hot start, like the paper's own
  active-set hierarchical solver (LexLS-like). Per level it softens the rows with slacks s,
  solves min 1/2 x^T H x + 1/(2 rho) ||s||^2, hardens the level at the slackened bounds and
  moves down. What this wrapper adds, and why (measured on the random problems of the tests):

  - One QP first. When every level above the last can be met exactly (the controller's usual
    case: its level 2, eq. 14, is met except after a push), the lexicographic optimum is that of
    one QP: those levels' rows hard, the last level's squared violation the cost
    (`_solve_single_qp`, a slack per inequality row of the last level, the tie-break weighted by
    `SINGLE_QP_TIE_BREAK`, against the last level's rows scaled to unit largest norm), then the
    exact polish below started from DAQP's active set. When DAQP finds those rows
    infeasible, or leaves one violated, the levels above the last are solved first, the same way
    (levels 1 to L-1, L-1's violation the cost, recursively), polished, and their violated rows
    held at the values they take there (a level's optimal violation is unique, so these rows
    define the set of the upper levels' minimisers) for one more QP of all levels
    (`_solve_qp_sequence`, since 2026-11-28: the controller after a push, 2.7 ms against 14.2
    ms for the hierarchical mode at the benchmark's contact switch, the same x after the
    polish). Only when one of those QPs fails, or the upper levels' answer cannot be polished,
    is the hierarchical mode run. Same answer (x within
    1e-7 of the hierarchical mode and 1e-6 of the cascade on the tests' problems, with violated
    last-level inequalities, a last level of norm 1e-4 and H = 1e8 I among them; level norms
    within 7e-7 and x within 2e-5 of the hierarchical mode on 660 problems recorded from `reach`
    and `reach_push`, where a review found the hierarchical mode's polish the one not kept and
    the one QP's answers equal to the cascade's), less work:
    the hierarchical mode softens every row of every level, the QP only the last level's, and
    its hot start then works as the paper's does ("most of the time solver does only one
    iteration", Sec. VII-B: 97 % of periods in a pushed standing episode; the hierarchical mode
    hot-started needed 19-60 iterations a period). `HierarchySolution.qps` tells the path (1:
    `single_qp`; 0: the hierarchical mode).

  - Weighting. DAQP scales every row (of A R^-1, H = R^T R) to unit norm before softening, so it
    minimises the row-normalised violation sum_j (r_j / ||a_j||_H^-1)^2, not ||r||^2: an
    infeasible level with rows of unequal norm lands elsewhere (level norms 0.2-1.6 off). Fix:
    one extra variable z, held at 0 by a hard bound ahead of level 1, with column
    c_j = sqrt(K_i^2 - ||a_j||^2_H^-1), K_i the largest row norm of the row's level i: the rows
    of a level then have one norm, and z = 0 changes neither the feasible set nor the cost.
    (Across levels the scale does not matter.)
  - Pinned rows. A row of a lower level lying in the span of the equality rows above (its value
    is fixed, so is its violation) breaks DAQP 0.11: the levels below come out wrong (1.7 instead
    of 0 on a feasible problem) with exitflag 2, whatever rho or sing_tol. Such rows (to within
    1e-6, relative) are not passed to DAQP; their violation is evaluated at the end.
  - Settings (`daqp_settings`). 1/rho weighs a level's violation against 1/2 x^T H x, so it is
    off by about rho |A x| (1e-6 by default), and with the z column a row of norm ||a_j|| feels
    rho (K_i / ||a_j||)^2: at 1 the answer is garbage. A small rho costs round-off (about
    1e-16 / rho) and needs sing_tol well below rho, else DAQP reports a level failed (exitflag 3).
    Chosen: rho_soft = min(1e-8, 1e-2 / ratio^2), ratio the largest row-norm ratio within a level
    (1e-8 up to ratio 1e3; level norms within 5e-7 of the reference before the polish),
    sing_tol = 1e-7 rho_soft, primal_tol = 1e-9 (the default 1e-6 lets rows be violated by 1e-6
    unnoticed). Ratios above 1e5 are refused (`HierarchyError`); up to 1e3 the answers are exact
    after the polish, at 1e4-1e5 one in six was left unpolished (6e-5 off).
  - Polish. The same trade-off moves x by about rho times the tie-break's multipliers (up to
    4e-5 on small problems whose least-norm step presses on many rows), and x depends on the
    path (a warm start changes it by up to 1.2e-7). So the rows active at DAQP's x (within
    1e-6 (1 + |A x|) of a bound, or violated) define an equality-only hierarchy, solved exactly by
    nested null spaces (rank-revealing QR; the H-weighted least norm last). While that answer
    crosses another row, the first row crossed on the way from DAQP's x joins and it is solved
    again (a primal active-set step, at most `_POLISH_ROUNDS` solves). It replaces DAQP's x
    unless it is lexicographically worse (level norms in turn, then x^T H x, beyond
    1e-7 (1 + norm)); `polished` tells. With the right active set it is the exact optimum and a
    function of the active set only, so a warm start repeats a cold start to round-off. On 240
    random problems (controller size, and 30 variables with free directions, H = I or not)
    every polish was kept; level norms matched the cascade to 3e-8 and x to 2e-8.

  Hot start: `active` holds DAQP sense flags (1 active, +2 at the lower bound) of the rows that
  were active when their own level was solved (the nonzero hierarchical-mode duals). Passing it
  as `warm_start` (same rows) activates them at the start of their level: 3-49 % (median 24 %)
  fewer iterations on 160 controller-size problems, repeated or with the bounds moved by 1e-3,
  never more. After the one QP, `active` holds the QP's own active rows (its nonzero duals) in
  the same flags, and a warm start activates them in either path; after a sequence of QPs, the
  last QP's, with each held row flagged at the bound it violates.

* ``"cascade"``, the reference: one QP per level through qpsolvers, variables (y, v) with
  x = x_p + Z y: min 1/2 ||v||^2 s.t. lower_i <= A_i x - v <= upper_i and every level j above
  held at its optimal violation r_j*, its equality rows exactly (A_j x = A_j x*, folded into
  x_p + Z y by a null-space step), its inequality rows in
  [lower_j + min(r_j*, 0), upper_j + max(r_j*, 0)] widened by 1e-10 (1 + |A x| / 100) for
  round-off; a last QP takes the least-norm (H) x. The level QPs are only positive semidefinite
  (x is free in the cost) and degenerate, so they go to piqp (a proximal interior-point method,
  ~1e-11 here), then proxqp and clarabel as fall-backs; each answer is checked against its
  constraints and a level no solver solves raises `HierarchyError`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse
from qpsolvers import solve_qp
from scipy.linalg import lapack

SOLVERS = ("daqp", "cascade")

DAQP_RHO_SOFT = 1e-8  # DAQP settings: see the module docstring and `daqp_settings`
DAQP_PRIMAL_TOL = 1e-9
_RHO_RATIO2 = 1e-2  # rho_soft times the squared row-norm ratio of a level stays below this
_SING_PER_RHO = 1e-7  # sing_tol = 1e-7 rho_soft
_MAX_ROW_RATIO = 1e5  # larger row-norm ratios within a level are refused by the DAQP backend
_DAQP_INF = 1e30  # DAQP's infinity
_DAQP_EQUALITY = 5  # sense flags: active + immutable
_ACTIVE_TOL = 1e-6  # polish: a row is active within 1e-6 (1 + |A x|) of a bound
_ACCEPT_TOL = 1e-7  # polish: kept unless lexicographically worse by 1e-7 (1 + norm)
_POLISH_ROUNDS = 8  # polish: at most 8 equality-only solves (7 rows joining)
_RANK_TOL = 1e-9  # null-space steps: pivots below 1e-9 times the largest row norm are zero
_PINNED_TOL = 1e-6  # rows within 1e-6 (relative) of the span of equality rows above are pinned
SINGLE_QP_TIE_BREAK = 1e-9  # the one QP's tie-break weight on x^T H x, the last level scaled
_SINGLE_QP_TOL = 1e-8  # an upper row violated by more than 1e-8 (1 + |A x|): level by level
_CASCADE_QP = (
    ("piqp", {"eps_abs": 1e-11, "eps_rel": 0.0}),
    ("proxqp", {"eps_abs": 1e-11, "eps_rel": 0.0, "max_iter": 100000}),
    ("clarabel", {"tol_gap_abs": 1e-12, "tol_gap_rel": 1e-12, "tol_feas": 1e-12}),
)
_CASCADE_SLACK = 1e-10  # fixed inequality rows widened by 1e-10 (1 + |A x| / 100)
_CASCADE_CHECK = 1e-7  # a QP answer off its constraints by more than 1e-7 (1 + |b|) is rejected


class HierarchyError(RuntimeError):
    """A backend found no solution."""


@dataclass(frozen=True)
class Level:
    """One priority level: lower <= a @ x <= upper row by row; a (m, n), lower and upper (m,)."""

    a: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    name: str = ""

    def __post_init__(self) -> None:
        label = f"level {self.name!r}" if self.name else "level"
        a = np.array(self.a, dtype=float)
        lower = np.array(self.lower, dtype=float)
        upper = np.array(self.upper, dtype=float)
        if a.ndim != 2:
            raise ValueError(f"{label}: a must be 2-D (m, n), got shape {a.shape}")
        m = a.shape[0]
        if lower.shape != (m,) or upper.shape != (m,):
            raise ValueError(
                f"{label}: lower and upper must have shape ({m},), got {lower.shape} and "
                f"{upper.shape}"
            )
        if not np.isfinite(a).all():
            raise ValueError(f"{label}: a has NaN or infinite entries")
        if np.isnan(lower).any() or np.isnan(upper).any():
            raise ValueError(f"{label}: lower or upper has NaN entries")
        if (lower > upper).any():
            rows = np.flatnonzero(lower > upper).tolist()
            raise ValueError(f"{label}: lower > upper in rows {rows[:10]}")
        if (lower == np.inf).any() or (upper == -np.inf).any():
            raise ValueError(f"{label}: lower = +inf or upper = -inf")
        for array in (a, lower, upper):
            array.flags.writeable = False
        object.__setattr__(self, "a", a)
        object.__setattr__(self, "lower", lower)
        object.__setattr__(self, "upper", upper)

    def violation(self, x: np.ndarray) -> np.ndarray:
        """r = a x - clip(a x, lower, upper)."""
        ax = self.a @ x
        return ax - np.minimum(np.maximum(ax, self.lower), self.upper)  # np.clip's, faster


@dataclass(frozen=True)
class HierarchySolution:
    x: np.ndarray
    violation: list[np.ndarray]  # r_i per level
    violation_norm: list[float]  # ||r_i|| per level
    iterations: int  # DAQP: active-set iterations (of the path taken); cascade: QPs solved
    active: np.ndarray | None  # DAQP: sense flags for `warm_start`; cascade: None
    exitflag: int  # DAQP's (1 optimal, 2 with rows of some level violated); cascade: 1
    solve_time_s: float
    polished: bool = False  # DAQP: the exact active-set polish was kept
    single_qp: bool = False  # DAQP: solved as one QP (`_solve_single_qp`), qps == 1
    qps: int = 0  # DAQP: QPs solved (`_solve_qp_sequence`), 0: DAQP's hierarchical mode


def solve_hierarchy(
    levels: Sequence[Level],
    n: int,
    *,
    solver: str = "daqp",
    regularization: np.ndarray | None = None,
    warm_start: np.ndarray | None = None,
) -> HierarchySolution:
    """Solve the lexicographic problem of the module docstring, levels[0] first. `warm_start`:
    a previous DAQP solution's `active` (same rows); the cascade ignores it."""
    start = time.perf_counter()
    if solver not in SOLVERS:
        raise ValueError(f"unknown solver {solver!r}; known: {', '.join(SOLVERS)}")
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
        raise ValueError(f"n must be a positive integer, got {n!r}")
    levels = list(levels)
    if not levels or not all(isinstance(level, Level) for level in levels):
        raise ValueError("levels must be a non-empty sequence of Level")
    for i, level in enumerate(levels):
        if level.a.shape[1] != n:
            raise ValueError(f"level {i} ({level.name!r}) has {level.a.shape[1]} columns, not {n}")
    chol = None  # H = chol chol^T; None for H = I
    if regularization is not None:
        hess = np.array(regularization, dtype=float)
        if hess.shape != (n, n) or not np.isfinite(hess).all() or not np.allclose(hess, hess.T):
            raise ValueError(f"regularization must be a finite symmetric ({n}, {n}) matrix")
        try:
            chol = np.linalg.cholesky(hess)
        except np.linalg.LinAlgError:
            raise ValueError("regularization must be positive definite") from None
    if solver == "daqp":
        x, iterations, active, exitflag, polished, qps = _solve_daqp(levels, n, chol, warm_start)
    else:
        x, iterations = _solve_cascade(levels, n, chol)
        active, exitflag, polished, qps = None, 1, False, 0
    violation = [level.violation(x) for level in levels]
    return HierarchySolution(
        x=x,
        violation=violation,
        violation_norm=[float(np.linalg.norm(r)) for r in violation],
        iterations=iterations,
        active=active,
        exitflag=exitflag,
        solve_time_s=time.perf_counter() - start,
        polished=polished,
        single_qp=qps == 1,
        qps=qps,
    )


def _whiten(chol: np.ndarray | None, a: np.ndarray) -> np.ndarray:
    """Rows in w = chol^T x coordinates (where x^T H x = ||w||^2): a chol^-T."""
    return a if chol is None else scipy.linalg.solve_triangular(chol, a.T, lower=True).T


def _unwhiten(chol: np.ndarray | None, w: np.ndarray) -> np.ndarray:
    return w if chol is None else scipy.linalg.solve_triangular(chol.T, w, lower=False)


def daqp_settings(ratio: float = 1.0) -> dict[str, float]:
    """DAQP settings for a hierarchy whose row norms within a level differ by up to `ratio`."""
    rho = min(DAQP_RHO_SOFT, _RHO_RATIO2 / ratio**2)
    return {"rho_soft": rho, "primal_tol": DAQP_PRIMAL_TOL, "sing_tol": _SING_PER_RHO * rho}


def _pinned_rows(levels: list[Level]) -> np.ndarray:
    """Rows (all levels stacked) in the span of the equality rows of the levels above, to
    within `_PINNED_TOL`: their values, hence violations, are the same at every minimiser."""
    pinned, span = [], None  # span: orthonormal columns spanning those equality rows
    for index, level in enumerate(levels):
        a = level.a
        if span is None:  # only zero rows
            pinned.append(~a.any(axis=1))
        else:
            rest = np.linalg.norm(a - (a @ span) @ span.T, axis=1)
            pinned.append(rest <= _PINNED_TOL * np.linalg.norm(a, axis=1))
        equal = a[level.lower == level.upper]
        if equal.shape[0] and index + 1 < len(levels):
            stacked = equal.T if span is None else np.hstack([span, equal.T])
            q, r, _ = scipy.linalg.qr(stacked, mode="economic", pivoting=True)
            pivots = np.abs(np.diag(r))
            span = q[:, : int(np.sum(pivots > _RANK_TOL * pivots[0]))]
    return np.concatenate(pinned)


def _solve_daqp(
    levels: list[Level], n: int, chol: np.ndarray | None, warm_start: np.ndarray | None
) -> tuple[np.ndarray, int, np.ndarray, int, bool, int]:
    import daqp

    a = np.vstack([level.a for level in levels])
    lower = np.concatenate([level.lower for level in levels])
    upper = np.concatenate([level.upper for level in levels])
    m = a.shape[0]
    sense = np.where(lower == upper, _DAQP_EQUALITY, 0).astype(np.intc)
    if warm_start is not None:
        flags = np.asarray(warm_start)
        if flags.shape != (m,) or not np.issubdtype(flags.dtype, np.integer):
            raise ValueError(f"warm_start must be the integer `active` flags of {m} rows")
        sense |= (flags & 3).astype(np.intc)
    by_qps = _solve_qp_sequence(levels, n, chol, lower, upper, sense)
    if by_qps is not None:
        x, iterations, active, qps = by_qps
        # after QPs with rows held, the rows active at x (the upper levels' violated rows among
        # them), as level by level; after the one QP, its own active set
        polished = _polish(levels, n, chol, x, start=active if qps == 1 else None)
        x = x if polished is None else polished
        # DAQP's convention: 2 when a row is left violated
        met = all(np.all(np.abs(level.violation(x)) <= _ACTIVE_TOL) for level in levels)
        return x, iterations, active, 1 if met else 2, polished is not None, qps
    keep = ~_pinned_rows(levels)  # DAQP mishandles them (see the module docstring)
    active = np.zeros(m, dtype=np.intc)
    if not keep.any():
        x, iterations, exitflag = np.zeros(n), 0, 1
    else:
        a, lower, upper, sense = a[keep], lower[keep], upper[keep], sense[keep]
        ends = np.cumsum([level.a.shape[0] for level in levels])
        sizes = np.diff(np.concatenate([[0], np.cumsum(keep)[ends - 1]]))
        # Equal row norms within each level through the column of the hard z = 0 (see the
        # module docstring); across levels the scale does not matter.
        norm2 = np.sum(_whiten(chol, a) ** 2, axis=1)
        groups = [g for g in np.split(norm2, np.cumsum(sizes)[:-1]) if g.size]
        column = np.sqrt(np.concatenate([g.max() - g for g in groups]).clip(min=0.0))
        ratio = np.sqrt(max(g.max() / g.min() for g in groups))
        if ratio > _MAX_ROW_RATIO:
            raise HierarchyError(
                f"DAQP backend: row norms within a level differ by {ratio:.1e} > "
                f"{_MAX_ROW_RATIO:.0e}; rescale rows or use solver='cascade'"
            )
        settings = daqp_settings(ratio)
        h_aug = np.eye(n + 1)
        if chol is not None:
            h_aug[1:, 1:] = chol @ chol.T
        x_aug, _, exitflag, info = daqp.solve(
            h_aug,
            np.zeros(n + 1),
            np.ascontiguousarray(np.hstack([column[:, None], a])),
            np.concatenate([[0.0], np.minimum(upper, _DAQP_INF)]),
            np.concatenate([[0.0], np.maximum(lower, -_DAQP_INF)]),
            np.concatenate([[_DAQP_EQUALITY], sense]).astype(np.intc),
            break_points=(1 + np.cumsum([0, *sizes[sizes > 0]])).astype(np.intc),
            **settings,
        )
        if exitflag not in (1, 2):
            raise HierarchyError(f"DAQP failed with exitflag {exitflag}")
        x, iterations = np.array(x_aug[1:]), int(info["iterations"])
        lam = np.asarray(info["lam"])[1:]
        active[keep] = (lam != 0) + 2 * (lam < 0)
    polished = _polish(levels, n, chol, x)
    if polished is not None:
        x = polished
    return x, iterations, active, int(exitflag), polished is not None, 0


def _solve_qp_sequence(
    levels: list[Level],
    n: int,
    chol: np.ndarray | None,
    lower: np.ndarray,
    upper: np.ndarray,
    sense: np.ndarray,
) -> tuple[np.ndarray, int, np.ndarray, int] | None:
    """The lexicographic optimum as a sequence of QPs: the one QP of `_solve_single_qp` when
    the levels above the last can be met; otherwise the levels above are solved first the same
    way (recursively: levels 1..L-1 with L-1's squared violation the cost, ...), polished to the
    exact optimum of their active set, and each of their rows violated there (beyond
    `_SINGLE_QP_TOL` (1 + |A x|)) is held at the value it has, as an equality, for the one QP of
    all levels. Exact, because a level's optimal violation vector r* is unique: among the
    minimisers of the levels above every violated row takes the same value, and a point of the
    upper levels' met rows' bounds with those values has their least violations; so the held
    rows and the met rows' bounds describe the upper levels' minimisers (the cascade's set), and
    the last QP minimises the last level over them. A row (nearly) in the span of equalities
    above is held too (a review found that freeing it lets a row pinned only to 1e-7 drift; DAQP
    takes the dependent equalities). At the benchmark's contact switch (level 2, eq. 14, not
    met): two QPs, 2.7 ms, against 14.2 ms for DAQP's hierarchical mode (`make benchmark`,
    2026-11-28), which softens every row of every level and needs a tiny rho_soft for the
    controller's objectives, whose row norms span 1e4. None, and the hierarchical mode
    decides, when a QP fails (DAQP's infeasibility or a violated hard row) or when the upper
    levels' answer cannot be polished (its values would be held off the optimum). Returns (x,
    iterations of the QPs that succeeded, active flags of the last QP with each held row
    flagged at the bound it violates, number of QPs)."""
    single = _solve_single_qp(levels, n, chol, lower, upper, sense)
    if single is not None:
        return (*single, 1)
    if len(levels) < 3:
        return None
    m_last = levels[-1].a.shape[0]
    m_upper = lower.shape[0] - m_last
    above = _solve_qp_sequence(
        levels[:-1], n, chol, lower[:m_upper], upper[:m_upper], sense[:m_upper]
    )
    if above is None:
        return None
    x_above, iterations_above, active_above, qps = above
    # the exact optimum of its active set (a DAQP answer's rows are off by up to 1e-6, and its
    # tie-break moves x): the values held below must be the optimum's, so without it, None
    x_above = _polish(levels[:-1], n, chol, x_above, start=active_above if qps == 1 else None)
    if x_above is None:
        return None
    ax = np.concatenate([level.a @ x_above for level in levels[:-1]])
    # violated beyond round-off (a met row's value may lie 1e-12 past its bound)
    tol = _SINGLE_QP_TOL * (1.0 + np.abs(ax))
    below, beyond = ax < lower[:m_upper] - tol, ax > upper[:m_upper] + tol
    hold = below | beyond  # each takes its value there (unique at the optimum), as an equality
    fixed_lower, fixed_upper, fixed_sense = lower.copy(), upper.copy(), sense.copy()
    fixed_lower[:m_upper][hold] = fixed_upper[:m_upper][hold] = ax[hold]
    fixed_sense[:m_upper][hold] = _DAQP_EQUALITY
    held = []
    start = 0
    for level in levels:
        end = start + level.a.shape[0]
        held.append(Level(level.a, fixed_lower[start:end], fixed_upper[start:end], level.name))
        start = end
    last = _solve_single_qp(held, n, chol, fixed_lower, fixed_upper, fixed_sense)
    if last is None:
        return None
    x, iterations, active = last
    # a held row's flag: the side of the bound it violates (not its multiplier's sign, which
    # may point at an infinite bound), for the next period's warm start
    active[:m_upper][below] = 3
    active[:m_upper][beyond] = 1
    return x, iterations_above + iterations, active, qps + 1


def _solve_single_qp(
    levels: list[Level],
    n: int,
    chol: np.ndarray | None,
    lower: np.ndarray,
    upper: np.ndarray,
    sense: np.ndarray,
) -> tuple[np.ndarray, int, np.ndarray] | None:
    """The lexicographic optimum as one QP, when every level above the last can be met exactly
    (the controller's case in most periods; not after a push, when level 2 cannot be met): the
    upper levels' rows hard, the last level's squared violation the cost,
    min 1/2 ||A_L x - t - v||^2 with a slack v per inequality row of the last level
    (lower_L <= A_L x - v <= upper_L), and `SINGLE_QP_TIE_BREAK` times the regularization for
    the tie-break (DAQP wants a positive definite Hessian). The last level's rows are scaled to
    a largest H-whitened norm of one first (the same optimum), so that the tie-break's pull is
    1e-9 relative to the level's own curvature whatever the rows' or H's scale (unscaled, a last
    level of norm 1e-4 or H = 1e8 I let the tie-break move x past an upper row: a wrong active
    set, which the polish cannot release). If DAQP finds the upper rows infeasible, or leaves
    one violated by more than `_SINGLE_QP_TOL` (1 + |A x|), None: the hierarchical mode
    decides. Otherwise (x, iterations, active flags of all rows); the caller polishes x to the
    exact optimum of this active set. Far less work than the hierarchical mode, which softens
    every row of every level and hardens level by level."""
    import daqp

    if len(levels) < 2:
        return None
    last = levels[-1]
    m_last = last.a.shape[0]
    m_upper = lower.shape[0] - m_last
    norm2 = np.sum(_whiten(chol, last.a) ** 2, axis=1) if m_last else np.zeros(0)
    scale = 1.0 / math.sqrt(norm2.max()) if m_last and norm2.max() > 0.0 else 1.0
    equal = last.lower == last.upper
    inequal = np.flatnonzero(~equal)
    k = inequal.size  # slack variables
    size = n + k
    hess = np.zeros((size, size))
    a_eq = scale * last.a[equal]
    hess[:n, :n] = a_eq.T @ a_eq + SINGLE_QP_TIE_BREAK * (
        np.eye(n) if chol is None else chol @ chol.T
    )
    linear = np.zeros(size)
    linear[:n] = -a_eq.T @ (scale * last.upper[equal])
    hess[n:, n:] = np.eye(k)
    rows = np.zeros((m_upper + k, size))
    rows[:m_upper, :n] = np.vstack([level.a for level in levels[:-1]])
    rows[m_upper:, :n] = scale * last.a[inequal]
    rows[m_upper:, n:] = -np.eye(k)
    rows_lower = np.concatenate([lower[:m_upper], scale * last.lower[inequal]])
    rows_upper = np.concatenate([upper[:m_upper], scale * last.upper[inequal]])
    x_all, _, exitflag, info = daqp.solve(
        hess,
        linear,
        rows,
        np.minimum(rows_upper, _DAQP_INF),
        np.maximum(rows_lower, -_DAQP_INF),
        np.concatenate([sense[:m_upper], sense[m_upper:][inequal] & 3]).astype(np.intc),
        primal_tol=DAQP_PRIMAL_TOL,
    )
    if exitflag != 1:
        return None
    x = np.array(x_all[:n])
    for level in levels[:-1]:
        if np.any(np.abs(level.violation(x)) > _SINGLE_QP_TOL * (1.0 + np.abs(level.a @ x))):
            return None
    lam = np.asarray(info["lam"])
    active = np.zeros(lower.shape[0], dtype=np.intc)
    active[:m_upper] = (lam[:m_upper] != 0) + 2 * (lam[:m_upper] < 0)
    active[m_upper + inequal] = (lam[m_upper:] != 0) + 2 * (lam[m_upper:] < 0)
    return x, int(info["iterations"]), active


def _null_step(
    rows: np.ndarray,
    targets: np.ndarray,
    w_p: np.ndarray,
    basis: np.ndarray,
    free: bool = True,
) -> tuple[np.ndarray, np.ndarray | None]:
    """Least squares rows w = targets over w in w_p + span(basis) with the minimum-norm step
    (rank-revealing QR); returns the new w_p and an orthonormal basis of what stays free
    (None when `free` is False: the last level's is not needed). The LAPACK calls are
    scipy.linalg's (`_qr_pivoted`, `_solve_triangular`), without its wrappers' overhead: the
    same bits. (So is `rows @ basis` for an identity basis: skipping that product would turn
    -0.0 into +0.0 and change the pivoted QR's bits, measured.)"""
    if rows.shape[0] == 0 or basis.shape[1] == 0:
        return w_p, basis if free else None
    q, packed, perm = _qr_pivoted((rows @ basis).T)  # (rows basis)^T P = q r
    pivots = np.abs(np.diag(packed))
    rank = int(np.sum(pivots > _RANK_TOL * np.linalg.norm(rows, axis=1).max()))
    if rank == 0:
        return w_p, basis if free else None
    r = np.triu(packed[:rank])  # r's first rows (C-ordered, as scipy's np.triu(packed))
    # rows basis = P r^T q^T: the step is q_1 u, with r_1^T u = P^T (targets - rows w_p).
    rhs = (targets - rows @ w_p)[perm]
    if rank == rows.shape[0]:  # r_1^T square, lower triangular
        u = _solve_triangular(r.T, rhs, lower=True)
    else:  # r_1^T tall with full column rank
        q2, r2 = np.linalg.qr(r.T)
        u = _solve_triangular(r2, q2.T @ rhs, lower=False)
    return w_p + basis @ (q[:, :rank] @ u), basis @ q[:, rank:] if free else None


_LWORK: dict[tuple, int] = {}  # LAPACK's optimal workspace per routine and shape


def _qr_pivoted(a: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """scipy.linalg.qr(a, pivoting=True) by the same LAPACK calls with the same workspace (so
    the same bits: a test holds this): (q (m, m), LAPACK's packed (m, n) whose upper triangle
    is r (np.triu of it is scipy's r), the permutation)."""
    a = np.asarray_chkfinite(a)
    m, n = a.shape
    key = ("geqp3", m, n)
    if key not in _LWORK:
        _LWORK[key] = int(lapack.dgeqp3(a, lwork=-1)[-2][0])
    qr, jpvt, tau, _, info = lapack.dgeqp3(a, lwork=_LWORK[key])
    if info < 0:
        raise ValueError(f"illegal value in {-info}th argument of internal geqp3")
    jpvt -= 1
    if m < n:
        reflectors = qr[:, :m]
    else:
        reflectors = np.empty((m, m))
        reflectors[:, :n] = qr
    key = ("orgqr", m, tau.shape[0])
    if key not in _LWORK:
        _LWORK[key] = int(lapack.dorgqr(reflectors, tau, lwork=-1)[-2][0])
    # (qr's own columns when m < n: not overwritten, the caller keeps r in them)
    q, _, info = lapack.dorgqr(reflectors, tau, lwork=_LWORK[key], overwrite_a=int(m >= n))
    if info < 0:
        raise ValueError(f"illegal value in {-info}th argument of internal orgqr")
    return q, qr, jpvt


def _solve_triangular(a: np.ndarray, b: np.ndarray, lower: bool) -> np.ndarray:
    """scipy.linalg.solve_triangular(a, b, lower=lower) by its own LAPACK call (trtrs)."""
    if a.flags.f_contiguous:
        x, info = lapack.dtrtrs(a, b, lower=lower, trans=0)
    else:  # as scipy: the transposed system, since trtrs expects Fortran order
        x, info = lapack.dtrtrs(a.T, b, lower=not lower, trans=1)
    if info > 0:
        raise np.linalg.LinAlgError(f"singular matrix: resolution failed at diagonal {info - 1}")
    if info < 0:
        raise ValueError(f"illegal value in {-info}-th argument of internal trtrs")
    return x


def _polish(
    levels: list[Level],
    n: int,
    chol: np.ndarray | None,
    x: np.ndarray,
    start: np.ndarray | None = None,
) -> np.ndarray | None:
    """Exact equality-only hierarchy on the rows active at x (or, given `start`, on the rows
    a solver's sense flags call active, and every equality row). While its answer violates
    other rows, the first of them met on the way from x (a primal active-set step) joins, up
    to `_POLISH_ROUNDS` times. None if the answer is lexicographically worse than x."""
    ax0 = [level.a @ x for level in levels]
    upper, lower = [], []  # per level: rows held at their upper / lower bound
    if start is not None:  # the solver's active rows, and every equality row
        flags = np.split(start, np.cumsum([level.a.shape[0] for level in levels])[:-1])
        for level, flag in zip(levels, flags, strict=True):
            equal = level.lower == level.upper
            upper.append(equal | ((flag & 1) != 0) & ((flag & 2) == 0))
            lower.append(~equal & ((flag & 3) == 3))
    else:  # the rows within the tolerance of a bound at x, or beyond it
        for level, ax in zip(levels, ax0, strict=True):
            tol = _ACTIVE_TOL * (1.0 + np.abs(ax))
            near_upper, near_lower = ax >= level.upper - tol, ax <= level.lower + tol
            both = near_upper & near_lower
            upper.append(near_upper & ~(both & (ax - level.lower < level.upper - ax)))
            lower.append(near_lower & ~upper[-1])
    for _ in range(_POLISH_ROUNDS):
        w_p, basis = np.zeros(n), np.eye(n)
        for index, (level, up, low) in enumerate(zip(levels, upper, lower, strict=True)):
            rows = up | low
            targets = np.where(up, level.upper, level.lower)[rows]
            w_p, basis = _null_step(
                _whiten(chol, level.a[rows]), targets, w_p, basis, index + 1 < len(levels)
            )
        candidate = _unwhiten(chol, w_p)
        first = (np.inf, -1, -1, False)  # (step, level, row, at the upper bound)
        for i, (level, ax, up, low) in enumerate(zip(levels, ax0, upper, lower, strict=True)):
            ax1 = level.a @ candidate
            tol = _ACTIVE_TOL * (1.0 + np.abs(ax1))
            for bound, crossed, is_upper in (
                (level.upper, ax1 > level.upper + tol, True),
                (level.lower, ax1 < level.lower - tol, False),
            ):
                crossed &= ~(up | low)
                if crossed.any():
                    step = (bound[crossed] - ax[crossed]) / (ax1[crossed] - ax[crossed])
                    j = int(np.argmin(step))
                    if step[j] < first[0]:
                        first = (step[j], i, int(np.flatnonzero(crossed)[j]), is_upper)
        if first[1] < 0:
            break
        (upper if first[3] else lower)[first[1]][first[2]] = True
    # Keep the candidate unless it is lexicographically worse than x (beyond the tolerance):
    # the level norms in order, then the tie-break sqrt(x^T H x) = ||chol^T x||; not the
    # tie-break after the one QP, whose x bought its smaller norm with a slightly larger last
    # level (by the tie-break's weight, within the tolerance).
    pairs = [(level.violation(x), level.violation(candidate)) for level in levels]
    if start is None:
        pairs.append((x if chol is None else chol.T @ x, w_p))
    for old, new in ((np.linalg.norm(o), np.linalg.norm(c)) for o, c in pairs):
        if new > old + _ACCEPT_TOL * (1.0 + old):
            return None
        if new < old - _ACCEPT_TOL * (1.0 + old):
            break
    return candidate


def _solve_cascade(levels: list[Level], n: int, chol: np.ndarray | None) -> tuple[np.ndarray, int]:
    w_p, basis = np.zeros(n), np.eye(n)  # w = chol^T x; the last QP is least-norm in w
    hard, hard_lower, hard_upper = np.zeros((0, n)), np.zeros(0), np.zeros(0)
    count = 0
    for index, level in enumerate(levels):
        m = level.a.shape[0]
        if m == 0:
            continue
        b = _whiten(chol, level.a)
        k = basis.shape[1]
        cost = np.zeros((k + m, k + m))  # variables (y, v), w = w_p + basis y
        cost[k:, k:] = np.eye(m)
        rows = np.hstack([b @ basis, -np.eye(m)])
        offset = b @ w_p
        equal = level.lower == level.upper
        g, h = _two_sided(
            np.vstack([rows[~equal], np.hstack([hard @ basis, np.zeros((hard.shape[0], m))])]),
            np.concatenate([level.lower[~equal] - offset[~equal], hard_lower - hard @ w_p]),
            np.concatenate([level.upper[~equal] - offset[~equal], hard_upper - hard @ w_p]),
        )
        where = f"level {index} ({level.name!r})"
        z = _cascade_qp(cost, g, h, rows[equal], level.upper[equal] - offset[equal], where)
        count += 1
        w = w_p + basis @ z[:k]
        ax = level.a @ _unwhiten(chol, w)
        r = ax - np.clip(ax, level.lower, level.upper)
        # Hold this level at its optimal violation for the levels below.
        w_p, basis = _null_step(b[equal], b[equal] @ w, w_p, basis)
        slack = (_CASCADE_SLACK * (1.0 + 0.01 * np.abs(ax)))[~equal]
        hard = np.vstack([hard, b[~equal]])
        hard_lower = np.concatenate([hard_lower, (level.lower + np.minimum(r, 0))[~equal] - slack])
        hard_upper = np.concatenate([hard_upper, (level.upper + np.maximum(r, 0))[~equal] + slack])
    k = basis.shape[1]
    if k > 0:  # the least-norm w among the minimisers: min 1/2 ||w_p + basis y||^2
        g, h = _two_sided(hard @ basis, hard_lower - hard @ w_p, hard_upper - hard @ w_p)
        cost = np.eye(k)
        y = _cascade_qp(cost, g, h, np.zeros((0, k)), np.zeros(0), "least-norm step", basis.T @ w_p)
        count += 1
        w_p = w_p + basis @ y
    return _unwhiten(chol, w_p), count


def _two_sided(
    rows: np.ndarray, lower: np.ndarray, upper: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """lower <= rows z <= upper as g z <= h, infinite sides dropped."""
    up, low = np.isfinite(upper), np.isfinite(lower)
    return np.vstack([rows[up], -rows[low]]), np.concatenate([upper[up], -lower[low]])


def _cascade_qp(
    cost: np.ndarray,
    g: np.ndarray,
    h: np.ndarray,
    a_eq: np.ndarray,
    b_eq: np.ndarray,
    where: str,
    linear: np.ndarray | None = None,
) -> np.ndarray:
    linear = np.zeros(cost.shape[0]) if linear is None else linear
    eq = (a_eq, b_eq) if a_eq.shape[0] else (None, None)
    for name, options in _CASCADE_QP:
        try:
            matrices = (cost, g, eq[0])
            if name == "clarabel":  # qpsolvers wants it sparse
                matrices = tuple(
                    None if m is None else scipy.sparse.csc_matrix(m) for m in matrices
                )
            z = solve_qp(
                matrices[0], linear, matrices[1], h, matrices[2], eq[1], solver=name, **options
            )
        except Exception:  # the next solver is tried
            z = None
        if z is None or not np.isfinite(z).all():
            continue
        if np.all(g @ z - h <= _CASCADE_CHECK * (1.0 + np.abs(h))) and np.all(
            np.abs(a_eq @ z - b_eq) <= _CASCADE_CHECK * (1.0 + np.abs(b_eq))
        ):
            return z
    solvers = ", ".join(name for name, _ in _CASCADE_QP)
    raise HierarchyError(f"cascade: the QP of {where} failed with every solver ({solvers})")
