"""The robot description: plain, simulator-independent data (SI units, world Z up).

A `RobotDescription` is a kinematic tree of rigid links joined by revolute joints, with the
floating base at the root. Every joint frame is aligned with its parent link frame in the zero
configuration (joint origins carry a translation only), so each joint's axis is a unit vector
of the parent/child link frame. Named frames (contact surfaces, IMU, force/torque sensors) are
rigidly attached to a link.

Generators turn one description into a URDF (pinocchio, PyBullet) and an MJCF (MuJoCo); see
`robots.urdf` and `robots.mjcf`. Nothing here imports a simulator.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

GeometryKind = Literal["box", "capsule", "sphere"]
FrameKind = Literal["contact", "imu", "force_torque"]


@dataclass(frozen=True)
class Geometry:
    """A primitive solid in its link's frame.

    `size`: box -> half extents (x, y, z) [m]; capsule -> (radius, half length of the
    cylinder part along the geometry's z axis) [m]; sphere -> (radius,) [m].
    `position_in_link` [m], `rpy_in_link` [rad] (fixed-axis roll, pitch, yaw).
    `collides`: whether the shape is also a collision shape (all shapes are visual).
    """

    kind: GeometryKind
    size: tuple[float, ...]
    position_in_link: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy_in_link: tuple[float, float, float] = (0.0, 0.0, 0.0)
    collides: bool = True


@dataclass(frozen=True)
class Inertial:
    """Mass [kg], centre of mass in the link frame [m], inertia tensor about the centre of mass
    expressed in the link frame [kg m^2] (a symmetric 3x3 as a nested tuple)."""

    mass: float
    com_in_link: tuple[float, float, float]
    inertia_at_com: tuple[tuple[float, float, float], ...]

    @property
    def inertia_matrix(self) -> np.ndarray:
        return np.array(self.inertia_at_com, dtype=float)


@dataclass(frozen=True)
class Link:
    name: str
    inertial: Inertial
    geometries: tuple[Geometry, ...] = ()


@dataclass(frozen=True)
class Joint:
    """A revolute joint. `origin_in_parent` [m] places the joint (and child link) frame in the
    parent link frame; `axis` is a unit vector in that frame. Limits: position [rad], velocity
    [rad/s], torque [N m]. Servo gains `kp` [N m/rad] and `kd` [N m s/rad] are the defaults of
    the joint servo law shared by every simulator (see `sims.servo`)."""

    name: str
    parent: str
    child: str
    origin_in_parent: tuple[float, float, float]
    axis: tuple[float, float, float]
    lower: float
    upper: float
    velocity_limit: float
    torque_limit: float
    kp: float
    kd: float


@dataclass(frozen=True)
class Frame:
    """A named frame rigidly attached to `link`, at `position_in_link` [m], axes aligned with
    the link frame. Contact frames (sole / palm centres) have their z axis pointing from the
    contact surface into the limb, so a pushing contact force has a positive z component."""

    name: str
    link: str
    position_in_link: tuple[float, float, float]
    kind: FrameKind


@dataclass(frozen=True)
class Limb:
    """A limb end that can make contact: its link, its contact frame (sole or palm centre), the
    force/torque sensor frame on it (described, not used: the simulators report the contact
    wrench at the contact frame, which leaves out the limb's own weight and inertia that a
    sensor in the ankle or wrist would carry), and the rectangular contact surface half
    extents in the contact frame's x and y [m]."""

    name: str
    link: str
    contact_frame: str
    sensor_frame: str
    half_extents: tuple[float, float]
    touch_links: tuple[str, ...] = ()
    """Other links of the limb that may touch the scene without the robot counting as fallen
    (a hand's arm beside the rail it holds, `sims.base`); their contacts are not
    in the limb's wrench, as a wrist force/torque sensor would not measure them."""


@dataclass(frozen=True)
class RobotDescription:
    """One humanoid, fully described. `links[0]` is the floating base."""

    name: str
    scale: float
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    frames: tuple[Frame, ...]
    limbs: tuple[Limb, ...]
    imu_frame: str
    nominal_posture: tuple[float, ...]
    """Joint positions of the standing posture [rad], in `joints` order."""
    fall_height: float
    """A base (pelvis) height below this [m] counts as a fall."""

    @property
    def base_link(self) -> str:
        return self.links[0].name

    @property
    def torso_link(self) -> str:
        """The link the arms branch from (the humanoid's base, JVRC-1's chest above its waist
        joints): the deepest link on the chains from the base to both hands; the base link for
        a robot with fewer than two hands. Pushes and payloads act on it."""
        parent_of = {joint.child: joint.parent for joint in self.joints}

        def chain(link: str) -> list[str]:
            links = [link]
            while links[-1] in parent_of:
                links.append(parent_of[links[-1]])
            return links[::-1]  # base first

        hands = [limb.link for limb in self.limbs if limb.name.endswith("hand")]
        if len(hands) < 2:
            return self.base_link
        left, right = chain(hands[0]), chain(hands[1])
        return [a for a, b in zip(left, right, strict=False) if a == b][-1]

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)

    @property
    def link_names(self) -> tuple[str, ...]:
        return tuple(link.name for link in self.links)

    @property
    def limb_names(self) -> tuple[str, ...]:
        return tuple(limb.name for limb in self.limbs)

    @property
    def total_mass(self) -> float:
        """[kg]"""
        return float(sum(link.inertial.mass for link in self.links))

    @property
    def n_joints(self) -> int:
        return len(self.joints)

    def array(self, attribute: str) -> np.ndarray:
        """A per-joint attribute (e.g. "kp", "torque_limit") as an array in joint order."""
        return np.array([getattr(j, attribute) for j in self.joints], dtype=float)

    def link(self, name: str) -> Link:
        for link in self.links:
            if link.name == name:
                return link
        raise KeyError(f"no link {name!r}; links: {', '.join(self.link_names)}")

    def frame(self, name: str) -> Frame:
        for frame in self.frames:
            if frame.name == name:
                return frame
        raise KeyError(f"no frame {name!r}; frames: {', '.join(f.name for f in self.frames)}")

    def limb(self, name: str) -> Limb:
        for limb in self.limbs:
            if limb.name == name:
                return limb
        raise KeyError(f"no limb {name!r}; limbs: {', '.join(self.limb_names)}")

    def validate(self) -> None:
        """Raise ValueError if the tree, limits or inertias are inconsistent."""
        names = set(self.link_names)
        if len(names) != len(self.links):
            raise ValueError("duplicate link names")
        seen = {self.base_link}
        for joint in self.joints:
            if joint.parent not in seen:
                raise ValueError(f"joint {joint.name}: parent {joint.parent} not defined before it")
            if joint.child not in names or joint.child in seen:
                raise ValueError(f"joint {joint.name}: bad child {joint.child}")
            seen.add(joint.child)
            if not joint.lower < joint.upper:
                raise ValueError(f"joint {joint.name}: lower limit must be below upper")
            if abs(np.linalg.norm(joint.axis) - 1.0) > 1e-12:
                raise ValueError(f"joint {joint.name}: axis is not a unit vector")
        if seen != names:
            raise ValueError(f"links not reached by any joint: {sorted(names - seen)}")
        for link in self.links:
            inertia = link.inertial.inertia_matrix
            eig = np.linalg.eigvalsh(inertia)
            if link.inertial.mass <= 0 or eig.min() <= 0:
                raise ValueError(f"link {link.name}: mass and inertia must be positive")
            a, b, c = sorted(eig)
            if a + b < c * (1 - 1e-12):
                raise ValueError(f"link {link.name}: inertia violates the triangle inequality")
        for frame in self.frames:
            if frame.link not in names:
                raise ValueError(f"frame {frame.name}: unknown link {frame.link}")
        for i, q in enumerate(self.nominal_posture):
            joint = self.joints[i]
            if not joint.lower <= q <= joint.upper:
                raise ValueError(f"nominal posture outside the limits of {joint.name}")
