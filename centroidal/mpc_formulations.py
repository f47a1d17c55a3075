"""The linear MPC of `centroidal.mpc` solved several ways, selectable by name (`FORMULATIONS`).

Over the ridge forces lambda (the issue's decision variables): qpsolvers (dense
`dense:<solver>`, sparse `sparse:<solver>`), cvxpy with Parameters (`cvxpy:<SOLVER>`), CasADi's
`conic` (`casadi:<plugin>`) and PIQP's own API on the partially condensed form (`native:piqp`).
Over the wrenches U_k with each sample's cone by its faces (`face:<solver>`, Caron et al.
2015; `face:quadprog` is the default, the fastest at 20 samples): see `FaceForm`.

Every formulation's `solve` returns the inputs U (N, 6) (contact wrench of each sample, moment
about c-hat_k) or raises `MpcSolverError`; the ridge formulations also give the stacked ridge
forces lambda (`ridges`). Problems are built once where the tool allows (cvxpy, CasADi,
native:piqp: fixed structure, every sample padded to `max_ridges`; face:quadprog: the constant
Hessian factorised once) and warm-started where it can (osqp through qpsolvers and cvxpy, from
the previous solution; PIQP is an interior-point method and starts afresh; quadprog's dual
active set starts from the unconstrained optimum, which is close: 0-4 faces are active).
"""

from __future__ import annotations

import functools
from typing import Protocol

import numpy as np
import qpsolvers
import quadprog
import scipy.linalg
import scipy.sparse

from centroidal.cone_faces import cone_faces
from centroidal.kernels import face_rows_hold, unit_face_rows
from centroidal.mpc import (
    MpcModel,
    MpcProblem,
    MpcSolverError,
    condensed,
    input_gradient,
    sparse_form,
    split,
)

DENSE_SOLVERS = ("daqp", "proxqp", "quadprog")
SPARSE_SOLVERS = ("osqp", "clarabel", "proxqp")
CVXPY_SOLVERS = ("OSQP", "CLARABEL")
CASADI_PLUGINS = ("osqp", "qpoases")
NATIVE_SOLVERS = ("piqp",)
FACE_SOLVERS = ("quadprog", "daqp")
FORMULATIONS = (
    *(f"dense:{s}" for s in DENSE_SOLVERS),
    *(f"sparse:{s}" for s in SPARSE_SOLVERS),
    *(f"cvxpy:{s}" for s in CVXPY_SOLVERS),
    *(f"casadi:{p}" for p in CASADI_PLUGINS),
    *(f"native:{s}" for s in NATIVE_SOLVERS),
    *(f"face:{s}" for s in FACE_SOLVERS),
)
DEFAULT_FORMULATION = "face:quadprog"
# [N or N m] how far face:quadprog may violate a unit-norm cone face (`FaceForm._slack`)
ANTI_CYCLING_SLACK = 1e-9

# PIQP at 1e-6 / 1e-7 rather than 1e-8 / 1e-9: 1-2 fewer interior-point iterations of 6-14
# (walk update 5.3 -> 4.7 ms median, `make benchmark`, 2026-11-23) for a planned wrench that
# moves by at most 1.2 mN of ~570 N; the plan stays in the cone (lambda >= 0 is enforced).
_TOLERANCES = {
    "osqp": {"eps_abs": 1e-7, "eps_rel": 1e-7, "polish": True, "max_iter": 20000},
    "clarabel": {"tol_gap_abs": 1e-9, "tol_gap_rel": 1e-9, "tol_feas": 1e-9},
    "proxqp": {"eps_abs": 1e-9, "eps_rel": 0.0},
    "piqp": {"eps_abs": 1e-6, "eps_rel": 1e-7, "preconditioner_reuse_on_update": True},
}


class Formulation(Protocol):
    name: str

    def solve(self, problem: MpcProblem) -> np.ndarray:
        """The inputs U (N, 6): each sample's contact wrench [N, N m], moment about c-hat_k."""
        ...


