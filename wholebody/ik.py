"""Whole-body inverse kinematics: one weighted least-squares QP per control period (ours: at the
velocity level, where Murooka Sec. V-A1's IK is acceleration-based; README's adaptations).

Each call takes the IK's own configuration q (the last solution, a floating-base model of the
robot: the base is a free variable, as in Murooka Sec. V-A1, where the IK output goes to joint
position servos) and finds the step dv (pinocchio tangent space, nv = 6 + n_joints) minimising

    sum_i w_i || J_i dv - gain e_i ||^2 + damping ||dv||^2

over the tasks i: each limb end's 6-D pose (contact limbs held with `contact` weight, free
limbs with a target tracked with `limb` weight, limbs without one left to the posture task),
the CoM position, the base orientation, a low-weight posture task toward the nominal joint
angles (Murooka V-A1) and an optional centroidal angular momentum task I_all dv = L^p dt
toward the plan's angular momentum (`WholeBodyTargets.angular_momentum_world`; zero without
one) (Murooka V-F), subject to the joint position limits and the joint velocity limits over
one period. The QP is solved by DAQP (the default: the fastest on this dense 26-variable
problem, see `make benchmark`), called directly with the bounds as DAQP's simple bounds (what
qpsolvers passes it, without qpsolvers' per-call problem checks: 33 against 71 us measured),
or by any other solver through qpsolvers. The task rows are written into buffers kept between calls;
the posture task's rows [0 I] enter the Hessian and gradient directly, and the QP's terms, the
bounds and the pose errors are compiled kernels (`qp_terms`, `centroidal.kernels.pose_errors`).

Orientation errors are log(R_target R^T) in world axes, matching the LOCAL_WORLD_ALIGNED
Jacobians.
"""

from __future__ import annotations

import math
from ctypes import c_int
from dataclasses import dataclass

import daqp
import numpy as np
import pinocchio as pin
import qpsolvers
from numba import njit

from centroidal.kernels import pose_errors
from robots.model import RobotModel
from robots.types import RobotState, WholeBodyTargets


@dataclass(frozen=True)
class IKWeights:
    """Task weights (dimensionless; errors in m and rad) and the fraction `gain` of each task
    error corrected per call. Ours (an adaptation): Murooka et al. give none (Sec. V-A1: an
    acceleration-based IK with a "low stiffness" posture task); these rank the tasks, contacts
    above the CoM above the base and free limbs, posture far below. The authors' mc_rtc
    configurations (MultiContactController, BaselineWalkingController `etc/*.yaml`) weight the
    CoM and every foot alike (1000, stiffness 1000), the base orientation 500 (stiffness 300)
    and the posture 10 (stiffness 10), at the acceleration level, so the numbers do not carry
    over."""

    contact: float = 1e5
    com: float = 1e3
    base_orientation: float = 1e2
    limb: float = 1e2
    posture: float = 1e-2
    angular_momentum: float = 0.0
    damping: float = 1e-6
    gain: float = 1.0


