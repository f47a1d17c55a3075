"""Whole-body layer `five_mass_pose`: our stand-in for Ficht & Behnke's pose generator (their
[12], not in the seeds), which turns the CoM, the CoM-relative foot frames and the inertia
orientation R_I and moments I_PA into joint positions.

It is the whole-body IK (`wholebody.ik`) with the tasks changed to the generator's inputs:
- the CoM at x_set and the feet at their frames (the IK's CoM and limb tasks; our feet targets
  are in the world, which is the same once the CoM is where it is set);
- the principal z axis of the five-mass inertia I_R (`robots.five_mass`) along the z axis of
  R_I^set: 3 rows with the analytic Jacobian of the eigenvector,
  de_z = sum_{j in x, y} e_j (e_j^T dI e_z) / (lambda_z - lambda_j), dI from the five point
  masses' Jacobians (pinocchio's subtree CoM Jacobians);
- the trunk's yaw at the targets' base yaw (`WholeBodyTargets.base_orientation_world`; the
  generator turns the trunk to the set inertia yaw psi_I, which `planners.five_mass_gait`
  plans from the same heading);
  the trunk's roll and pitch are free, so that the inertia tilt is realised by the upper body
  against the legs, as the generator's dumbbell tilt;
- the arms held to the trunk (each free arm's own joints at their nominal angles,
  `ARM_POSTURE_WEIGHT`; ours): the generator places the trunk "with its mass pointing towards
  m_u" (Sec. 2), so the tilt is the trunk's. Until 2026-12-01 only the weak posture task held
  the arms, and the IK realised a lateral tilt by swinging them sideways (with both knees
  straight, shoulder rolls 9-18 rad per rad of tilt and the base roll 0.05; in single support
  5.9 and 2.2; with bent knees 1.4 and 2.9); held, the base rolls 3.1 rad per rad with bent
  knees or in single support. With both knees held straight in a double support the trunk
  cannot roll far (the hips' heights are fixed): the base rolls 0.09 rad per rad, an arm
  joint still moves 2.4, and the tilt is hardly realised (measured with the knees at their
  target; 0.46 and 2.1 with them still bending, until 2026-12-04). The paper's generator moves its
  arms by its own rules (their triangle parameters, the m_u dumbbell's yaw psi_u, the CoM
  height under the straight-leg constraint); this one holds them;
- joint positions to the servos, no feed-forward torque (the paper's robot is position
  controlled, Sec. 4); or, as a variant (`feedforward=True`, `five_mass_pose_feedforward`),
  with the gravity torques of the limbs that carry no contact (`FreeLimbGravity`): the
  gravity part, on the joints where it does not depend on how the load splits between the
  feet, of the model feed-forward of the authors' platform software. humanoid_op_ros (the
  paper's [3]; AIS-Bonn/humanoid_op_ros, `nimbro_op_interface/src/robotinterface.cpp`)
  offsets each servo's position command by a model torque
  (`ServoCommandGenerator::servoCommandFor(pos, vel, acc, outsideTorque)`, called with the
  joint's `modelTorque`: pos + a factor x (k_m torque + viscous and Stribeck friction terms),
  the same as a feed-forward torque on a position servo, blended in through a slope-limited
  `rawState`); the model torque is the inverse dynamics (gravity, and the commanded joint
  velocities and accelerations) of single-support models weighted by the gait's support
  coefficients (`SingleSupportModel`); it is on when `useModel` is set (in one of the
  repository's three robot configurations, `config_xs1.yaml`; the paper does not say). Left
  out here: the friction terms, the velocity and acceleration terms, the support legs' share,
  and the support coefficients' ramps (this torque switches at each exchange).

How it differs from the paper's generator: it solves one weighted least-squares step per
period instead of the generator's closed-form top-down construction (virtual leg, dumbbells);
it does not set the principal moments I_PA (the posture task keeps the arms and legs near the
nominal posture instead) nor the separate dumbbell yaws psi_l, psi_u; and the straight-support
-leg constraint (Sec. 2) is an option (`straight_leg`): a task holding each contact leg's knee
at its lower limit plus a margin (both knees in double support, where the paper straightens
the one supporting leg), with the CoM height left free (the paper keeps vertical CoM control,
by the upper body and arms), instead of a shift of the base frame.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from numba import njit

from robots.five_mass import FiveMassModel
from robots.model import RobotModel
from robots.types import JointCommand, RobotState, WholeBodyTargets
from wholebody.base import ComponentSpec, register
from wholebody.ik import IKWeights, WholeBodyIK
from wholebody.ik_only import IkLayer

INERTIA_AXIS_WEIGHT = 1e2  # as the base orientation task's (errors in rad)
ARM_POSTURE_WEIGHT = 1.0  # the free arms held to the trunk: 100x the posture task's
KNEE_MARGIN_RAD = 0.1  # a straight knee less this margin (5.7 deg): away from the singularity
KNEE_WEIGHT = 1e3  # as the CoM task's; its error is scaled by dt / KNEE_TIME_CONSTANT_S
# (0.0067 at 2 ms), so against a conflicting task at rest it weighs about 1e3 x 0.0067 = 7,
# below the inertia axis's 1e2 (ours: measured, the knees still reach their target within
# 5 mrad when only the CoM, feet and inertia axis are held, tests/wholebody)
KNEE_TIME_CONSTANT_S = 0.3  # [s] how fast a knee straightens (not in one period: it jumps)


@njit(cache=True)
def inertia_axis_jacobian(
    mass: np.ndarray,
    position_world: np.ndarray,
    jacobians: np.ndarray,
    axes_world: np.ndarray,
    moments: np.ndarray,
) -> np.ndarray:
    """(3, nv) Jacobian of the principal z axis of the point masses' inertia about their CoM
    (first-order perturbation of a symmetric eigenproblem): de_z = sum_{j in x, y} e_j
    (e_j^T dI e_z) / (lambda_z - lambda_j), where for j != z
    e_j^T dI e_z = -sum_i m_i ((e_j . dd_i)(d_i . e_z) + (e_j . d_i)(e_z . dd_i)),
    d_i = r_i - c, dd_i = (J_i - J_c) dv. mass (k,), position_world (k, 3), jacobians
    (k, 3, nv) of the positions, axes_world columns (x, y, z), moments (3,)."""
    k, _, nv = jacobians.shape
    total = mass.sum()
    com = np.zeros(3)
    jacobian_com = np.zeros((3, nv))
    for i in range(k):
        com += mass[i] * position_world[i]
        jacobian_com += mass[i] * jacobians[i]
    com /= total
    jacobian_com /= total
    e_z = axes_world[:, 2].copy()
    result = np.zeros((3, nv))
    for j in range(2):
        e_j = axes_world[:, j].copy()
        coupling = np.zeros(nv)
        for i in range(k):
            d = position_world[i] - com
            jd = jacobians[i] - jacobian_com
            coupling -= mass[i] * ((e_j @ jd) * (d @ e_z) + (e_j @ d) * (e_z @ jd))
        coupling /= moments[2] - moments[j]
        for row in range(3):
            result[row] += e_j[row] * coupling
    return result


def limb_chains(model: RobotModel) -> list[np.ndarray]:
    """Per limb (in limb order), the indices (in joint order) of the joints between the base
    and the limb's link, from the limb toward the base (the humanoid's left foot: ankle roll,
    ankle pitch, knee, hip pitch, hip roll, hip yaw): the joints whose torques a contact at
    that limb loads."""
    robot = model.robot
    parent_joint = {j.child: j for j in robot.joints}
    chains = []
    for limb in robot.limbs:
        link, chain = limb.link, []
        while link in parent_joint:
            joint = parent_joint[link]
            chain.append(robot.joint_names.index(joint.name))
            link = joint.parent
        chains.append(np.array(chain, dtype=int))
    return chains


def knee_indices(model: RobotModel) -> dict[str, int]:
    """Per foot limb, the index (in joint order) of the knee on its chain: the joint whose
    name contains "knee" in any case (the humanoid's `left_knee`, JVRC-1's `L_KNEE`) between the
    base and the foot (the one nearest the base if several). ValueError naming the foot
    without one."""
    robot = model.robot
    result = {}
    for limb, chain in zip(robot.limbs, limb_chains(model), strict=True):
        if not limb.name.endswith("foot"):
            continue
        knees = [j for j in chain.tolist() if "knee" in robot.joint_names[j].lower()]
        if not knees:
            raise ValueError(f"{robot.name}: no joint named *knee on the chain of {limb.name}")
        result[limb.name] = knees[-1]
    return result


def arm_joints(model: RobotModel) -> dict[int, np.ndarray]:
    """Per hand limb (by limb index), the indices (in joint order) of the joints on its chain
    (`limb_chains`) and on no other limb's: the arm's own joints, without a waist that carries
    both arms (JVRC-1's three waist joints are on both hands' chains; the humanoid has none).
    The same rule as the five-mass groups' (`robots.five_mass.chain_roots`), as joint indices."""
    robot = model.robot
    chains = limb_chains(model)
    result = {}
    for k, limb in enumerate(robot.limbs):
        if not limb.name.endswith("hand"):
            continue
        shared = set().union(*(set(c.tolist()) for i, c in enumerate(chains) if i != k))
        result[k] = np.array([j for j in chains[k].tolist() if j not in shared], dtype=int)
    return result