class RidgeForm:
    """A formulation over the ridge forces: `ridges` gives lambda, `solve` U_k = W_k lambda_k."""

    def ridges(self, problem: MpcProblem) -> np.ndarray:
        raise NotImplementedError

    def solve(self, problem: MpcProblem) -> np.ndarray:
        lambdas = split(self.ridges(problem), problem.sizes)
        return np.array([w @ lam for w, lam in zip(problem.maps, lambdas, strict=True)])


class DenseQpsolvers(RidgeForm):
    """Condensed QP in lambda through qpsolvers (dense matrices)."""

    def __init__(self, model: MpcModel, solver: str, max_ridges: int) -> None:
        self.model, self.solver, self.name = model, solver, f"dense:{solver}"

    def ridges(self, problem: MpcProblem) -> np.ndarray:
        hessian, gradient = condensed(self.model, problem)
        n = len(gradient)
        upper = None if problem.upper is None else np.concatenate(problem.upper)
        with np.errstate(all="ignore"):
            solution = qpsolvers.solve_qp(
                hessian,
                gradient,
                lb=np.zeros(n),
                ub=upper,
                solver=self.solver,
                **_TOLERANCES.get(self.solver, {}),
            )
        if solution is None or not np.all(np.isfinite(solution)):
            raise MpcSolverError(f"{self.name} found no solution")
        return np.maximum(solution, 0.0)


class SparseQpsolvers(RidgeForm):
    """Sparse QP in (lambda, u, x) through qpsolvers; osqp warm-started from the last z."""

    def __init__(self, model: MpcModel, solver: str, max_ridges: int) -> None:
        self.model, self.solver, self.name = model, solver, f"sparse:{solver}"
        self._last: np.ndarray | None = None

    def ridges(self, problem: MpcProblem) -> np.ndarray:
        p, q, a, b, lower, upper, offsets = sparse_form(self.model, problem)
        initial = self._last if self._last is not None and len(self._last) == len(q) else None
        with np.errstate(all="ignore"):
            solution = qpsolvers.solve_qp(
                p,
                q,
                A=a,
                b=b,
                lb=lower,
                ub=upper,
                solver=self.solver,
                initvals=initial if self.solver == "osqp" else None,
                **_TOLERANCES.get(self.solver, {}),
            )
        if solution is None or not np.all(np.isfinite(solution)):
            self._last = None
            raise MpcSolverError(f"{self.name} found no solution")
        self._last = solution
        return np.maximum(solution[: offsets[-1]], 0.0)


class CvxpyFormulation(RidgeForm):
    """The padded sparse form as one cvxpy problem with Parameters (DPP), built once."""

    def __init__(self, model: MpcModel, solver: str, max_ridges: int) -> None:
        import cvxpy as cp

        self.model, self.solver, self.name = model, solver, f"cvxpy:{solver}"
        self.max_ridges = n_r = max_ridges
        n = model.horizon
        self.lam = cp.Variable((n, n_r))
        self.u = cp.Variable((n, 6))
        self.x = cp.Variable((n, 12))
        self.maps = [cp.Parameter((6, n_r)) for _ in range(n)]
        self.upper = cp.Parameter((n, n_r), nonneg=True)
        self.x0 = cp.Parameter(12)
        self.y_ref = cp.Parameter((n, 6))
        m = model
        constraints = [self.lam >= 0, self.lam <= self.upper]
        for k in range(n):
            constraints.append(self.u[k] == self.maps[k] @ self.lam[k])
            previous = self.x0 if k == 0 else self.x[k - 1]
            constraints.append(self.x[k] == m.a @ previous + m.b @ self.u[k] + m.e)
        outputs = self.x @ m.c.T  # (n, 6)
        cost = cp.sum(cp.multiply(np.tile(m.q_output, (n, 1)), cp.square(outputs - self.y_ref)))
        cost += cp.sum(
            cp.multiply(np.tile(m.r_input, (n, 1)), cp.square(self.u - m.u_reference[None, :]))
        )
        cost += m.weights.ridge * cp.sum_squares(self.lam)
        self.problem = cp.Problem(cp.Minimize(cost), constraints)

    def ridges(self, problem: MpcProblem) -> np.ndarray:
        n_r = self.max_ridges
        upper = np.zeros((self.model.horizon, n_r))
        for k, w in enumerate(problem.maps):
            padded = np.zeros((6, n_r))
            padded[:, : w.shape[1]] = w
            self.maps[k].value = padded
            upper[k, : w.shape[1]] = 1e6 if problem.upper is None else problem.upper[k]
        self.upper.value = upper
        self.x0.value = problem.x0
        self.y_ref.value = problem.y_reference
        options = (
            {"eps_abs": 1e-6, "eps_rel": 1e-6, "polish": True, "max_iter": 200000}
            if self.solver == "OSQP"
            else {}
        )
        try:
            self.problem.solve(solver=self.solver, warm_start=True, **options)
        except Exception as exc:  # cvxpy raises SolverError on failure
            raise MpcSolverError(f"{self.name}: {exc}") from exc
        if self.lam.value is None or self.problem.status not in ("optimal", "optimal_inaccurate"):
            raise MpcSolverError(f"{self.name} found no solution ({self.problem.status})")
        return np.maximum(
            np.concatenate([self.lam.value[k, :size] for k, size in enumerate(problem.sizes)]),
            0.0,
        )


