"""`inverse_dynamics`: joint torques from whole-body accelerations and contact wrenches, the
first block of the Lagrangian dynamics (Sherikov et al. 2014, eq. 1):

    H_1 q'' + h_1 = tau + J_c,1^T f,   so   tau = (RNEA(q, q', q'') - sum_c J_c^T f_c)_joints

with pinocchio's RNEA for H q'' + h, and each contact's Jacobian in its own contact frame
(pin.LOCAL) so that the wrench f_c (force, moment about the frame origin, in that frame; as
`WholeBodyTargets.contact_wrench_desired_limb`) maps through J_c^T directly.

Torque control through the common servo law tau = kp (q_d - q) + kd (dq_d - dq) + tau_ff:
kp = kd = 0, so the feed-forward is the joint torque, held over the control period (zero-order
hold at 500 Hz, both simulators; clipped to the torque limits as every command is). Why no
gains: the paper's controller is torque-level (eq. 1); any PD added here would be a second
controller that the hierarchy does not know about (it already holds the posture, eq. 19).
The robot has no passive joint damping, armature or friction in either simulator (sims/), so
pinocchio's model is the simulated one.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from robots.model import RobotModel
from robots.types import JointCommand, RobotState, WholeBodyTargets
from wholebody.base import ComponentSpec, register


def joint_torques(
    model: RobotModel,
    data: pin.Data,
    q: np.ndarray,
    v: np.ndarray,
    acceleration: np.ndarray,
    wrenches_limb: np.ndarray,
    in_contact: np.ndarray,
    frames: list[int],
) -> np.ndarray:
    """(n_joints,) [N m] the joint rows of RNEA(q, v, a) - sum_c J_c^T f_c over the limbs in
    contact; q, v, a in pinocchio's convention; wrenches_limb (n_limbs, 6) in the limbs' contact
    frames; frames: the limbs' pinocchio frame ids."""
    pin_model = model.model
    generalized = pin.rnea(pin_model, data, q, v, acceleration).copy()
    contacts = np.flatnonzero(in_contact)
    if contacts.size:
        pin.computeJointJacobians(pin_model, data, q)
        pin.updateFramePlacements(pin_model, data)
        for k in contacts:
            jacobian = pin.getFrameJacobian(pin_model, data, frames[k], pin.LOCAL)
            generalized -= jacobian.T @ wrenches_limb[k]
    return generalized[6:]


class InverseDynamicsLayer:
    """Torques from `WholeBodyTargets.generalized_acceleration` and the desired contact
    wrenches of the limbs in contact (see the module)."""

    name = "inverse_dynamics"

    def __init__(self, model: RobotModel, dt: float) -> None:
        self.robot_model = model
        self.data = model.model.createData()
        robot = model.robot
        self.frames = [model.frame_id[limb.contact_frame] for limb in robot.limbs]
        self.zero_gain = np.zeros(robot.n_joints)

    def reset(self, model: RobotModel, state: RobotState) -> None:
        pass

    def command(self, targets: WholeBodyTargets, state: RobotState) -> JointCommand:
        if targets.generalized_acceleration is None or targets.contact_wrench_desired_limb is None:
            raise ValueError(
                "inverse_dynamics needs a stabilizer that gives generalized_acceleration and "
                "contact_wrench_desired_limb (a whole-body dynamics controller)"
            )
        q = self.robot_model.configuration(state)
        v = self.robot_model.velocity(state, q)
        torque = joint_torques(
            self.robot_model,
            self.data,
            q,
            v,
            targets.generalized_acceleration,
            targets.contact_wrench_desired_limb,
            targets.limb_in_contact,
            self.frames,
        )
        return JointCommand(
            position=np.array(state.joint_position, dtype=float),
            velocity=np.array(state.joint_velocity, dtype=float),
            torque_feedforward=torque,
            kp=self.zero_gain,
            kd=self.zero_gain,
        )


register(
    ComponentSpec(
        "inverse_dynamics",
        InverseDynamicsLayer,
        "joint torques from accelerations and contact wrenches (eq. 1), torque control",
    )
)
