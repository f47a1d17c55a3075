"""`ik`: joint position and velocity targets from the IK only, no feed-forward torque, as on
Murooka et al.'s robot: "the calculated joint angles are commanded to the low-level joint
position PD controller" (Sec. V-A1). Servo gains are the description's, as for every layer.
"""

from __future__ import annotations

import numpy as np

from robots.model import RobotModel
from robots.types import JointCommand, RobotState, WholeBodyTargets
from wholebody.base import ComponentSpec, register
from wholebody.ik import IKWeights, WholeBodyIK


class IkLayer:
    name = "ik"

    def __init__(
        self, model: RobotModel, dt: float, weights: IKWeights | None = None, solver: str = "daqp"
    ) -> None:
        self.ik = WholeBodyIK(model, dt, weights, solver)
        robot = model.robot
        self.kp = robot.array("kp")
        self.kd = robot.array("kd")
        self.zero_torque = np.zeros(robot.n_joints)

    def reset(self, model: RobotModel, state: RobotState) -> None:
        self.ik.reset(state)

    def command(self, targets: WholeBodyTargets, state: RobotState) -> JointCommand:
        position, velocity = self.ik.solve(targets)
        return JointCommand(position, velocity, self.zero_torque, self.kp, self.kd)


register(
    ComponentSpec(
        "ik",
        IkLayer,
        "IK joint targets to the position servos, no feed-forward torque (Murooka Sec. V-A1)",
    )
)


IK_ANGULAR_MOMENTUM_WEIGHT = 100.0
"""`ik_angular_momentum`'s weight on the centroidal angular momentum of the IK's step, I_all dq
-> L^p dt, the plan's angular momentum I omega^p (eq. 6) over the period (Murooka Sec. V-F:
"adding the angular momentum task [1] to the whole-body IK"; the authors' MultiContactController
sets its momentum task's target to the planned centroidal momentum; until 2026-12-03 ours drove
it to zero, which held the base back from a planned turn, 8.5 % of a 0.1 rad pitch). The paper
gives no weight: ours, as the IK's other weights, dimensionless on dq [rad or m]."""


def _ik_angular_momentum(model: RobotModel, dt: float) -> IkLayer:
    layer = IkLayer(model, dt, IKWeights(angular_momentum=IK_ANGULAR_MOMENTUM_WEIGHT))
    layer.name = "ik_angular_momentum"
    return layer


register(
    ComponentSpec(
        "ik_angular_momentum",
        _ik_angular_momentum,
        "`ik` with the centroidal angular momentum task (Murooka Sec. V-F's option)",
    )
)