class CasadiFormulation(RidgeForm):
    """The padded sparse form as one `casadi.conic` (sparsity fixed at construction)."""

    def __init__(self, model: MpcModel, plugin: str, max_ridges: int) -> None:
        import casadi as ca

        self.model, self.plugin, self.name = model, plugin, f"casadi:{plugin}"
        self.max_ridges = max_ridges
        n = model.horizon
        dummy = MpcProblem([np.ones((6, max_ridges))] * n, np.zeros(12), np.zeros((n, 6)), None)
        p, _, a, _, _, _, _ = sparse_form(model, dummy, pad_to=max_ridges)
        self._p = ca.DM(_casadi_sparsity(ca, p), p.tocsc().data)
        self._a_pattern = a.tocsc()
        self._a_pattern.sort_indices()
        options: dict = {"error_on_fail": False}
        if plugin == "qpoases":
            options.update(printLevel="none", sparse=True)
        elif plugin == "osqp":
            options["osqp"] = {
                "verbose": False,
                "eps_abs": 1e-7,
                "eps_rel": 1e-7,
                "polish": True,
                "max_iter": 20000,
            }
            options["warm_start_primal"] = True
        self.solver = ca.conic(
            "mpc",
            plugin,
            {"h": _casadi_sparsity(ca, p), "a": _casadi_sparsity(ca, self._a_pattern)},
            options,
        )
        self._ca = ca
        self._last = None

    def ridges(self, problem: MpcProblem) -> np.ndarray:
        ca = self._ca
        _, q, a, b, lower, upper, offsets = sparse_form(self.model, problem, pad_to=self.max_ridges)
        # same pattern as at construction: copy values into it
        values = _values_on_pattern(a, self._a_pattern)
        arguments = {
            "h": self._p,
            "g": q,
            "a": ca.DM(_casadi_sparsity(ca, self._a_pattern), values),
            "lba": b,
            "uba": b,
            "lbx": lower,
            "ubx": np.minimum(upper, 1e20),
        }
        if self._last is not None:
            arguments["x0"] = self._last
        result = self.solver(**arguments)
        if not self.solver.stats()["success"]:
            self._last = None
            raise MpcSolverError(f"{self.name} found no solution")
        z = np.asarray(result["x"]).ravel()
        self._last = z
        return np.maximum(np.concatenate(split(z, problem.sizes, offsets)), 0.0)