@njit(cache=True)
def qp_terms(
    jacobian: np.ndarray,
    weight: np.ndarray,
    error: np.ndarray,
    gain: float,
    damping_and_posture: np.ndarray,
    posture_weight: float,
    nominal: np.ndarray,
    joints: np.ndarray,
    joint_lower: np.ndarray,
    joint_upper: np.ndarray,
    max_step: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The IK's QP in one call: H = J^T W J + damping I + w_p [0 I] (the posture task's rows
    [0 I] added directly), g = -(W J)^T gain e - w_p [0; gain (q_nominal - q)], and the joint
    steps' bounds (position limits and velocity limits over one period, always admitting 0)
    written into lower[6:] and upper[6:]."""
    weighted = jacobian * weight.reshape(-1, 1)
    hessian = jacobian.T @ weighted + damping_and_posture
    gradient = -(weighted.T @ (error * gain))
    for j in range(len(joints)):
        gradient[6 + j] -= posture_weight * (gain * (nominal[j] - joints[j]))
        lower[6 + j] = min(max(joint_lower[j] - joints[j], -max_step[j]), 0.0)
        upper[6 + j] = max(min(joint_upper[j] - joints[j], max_step[j]), 0.0)
    return hessian, gradient


class WholeBodyIK:
    """Differential IK over a floating-base pinocchio model; see the module docstring."""

    def __init__(
        self,
        model: RobotModel,
        dt: float,
        weights: IKWeights | None = None,
        solver: str = "daqp",
        extra_rows: int = 0,
    ) -> None:
        if solver not in qpsolvers.available_solvers:
            raise ValueError(
                f"QP solver {solver!r} is not available; available: "
                f"{', '.join(qpsolvers.available_solvers)}"
            )
        self.robot_model = model
        self.model = model.model
        self.data = self.model.createData()
        self.dt = dt
        self.weights = weights or IKWeights()
        self.solver = solver
        robot = model.robot
        self.nv = self.model.nv
        self.n_joints = robot.n_joints
        self.limb_frames = [model.frame_id[limb.contact_frame] for limb in robot.limbs]
        self.base_frame = model.frame_id[robot.base_link]
        self.lower = robot.array("lower")
        self.upper = robot.array("upper")
        self.max_step = robot.array("velocity_limit") * dt
        self.nominal = np.array(robot.nominal_posture)
        self.q = pin.neutral(self.model)
        # Task rows in kept buffers: at most 6 per limb, CoM 3, base orientation 3, angular
        # momentum 3 (the posture task's rows [0 I] enter the QP directly, see `solve`).
        n_rows = 6 * len(self.limb_frames) + 3 + 3 + 3 + extra_rows
        # the base orientation task's weight per world axis (a subclass may free roll, pitch)
        self.base_orientation_weights = np.full(3, self.weights.base_orientation)
        self._jacobian = np.zeros((n_rows, self.nv))
        self._error = np.zeros(n_rows)
        self._weight = np.zeros(n_rows)
        self._damping_and_posture = self.weights.damping * np.eye(self.nv)
        self._damping_and_posture[6:, 6:] += self.weights.posture * np.eye(self.n_joints)
        # The base step is bounded too, by 1 m / 1 rad per call: never active in practice, and
        # interior-point solvers (clarabel) fail on huge placeholder bounds.
        self._base_step = 1.0
        self._lower = np.full(self.nv, -self._base_step)
        self._upper = np.full(self.nv, self._base_step)
        n_poses = len(self.limb_frames) + 1  # the limbs and the base
        self._positions = np.zeros((n_poses, 3))
        self._rotations = np.zeros((n_poses, 3, 3))
        self._target_orientations = np.zeros((n_poses, 4))
        self._no_rows = np.zeros((0, self.nv))  # DAQP: no general constraints,
        self._sense = np.zeros(self.nv, dtype=c_int)  # every variable a simple bound

    def reset(self, state: RobotState) -> None:
        """Start from `state`'s configuration."""
        self.q = self.robot_model.configuration(state)

    def joint_position(self) -> np.ndarray:
        return self.q[7:].copy()

    def solve(self, targets: WholeBodyTargets) -> tuple[np.ndarray, np.ndarray]:
        """One IK step toward `targets`: the new joint positions [rad] and the joint velocities
        [rad/s] of the step."""
        model, data, w = self.model, self.data, self.weights
        q = self.q
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        jacobian_com = pin.jacobianCenterOfMass(model, data, False)  # also sets data.com[0]
        com = data.com[0]

        jacobian_rows, error_rows, weight_rows = self._jacobian, self._error, self._weight
        tracked = targets.limb_tracked
        limbs = [k for k in range(len(self.limb_frames)) if tracked is None or tracked[k]]
        # the pose tasks (tracked limbs, then the base): Jacobians and placements from
        # pinocchio, errors (position; log(R_target R^T)) in one compiled call
        positions, rotations = self._positions, self._rotations
        for i, k in enumerate(limbs):
            frame = self.limb_frames[k]
            placement = data.oMf[frame]
            positions[i] = placement.translation
            rotations[i] = placement.rotation
            jacobian_rows[6 * i : 6 * i + 6] = pin.getFrameJacobian(
                model, data, frame, pin.LOCAL_WORLD_ALIGNED
            )
            weight_rows[6 * i : 6 * i + 6] = w.contact if targets.limb_in_contact[k] else w.limb
        m = len(limbs)
        base = data.oMf[self.base_frame]
        rotations[m] = base.rotation
        target_orientations = self._target_orientations
        every = m == len(self.limb_frames)
        target_orientations[:m] = (
            targets.limb_orientation_world if every else targets.limb_orientation_world[limbs]
        )
        target_orientations[m] = targets.base_orientation_world
        errors = pose_errors(
            targets.limb_position_world if every else targets.limb_position_world[limbs],
            target_orientations[: m + 1],
            positions[:m],
            rotations[: m + 1],
        )
        n = 6 * m
        error_rows[:n] = errors[:m].reshape(-1)
        jacobian_rows[n : n + 3] = jacobian_com
        error_rows[n : n + 3] = targets.com_position_world - com
        weight_rows[n : n + 3] = w.com
        n += 3
        jacobian_rows[n : n + 3] = pin.getFrameJacobian(
            model, data, self.base_frame, pin.LOCAL_WORLD_ALIGNED
        )[3:]
        error_rows[n : n + 3] = errors[m, 3:]
        weight_rows[n : n + 3] = self.base_orientation_weights
        n += 3
        n = self._extra_rows(q, targets, n)
        if w.angular_momentum > 0:
            centroidal = pin.computeCentroidalMap(model, data, q)
            jacobian_rows[n : n + 3] = centroidal[3:]
            # L = I_all q' toward the plan's L^p: I_all dv = L^p dt (times the gain; Murooka
            # Sec. V-F, the authors' momentum task targets the planned momentum)
            planned = targets.angular_momentum_world
            error_rows[n : n + 3] = 0.0 if planned is None else planned * self.dt
            weight_rows[n : n + 3] = w.angular_momentum
            n += 3

        lower, upper = self._lower, self._upper
        hessian, gradient = qp_terms(
            jacobian_rows[:n],
            weight_rows[:n],
            error_rows[:n],
            w.gain,
            self._damping_and_posture,
            w.posture,
            self.nominal,
            q[7:],
            self.lower,
            self.upper,
            self.max_step,
            lower,
            upper,
        )
        step = self._solve_qp(hessian, gradient, lower, upper)
        if step is None or not math.isfinite(step.sum()):
            raise RuntimeError(f"IK QP ({self.solver}) found no solution")
        self.q = pin.integrate(model, q, step)
        # Keep the joints inside their limits exactly (the solver's tolerance may leave 1e-9).
        joints = self.q[7:]
        np.minimum(np.maximum(joints, self.lower, out=joints), self.upper, out=joints)
        return self.q[7:].copy(), step[6:] / self.dt

    def _extra_rows(self, q: np.ndarray, targets: WholeBodyTargets, n: int) -> int:
        """Write a subclass's task rows from row `n` of the buffers (`extra_rows` of them at
        most); return the next free row. None here."""
        return n

    def _solve_qp(
        self, hessian: np.ndarray, gradient: np.ndarray, lower: np.ndarray, upper: np.ndarray
    ) -> np.ndarray | None:
        """argmin 1/2 x^T H x + g^T x subject to lower <= x <= upper, or None."""
        if self.solver == "daqp":
            step, _, exitflag, _ = daqp.solve(
                hessian, gradient, self._no_rows, upper, lower, self._sense
            )
            return step if exitflag > 0 else None
        return qpsolvers.solve_qp(hessian, gradient, lb=lower, ub=upper, solver=self.solver)
