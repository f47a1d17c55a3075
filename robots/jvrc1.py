"""JVRC-1, a third-party humanoid (the robot of Murooka et al.'s open-source controllers, mc_rtc),
as a `RobotDescription` read from the pinned `jvrc-description` package's URDF (1.1.1: 62.4 kg,
44 revolute joints, DAE meshes, placeholder efforts of 100 N m).

The adapter, and the source of everything it adds to the URDF:
- Kinematics and inertials: the URDF's, verbatim (every joint origin there is a translation;
  every inertial is at its link's axes). The massless root `base_link` and its fixed joint are
  dropped: PELVIS_S is the floating base, so no simulator makes the robot fixed-base or gives a
  massless root a default 1 kg.
- Locked joints: the neck (3) and the fingers (6 per hand), as mc_rtc's JVRC1 without hands;
  their links are merged into the link they hang from at the joints' zero angle (composite mass
  properties, `robots.inertia.combined_inertial`), leaving 29 actuated joints.
- Limbs: the feet (`L_ANKLE_P_S`, `R_ANKLE_P_S`) and the hands (`L_WRIST_Y_S`, `R_WRIST_Y_S`).
  Sole frames at the soles' centres, 0.20 x 0.08 m: mc_rtc's `LeftFootCenter` /
  `RightFootCenter` surfaces (jrl-umi3218/jvrc_description, rsdf/jvrc1/L_ANKLE_P_S.rsdf).
  Palm frames at mc_rtc's gripper surfaces (rsdf/jvrc1/l_wrist.rsdf, `LeftGripper`: 0.095 m
  down the wrist link), with the link's axes (z up the forearm, into the hand, as every contact
  frame here). Force/torque frames at the ankle and wrist link origins (mc_rtc's
  `LeftFootForceSensor` ... `RightHandForceSensor`, identity on those links); the IMU at mc_rtc's
  `Accelerometer`, (-0.0325, 0, 0.1095) m on PELVIS_S (mc_rtc src/mc_robots/jvrc1.cpp).
- Collision shapes: the meshes' bounding boxes, fitted once (`robots.jvrc1_shapes`); each
  foot's box is the sole's rectangle (so that the simulators' support polygon is the one the
  controllers use), from the sole down to the mesh's top.
- Nominal posture: mc_rtc's half-sitting (`default_q` of src/mc_robots/jvrc1.cpp), with the
  ankles turned so that both soles are level under the upright base (`level_soles`).
- Servo gains and torque limits: `_SOURCE_SERVO` below, with their sources, adapted by
  `servo_gains_without_rotor_inertia` and `torque_limits`.
"""

from __future__ import annotations

import functools
import xml.etree.ElementTree as ET
from dataclasses import replace
from importlib import resources
from pathlib import Path

import numpy as np

from robots.humanoid import FALL_HEIGHT_M, HIP_TO_SOLE_M, NOMINAL_MASS_KG, torque_limit_at_scale_1
from robots.inertia import combined_inertial
from robots.jvrc1_shapes import BOXES
from robots.scene import Scene
from robots.spec import Frame, Geometry, Inertial, Joint, Limb, Link, RobotDescription

PACKAGE = "jvrc_description"
FINGERS = ("UTHUMB", "LTHUMB", "UINDEX", "LINDEX", "ULITTLE", "LLITTLE")
LOCKED_JOINTS = frozenset(
    {"NECK_Y", "NECK_R", "NECK_P"} | {f"{side}_{finger}" for side in "LR" for finger in FINGERS}
)
"""Held at zero and merged into their parent links (mc_rtc's JVRC1 without hands)."""