class NativePiqp(RidgeForm):
    """The partially condensed QP through PIQP's own sparse API, set up once and updated each
    period (new gradient, new W_k, same sparsity).

    Variables z = [lambda (N x max_ridges, padded), U (6N)]; equality U_k - W_k lambda_k = 0;
    cost eps ||lambda||^2 + U^T M U + 2 l^T U with the constant M = Phi^T Q Phi + R and l as in
    `condensed` (the states are eliminated, the wrenches are not, so the KKT system has one
    dense 6N x 6N block and a diagonal instead of a dense (sum n_k)^2 Hessian). Padded ridges
    have zero columns in W: the regularisation alone puts them at zero.
    """

    def __init__(self, model: MpcModel, solver: str, max_ridges: int) -> None:
        import piqp

        self.model, self.max_ridges, self.name = model, max_ridges, f"native:{solver}"
        n, r = model.horizon, max_ridges
        self.n_lambda = n_lambda = n * r
        self.hessian = scipy.sparse.block_diag(
            [
                scipy.sparse.diags(np.full(n_lambda, 2.0 * model.weights.ridge)),
                scipy.sparse.csc_matrix(2.0 * np.triu(model.middle)),
            ],
            format="csc",
        )
        # A (6N, n_lambda + 6N) in CSC: lambda column j of sample k has rows 6k..6k+5, U rows 1
        sample_of_column = np.arange(n_lambda) // r
        self._indices = np.concatenate(
            [(6 * sample_of_column[:, None] + np.arange(6)).ravel(), np.arange(6 * n)]
        )
        self._indptr = np.concatenate(
            [np.arange(0, 6 * n_lambda + 1, 6), 6 * n_lambda + np.arange(1, 6 * n + 1)]
        )
        self._shape = (6 * n, n_lambda + 6 * n)
        self._lower = np.concatenate([np.zeros(n_lambda), np.full(6 * n, -np.inf)])
        self._upper = np.full(n_lambda + 6 * n, np.inf)
        self._equality: scipy.sparse.csc_matrix | None = None
        self._piqp = piqp
        self.solver = piqp.SparseSolver()
        for key, value in _TOLERANCES["piqp"].items():
            setattr(self.solver.settings, key, value)
        self._ready = False

    def ridges(self, problem: MpcProblem) -> np.ndarray:
        m, r = self.model, self.max_ridges
        n = m.horizon
        columns = np.zeros((n, r, 6))  # W_k^T, padded
        upper = self._upper
        if problem.upper is not None:
            upper = upper.copy()
        for k, w in enumerate(problem.maps):
            columns[k, : w.shape[1]] = w.T
            if problem.upper is not None:
                upper[k * r : k * r + w.shape[1]] = problem.upper[k]
        if self._equality is None:
            self._equality = scipy.sparse.csc_matrix(
                (np.ones(len(self._indices)), self._indices, self._indptr), shape=self._shape
            )
        equality = self._equality  # same pattern every period: new values in place
        equality.data[: columns.size] = -columns.ravel()
        gradient = np.zeros(self._shape[1])
        gradient[self.n_lambda :] = input_gradient(m, problem)
        if self._ready:
            self.solver.update(c=gradient, A=equality, x_u=upper)
        else:
            self.solver.setup(
                self.hessian,
                gradient,
                equality,
                np.zeros(6 * n),
                None,
                None,
                None,
                self._lower,
                upper,
            )
            self._ready = True
        status = self.solver.solve()
        if status != self._piqp.PIQP_SOLVED:
            raise MpcSolverError(f"{self.name} found no solution ({status})")
        z = self.solver.result.x
        return np.maximum(
            np.concatenate([z[k * r : k * r + size] for k, size in enumerate(problem.sizes)]),
            0.0,
        )


