"""`ik_feedforward`: a whole-body layer (ours; the default is the paper's `ik`),
`WholeBodyTargets` -> `JointCommand`.

Joint position and velocity targets from the IK (`wholebody.ik`); feed-forward torques that hold
the IK's configuration against gravity with the contact limbs carrying the load:
tau_ff = g_j(q) - J_c,j^T w, with w the desired contact wrenches if the stabilizer gives them
(converted to world axes at each contact frame), else the least-norm static wrenches (as in
`RobotModel.static_torques`); plus the stabilizer's own joint torques, if any. Servo gains are
the description's.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from robots.model import RobotModel
from robots.types import JointCommand, RobotState, WholeBodyTargets
from wholebody.base import ComponentSpec, register
from wholebody.ik import IKWeights, WholeBodyIK


class IkFeedforwardLayer:
    name = "ik_feedforward"

    def __init__(
        self, model: RobotModel, dt: float, weights: IKWeights | None = None, solver: str = "daqp"
    ) -> None:
        self.robot_model = model
        self.ik = WholeBodyIK(model, dt, weights, solver)
        self.model = model.model
        self.data = self.model.createData()
        robot = model.robot
        self.limb_frames = [model.frame_id[limb.contact_frame] for limb in robot.limbs]
        self.kp = robot.array("kp")
        self.kd = robot.array("kd")

    def reset(self, model: RobotModel, state: RobotState) -> None:
        self.ik.reset(state)

    def command(self, targets: WholeBodyTargets, state: RobotState) -> JointCommand:
        position, velocity = self.ik.solve(targets)
        return JointCommand(position, velocity, self._feedforward(targets), self.kp, self.kd)

    def _feedforward(self, targets: WholeBodyTargets) -> np.ndarray:
        model, data, q = self.model, self.data, self.ik.q
        gravity = pin.computeGeneralizedGravity(model, data, q)
        contacts = [k for k, flag in enumerate(targets.limb_in_contact.tolist()) if flag]
        torque = gravity[6:].copy()
        if len(contacts):
            pin.computeJointJacobians(model, data, q)
            pin.updateFramePlacements(model, data)
            jacobian = np.vstack(
                [
                    pin.getFrameJacobian(model, data, self.limb_frames[k], pin.LOCAL_WORLD_ALIGNED)
                    for k in contacts
                ]
            )
            if targets.contact_wrench_desired_limb is not None:
                wrenches = np.concatenate(
                    [  # force and moment, each rotated from the limb frame to the world
                        (
                            np.reshape(targets.contact_wrench_desired_limb[k], (2, 3))
                            @ data.oMf[self.limb_frames[k]].rotation.T
                        ).ravel()
                        for k in contacts
                    ]
                )
            else:  # least-norm solution of J_b^T w = g_b: w = J_b (J_b^T J_b)^-1 g_b
                base = jacobian[:, :6]
                wrenches = base @ np.linalg.solve(base.T @ base, gravity[:6])
            torque -= jacobian[:, 6:].T @ wrenches
        if targets.joint_torque is not None:
            torque += targets.joint_torque
        return torque


register(
    ComponentSpec(
        "ik_feedforward",
        IkFeedforwardLayer,
        "IK joint targets plus feed-forward torques g(q) - J_c^T w^d",
    )
)