class FiveMassIK(WholeBodyIK):
    """The IK with the inertia-axis task and the base's yaw only (see the module)."""

    def __init__(
        self,
        model: RobotModel,
        dt: float,
        weights: IKWeights | None = None,
        straight_leg: bool = True,
    ) -> None:
        knees = knee_indices(model)
        limbs = model.robot.limb_names
        self.knees = [(limbs.index(name), index) for name, index in knees.items()]
        self.arm_joints = arm_joints(model)
        n_arm = sum(len(joints) for joints in self.arm_joints.values())
        # rows: the inertia axis (3), a knee per leg, an arm's own joints
        super().__init__(model, dt, weights, extra_rows=3 + len(self.knees) + n_arm)
        self.five = FiveMassModel(model)
        self.base_orientation_weights[:2] = 0.0  # roll and pitch: free
        self.straight_leg = straight_leg
        self.knee_rate = min(1.0, dt / KNEE_TIME_CONSTANT_S)

    def _extra_rows(self, q: np.ndarray, targets: WholeBodyTargets, n: int) -> int:
        if self.straight_leg:
            n = self._straight_legs(q, targets, n)
        n = self._held_arms(q, targets, n)
        axes_target = targets.inertia_axes_world
        if axes_target is None:
            return n
        five, jacobians = self.five.jacobians(q)
        self._jacobian[n : n + 3] = inertia_axis_jacobian(
            five.mass, five.position_world, jacobians, five.axes_world, five.moments
        )
        self._error[n : n + 3] = axes_target[:, 2] - five.axes_world[:, 2]
        self._weight[n : n + 3] = INERTIA_AXIS_WEIGHT
        return n + 3

    def _held_arms(self, q: np.ndarray, targets: WholeBodyTargets, n: int) -> int:
        """Ours, after Sec. 2's trunk "placed with its mass pointing towards m_u": every joint
        of an untracked arm's own (`arm_joints`) held at its nominal angle with
        `ARM_POSTURE_WEIGHT`, so that the inertia tilt is realised by the trunk against the
        legs and not by swinging the arms (with the plain posture task a lateral tilt moved a
        shoulder roll 1.4 rad per rad of tilt with bent knees, 5.9 in single support on a
        straight leg). The paper's generator does move its arms (their own triangle
        parameters, the m_u dumbbell's yaw psi_u, the CoM height under the straight-leg
        constraint); this one holds them. With both knees straight in a double support the
        trunk can hardly roll and the arms still give (2.1 rad per rad, from 18). A tracked
        arm (or every limb, `limb_tracked` None, as `WholeBodyIK.solve` reads it) follows its
        target instead."""
        tracked = targets.limb_tracked
        for k, joints in self.arm_joints.items():
            if tracked is None or tracked[k]:
                continue
            for j in joints:
                self._jacobian[n] = 0.0
                self._jacobian[n, 6 + j] = 1.0
                self._error[n] = self.nominal[j] - q[7 + j]
                self._weight[n] = ARM_POSTURE_WEIGHT
                n += 1
        return n

    def _straight_legs(self, q: np.ndarray, targets: WholeBodyTargets, n: int) -> int:
        """The straight-support-leg constraint: each contact leg's knee at its lower limit
        plus `KNEE_MARGIN_RAD` (weight `KNEE_WEIGHT`), and the CoM's height task freed (its
        row is the last of the CoM rows written before this call: see `WholeBodyIK.solve`)."""
        supporting = [(limb, j) for limb, j in self.knees if targets.limb_in_contact[limb]]
        if not supporting:
            return n
        self._weight[n - 6 + 2] = 0.0  # the CoM z row (CoM rows, then 3 base rows, end at n)
        for _, j in supporting:
            self._jacobian[n] = 0.0
            self._jacobian[n, 6 + j] = 1.0
            # approached with the time constant KNEE_TIME_CONSTANT_S, not in one period
            self._error[n] = (self.lower[j] + KNEE_MARGIN_RAD - q[7 + j]) * self.knee_rate
            self._weight[n] = KNEE_WEIGHT
            n += 1
        return n