class FaceForm:
    """The same MPC over the inputs U (6N) with each sample's contact cone by its faces:
    min U^T M U + l^T U  s.t.  F_k T_k^-1 U_k <= 0  (k = 0..N-1),
    with M = Phi^T Q Phi + R (constant), l from `input_gradient`, F_k the face form of cone(G_k)
    (`cone_faces`, computed once per contact phase and kept) and T_k^-1 taking the moment about
    c-hat_k back to the origin (n_o = n + c-hat_k x f). {F_k w <= 0} = {G_k lambda : lambda >= 0},
    so the feasible wrenches are those of the ridge form, with 6N variables instead of
    sum n_k (120 instead of 320-640 at 20 samples).

    A written-down difference from the ridge form: its eps ||lambda||^2 (MpcWeights.ridge,
    1e-8), which only makes the ridge problem strictly convex, has no counterpart (the wrench
    here is unique without it: M is positive definite through R). Ridge-force upper bounds
    cannot be expressed on the faces: a problem with `upper` is refused (MpcSolverError).

    `face:quadprog` calls quadprog (Goldfarb-Idnani dual active set) directly with the inverse
    Cholesky factor of the constant Hessian, computed once (`factorized=True`), on a working
    set of the faces (`_quadprog`: the same optimum; the preview stage 1.5x faster on `walk`,
    430 against 282 us a period, measured side by side; the rows made by compiled kernels
    since, `unit_face_rows` and `face_rows_hold`: 1.6x faster again, docs/latency.md);
    `face:daqp` goes through qpsolvers and factorises every period. The constraint rows are
    scaled to unit norm (the same cone). quadprog has no iteration or time limit of its own:
    in a sweep, the episode's wall-clock budget bounds it (`bench.executors`); DAQP has both,
    at 4.4x the solve time on our walks (1.56 against 0.35 ms median with a kept
    `daqp.Model`).
    """

    needs_maps = False  # the faces replace the ridges' W_k

    def __init__(self, model: MpcModel, solver: str, max_ridges: int) -> None:
        self.model, self.solver, self.name = model, solver, f"face:{solver}"
        self.hessian = 2.0 * model.middle
        self._inverse_factor: np.ndarray | None = None  # R^-1 with H = R^T R, for quadprog
        if solver == "quadprog":
            factor = scipy.linalg.cholesky(self.hessian)  # R, upper triangular
            self._inverse_factor = scipy.linalg.solve_triangular(factor, np.eye(len(factor)))
        self._faces: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        # (the samples' face arrays, their stack (m, 6), each row's sample (m,)), kept while
        # every sample keeps its contact phase (`_stacked`)
        self._stack: tuple[list[np.ndarray], np.ndarray, np.ndarray] | None = None
        # (sizes, flat positions, buffer), kept while the sizes stay (`face:daqp`'s matrix)
        self._layout: tuple[list[int], np.ndarray, np.ndarray] | None = None
        self._active: tuple[list[int], np.ndarray] | None = None  # (sizes, rows) last active
        self.working_set = True  # False: quadprog on every row (the reference, for tests)
        self.working_rows = 0  # rows quadprog was given in the last solve

    def _stacked(self, faces: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """The samples' faces stacked (m, 6) and each row's sample (m,), kept while every
        sample has the same face array (the same contact phase): on a walk the phases move
        past the horizon's samples every 10-12 periods, not every period."""
        kept = self._stack
        if (
            kept is None
            or len(kept[0]) != len(faces)
            or any(a is not b for a, b in zip(kept[0], faces, strict=True))
        ):
            sizes = [len(f) for f in faces]
            kept = self._stack = (
                list(faces),
                np.vstack(faces),
                np.repeat(np.arange(len(faces)), sizes),
            )
        return kept[1], kept[2]

    def _negated_constraint(
        self, sizes: list[int], rows: np.ndarray, sample: np.ndarray
    ) -> np.ndarray:
        """The block-diagonal constraint matrix, negated, in a buffer kept while the samples'
        face counts stay the same (a fresh 0.6 MB array every period costs more than the
        solve: page faults); `rows` (m, 6) is negated in place and written at flat positions
        kept with the buffer; `sample` (m,) each row's sample (`_stacked`). Only a solver given
        every row uses it (`face:daqp`); quadprog's working set is built from its own rows
        (`_working_constraint`)."""
        if self._layout is None or self._layout[0] != sizes:
            n = self.model.horizon
            columns = 6 * sample[:, None] + np.arange(6)
            flat = np.arange(len(rows))[:, None] * (6 * n) + columns  # row-major positions
            self._layout = (sizes, flat.ravel(), np.zeros((len(rows), 6 * n)))
        _, flat, buffer = self._layout
        np.negative(rows, out=rows)
        buffer.put(flat, rows)
        return buffer

    def _working_constraint(
        self, rows: np.ndarray, sample: np.ndarray, index: np.ndarray
    ) -> np.ndarray:
        """quadprog's C (6N, w) for the working rows `index` (w of them): column j holds
        -rows[index[j]] at its sample's 6 inputs, so that C'U >= -slack is F T^-1 U <= slack
        on those rows. Built from the w rows alone (the full (m, 6N) matrix is 0.6 MB)."""
        constraint = np.zeros((len(index), 6 * self.model.horizon))
        for j, i in enumerate(index.tolist()):
            start = 6 * int(sample[i])
            constraint[j, start : start + 6] = -rows[i]
        return constraint.T

    @staticmethod
    @functools.cache
    def _slack(m: int) -> np.ndarray:
        """quadprog's anti-cycling perturbation: row i of the unit-norm constraints may be
        violated by ANTI_CYCLING_SLACK (1 + i / m) [N or N m], distinct for every row. At a
        degenerate optimum (friction 0.01: many more faces active than the 6 dimensions of
        a sample) the Goldfarb-Idnani active set cycled for ever on exact ties; distinct
        slacks break them (the QP solved in 51 iterations)."""
        return ANTI_CYCLING_SLACK * (1.0 + np.arange(m) / m)

    def _quadprog(
        self, rows: np.ndarray, sample: np.ndarray, gradient: np.ndarray, sizes: list[int]
    ) -> np.ndarray:
        """quadprog on a working set of the rows, grown until no other row is violated: the
        same optimum as on all rows (the QP is strictly convex; every row left out holds at
        the answer, so adding it changes nothing), at a fraction of the cost: at the optimum
        one or two of the 600-750 faces are active (measured on `walk`), and quadprog's
        wrapper copies every row it is given. The working set starts from the rows violated
        at the unconstrained optimum and the rows active in the last period (while the
        samples' face counts are the same). `rows` (m, 6) the unit face rows (F T^-1 U <= 0
        row by row), `sample` (m,) each row's sample, `sizes` the samples' face counts."""
        slack = self._slack(len(rows))
        factor = self._inverse_factor  # R^-1, H = R^T R: H^-1 a = R^-1 R^-T a
        n = self.model.horizon

        def holds(u: np.ndarray) -> np.ndarray:
            """Each row's F T^-1 u <= slack (C'u >= -slack), from its 6 nonzeros."""
            return face_rows_hold(rows, sample, u.reshape(n, 6), slack)

        working = ~holds(factor @ (factor.T @ -gradient))
        if not self.working_set:
            working[:] = True
        if self._active is not None and self._active[0] == sizes:
            working[self._active[1]] = True
        while True:
            index = np.flatnonzero(working)
            if len(index) == 0:
                solution, lagrangian = factor @ (factor.T @ -gradient), np.zeros(0)
            else:
                try:
                    result = quadprog.solve_qp(
                        factor,
                        -gradient,
                        self._working_constraint(rows, sample, index),
                        -slack[index],
                        0,
                        True,
                    )
                except ValueError as exc:  # "constraints are inconsistent, no solution"
                    raise MpcSolverError(f"{self.name}: {exc}") from exc
                solution, lagrangian = result[0], result[4]
            violated = ~holds(solution) & ~working
            if not violated.any():
                self._active = (sizes, index[lagrangian != 0])
                self.working_rows = len(index)
                return solution
            working |= violated

    def faces_of(self, generators: np.ndarray) -> np.ndarray:
        """F of cone(G) (moments about the origin), kept per generator array: the planner
        passes the same array for every sample of a contact phase. A sample without contacts
        gets U_k = 0 (its rows bound every component both ways)."""
        kept = self._faces.get(id(generators))
        if kept is None or kept[0] is not generators:
            if generators.shape[1] == 0:
                faces = np.vstack([np.eye(6), -np.eye(6)])
            else:
                try:
                    faces = cone_faces(generators)
                except ValueError as exc:
                    raise MpcSolverError(f"{self.name}: {exc}") from exc
            kept = self._faces[id(generators)] = (generators, faces)
        return kept[1]

    def solve(self, problem: MpcProblem) -> np.ndarray:
        if problem.upper is not None:
            raise MpcSolverError(
                f"{self.name} cannot bound ridge forces; use a ridge formulation for ridge_upper"
            )
        if problem.generators is None or problem.points is None:
            raise ValueError(f"{self.name} needs the problem's generators and points")
        n = self.model.horizon
        faces = [self.faces_of(g) for g in problem.generators]
        stacked, sample = self._stacked(faces)  # (m, 6) moments about the origin, (m,)
        # F T^-1 (the moment about c-hat_k) in unit rows (`unit_face_rows`): the same cone
        # (each row <= 0 scaled by a positive number), but a well-scaled active set; with rows
        # of norms 0.98-2.7 quadprog's dual active set cycled for ever at friction 0.01
        # (tests/planners/test_linear_mpc.py)
        points = np.asarray(problem.points, dtype=float)
        if points.shape != (n, 3):  # the kernel reads points[sample] unchecked
            raise ValueError(f"{self.name}: points must be ({n}, 3), got {points.shape}")
        rows = unit_face_rows(stacked, sample, points)
        gradient = input_gradient(self.model, problem)
        if not len(rows):  # every sample's cone is the whole space (grasps): unconstrained
            return np.linalg.solve(self.hessian, -gradient).reshape(n, 6)
        sizes = [len(f) for f in faces]
        if self.solver == "quadprog":  # min 1/2 U'HU - a'U  s.t.  C'U >= -slack
            solution = self._quadprog(rows, sample, gradient, sizes)
        else:
            negated = self._negated_constraint(sizes, rows, sample)  # -(F T^-1), (m, 6N)
            with np.errstate(all="ignore"):
                solution = qpsolvers.solve_qp(
                    self.hessian, gradient, G=-negated, h=np.zeros(len(rows)), solver=self.solver
                )
        if solution is None or not np.all(np.isfinite(solution)):
            raise MpcSolverError(f"{self.name} found no solution")
        return solution.reshape(n, 6)


def _casadi_sparsity(ca, matrix: scipy.sparse.spmatrix):
    m = matrix.tocsc()
    m.sort_indices()
    return ca.Sparsity(m.shape[0], m.shape[1], m.indptr.tolist(), m.indices.tolist())


def _values_on_pattern(matrix: scipy.sparse.spmatrix, pattern: scipy.sparse.csc_matrix):
    """The entries of `matrix` at `pattern`'s nonzeros (zeros where `matrix` has none)."""
    m = matrix.tocsc()
    rows = pattern.indices
    cols = np.repeat(np.arange(pattern.shape[1]), np.diff(pattern.indptr))
    return np.asarray(m[rows, cols]).ravel()


_CLASSES = {
    "dense": DenseQpsolvers,
    "sparse": SparseQpsolvers,
    "cvxpy": CvxpyFormulation,
    "casadi": CasadiFormulation,
    "native": NativePiqp,
    "face": FaceForm,
}


def make_formulation(name: str, model: MpcModel, max_ridges: int) -> Formulation:
    """A formulation by name (one of `FORMULATIONS`); KeyError naming the valid ones."""
    if name not in FORMULATIONS:
        raise KeyError(
            f"unknown MPC formulation {name!r}; choose one of: {', '.join(FORMULATIONS)}"
        )
    kind, solver = name.split(":")
    return _CLASSES[kind](model, solver, max_ridges)
