"""Wrench projection and distribution (Murooka et al. 2022, eqs. 9 and 13):

    min_lambda ||G lambda - w||^2 + eps ||lambda||^2   s.t.  0 <= lambda (<= upper)

(with `WrenchProjector(ridge_bounds=(lower, ceiling))`: lower <= lambda <= ceiling, and eps on
lambda - lower; the authors' bounds, off by default).

G (6 x n) stacks the contacts' generator matrices (`centroidal.contacts`), w the wanted contact
wrench (force; moment about the world origin). eps (default 1e-8, relative to the problem
scale it is negligible: 1e-8 N of force per unit ridge force) makes the problem strictly convex
so every backend has the same unique answer; `upper` optionally bounds each ridge force.
An adaptation: eqs. 9 and 13 have no eps term; 1e-8 on unit ridges is the authors' own
(isri-aist/ForceControlCollection `WrenchDistribution`, `regularWeight`, used by their
CentroidalControlCollection and MultiContactController). That code also bounds every ridge
force to [3, 1000] N and takes moments about the CoM; here the paper's lambda >= 0 and world
origin are kept. Without eps the optimum is a set whenever w is inside the cone, and the
answer is the solver's (docs/murooka-walking.md: Lawson-Hanson's vertex answers double the CoM
error on the handrail stairs).

Backends, chosen by name (`BACKEND_NAMES`): scipy `nnls`; `daqp_native` (daqp's own API on
the condensed problem, with G^T G + eps I kept while G stays the same object); daqp, quadprog,
proxqp, osqp, clarabel through qpsolvers (proxqp, osqp and clarabel in the lifted form of
`_qpsolvers_lifted`); `cvxpy` (one Parameter-based problem per ridge count, built once, OSQP
underneath); `casadi` (a `conic` QP per ridge count, built once, qpOASES). The default is
`DEFAULT_BACKEND`, the fastest accurate one on the walk's contact sets in `make benchmark`
(tests/benchmarks/test_projection.py: 12 / 22 us at 16 / 32 ridges against nnls' 19 / 40 and
daqp-through-qpsolvers' 22 / 34); see docs/latency.md.
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np
import qpsolvers
import scipy.optimize
import scipy.sparse

from centroidal import gravity

GRAVITY = np.array([0.0, 0.0, gravity.GRAVITY])  # [m/s^2] (0, 0, g)
DEFAULT_BACKEND = "daqp_native"  # fastest accurate on the walk's contact sets; see docs/latency.md
REGULARIZATION = 1e-8
AUTHORS_RIDGE_BOUNDS = (3.0, 1000.0)
"""[N] every ridge force's bounds in the authors' code (isri-aist/ForceControlCollection,
`WrenchDistribution::Configuration::ridgeForceMinMax`, include/ForceColl/WrenchDistribution.h,
the same in MultiContactController's and BaselineWalkingController's configurations); the paper
has lambda >= 0 only. An option of `WrenchProjector` (`ridge_bounds`), off by default; measured
in docs/murooka-walking.md."""


class Backend(Protocol):
    def __call__(
        self, G: np.ndarray, w: np.ndarray, eps: float, upper: np.ndarray | None
    ) -> np.ndarray: ...


class ProjectionError(RuntimeError):
    """The backend returned no solution."""


def _nnls(G, w, eps, upper):
    if upper is not None:
        raise ValueError("the nnls backend has no upper bounds; choose a QP backend")
    n = G.shape[1]
    a = np.vstack([G, np.sqrt(eps) * np.eye(n)])
    b = np.concatenate([w, np.zeros(n)])
    return scipy.optimize.nnls(a, b, maxiter=50 * n)[0]


# Per-solver settings so that every backend reaches the same answer to ~1e-9 relative.
_QP_SETTINGS = {
    "osqp": {"eps_abs": 1e-9, "eps_rel": 1e-9, "polish": True, "max_iter": 400000},
    "clarabel": {"tol_gap_abs": 1e-10, "tol_gap_rel": 1e-10, "tol_feas": 1e-10},
    "proxqp": {"eps_abs": 1e-11, "eps_rel": 0.0},
}


def _qpsolvers_lifted(solver: str) -> Backend:
    """The same problem in lifted form: variables (lambda, r), min ||r||^2 + eps ||lambda||^2
    s.t. G lambda - r = w. Its KKT system is well conditioned where the condensed Hessian
    G^T G + eps I (rank <= 6 plus eps) is not, which ADMM and interior-point solvers need."""
    settings = _QP_SETTINGS.get(solver, {})

    def solve(G, w, eps, upper):
        n = G.shape[1]
        hessian = scipy.sparse.diags(np.r_[np.full(n, 2 * eps), np.full(6, 2.0)]).tocsc()
        equality = scipy.sparse.hstack(
            [scipy.sparse.csc_matrix(G), -scipy.sparse.identity(6)]
        ).tocsc()
        lower = np.r_[np.zeros(n), np.full(6, -np.inf)]
        upper_all = np.r_[upper if upper is not None else np.full(n, np.inf), np.full(6, np.inf)]
        solution = qpsolvers.solve_qp(
            hessian,
            np.zeros(n + 6),
            A=equality,
            b=w,
            lb=lower,
            ub=upper_all,
            solver=solver,
            **settings,
        )
        return None if solution is None else solution[:n]

    return solve


def _qpsolvers(solver: str) -> Backend:
    settings = _QP_SETTINGS.get(solver, {})

    def solve(G, w, eps, upper):
        n = G.shape[1]
        hessian = G.T @ G + eps * np.eye(n)
        gradient = -G.T @ w
        return qpsolvers.solve_qp(
            hessian, gradient, lb=np.zeros(n), ub=upper, solver=solver, **settings
        )

    return solve


class _DaqpNative:
    """daqp through its own API, without qpsolvers' per-call checks and conversions, on the
    condensed problem (H = G^T G + eps I, f = -G^T w, bounds 0 <= lambda <= upper). H depends
    only on G, which changes at contact switches, so it is kept for the last G seen (compared
    by identity: callers pass the same cached `ContactSet.matrix` while the contacts last;
    arrays passed here are treated as read-only)."""

    def __init__(self) -> None:
        import daqp

        self._daqp_solve = daqp.solve
        self._matrix: np.ndarray | None = None
        self._eps: float | None = None

    def __call__(self, G, w, eps, upper):
        if G is not self._matrix or eps != self._eps:
            n = G.shape[1]
            self._hessian = G.T @ G + eps * np.eye(n)
            self._transpose = np.ascontiguousarray(-G.T)
            self._no_rows = np.zeros((0, n))
            self._unbounded = np.full(n, 1e30)
            self._lower = np.zeros(n)
            self._sense = np.zeros(n, dtype=np.int32)
            self._matrix, self._eps = G, eps
        solution, _, exitflag, _ = self._daqp_solve(
            self._hessian,
            self._transpose @ w,
            self._no_rows,
            self._unbounded if upper is None else upper,
            self._lower,
            self._sense.copy(),
        )
        return solution if exitflag >= 1 else None


class _Cvxpy:
    """One problem per (ridge count, bounded or not), G and w as Parameters: built once."""

    def __init__(self, solver: str = "OSQP") -> None:
        self.solver = solver
        self.problems: dict = {}

    def __call__(self, G, w, eps, upper):
        import cvxpy as cp

        key = (G.shape[1], upper is not None, eps)
        if key not in self.problems:
            n = G.shape[1]
            g, target, x = cp.Parameter((6, n)), cp.Parameter(6), cp.Variable(n)
            residual = cp.Variable(6)  # lifted form, see _qpsolvers_lifted
            bound = cp.Parameter(n) if upper is not None else None
            constraints = [x >= 0, g @ x - residual == target]
            constraints += [x <= bound] if bound is not None else []
            objective = cp.sum_squares(residual) + eps * cp.sum_squares(x)
            self.problems[key] = (
                cp.Problem(cp.Minimize(objective), constraints),
                g,
                target,
                bound,
                x,
            )
        problem, g, target, bound, x = self.problems[key]
        g.value, target.value = G, w
        if bound is not None:
            bound.value = upper
        problem.solve(
            solver=self.solver,
            eps_abs=1e-11,
            eps_rel=1e-11,
            polish=True,
            max_iter=100000,
            warm_start=True,
        )
        return None if x.value is None else np.asarray(x.value)


class _Casadi:
    """One `casadi.conic` QP per ridge count (dense Hessian, no linear constraints)."""

    def __init__(self, plugin: str = "qpoases") -> None:
        self.plugin = plugin
        self.solvers: dict = {}

    def __call__(self, G, w, eps, upper):
        import casadi as ca

        n = G.shape[1]
        if n not in self.solvers:
            options = {"printLevel": "none"} if self.plugin == "qpoases" else {}
            options["error_on_fail"] = False
            sparsity = {"h": ca.Sparsity.dense(n, n), "a": ca.Sparsity(0, n)}
            self.solvers[n] = ca.conic("projection", self.plugin, sparsity, options)
        hessian = G.T @ G + eps * np.eye(n)
        result = self.solvers[n](
            h=hessian,
            g=-G.T @ w,
            lbx=np.zeros(n),
            ubx=upper if upper is not None else np.full(n, np.inf),
        )
        if not self.solvers[n].stats()["success"]:
            return None
        return np.asarray(result["x"]).ravel()


def _backends() -> dict[str, Backend]:
    return {
        "nnls": _nnls,
        "daqp_native": _DaqpNative(),
        "daqp": _qpsolvers("daqp"),
        "quadprog": _qpsolvers("quadprog"),
        "proxqp": _qpsolvers_lifted("proxqp"),
        "osqp": _qpsolvers_lifted("osqp"),
        "clarabel": _qpsolvers_lifted("clarabel"),
        "cvxpy": _Cvxpy(),
        "casadi": _Casadi(),
    }


BACKEND_NAMES = (
    "nnls",
    "daqp_native",
    "daqp",
    "quadprog",
    "proxqp",
    "osqp",
    "clarabel",
    "cvxpy",
    "casadi",
)


class WrenchProjector:
    """Solves the problem of the module docstring with one backend.

    `ridge_bounds` (lower, upper) [N], None by default (the paper's lambda >= 0): every ridge
    force kept in [lower, upper], as the authors' code does (`AUTHORS_RIDGE_BOUNDS`). It is
    solved as lambda = lower + mu with 0 <= mu <= upper - lower and G mu fitted to w - G lower,
    so eps regularises mu instead of lambda: at eps = 1e-8 and lower = 3 N a difference of
    6e-8 N in each ridge's gradient. A caller's `upper` at or below `lower` (a contact to be
    released) is a ValueError then: release a contact by leaving it out of G."""

    def __init__(
        self,
        backend: str = DEFAULT_BACKEND,
        regularization: float = REGULARIZATION,
        ridge_bounds: tuple[float, float] | None = None,
    ):
        if backend not in BACKEND_NAMES:
            raise KeyError(
                f"unknown projection backend {backend!r}; choose one of: {', '.join(BACKEND_NAMES)}"
            )
        if ridge_bounds is not None and not 0.0 <= ridge_bounds[0] < ridge_bounds[1]:
            raise ValueError(f"ridge_bounds must be 0 <= lower < upper [N], got {ridge_bounds}")
        if ridge_bounds is not None and backend == "nnls":
            raise ValueError("the nnls backend has no upper bounds; choose a QP backend")
        self.backend = backend
        self.regularization = regularization
        self.ridge_bounds = ridge_bounds
        self._solve = _backends()[backend]

    def ridge_forces(
        self, G: np.ndarray, w: np.ndarray, upper: np.ndarray | None = None
    ) -> np.ndarray:
        """lambda (n,) >= 0 [N] (within `ridge_bounds` if set, and below `upper` [N] if given);
        ProjectionError if the backend fails."""
        if G.shape[1] == 0:
            return np.zeros(0)
        w = np.asarray(w, dtype=float)
        if self.ridge_bounds is not None:
            return self._bounded_ridge_forces(G, w, upper)
        return np.maximum(self._solved(G, w, upper), 0.0)  # solver tolerance may leave -1e-12

    def _solved(self, G: np.ndarray, w: np.ndarray, upper: np.ndarray | None) -> np.ndarray:
        solution = self._solve(G, w, self.regularization, upper)
        if solution is None or not math.isfinite(solution.sum()):
            raise ProjectionError(f"wrench projection ({self.backend}) found no solution")
        return solution

    def _bounded_ridge_forces(
        self, G: np.ndarray, w: np.ndarray, upper: np.ndarray | None
    ) -> np.ndarray:
        lower, ceiling = self.ridge_bounds
        ceilings = np.full(G.shape[1], ceiling)
        if upper is not None:
            ceilings = np.minimum(ceilings, upper)
        if np.any(ceilings <= lower):
            raise ValueError(f"an upper ridge bound is at or below the lower one, {lower} N")
        solution = self._solved(G, w - lower * G.sum(axis=1), ceilings - lower)
        return lower + np.clip(solution, 0.0, ceilings - lower)

    def project(
        self, G: np.ndarray, w: np.ndarray, upper: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """(G lambda, lambda): the feasible contact wrench closest to `w`, and its ridge forces."""
        forces = self.ridge_forces(G, w, upper)
        return G @ forces, forces


def project_resultant(
    projector: WrenchProjector, contacts, mass: float, com: np.ndarray, resultant: np.ndarray
):
    """Eqs. 9-10: the resultant wrench w-bar (force [N]; moment about the CoM [N m]) as a
    contact wrench w = w-bar + [m g; c x f], projected onto the contacts' cone, and back:
    (w-bar', G lambda)."""
    offset = gravity_offset(mass, com, resultant)
    projected_contact, _ = projector.project(contacts.matrix, resultant + offset)
    return projected_contact - offset, projected_contact


def gravity_offset(mass: float, com: np.ndarray, resultant: np.ndarray) -> np.ndarray:
    """[m g; c x f] with f = f-bar + m g (eqs. 9 and 13): what turns a resultant wrench about
    the CoM `com` [m] into the contact wrench about the world origin (scalar arithmetic: this
    runs twice per control period)."""
    weight = mass * float(GRAVITY[2])
    fx, fy, fz = resultant[:3].tolist()
    fz += weight
    cx, cy, cz = com.tolist()
    return np.array([0.0, 0.0, weight, cy * fz - cz * fy, cz * fx - cx * fz, cx * fy - cy * fx])
