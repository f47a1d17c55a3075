"""Constrained linear centroidal MPC over the contact wrenches (friction-pyramid ridge forces, or
on the cone's faces: `centroidal.mpc_formulations`; the linear MPC that
Murooka et al. 2022, Sec. V-E, compare their preview control with: Audren et al. 2014, "Model
preview control in multi-contact motion").

Model (per horizon sample k = 0..N-1 of length dtau, the wrench held constant over it):
state x = [c, c', alpha, omega] (CoM [m], its velocity, base angle [rad] and angular velocity),
input the contact wrench u_k = [f_k; n_k] with f_k the total contact force [N] and n_k its moment
about the linearisation point c-hat_k [N m]; c'' = f / m - g and alpha'' = I^-1 n (the constant
diagonal inertia of Murooka eq. 6, so I omega approximates the centroidal angular momentum).
The contacts active at sample k give u_k = W_k lambda_k with lambda_k >= 0 the ridge forces of
their friction pyramids (G_k of eq. 8) and W_k = [F_k; N_k - [c-hat_k]x F_k].

Linearity (a written-down choice in place of Audren's two passes, vertical then horizontal):
the moment about the CoM, (p - c) x f, is bilinear; it is taken about c-hat_k, the CoM that the
previous solution predicted for that sample (the reference before the first solution). The
problem is then one QP in lambda.

Cost (Murooka's Table I output weights, so that the comparison with preview control weighs the
same things): sum_{k=1..N} q_c ||c_k - c_ref,k||^2 + q_alpha ||alpha_k||^2 over the outputs and
sum_{k=0..N-1} q_f ||f_k - m g||^2 + q_n ||n_k||^2 + eps ||lambda_k||^2 over the inputs (the
resultant force and moment toward zero, as preview control's reference; eps regularises).

Formulations, all on the same problem (`FORMULATIONS`):
- `dense:<solver>` (qpsolvers; daqp, proxqp, quadprog): lambda only. Because the dynamics do
  not change, Y = Psi x0 + Phi U + Y_g with constant Psi, Phi, and the Hessian is
  W^T (Phi^T Q Phi + R) W + eps I, built per period from the constant 6N x 6N middle matrix and
  the block-diagonal W (one small product per sample).
- `sparse:<solver>` (qpsolvers; osqp, clarabel, proxqp): variables (lambda, u, x), equality
  constraints u_k = W_k lambda_k and the dynamics; diagonal cost.
- `cvxpy:<SOLVER>` (OSQP, CLARABEL): the sparse form as a cvxpy problem with Parameters, built
  once with every sample padded to the largest ridge count (absent ridges bounded to zero).
- `casadi:<plugin>` (osqp, qpoases): the same padded sparse form as one `casadi.conic`, built
  once with its sparsity; each period passes new numbers.
- `native:piqp`: PIQP's own API on the partially condensed form (lambda and U), set up once.
- `face:<solver>` (quadprog, daqp; `face:quadprog` is the default): the same feasible wrenches
  with each sample's cone by its faces (Caron et al. 2015), over U alone (6N variables): the
  Hessian 2M is constant, so quadprog gets its inverse Cholesky factor once. It drops the
  eps ||lambda||^2 regulariser, which only makes the ridge problem strictly convex (the
  formulations still agree within 0.05 N / N m, faces active or not), and cannot bound ridge
  forces. Written down as our choice for speed: the decision variables of the issue (lambda)
  remain in every other formulation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse

from centroidal.gravity import GRAVITY


@dataclass(frozen=True)
class MpcWeights:
    """Cost weights (Murooka Table I's output weights): CoM [1/m^2], base angle [1/rad^2],
    resultant force [1/N^2], resultant moment [1/(N m)^2]; ridge regularisation [1/N^2]."""

    com: float = 2e2
    angle: float = 1e2
    force: float = 5e-4
    moment: float = 5e-3
    ridge: float = 1e-8


class MpcModel:
    """The constant part of the problem: dynamics, prediction matrices, cost matrices."""

    def __init__(
        self,
        mass: float,
        inertia: np.ndarray,
        dtau: float,
        horizon: int,
        weights: MpcWeights | None = None,
    ) -> None:
        if horizon < 1:
            raise ValueError(f"the MPC horizon needs at least 1 sample, got {horizon}")
        if dtau <= 0:
            raise ValueError(f"the MPC sample period must be positive, got {dtau}")
        self.mass, self.dtau, self.horizon = float(mass), float(dtau), int(horizon)
        self.inertia = np.asarray(inertia, dtype=float)
        self.weights = weights or MpcWeights()
        eye = np.eye(3)
        step = np.block([[eye, dtau * eye], [np.zeros((3, 3)), eye]])
        self.a = scipy.linalg.block_diag(step, step)  # (12, 12)
        inverse_inertia = np.diag(1.0 / self.inertia)
        self.b = np.vstack(
            [
                np.hstack([0.5 * dtau**2 / mass * eye, np.zeros((3, 3))]),
                np.hstack([dtau / mass * eye, np.zeros((3, 3))]),
                np.hstack([np.zeros((3, 3)), 0.5 * dtau**2 * inverse_inertia]),
                np.hstack([np.zeros((3, 3)), dtau * inverse_inertia]),
            ]
        )  # (12, 6)
        g = np.array([0.0, 0.0, GRAVITY])
        self.e = np.concatenate([-0.5 * dtau**2 * g, -dtau * g, np.zeros(6)])
        self.c = np.zeros((6, 12))  # outputs: c and alpha
        self.c[:3, :3] = eye
        self.c[3:, 6:9] = eye
        w = self.weights
        self.q_output = np.r_[np.full(3, w.com), np.full(3, w.angle)]
        self.r_input = np.r_[np.full(3, w.force), np.full(3, w.moment)]
        self.u_reference = np.array([0.0, 0.0, mass * GRAVITY, 0.0, 0.0, 0.0])
        n = self.horizon
        # Y (6N) = psi x0 + phi U + y_g, with Y_k the output after sample k (k = 1..N)
        self.psi = np.zeros((6 * n, 12))
        self.phi = np.zeros((6 * n, 6 * n))
        self.y_gravity = np.zeros(6 * n)
        powers = [np.eye(12)]
        for _ in range(n):
            powers.append(self.a @ powers[-1])
        drift = np.zeros(12)
        for k in range(n):
            self.psi[6 * k : 6 * k + 6] = self.c @ powers[k + 1]
            drift = self.a @ drift + self.e
            self.y_gravity[6 * k : 6 * k + 6] = self.c @ drift
            for j in range(k + 1):
                self.phi[6 * k : 6 * k + 6, 6 * j : 6 * j + 6] = self.c @ powers[k - j] @ self.b
        q = np.tile(self.q_output, n)
        self.middle = self.phi.T @ (q[:, None] * self.phi) + np.diag(np.tile(self.r_input, n))
        self.q_stacked = q
        self.input_reference = np.tile(self.r_input * self.u_reference, n)  # R U_ref (6N)
        self._sparse_constants = None

    def sparse_constants(self):
        """The parts of the sparse form that do not change between periods, built on first
        use: its Hessian block and dynamics rows over (u, x), and the gradient over u."""
        if self._sparse_constants is None:
            n = self.horizon
            q_x = self.c.T @ np.diag(self.q_output) @ self.c
            hessian = scipy.sparse.block_diag(
                [
                    scipy.sparse.diags(np.tile(2.0 * self.r_input, n)),
                    scipy.sparse.kron(scipy.sparse.identity(n), 2.0 * q_x),
                ],
                format="csc",
            )
            dynamics = scipy.sparse.lil_matrix((12 * n, 18 * n))
            for k in range(n):
                rows = slice(12 * k, 12 * k + 12)
                x_col = 6 * n + 12 * k
                dynamics[rows, x_col : x_col + 12] = np.eye(12)
                dynamics[rows, 6 * k : 6 * k + 6] = -self.b
                if k > 0:
                    dynamics[rows, x_col - 12 : x_col] = -self.a
            gradient_u = np.tile(-2.0 * self.r_input * self.u_reference, n)
            self._sparse_constants = (hessian, dynamics.tocsc(), gradient_u)
        return self._sparse_constants

    def wrench_maps(self, generators: list[np.ndarray], points: np.ndarray) -> list[np.ndarray]:
        """W_k (6, n_k) from each sample's G_k (moments about the origin) and c-hat_k: the
        moment rows taken about c-hat_k, n - c-hat_k x f (all samples in one array operation)."""
        sizes = [g.shape[1] for g in generators]
        stacked = np.hstack(generators)  # (6, sum n_k)
        forces = stacked[:3]
        about = np.repeat(np.asarray(points, dtype=float), sizes, axis=0)  # c-hat per column
        fx, fy, fz = forces
        px, py, pz = about.T
        moments = stacked[3:] - np.array([py * fz - pz * fy, pz * fx - px * fz, px * fy - py * fx])
        return np.split(np.vstack([forces, moments]), np.cumsum(sizes)[:-1], axis=1)

    def predict_outputs(self, x0: np.ndarray, inputs: np.ndarray) -> np.ndarray:
        """Outputs y_1..y_N (N, 6) = [c, alpha] for inputs u_0..u_{N-1} (N, 6):
        Psi x0 + Phi U + Y_g (the same prediction as `predict`, in one product)."""
        return (self.psi @ x0 + self.phi @ np.ravel(inputs) + self.y_gravity).reshape(-1, 6)

    def predict(self, x0: np.ndarray, inputs: np.ndarray) -> np.ndarray:
        """States x_1..x_N (N, 12) for inputs u_0..u_{N-1} (N, 6)."""
        states = np.empty((self.horizon, 12))
        x = np.asarray(x0, dtype=float)
        for k in range(self.horizon):
            x = self.a @ x + self.b @ inputs[k] + self.e
            states[k] = x
        return states


@dataclass
class MpcProblem:
    """One period's data: W_k per sample, the initial state, the output references (N, 6),
    optional ridge-force upper bounds per sample and, for the face form, each sample's G_k
    (moments about the origin; the same array object for the samples of one contact phase) and
    c-hat_k (N, 3) [m] from which W_k was made. `maps` is None for a formulation that does not
    use them (`needs_maps` False: the face form), which saves making them every period."""

    maps: list[np.ndarray] | None
    x0: np.ndarray
    y_reference: np.ndarray
    upper: list[np.ndarray] | None = None
    generators: list[np.ndarray] | None = None
    points: np.ndarray | None = None

    @property
    def sizes(self) -> list[int]:
        matrices = self.maps if self.maps is not None else self.generators
        return [m.shape[1] for m in matrices]


class MpcSolverError(RuntimeError):
    """The formulation's solver returned no solution."""


def condensed(model: MpcModel, problem: MpcProblem) -> tuple[np.ndarray, np.ndarray]:
    """(H, g) of min 1/2 lambda' H lambda + g' lambda (lambda stacked over the samples)."""
    sizes = problem.sizes
    offsets = np.concatenate([[0], np.cumsum(sizes)])
    n = int(offsets[-1])
    middle_times_w = np.zeros((6 * model.horizon, n))
    for k, w in enumerate(problem.maps):
        middle_times_w[:, offsets[k] : offsets[k + 1]] = model.middle[:, 6 * k : 6 * k + 6] @ w
    hessian = np.empty((n, n))
    for k, w in enumerate(problem.maps):
        hessian[offsets[k] : offsets[k + 1]] = w.T @ middle_times_w[6 * k : 6 * k + 6]
    hessian = hessian + hessian.T  # 2 W^T M W, symmetrised
    hessian[np.diag_indices(n)] += 2.0 * model.weights.ridge
    linear = input_gradient(model, problem)
    gradient = np.concatenate([w.T @ linear[6 * k : 6 * k + 6] for k, w in enumerate(problem.maps)])
    return hessian, gradient


def input_gradient(model: MpcModel, problem: MpcProblem) -> np.ndarray:
    """l (6N): the cost's linear term over the stacked inputs U, so that the cost is
    U^T M U + l^T U + const with the constant M = Phi^T Q Phi + R (`model.middle`):
    l = 2 (Phi^T Q (Psi x0 + Y_g - Y_ref) - R U_ref)."""
    free = model.psi @ problem.x0 + model.y_gravity - problem.y_reference.ravel()
    return 2.0 * (model.phi.T @ (model.q_stacked * free) - model.input_reference)


def sparse_form(model: MpcModel, problem: MpcProblem, pad_to: int | None = None):
    """The sparse QP in z = [lambda, u (6N), x (12N)]: (P, q, A_eq, b_eq, lower, upper).
    With `pad_to`, every sample has `pad_to` ridge columns (absent ones bounded to zero), so the
    sparsity pattern is the same every period."""
    n_samples = model.horizon
    sizes = problem.sizes if pad_to is None else [pad_to] * n_samples
    offsets = np.concatenate([[0], np.cumsum(sizes)])
    n_lambda = int(offsets[-1])
    n_u, n_x = 6 * n_samples, 12 * n_samples
    n_z = n_lambda + n_u + n_x
    hessian_ux, dynamics_ux, gradient_u = model.sparse_constants()
    hessian = scipy.sparse.block_diag(
        [scipy.sparse.diags(np.full(n_lambda, 2.0 * model.weights.ridge)), hessian_ux],
        format="csc",
    )
    gradient = np.zeros(n_z)
    gradient[n_lambda : n_lambda + n_u] = gradient_u
    gradient[n_lambda + n_u :] = (-2.0 * (problem.y_reference * model.q_output) @ model.c).ravel()
    # u_k - W_k lambda_k = 0
    rows, cols, values = [], [], []
    for k, m in enumerate(problem.maps):
        block = np.zeros((6, sizes[k]))
        block[:, : m.shape[1]] = m
        r, c = np.meshgrid(np.arange(6), np.arange(sizes[k]), indexing="ij")
        rows.append((6 * k + r).ravel())
        cols.append((offsets[k] + c).ravel())
        values.append(-block.ravel())
    eye6 = np.arange(n_u)
    rows.append(eye6)
    cols.append(n_lambda + eye6)
    values.append(np.ones(n_u))
    coupling = scipy.sparse.csc_matrix(
        (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))), shape=(n_u, n_z)
    )
    # x_{k+1} - A x_k - B u_k = e (x_0 known: x_1 - B u_0 = A x0 + e); no lambda in it
    dynamics = scipy.sparse.hstack(
        [scipy.sparse.csc_matrix((n_x, n_lambda)), dynamics_ux], format="csc"
    )
    right = np.tile(model.e, n_samples)
    right[:12] += model.a @ problem.x0
    equality = scipy.sparse.vstack([coupling, dynamics], format="csc")
    b_eq = np.concatenate([np.zeros(n_u), right])
    lower = np.full(n_z, -np.inf)
    upper = np.full(n_z, np.inf)
    lower[:n_lambda] = 0.0
    for k, m in enumerate(problem.maps):
        start = offsets[k]
        if problem.upper is not None:
            upper[start : start + m.shape[1]] = problem.upper[k]
        upper[start + m.shape[1] : offsets[k + 1]] = 0.0  # padding
    return hessian, gradient, equality, b_eq, lower, upper, offsets


def split(lambdas: np.ndarray, sizes: list[int], offsets=None) -> list[np.ndarray]:
    """Per-sample ridge forces from the stacked vector (offsets: padded layout, if any)."""
    if offsets is None:
        offsets = np.concatenate([[0], np.cumsum(sizes)])
    return [lambdas[offsets[k] : offsets[k] + size] for k, size in enumerate(sizes)]
