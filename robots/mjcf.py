"""MJCF text from a `RobotDescription` (read by MuJoCo through `mujoco.MjSpec`).

The robot only: a free joint at the root, explicit full inertias (MuJoCo ignores geom masses
when a body has an <inertial>), hinge joints without armature, damping or friction loss (the
servo law lives in `sims.servo`, identical for every simulator), one torque motor per joint,
sites for the named frames, and IMU sensors. The scene (ground, boxes) is added by
`sims.mujoco_sim` through MjSpec.

Collision filtering: robot geoms have contype=1, conaffinity=0, so they collide with the scene
(contype=0, conaffinity=1) and never with each other; PyBullet's default (no self-collision)
matches.
"""

from __future__ import annotations

from robots.spec import Geometry, RobotDescription

_MJ_KIND = {"box": "box", "sphere": "sphere", "capsule": "capsule"}


def _vec(values) -> str:
    return " ".join(f"{float(x):.17g}" for x in values)


def _geom(g: Geometry, name: str) -> str:
    if g.collides:
        collision = 'contype="1" conaffinity="0" group="0"'
    else:
        collision = 'contype="0" conaffinity="0" group="1"'
    return (
        f'<geom name="{name}" type="{_MJ_KIND[g.kind]}" size="{_vec(g.size)}" '
        f'pos="{_vec(g.position_in_link)}" euler="{_vec(g.rpy_in_link)}" {collision}/>'
    )


def to_mjcf(robot: RobotDescription) -> str:
    """The MJCF document of `robot` (angles in radians, XYZ fixed-axis euler for geoms)."""
    children: dict[str, list] = {link.name: [] for link in robot.links}
    for j in robot.joints:
        children[j.parent].append(j)
    frames_on: dict[str, list] = {link.name: [] for link in robot.links}
    for f in robot.frames:
        frames_on[f.link].append(f)

    def body(name: str, joint, indent: str) -> list[str]:
        link = robot.link(name)
        inertial = link.inertial
        i = inertial.inertia_matrix
        pos = joint.origin_in_parent if joint is not None else (0.0, 0.0, 0.0)
        out = [f'{indent}<body name="{name}" pos="{_vec(pos)}">']
        inner = indent + "  "
        if joint is None:
            out.append(f'{inner}<freejoint name="root"/>')
        else:
            out.append(
                f'{inner}<joint name="{joint.name}" type="hinge" axis="{_vec(joint.axis)}" '
                f'range="{joint.lower:.17g} {joint.upper:.17g}" limited="true" '
                'armature="0" damping="0" frictionloss="0"/>'
            )
        out.append(
            f'{inner}<inertial pos="{_vec(inertial.com_in_link)}" mass="{inertial.mass:.17g}" '
            f'fullinertia="{_vec([i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]])}"/>'
        )
        for n, g in enumerate(link.geometries):
            out.append(inner + _geom(g, f"{name}_geom{n}"))
        for f in frames_on[name]:
            out.append(
                f'{inner}<site name="{f.name}" pos="{_vec(f.position_in_link)}" size="0.01"/>'
            )
        for child in children[name]:
            out += body(child.child, child, inner)
        out.append(f"{indent}</body>")
        return out

    lines = [
        f'<mujoco model="{robot.name}">',
        '  <compiler angle="radian" inertiafromgeom="false" autolimits="true"'
        ' balanceinertia="false"/>',
        "  <worldbody>",
        *body(robot.base_link, None, "    "),
        "  </worldbody>",
        "  <actuator>",
    ]
    for j in robot.joints:
        lines.append(
            f'    <motor name="{j.name}" joint="{j.name}" gear="1" ctrllimited="true" '
            f'ctrlrange="{-j.torque_limit:.17g} {j.torque_limit:.17g}"/>'
        )
    lines += [
        "  </actuator>",
        "  <sensor>",
        f'    <framequat name="imu_quat" objtype="site" objname="{robot.imu_frame}"/>',
        f'    <gyro name="imu_gyro" site="{robot.imu_frame}"/>',
        f'    <accelerometer name="imu_accel" site="{robot.imu_frame}"/>',
        "  </sensor>",
        "</mujoco>",
    ]
    return "\n".join(lines) + "\n"
