"""Whole-body inverse kinematics: one weighted least-squares QP per control period.

Each call takes the IK's own configuration q (the last solution, a floating-base model of the
robot: the base is a free variable, as in Murooka Sec. V-A1, where the IK output goes to joint
position servos) and finds the step dv (pinocchio tangent space, nv = 6 + n_joints) minimising

    sum_i w_i || J_i dv - gain e_i ||^2 + damping ||dv||^2

over the tasks i: each limb end's 6-D pose (contact limbs held with `contact` weight, free
limbs with a target tracked with `limb` weight, limbs without one left to the posture task),
the CoM position, the base orientation, a low-weight posture task toward the nominal joint
angles (Murooka V-A1) and an optional centroidal angular momentum task I_all dv = 0 (Murooka
V-F), subject to the joint position limits and the joint velocity limits over one period. The
QP is solved by DAQP (the default: the fastest on this dense 26-variable problem, see
`make benchmark`), called directly with the bounds as DAQP's simple bounds (what qpsolvers
passes it, without qpsolvers' per-call problem checks: 33 against 71 us measured), or by any
other solver through qpsolvers. The task rows are written into buffers kept between calls.

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

from robots.model import RobotModel
from robots.types import RobotState, WholeBodyTargets


@dataclass(frozen=True)
class IKWeights:
    """Task weights (dimensionless; errors in m and rad) and the fraction `gain` of each task
    error corrected per call."""

    contact: float = 1e5
    com: float = 1e3
    base_orientation: float = 1e2
    limb: float = 1e2
    posture: float = 1e-2
    angular_momentum: float = 0.0
    damping: float = 1e-6
    gain: float = 1.0


def _quaternion_matrix(quaternion_wxyz: np.ndarray) -> np.ndarray:
    w, x, y, z = np.asarray(quaternion_wxyz).tolist()  # Python floats: faster to convert
    return pin.Quaternion(w, x, y, z).normalized().toRotationMatrix()


class WholeBodyIK:
    """Differential IK over a floating-base pinocchio model; see the module docstring."""

    def __init__(
        self,
        model: RobotModel,
        dt: float,
        weights: IKWeights | None = None,
        solver: str = "daqp",
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
        # Task rows in kept buffers: at most 6 per limb, CoM 3, base orientation 3, posture
        # n_joints, angular momentum 3. The posture rows (the joints' own) never change.
        n_rows = 6 * len(self.limb_frames) + 3 + 3 + self.n_joints + 3
        self._jacobian = np.zeros((n_rows, self.nv))
        self._error = np.zeros(n_rows)
        self._weight = np.zeros(n_rows)
        self._weighted = np.zeros((n_rows, self.nv))
        self._posture_rows = np.zeros((self.n_joints, self.nv))
        self._posture_rows[:, 6:] = np.eye(self.n_joints)
        self._damping = self.weights.damping * np.eye(self.nv)
        # The base step is bounded too, by 1 m / 1 rad per call: never active in practice, and
        # interior-point solvers (clarabel) fail on huge placeholder bounds.
        self._base_step = 1.0
        self._lower = np.full(self.nv, -self._base_step)
        self._upper = np.full(self.nv, self._base_step)
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
        com = pin.centerOfMass(model, data, q, False)
        jacobian_com = pin.jacobianCenterOfMass(model, data, False)

        jacobian_rows, error_rows, weight_rows = self._jacobian, self._error, self._weight
        n = 0

        def add(jacobian: np.ndarray, error: np.ndarray, weight: float) -> None:
            nonlocal n
            m = len(error)
            jacobian_rows[n : n + m] = jacobian
            error_rows[n : n + m] = error
            weight_rows[n : n + m] = weight
            n += m

        tracked = targets.limb_tracked
        for k, frame in enumerate(self.limb_frames):
            if tracked is not None and not tracked[k]:
                continue  # left to the posture task
            placement = data.oMf[frame]
            jacobian = pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
            target_rotation = _quaternion_matrix(targets.limb_orientation_world[k])
            error = np.concatenate(
                [
                    targets.limb_position_world[k] - placement.translation,
                    pin.log3(target_rotation @ placement.rotation.T),
                ]
            )
            add(jacobian, error, w.contact if targets.limb_in_contact[k] else w.limb)
        add(jacobian_com, targets.com_position_world - com, w.com)
        base = data.oMf[self.base_frame]
        base_jacobian = pin.getFrameJacobian(model, data, self.base_frame, pin.LOCAL_WORLD_ALIGNED)
        base_error = pin.log3(_quaternion_matrix(targets.base_orientation_world) @ base.rotation.T)
        add(base_jacobian[3:], base_error, w.base_orientation)
        add(self._posture_rows, self.nominal - q[7:], w.posture)
        if w.angular_momentum > 0:
            centroidal = pin.computeCentroidalMap(model, data, q)
            add(centroidal[3:], np.zeros(3), w.angular_momentum)

        jacobian = jacobian_rows[:n]
        error = error_rows[:n] * w.gain
        weighted = np.multiply(jacobian, weight_rows[:n, None], out=self._weighted[:n])
        hessian = jacobian.T @ weighted + self._damping
        gradient = -weighted.T @ error

        lower, upper = self._lower, self._upper
        joints = q[7:]
        lower[6:] = np.minimum(np.maximum(self.lower - joints, -self.max_step), 0.0)
        upper[6:] = np.maximum(np.minimum(self.upper - joints, self.max_step), 0.0)
        step = self._solve_qp(hessian, gradient, lower, upper)
        if step is None or not math.isfinite(step.sum()):
            raise RuntimeError(f"IK QP ({self.solver}) found no solution")
        self.q = pin.integrate(model, q, step)
        # Keep the joints inside their limits exactly (the solver's tolerance may leave 1e-9).
        self.q[7:] = np.clip(self.q[7:], self.lower, self.upper)
        return self.q[7:].copy(), step[6:] / self.dt

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
