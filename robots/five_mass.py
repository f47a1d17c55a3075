"""The five-mass centroidal description of a humanoid (Ficht & Behnke, Sec. 2).

Each leg, each arm and the torso (with pelvis, head and whatever else is not a limb) is one
point mass at the centre of mass of its links. From the five masses come the system CoM
(exactly the full robot's: the mass-weighted mean of group CoMs is the CoM of all links), the
inertia I_R about the CoM that the point masses imply,

    I_R = sum_i m_i (|d_i|^2 E - d_i d_i^T),   d_i = r_i - c,

its principal axes R_I (columns x, y, z; z the axis of the smallest moment, which points
along the body for a standing humanoid) and principal moments I_PA. What five point masses
leave out is each group's own rotational inertia about its CoM: `inertia_error` measures it
against pinocchio's composite rigid-body inertia (tests/robots/test_five_mass.py).

The groups come from the description: a limb's group is the subtree of the joint where its
chain leaves the base link (pinocchio's subtree CoMs and subtree CoM Jacobians give each in one
call), the torso is the rest. `kind` of a group: "leg" for limbs named *foot, "arm" for *hand.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from numba import njit

from robots.model import RobotModel

GROUPS = ("torso", "left_arm", "right_arm", "left_leg", "right_leg")
_LIMB_GROUP = {
    "left_hand": "left_arm",
    "right_hand": "right_arm",
    "left_foot": "left_leg",
    "right_foot": "right_leg",
}


@dataclass(frozen=True)
class FiveMass:
    """One evaluation of the five-mass description (world frame, SI units).

    mass (5,) [kg] and position_world (5, 3) [m] in `GROUPS` order; com_world (3,) [m];
    inertia_world (3, 3) [kg m^2] I_R about the CoM; axes_world (3, 3) R_I, columns the
    principal axes x, y, z (z: smallest moment, pointing up; x: closest to the base's forward
    axis; right-handed); moments (3,) [kg m^2] I_PA about x, y, z."""

    mass: np.ndarray
    position_world: np.ndarray
    com_world: np.ndarray
    inertia_world: np.ndarray
    axes_world: np.ndarray
    moments: np.ndarray


def chain_roots(model: RobotModel) -> dict[str, int]:
    """Per limb group, the pinocchio joint id where the limb's own chain begins: the topmost
    joint between the base and the limb that no other limb's chain passes through (the root
    of the subtree that is the group). On a robot whose limbs all leave the base link (the
    humanoid) it is the joint at the base; on one with a waist (JVRC-1) the arms begin at the
    shoulders, and the waist's links are the torso's, as "whatever else is not a limb" (the
    joint where the chain leaves the base, the waist, had put the whole upper body into each
    arm). ValueError if the robot lacks one of the limbs."""
    pin_model = model.model
    chains = {}
    for limb in model.robot.limbs:
        group = _LIMB_GROUP.get(limb.name)
        if group is None:
            continue
        joint = pin_model.frames[model.frame_id[limb.link]].parentJoint
        chains[group] = [j for j in pin_model.supports[joint] if j > 1]  # 1: the free flyer
    roots = {}
    for group, chain in chains.items():
        shared = {j for other, joints in chains.items() if other != group for j in joints}
        roots[group] = next(j for j in chain if j not in shared)
    missing = [g for g in GROUPS[1:] if g not in roots]
    if missing:
        raise ValueError(f"robot {model.robot.name!r} has no limb for {', '.join(missing)}")
    return roots


@njit(cache=True)
def principal_axes(
    inertia: np.ndarray, forward_world: np.ndarray, up_world: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(R_I, I_PA) of a symmetric inertia tensor: z is the eigenvector of the smallest moment
    with z . up > 0; x the eigenvector of the other two most aligned with `forward_world`
    (x . forward > 0); y = z x x."""
    moments, vectors = np.linalg.eigh(inertia)  # ascending
    z = vectors[:, 0].copy()
    if z @ up_world < 0:
        z = -z
    first, second = vectors[:, 1].copy(), vectors[:, 2].copy()
    if abs(first @ forward_world) >= abs(second @ forward_world):
        x, x_moment, y_moment = first, moments[1], moments[2]
    else:
        x, x_moment, y_moment = second, moments[2], moments[1]
    if x @ forward_world < 0:
        x = -x
    axes = np.empty((3, 3))
    axes[:, 0] = x
    axes[:, 1] = np.array(
        [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
    )
    axes[:, 2] = z
    return axes, np.array([x_moment, y_moment, moments[0]])


@njit(cache=True)
def point_mass_inertia(
    mass: np.ndarray, position_world: np.ndarray, com_world: np.ndarray
) -> np.ndarray:
    """I_R [kg m^2] about `com_world` of point masses (k,) [kg] at (k, 3) [m]."""
    second_moment = np.zeros((3, 3))  # sum_i m_i d_i d_i^T
    for i in range(len(mass)):
        d = position_world[i] - com_world
        second_moment += mass[i] * np.outer(d, d)
    return np.trace(second_moment) * np.eye(3) - second_moment


@njit(cache=True)
def five_masses(
    total_mass: float,
    com_world: np.ndarray,
    limbs_mass: np.ndarray,
    limbs_position_world: np.ndarray,
    forward_world: np.ndarray,
    up_world: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The five masses (torso first: the rest of the robot), positions, I_R, R_I and I_PA
    from the four limb groups' masses (4,) [kg] and CoMs (4, 3) [m] and the system CoM."""
    torso_mass = total_mass - limbs_mass.sum()
    mass = np.empty(5)
    position = np.empty((5, 3))
    mass[0] = torso_mass
    mass[1:] = limbs_mass
    position[0] = (total_mass * com_world - limbs_mass @ limbs_position_world) / torso_mass
    position[1:] = limbs_position_world
    inertia = point_mass_inertia(mass, position, com_world)
    axes, moments = principal_axes(inertia, forward_world, up_world)
    return mass, position, inertia, axes, moments


class FiveMassModel:
    """Evaluates the five-mass description of one robot; keeps its own pinocchio data."""

    def __init__(self, model: RobotModel) -> None:
        self.robot_model = model
        self.model = model.model
        self.data = self.model.createData()
        self.roots = chain_roots(model)
        self.root_ids = [self.roots[g] for g in GROUPS[1:]]
        self.total_mass = model.total_mass
        self.base_frame = model.frame_id[model.robot.base_link]

    def evaluate(self, q: np.ndarray) -> FiveMass:
        """The description at pinocchio configuration `q` (base included)."""
        pin.centerOfMass(self.model, self.data, q, True)  # subtree CoMs in data.com / mass
        pin.updateFramePlacement(self.model, self.data, self.base_frame)
        return self.from_data()

    def from_data(self, data: pin.Data | None = None) -> FiveMass:
        """The description from the subtree CoMs already in `data` (default `self.data`; after
        `pin.centerOfMass(..., True)`) and the base frame's placement in it."""
        data = self.data if data is None else data
        com = np.array(data.com[0])
        limbs_mass = np.array([data.mass[j] for j in self.root_ids])
        # a subtree's CoM is in its joint's frame (pinocchio's data.com[j], j > 0)
        limbs_position = np.array([data.oMi[j].act(data.com[j]) for j in self.root_ids])
        base = data.oMf[self.base_frame].rotation
        mass, position, inertia, axes, moments = five_masses(
            self.total_mass, com, limbs_mass, limbs_position, base[:, 0].copy(), base[:, 2].copy()
        )
        return FiveMass(mass, position, com, inertia, axes, moments)

    def jacobians(self, q: np.ndarray) -> tuple[FiveMass, np.ndarray]:
        """The description at `q` and the Jacobians (5, 3, nv) of the five positions (world
        axes, pinocchio's velocity: base twist in the base frame, then the joints)."""
        model, data = self.model, self.data
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        jacobian_com = pin.jacobianCenterOfMass(model, data, q, False).copy()
        pin.centerOfMass(model, data, q, True)
        five = self.from_data()  # before the subtree Jacobians, which rewrite data.com
        limb_jacobians = [
            pin.jacobianSubtreeCenterOfMass(model, data, j).copy() for j in self.root_ids
        ]
        limbs = np.array(limb_jacobians)
        torso = (self.total_mass * jacobian_com - np.einsum("i,ijk->jk", five.mass[1:], limbs)) / (
            five.mass[0]
        )
        return five, np.concatenate([torso[None], limbs])


def inertia_error(model: RobotModel, q: np.ndarray) -> tuple[float, float]:
    """How far five point masses are from the full robot at `q`: (CoM distance [m], relative
    Frobenius error of I_R against pinocchio's composite rigid-body inertia about the CoM)."""
    five = FiveMassModel(model).evaluate(q)
    data = model.model.createData()
    pin.ccrba(model.model, data, q, np.zeros(model.model.nv))
    full_com = np.array(data.com[0])
    full = np.array(data.Ig.inertia)  # rotational inertia about the CoM, world axes
    com_error = float(np.linalg.norm(five.com_world - full_com))
    return com_error, float(np.linalg.norm(five.inertia_world - full) / np.linalg.norm(full))


__all__ = [
    "GROUPS",
    "FiveMass",
    "FiveMassModel",
    "chain_roots",
    "inertia_error",
    "point_mass_inertia",
    "principal_axes",
]
