"""Load one robot into pinocchio, MuJoCo and PyBullet and measure how far apart the three
models are (mass, centre of mass, inertia, joint order and limits). Backs `centrobench robot`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robots.model import RobotModel
from robots.scene import Scene
from robots.spec import RobotDescription
from robots.types import MassProperties, RobotState
from sims.base import make_simulator


@dataclass(frozen=True)
class Discrepancy:
    """Largest differences of `other` from `reference` over all bodies: mass and inertia as
    relative differences (to the body's mass / the largest entry of its tensor), centre of mass
    in m; joint names and limits equal or not."""

    reference: str
    other: str
    mass_rel: float
    com_m: float
    inertia_rel: float
    same_bodies: bool
    same_joint_order: bool
    joint_limit_rad: float


def discrepancy(reference: MassProperties, other: MassProperties) -> Discrepancy:
    same_bodies = set(reference.body_names) == set(other.body_names)
    mass_rel = com = inertia_rel = np.inf
    if same_bodies:
        order = [other.body_names.index(n) for n in reference.body_names]
        m_ref, m_other = reference.mass, other.mass[order]
        mass_rel = float(np.max(np.abs(m_ref - m_other) / m_ref))
        com = float(np.max(np.abs(reference.com_in_body - other.com_in_body[order])))
        i_ref, i_other = reference.inertia_at_com_in_body, other.inertia_at_com_in_body[order]
        scale = np.abs(i_ref).reshape(len(m_ref), -1).max(axis=1)
        inertia_rel = float(
            np.max(np.abs(i_ref - i_other).reshape(len(m_ref), -1).max(axis=1) / scale)
        )
    same_joints = reference.joint_names == other.joint_names
    limits = np.inf
    if same_joints:
        limits = float(
            max(
                np.abs(reference.joint_lower - other.joint_lower).max(),
                np.abs(reference.joint_upper - other.joint_upper).max(),
            )
        )
    return Discrepancy(
        reference.source,
        other.source,
        mass_rel,
        com,
        inertia_rel,
        same_bodies,
        same_joints,
        limits,
    )


def all_mass_properties(robot: RobotDescription) -> list[MassProperties]:
    """Mass properties as pinocchio, MuJoCo and PyBullet each report them."""
    model = RobotModel(robot)
    result = [model.mass_properties()]
    for name in ("mujoco", "pybullet"):
        sim = make_simulator(name)
        try:
            sim.reset(robot, Scene(), model.standing_state())
            result.append(sim.mass_properties())
        finally:
            sim.close()
    return result


def robot_report(robot: RobotDescription) -> dict:
    """Per model: total mass, body and joint counts; the largest discrepancy of MuJoCo and
    PyBullet from pinocchio. JSON-ready."""
    props = all_mass_properties(robot)
    reference = props[0]
    models = {
        p.source: {
            "total_mass_kg": p.total_mass,
            "bodies": len(p.body_names),
            "dof": len(p.joint_names) + 6,
            "actuated_joints": len(p.joint_names),
        }
        for p in props
    }
    gaps = [discrepancy(reference, p) for p in props[1:]]
    return {
        "robot": robot.name,
        "scale": robot.scale,
        "height_m": robot_height(robot),
        "models": models,
        "max_discrepancy_vs_pinocchio": {
            g.other: {
                "mass_rel": g.mass_rel,
                "com_m": g.com_m,
                "inertia_rel": g.inertia_rel,
                "same_bodies": g.same_bodies,
                "same_joint_order": g.same_joint_order,
                "joint_limit_rad": g.joint_limit_rad,
            }
            for g in gaps
        },
    }


def robot_height(robot: RobotDescription) -> float:
    """Standing height [m] in the zero posture (every joint at 0, base upright): the top of the
    highest shape of any link above the lowest sole centre (boxes and capsules are axis-aligned
    in that posture, as every description builds them)."""
    model = RobotModel(robot)
    state = RobotState.at_rest(np.zeros(3), np.array([1.0, 0, 0, 0]), np.zeros(robot.n_joints))
    soles = [limb.contact_frame for limb in robot.limbs if limb.name.endswith("foot")]
    sole = model.frame_positions_world(state, soles)[:, 2].min()
    origins = model.frame_positions_world(state, list(robot.link_names))
    top = max(
        origin[2]
        + g.position_in_link[2]
        + (g.size[0] if g.kind == "sphere" else g.size[-1])
        + (g.size[0] if g.kind == "capsule" else 0.0)
        for link, origin in zip(robot.links, origins, strict=True)
        for g in link.geometries
    )
    return float(top - sole)