HALF_SITTING = {
    "R_HIP_P": -0.38, "R_HIP_R": -0.01, "R_HIP_Y": 0.0, "R_KNEE": 0.72, "R_ANKLE_R": -0.01,
    "R_ANKLE_P": -0.33, "L_HIP_P": -0.38, "L_HIP_R": 0.02, "L_HIP_Y": 0.0, "L_KNEE": 0.72,
    "L_ANKLE_R": -0.02, "L_ANKLE_P": -0.33, "WAIST_Y": 0.0, "WAIST_P": 0.13, "WAIST_R": 0.0,
    "R_SHOULDER_P": -0.052, "R_SHOULDER_R": -0.17, "R_SHOULDER_Y": 0.0, "R_ELBOW_P": -0.52,
    "R_ELBOW_Y": 0.0, "R_WRIST_R": 0.0, "R_WRIST_Y": 0.0, "L_SHOULDER_P": -0.052,
    "L_SHOULDER_R": 0.17, "L_SHOULDER_Y": 0.0, "L_ELBOW_P": -0.52, "L_ELBOW_Y": 0.0,
    "L_WRIST_R": 0.0, "L_WRIST_Y": 0.0,
}  # fmt: skip
"""mc_rtc's half-sitting stance of JVRC-1 [rad] (src/mc_robots/jvrc1.cpp, `default_q`, in the
URDF's joint order; the locked joints' entries are 0)."""

SOLE_IN_ANKLE = (0.030310330912470818, -0.001216750591993332, -0.10773589462041855)
"""mc_rtc's `LeftFootCenter` on L_ANKLE_P_S and `RightFootCenter` on R_ANKLE_P_S [m]: the same
numbers for both feet (not mirrored in y)."""
SOLE_HALF_EXTENTS = (0.10, 0.04)
"""mc_rtc's foot surfaces: x from -0.1 to 0.1, y from -0.04 to 0.04 [m]."""
GRIPPER_IN_WRIST = (0.0, 0.0085, -0.095)
"""mc_rtc's `LeftGripper` on l_wrist (= L_WRIST_Y_S) [m] with y negated: left y = -0.0085."""
IMU_IN_PELVIS = (-0.0325, 0.0, 0.1095)
"""mc_rtc's `Accelerometer` body sensor on PELVIS_S [m]."""

PHYSICS_DT = Scene.physics_dt
"""[s] the physics step the servo gains are made stable for (every scene's default)."""
_FOOT_LINKS = {"left": "L_ANKLE_P_S", "right": "R_ANKLE_P_S"}
_HAND_LINKS = {"left": "L_WRIST_Y_S", "right": "R_WRIST_Y_S"}


def urdf_path() -> Path:
    """The installed package's URDF."""
    return Path(str(resources.files(PACKAGE) / "urdf" / "jvrc1.urdf"))


def _floats(text: str | None, default: str = "0 0 0") -> tuple[float, ...]:
    return tuple(float(x) for x in (text or default).split())