class FreeLimbGravity:
    """Feed-forward torques [N m] that hold the limbs carrying no contact against gravity:
    g_j(q) (pinocchio's generalised gravity at the IK's configuration) on every joint that lies
    on no contact limb's chain, 0 on the contact limbs' chains. On a free joint the torque
    holds the subtree beyond it, whatever the contacts carry, so it is exact at rest (a moving
    base or limb adds inertial terms, left out); on a contact chain it would depend on how the
    load splits between the contacts, which this layer does not know (the stabilizer sets no
    contact wrenches), so none is given there."""

    def __init__(self, model: RobotModel) -> None:
        self.model = model.model
        self.data = self.model.createData()
        self.chains = limb_chains(model)

    def torques(self, q: np.ndarray, limb_in_contact: np.ndarray) -> np.ndarray:
        gravity = pin.computeGeneralizedGravity(self.model, self.data, q)[6:].copy()
        for chain, contact in zip(self.chains, limb_in_contact.tolist(), strict=True):
            if contact:
                gravity[chain] = 0.0
        return gravity


class FiveMassPoseLayer(IkLayer):
    """`ik`'s command (joint positions to the servos, no feed-forward torque) from the
    five-mass IK; with `feedforward`, plus the free limbs' gravity torques
    (`FreeLimbGravity`)."""

    name = "five_mass_pose"

    def __init__(
        self, model: RobotModel, dt: float, straight_leg: bool = True, feedforward: bool = False
    ) -> None:
        super().__init__(model, dt)
        self.ik = FiveMassIK(model, dt, straight_leg=straight_leg)
        self.gravity = FreeLimbGravity(model) if feedforward else None

    def command(self, targets: WholeBodyTargets, state: RobotState) -> JointCommand:
        position, velocity = self.ik.solve(targets)
        torque = (
            self.zero_torque
            if self.gravity is None
            else self.gravity.torques(self.ik.q, targets.limb_in_contact)
        )
        return JointCommand(position, velocity, torque, self.kp, self.kd)


