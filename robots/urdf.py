"""URDF text from a `RobotDescription` (read by pinocchio and PyBullet).

Every link carries an explicit <inertial> (PyBullet's URDF_USE_INERTIA_FROM_FILE then uses it as
written). Named frames become massless child links on fixed joints, so that pinocchio and
PyBullet both compute their poses with their own forward kinematics.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from robots.spec import Geometry, Link, RobotDescription


def _vec(values) -> str:
    return " ".join(f"{float(x):.17g}" for x in values)


def _shapes(g: Geometry) -> list[str]:
    """URDF <origin>+<geometry> strings for one primitive. A capsule, which standard URDF
    (urdfdom, used by pinocchio) lacks, is written as the same solid: a cylinder and two
    spheres."""
    rpy = _vec(g.rpy_in_link)
    if g.kind == "box":
        return [
            f'<origin xyz="{_vec(g.position_in_link)}" rpy="{rpy}"/>'
            f'<geometry><box size="{_vec(2 * x for x in g.size)}"/></geometry>'
        ]
    if g.kind == "sphere":
        return [
            f'<origin xyz="{_vec(g.position_in_link)}" rpy="{rpy}"/>'
            f'<geometry><sphere radius="{g.size[0]:.17g}"/></geometry>'
        ]
    radius, half = g.size
    axis = Rotation.from_euler("xyz", g.rpy_in_link).as_matrix()[:, 2]
    centre = np.asarray(g.position_in_link, dtype=float)
    out = [
        f'<origin xyz="{_vec(centre)}" rpy="{rpy}"/>'
        f'<geometry><cylinder radius="{radius:.17g}" length="{2 * half:.17g}"/></geometry>'
    ]
    for end in (centre + half * axis, centre - half * axis):
        out.append(
            f'<origin xyz="{_vec(end)}" rpy="0 0 0"/>'
            f'<geometry><sphere radius="{radius:.17g}"/></geometry>'
        )
    return out


def principal_axes(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The principal moments (3,) [kg m^2] and the rotation (3, 3) whose columns are the
    principal axes in the link frame (right-handed), so that inertia = R diag(moments) R^T. A
    diagonal tensor is its own: moments its diagonal, R the identity."""
    if not np.any(inertia - np.diag(np.diag(inertia))):
        return np.diag(inertia).copy(), np.eye(3)
    moments, axes = np.linalg.eigh(inertia)
    if np.linalg.det(axes) < 0:
        axes[:, 0] = -axes[:, 0]
    return moments, axes


def _link(link: Link) -> str:
    """The link's <link> element. Its inertia is written in principal axes (the <inertial>
    origin rotated onto them, the tensor diagonal): PyBullet diagonalises any other tensor
    itself, with an iterative method whose precision is its own; pinocchio rotates it back."""
    inertial = link.inertial
    moments, axes = principal_axes(inertial.inertia_matrix)
    rpy = Rotation.from_matrix(axes).as_euler("xyz") if np.any(axes != np.eye(3)) else np.zeros(3)
    parts = [
        f'  <link name="{link.name}">',
        "    <inertial>",
        f'      <origin xyz="{_vec(inertial.com_in_link)}" rpy="{_vec(rpy)}"/>',
        f'      <mass value="{inertial.mass:.17g}"/>',
        f'      <inertia ixx="{moments[0]:.17g}" ixy="0" ixz="0" '
        f'iyy="{moments[1]:.17g}" iyz="0" izz="{moments[2]:.17g}"/>',
        "    </inertial>",
    ]
    for g in link.geometries:
        for shape in _shapes(g):
            parts.append(f"    <visual>{shape}</visual>")
            if g.collides:
                parts.append(f"    <collision>{shape}</collision>")
    parts.append("  </link>")
    return "\n".join(parts)


def to_urdf(robot: RobotDescription) -> str:
    """The URDF document of `robot` (floating base: the root link has no parent joint)."""
    parts = ['<?xml version="1.0"?>', f'<robot name="{robot.name}">']
    parts += [_link(link) for link in robot.links]
    for j in robot.joints:
        parts += [
            f'  <joint name="{j.name}" type="revolute">',
            f'    <parent link="{j.parent}"/><child link="{j.child}"/>',
            f'    <origin xyz="{_vec(j.origin_in_parent)}" rpy="0 0 0"/>',
            f'    <axis xyz="{_vec(j.axis)}"/>',
            f'    <limit lower="{j.lower:.17g}" upper="{j.upper:.17g}" '
            f'velocity="{j.velocity_limit:.17g}" effort="{j.torque_limit:.17g}"/>',
            "  </joint>",
        ]
    for f in robot.frames:
        parts += [
            f'  <link name="{f.name}">',
            '    <inertial><origin xyz="0 0 0" rpy="0 0 0"/><mass value="0"/>'
            '<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>',
            "  </link>",
            f'  <joint name="{f.name}_fixed" type="fixed">',
            f'    <parent link="{f.link}"/><child link="{f.name}"/>',
            f'    <origin xyz="{_vec(f.position_in_link)}" rpy="0 0 0"/>',
            "  </joint>",
        ]
    parts.append("</robot>")
    return "\n".join(parts) + "\n"