def _read_urdf(path: Path):
    """Links' inertials and joints (name, type, parent, child, origin xyz, axis, limits) of the
    URDF, checking the two facts the adapter relies on: no joint or inertial rotation. Fixed
    joints to massless links (sensors, cameras: mc_rtc's frames are used instead) are left
    out."""
    root = ET.parse(path).getroot()
    inertials: dict[str, Inertial] = {}
    for link in root.findall("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        origin = inertial.find("origin")
        if origin is not None and any(_floats(origin.get("rpy"))):
            raise ValueError(f"{path}: {link.get('name')}'s inertial is rotated")
        i = {k: float(v) for k, v in inertial.find("inertia").attrib.items()}
        inertials[link.get("name")] = Inertial(
            mass=float(inertial.find("mass").get("value")),
            com_in_link=_floats(origin.get("xyz") if origin is not None else None),
            inertia_at_com=(
                (i["ixx"], i["ixy"], i["ixz"]),
                (i["ixy"], i["iyy"], i["iyz"]),
                (i["ixz"], i["iyz"], i["izz"]),
            ),
        )
    joints = []
    for joint in root.findall("joint"):
        child = joint.find("child").get("link")
        if joint.get("type") == "fixed" and child not in inertials:
            continue  # a massless sensor or camera link: not a body
        origin = joint.find("origin")
        if origin is not None and any(_floats(origin.get("rpy"))):
            raise ValueError(f"{path}: joint {joint.get('name')} is rotated")
        limit = joint.find("limit")
        axis = joint.find("axis")
        joints.append(
            {
                "name": joint.get("name"),
                "type": joint.get("type"),
                "parent": joint.find("parent").get("link"),
                "child": joint.find("child").get("link"),
                "xyz": np.array(_floats(origin.get("xyz") if origin is not None else None)),
                "axis": _floats(axis.get("xyz") if axis is not None else None, "1 0 0"),
                "limit": None if limit is None else {k: float(v) for k, v in limit.attrib.items()},
            }
        )
    return inertials, joints


def size_relative_to_humanoid(hip_to_sole_m: float) -> float:
    """JVRC-1's `scale`: its leg length (hip pitch axis to sole in the zero posture) over the
    centrobench humanoid's at scale 1 (0.80 m), so that scenes, steps and times sized by a
    robot's scale fit it as they fit the humanoid (geometric and Froude similarity, as
    `robots.humanoid`). An adaptation: JVRC-1 is not a scaled humanoid."""
    return hip_to_sole_m / HIP_TO_SOLE_M


# Per joint kind: servo kp [N m/rad] and kd [N m s/rad] as mc_mujoco simulates JVRC-1
# (isri-aist/jvrc_mj_description, pdgains/PDgains_sim.dat, in the URDF's joint order), the rotor
# inertia [kg m^2] that model gives the joint (xml/jvrc1.xml `armature`, JVRC-1's VRML
# `rotorInertia`), and the humanoid joint whose torque limit it takes (`torque_limits`).
_SOURCE_SERVO = {
    "HIP_P": (5000.0, 30.0, 0.1925, "hip_pitch"),
    "HIP_R": (5000.0, 30.0, 0.1813, "hip_roll"),
    "HIP_Y": (5000.0, 30.0, 0.1237, "hip_yaw"),
    "KNEE": (6000.0, 50.0, 0.1305, "knee"),
    "ANKLE_R": (3000.0, 20.0, 0.0653, "ankle_roll"),
    "ANKLE_P": (3000.0, 20.0, 0.1337, "ankle_pitch"),
    "WAIST_Y": (5000.0, 32.0, 0.1221, "hip_yaw"),
    "WAIST_P": (5000.0, 32.0, 0.1813, "hip_pitch"),
    "WAIST_R": (5000.0, 32.0, 0.1054, "hip_roll"),
    "SHOULDER_P": (1100.0, 70.0, 0.1210, "shoulder_pitch"),
    "SHOULDER_R": (1100.0, 70.0, 0.1210, "shoulder_roll"),
    "SHOULDER_Y": (1100.0, 70.0, 0.1231, "shoulder_yaw"),
    "ELBOW_P": (1200.0, 80.0, 0.1054, "elbow"),
    "ELBOW_Y": (1200.0, 80.0, 0.1240, "shoulder_yaw"),
    "WRIST_R": (500.0, 24.0, 0.0876, "wrist_roll"),
    "WRIST_Y": (500.0, 24.0, 0.1240, "wrist_roll"),
}


SERVO_DAMPING_STEP = 0.8
"""Largest kd dt / I of a joint's servo (I: the inertia it sees with everything else free; dt the
1 ms physics step), as the humanoid's (0.5-0.96): the explicit servo fails near 2."""
SERVO_STIFFNESS_STEP = 0.5
"""Largest kp dt^2 / I of a joint's servo (the explicit servo fails near 4 undamped)."""


def servo_gains_without_rotor_inertia(
    kp: float, kd: float, link_inertia: float, physics_dt: float
) -> tuple[float, float]:
    """The source's servo gains (kp [N m/rad], kd [N m s/rad]) for a joint that has no rotor
    inertia, capped so that the servo is stable at the physics step dt [s]:
    kp' = min(kp, SERVO_STIFFNESS_STEP I / dt^2), kd' = min(kd, SERVO_DAMPING_STEP I / dt), with
    I [kg m^2] the inertia the joint sees with every other joint and the base free
    (`_with_servo_adapted`). The source model gives each joint a rotor inertia (`armature`,
    0.07-0.19 kg m^2) that ours cannot have (PyBullet has none, and the three models must be
    identical); with it the source gains are stable, without it they make the explicit servo at
    the 1 ms step diverge (a spectral radius of 117, tests/robots/test_servo_stability.py).
    Keeping the source's stiffness where it is stable keeps its static stiffness: the stance
    ankle's, which balance needs (keeping the source's loop frequency instead, kp I / (I + A),
    left the ankles at 200 N m/rad, less than the 526 N m/rad of gravity's toppling torque per
    radian, and the standing robot swayed 5 cm, growing). An adaptation."""
    return (
        min(kp, SERVO_STIFFNESS_STEP * link_inertia / physics_dt**2),
        min(kd, SERVO_DAMPING_STEP * link_inertia / physics_dt),
    )


def _kind(joint_name: str) -> str:
    """ "R_HIP_P" -> "HIP_P", "WAIST_Y" -> "WAIST_Y"."""
    return joint_name[2:] if joint_name[:2] in ("R_", "L_") else joint_name


def _merge_locked(inertials: dict[str, Inertial], joints: list[dict]):
    """Bodies after locking: every link reached from PELVIS_S through actuated joints is a body;
    links hanging from it by fixed or locked joints (at their zero angle: a translation) are
    merged into it. Returns per body the parts (original link, offset [m] in the body frame)
    and the actuated joints in the URDF's order, each from the body its parent link is in."""
    children: dict[str, list[dict]] = {}
    for joint in joints:
        children.setdefault(joint["parent"], []).append(joint)
    parts: dict[str, list[tuple[str, np.ndarray]]] = {}
    actuated: list[dict] = []

    def visit(link: str, body: str, offset: np.ndarray) -> None:
        parts.setdefault(body, []).append((link, offset))
        for joint in children.get(link, []):
            if joint["type"] == "revolute" and joint["name"] not in LOCKED_JOINTS:
                # re-parented onto the body the link was merged into (a no-op unless a locked
                # joint lies between two actuated ones)
                actuated.append({**joint, "parent": body, "xyz": offset + joint["xyz"]})
                visit(joint["child"], joint["child"], np.zeros(3))
            else:  # fixed, or locked at zero: the child moves with this body
                visit(joint["child"], body, offset + joint["xyz"])

    visit("PELVIS_S", "PELVIS_S", np.zeros(3))
    order = {joint["name"]: k for k, joint in enumerate(joints)}
    actuated.sort(key=lambda joint: order[joint["name"]])
    parts = {
        body: [(link, offset) for link, offset in linked if link in inertials]
        for body, linked in parts.items()
    }
    return parts, actuated


def _depth_first(actuated: list[dict]) -> list[dict]:
    """The joints in the depth-first order of the tree with siblings sorted by joint name (the
    order pinocchio's URDF parser produces, which the description must follow)."""
    children: dict[str, list[dict]] = {}
    for joint in actuated:
        children.setdefault(joint["parent"], []).append(joint)
    ordered: list[dict] = []

    def visit(link: str) -> None:
        for joint in sorted(children.get(link, []), key=lambda j: j["name"]):
            ordered.append(joint)
            visit(joint["child"])

    visit("PELVIS_S")
    return ordered


def _geometries(parts: list[tuple[str, np.ndarray]]) -> tuple[Geometry, ...]:
    """The fitted boxes of a body's links, placed in the body frame; a foot's own box is
    replaced by its sole's rectangle from the sole up to the mesh's top."""
    shapes = []
    for link, offset in parts:
        if link not in BOXES:
            continue
        centre, half = BOXES[link]
        if link in _FOOT_LINKS.values():
            x, y, z = SOLE_IN_ANKLE
            top = centre[2] + half[2]
            centre = (x, y, 0.5 * (z + top))
            half = (*SOLE_HALF_EXTENTS, 0.5 * (top - z))
        shapes.append(Geometry("box", half, tuple(float(c) for c in np.add(centre, offset))))
    return tuple(shapes)


def torque_limits(kind: str, mass_kg: float, hip_to_sole_m: float) -> float:
    """A joint's torque limit [N m]: the centrobench humanoid's for the same kind of joint
    (`robots.humanoid`, ours), scaled by geometric similarity with gravity torques, m g l (the
    ratio of total masses times the ratio of leg lengths). An adaptation: the JVRC-1 package
    has placeholder efforts (100 N m for every joint) and no other published limits."""
    return (
        torque_limit_at_scale_1(kind)
        * (mass_kg / NOMINAL_MASS_KG)
        * size_relative_to_humanoid(hip_to_sole_m)
    )


@functools.lru_cache(maxsize=2)
def jvrc1() -> RobotDescription:
    """JVRC-1 from the installed `jvrc-description` package (module docstring: what is added
    and its sources). Cached per process."""
    inertials, joints = _read_urdf(urdf_path())
    parts, actuated = _merge_locked(inertials, joints)
    ordered = _depth_first(actuated)
    links = [
        Link(body, combined_inertial([(inertials[n], o) for n, o in parts[body]]), ())
        for body in ["PELVIS_S", *[j["child"] for j in ordered]]
    ]
    links = [Link(link.name, link.inertial, _geometries(parts[link.name])) for link in links]
    mass = sum(link.inertial.mass for link in links)
    hip_to_sole = _hip_to_sole(joints)
    description_joints = []
    for joint in ordered:
        kp, kd, _, kind = _SOURCE_SERVO[_kind(joint["name"])]
        limit = joint["limit"]
        description_joints.append(
            Joint(
                name=joint["name"],
                parent=joint["parent"],
                child=joint["child"],
                origin_in_parent=tuple(float(x) for x in joint["xyz"]),
                axis=joint["axis"],
                lower=limit["lower"],
                upper=limit["upper"],
                velocity_limit=limit["velocity"],
                torque_limit=torque_limits(kind, mass, hip_to_sole),
                kp=kp,
                kd=kd,
            )
        )
    frames = [Frame("imu", "PELVIS_S", IMU_IN_PELVIS, "imu")]
    limbs = []
    for side in ("left", "right"):
        foot = _FOOT_LINKS[side]
        frames += [
            Frame(f"{side}_sole", foot, SOLE_IN_ANKLE, "contact"),
            Frame(f"{side}_ankle_ft", foot, (0.0, 0.0, 0.0), "force_torque"),
        ]
        limbs.append(
            Limb(f"{side}_foot", foot, f"{side}_sole", f"{side}_ankle_ft", SOLE_HALF_EXTENTS)
        )
    for side in ("left", "right"):
        hand, prefix = _HAND_LINKS[side], "L" if side == "left" else "R"
        x, y, z = GRIPPER_IN_WRIST
        palm = (x, -y if side == "left" else y, z)
        _, half = BOXES[hand]
        frames += [
            Frame(f"{side}_palm", hand, palm, "contact"),
            Frame(f"{side}_wrist_ft", hand, (0.0, 0.0, 0.0), "force_torque"),
        ]
        limbs.append(
            Limb(
                f"{side}_hand",
                hand,
                f"{side}_palm",
                f"{side}_wrist_ft",
                (half[0], half[1]),
                touch_links=(
                    f"{prefix}_SHOULDER_Y_S",
                    f"{prefix}_ELBOW_P_S",
                    f"{prefix}_ELBOW_Y_S",
                ),
            )
        )
    names = [j.name for j in description_joints]
    description = RobotDescription(
        name="jvrc1",
        scale=size_relative_to_humanoid(hip_to_sole),
        links=tuple(links),
        joints=tuple(description_joints),
        frames=tuple(frames),
        limbs=tuple(limbs),
        imu_frame="imu",
        nominal_posture=tuple(HALF_SITTING[n] for n in names),
        fall_height=FALL_HEIGHT_M * size_relative_to_humanoid(hip_to_sole),
    )
    description.validate()
    return _with_servo_adapted(level_soles(description))


def level_soles(description: RobotDescription, tolerance_rad: float = 1e-12) -> RobotDescription:
    """`description` with each foot's two ankle joints (the joints named *ankle* in any case
    on its chain) turned in the nominal posture so that its sole is level, the sole's z axis
    vertical, when the base is upright (as `RobotModel.standing_state` places the robot).

    Adaptation: mc_rtc's half-sitting, with an upright pelvis, pitches both soles 0.010 rad
    toes-up (hip -0.38 + knee 0.72 + ankle -0.33 rad) and rolls the right one 0.019 rad (hip
    roll -0.01, ankle roll -0.01; the left's 0.02 and -0.02 nearly cancel). The robot then started
    with a sole corner up to 1.75 mm inside the ground, and every controller's first command,
    which holds the soles flat on the scenario's level footholds, turned both ankles at once:
    the feet carried up to 2.4 m g in the first periods (Murooka's controllers, MuJoCo; the
    humanoid 1.1 m g). The change: -0.010 rad of ankle pitch on each foot, +0.020 rad of ankle
    roll on the right one (+0.0003 on the left); the CoM moves 1.0 mm back, 0.9 mm right and
    0.3 mm down; the soles' centres stand 0.1 mm apart in height (the hips' rolls differ), the
    lower one on the ground."""
    from robots.model import RobotModel
    from robots.types import RobotState

    model = RobotModel(description)
    names = [joint.name for joint in description.joints]
    posture = np.array(description.nominal_posture)
    upright = np.array([1.0, 0.0, 0.0, 0.0])
    for limb in description.limbs:
        if not limb.name.endswith("foot"):
            continue
        ankles, joint = [], model.model.frames[model.frame_id[limb.contact_frame]].parentJoint
        while joint > 0:
            if "ankle" in model.model.names[joint].lower():
                ankles.append(names.index(model.model.names[joint]))
            joint = model.model.parents[joint]
        if len(ankles) != 2:
            raise ValueError(f"{description.name}: {limb.name} has {len(ankles)} ankle joints")

        def tilt(q: np.ndarray, frame: str = limb.contact_frame) -> np.ndarray:
            """The sole's z axis's horizontal components in the world."""
            state = RobotState.at_rest(np.zeros(3), upright, q)
            return model.frame_pose(state, frame)[1][:2, 2]

        for _ in range(20):  # Newton on the two ankle angles, finite-difference Jacobian
            error = tilt(posture)
            if np.abs(error).max() < tolerance_rad:
                break
            jacobian = np.empty((2, 2))
            for column, index in enumerate(ankles):
                moved = posture.copy()
                moved[index] += 1e-7
                jacobian[:, column] = (tilt(moved) - error) / 1e-7
            posture[ankles] -= np.linalg.solve(jacobian, error)
        else:
            raise ValueError(f"{description.name}: cannot level the sole of {limb.name}")
    levelled = replace(description, nominal_posture=tuple(float(q) for q in posture))
    levelled.validate()
    return levelled


def _with_servo_adapted(description: RobotDescription) -> RobotDescription:
    """`description` with every joint's gains from `servo_gains_without_rotor_inertia`: each
    joint's link inertia is the one it sees with every other joint and the base free,
    1 / (M^-1)_jj of the floating-base mass matrix M in the nominal posture (pinocchio's CRBA).
    The diagonal M_jj itself is too large where joint axes line up (the hanging arm's shoulder,
    elbow and wrist yaw): gains from it left a closed-loop mode growing 1.67x per step."""
    import pinocchio as pin

    from robots.model import RobotModel

    model = RobotModel(description)
    q = model.configuration(model.standing_state())
    mass_matrix = pin.crba(model.model, model.model.createData(), q)
    mass_matrix = np.triu(mass_matrix) + np.triu(mass_matrix, 1).T
    inertia = 1.0 / np.diag(np.linalg.inv(mass_matrix))[6:]
    joints = []
    for joint, link_inertia in zip(description.joints, inertia, strict=True):
        kp, kd, _, _ = _SOURCE_SERVO[_kind(joint.name)]
        kp, kd = servo_gains_without_rotor_inertia(kp, kd, float(link_inertia), PHYSICS_DT)
        joints.append(replace(joint, kp=kp, kd=kd))
    adapted = replace(description, joints=tuple(joints))
    adapted.validate()
    return adapted


def _hip_to_sole(joints: list[dict]) -> float:
    """[m] from the left hip pitch axis down to the left sole in the zero posture."""
    by_child = {j["child"]: j for j in joints}
    depth, link = 0.0, _FOOT_LINKS["left"]
    while link != "L_HIP_P_S":
        joint = by_child[link]
        depth += joint["xyz"][2]
        link = joint["parent"]
    return float(-(depth + SOLE_IN_ANKLE[2]))