def _bent(model: RobotModel, dt: float) -> FiveMassPoseLayer:
    return FiveMassPoseLayer(model, dt, straight_leg=False)


def _feedforward(model: RobotModel, dt: float) -> FiveMassPoseLayer:
    return FiveMassPoseLayer(model, dt, feedforward=True)


def _bent_feedforward(model: RobotModel, dt: float) -> FiveMassPoseLayer:
    return FiveMassPoseLayer(model, dt, straight_leg=False, feedforward=True)


register(
    ComponentSpec(
        "five_mass_pose",
        FiveMassPoseLayer,
        "IK with five-mass CoM, inertia-axis, foot and straight-support-leg tasks (Ficht & Behnke)",
    )
)
register(
    ComponentSpec(
        "five_mass_pose_bent",
        _bent,
        "five_mass_pose without the straight-support-leg constraint (Table 1 ablation)",
    )
)
register(
    ComponentSpec(
        "five_mass_pose_feedforward",
        _feedforward,
        "five_mass_pose plus the free limbs' gravity torques (the authors' platform's servo "
        "model, in part)",
    )
)
register(
    ComponentSpec(
        "five_mass_pose_bent_feedforward",
        _bent_feedforward,
        "five_mass_pose_bent plus the free limbs' gravity torques",
    )
)
