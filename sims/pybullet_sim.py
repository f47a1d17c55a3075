"""PyBullet backend: the generated URDF loaded with URDF_USE_INERTIA_FROM_FILE, one DIRECT
client per simulator instance.

PyBullet quaternions are (x, y, z, w); they are converted to (w, x, y, z) here and nowhere else.
PyBullet places a link's dynamic state at its centre of mass ("inertial frame"); this module
converts to the link frame that `RobotState` and the other backends use.

Physics settings (same intent as `sims.mujoco_sim`; see docs/simulators.md):
- default velocity motors disabled, joint torques from `sims.servo` each physics step;
- PyBullet's default link damping (0.04 linear and angular) set to 0, joint damping 0;
- contact and friction ERP 0.2 (see CONTACT_ERP);
- friction: Bullet multiplies the two bodies' coefficients, so robot links get 1.0 and the
  scene gets `scene.friction`; Coulomb's cone (`CONE_FRICTION`); restitution 0; no spinning
  or rolling friction; no self-collision (the URDF_USE_SELF_COLLISION flag is not given);
- the IMU accelerometer is the finite difference of the IMU frame's velocity over the last
  physics step, minus gravity (PyBullet has no IMU sensor).

Moving boxes (`robots.scene.MovingBox`): each is a mass-0 (fixed-base) multibody put at its
prescribed pose and velocity at every physics step (`_move_boxes`: resetBasePositionAndOrientation
and resetBaseVelocity). Bullet's solver uses a fixed base's velocity in its contacts (measured:
a cube on a plate moving 20 mm sideways follows it to 0.3 mm), and a step moves the base by
its velocity; `_move_boxes` puts it back on its path after the step. A static rigid body
(createMultiBody with useMaximalCoordinates) would not do: its velocity is ignored (the cube
stayed put).

Grasps (`sims.base` docstring): a fixed constraint (`createConstraint(..., JOINT_FIXED)`)
between the limb's link and the box's body, made at grasp time with both frames at the palm
centre and orientation (the current relative pose; PyBullet wants them relative to each body's
centre-of-mass frame), removed at release (`removeConstraint`). Bullet solves it rigidly, with
`GRASP_ERP` and a force limit `GRASP_MAX_FORCE_WEIGHTS` (see them). Its force is read with
`getConstraintState` (the last step's impulses / dt): measured on a welded block, the three
linear rows are the force on the limb in world axes, the three angular ones the moment on it
about the pivot in the constraint frames' axes (the parent's and the child's coincide while it
holds): the palm centre and the palm frame. So the moment is added to the limb's contact
wrench as it is, and the force rotated into the palm frame.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np
from scipy.spatial.transform import Rotation

from robots.build import generate
from robots.scene import Scene
from robots.spec import RobotDescription
from robots.types import MassProperties, RobotState, Sensors
from sims.base import (
    SimulatorBase,
    cross,
    quaternion_product,
    quaternion_to_matrix,
)
from sims.kernels import pybullet_sensors
from sims.sensor_buffer import SensorLayout


def _import_pybullet():
    """Import pybullet with its C-level build banner (written to fd 2) kept out of the output."""
    sys.stderr.flush()
    saved, devnull = os.dup(2), os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 2)
        import pybullet
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(devnull)
    return pybullet


pb = _import_pybullet()

CONE_FRICTION = 1
"""Bullet's friction law: Coulomb's cone |f_t| <= mu f_n (its default, set explicitly; 0 clamps
each of two friction directions separately, a square that allows 1.41 mu along a diagonal).
Measured (a box on a 25 deg incline, `tests/sims/test_agreement.py`): it slips sideways at the
circle's load, as MuJoCo with its elliptic cone (`sims.mujoco_sim.FRICTION_CONE`)."""
CONTACT_ERP = 0.2
"""PyBullet's penetration-recovery gain for contacts and friction (Bullet's default, set
explicitly). Measured trade-off: with 0 the robot standing 10 s sinks 0.34 mm and its weight
drifts to a 54/46 left/right split; with 0.2 it stays at 50/50 and 0.11 mm. The cost: while a
deep overlap is being recovered (a body that starts 15 mm inside a box), the `normalForce`
PyBullet reports includes the recovery impulse, which does not change momentum (reported forces
averaged 1.07 m g at rest), so scenarios must not start with bodies interpenetrating."""


GRASP_ERP = CONTACT_ERP
"""Position-error reduction of a grasp's constraint, as a contact's (Bullet's default, set
explicitly)."""
GRASP_MAX_FORCE_WEIGHTS = 10.0
"""A grasp's force limit, per constraint row (N for the three force rows, N m for the three
moment rows), in robot weights (m g: 5.7 kN at scale 1). MuJoCo's weld has no limit; this one
never binds in a scene that makes sense (Fig. 7's ladder pulls about 200 N, the robot's whole
weight on one hand is 573 N), and only keeps a scene that asks the impossible (a hand welded to
a box that moves away from the robot's feet) finite. PyBullet's own default (reported as 500)
is no limit either: it held a 1000 N load on a welded block."""


def _wxyz_tuple(q_xyzw) -> tuple[float, float, float, float]:
    return q_xyzw[3], q_xyzw[0], q_xyzw[1], q_xyzw[2]


def _wxyz(q_xyzw) -> np.ndarray:
    return np.array(_wxyz_tuple(q_xyzw))


def _xyzw(q_wxyz) -> list[float]:
    return [float(q_wxyz[1]), float(q_wxyz[2]), float(q_wxyz[3]), float(q_wxyz[0])]


IDLE_CLIENTS_MAX = 2
_idle_clients: list[int] = []
"""Connected physics clients that closed simulators left (at most `IDLE_CLIENTS_MAX`; more
are disconnected): the next simulator in this process empties one (`resetSimulation`) instead
of connecting again (15 of an episode's 45 ms of set-up). Restoring a world saved after
loading (`saveState` / `restoreState`) would save the loading too, but Bullet keeps contact
state across a restore: an episode after another then differs from the same episode run first
(measured), which `resetSimulation` avoids."""


def clear_cache() -> None:
    """Disconnect the idle clients (`sims.base.clear_backend_caches`)."""
    while _idle_clients:
        pb.disconnect(physicsClientId=_idle_clients.pop())


def engine_parameters(physics_dt: float) -> dict:
    """`setPhysicsEngineParameter`'s arguments for every world here: the step [s], no
    sub-steps, deterministic pairs, `CONTACT_ERP` and the friction law (`CONE_FRICTION`)."""
    return {
        "fixedTimeStep": physics_dt,
        "numSubSteps": 0,
        "deterministicOverlappingPairs": 1,
        "contactERP": CONTACT_ERP,
        "frictionERP": CONTACT_ERP,
        "enableConeFriction": CONE_FRICTION,
    }


class PybulletSimulator(SimulatorBase):
    name = "pybullet"

    def __init__(self) -> None:
        super().__init__()
        self.client: int | None = None

    def close(self) -> None:
        """Release the client: kept for the next simulator in this process (`_idle_clients`)."""
        if self.client is not None:
            if len(_idle_clients) < IDLE_CLIENTS_MAX:
                _idle_clients.append(self.client)
            else:
                pb.disconnect(physicsClientId=self.client)
            self.client = None

    def _load(self, robot: RobotDescription, scene: Scene) -> None:
        if _idle_clients:
            c = self.client = _idle_clients.pop()
            pb.resetSimulation(physicsClientId=c)
        else:
            c = self.client = pb.connect(pb.DIRECT)
        self._load_new(robot, scene)

    def _reset_caches(self) -> None:
        self._imu_velocity_before = np.zeros(3)
        self._contact_cache: tuple[list[int], np.ndarray, np.ndarray] | None = None
        self._joint_cache: tuple[np.ndarray, np.ndarray] | None = None
        self._checks_fresh = False

    def _load_new(self, robot: RobotDescription, scene: Scene) -> None:
        """Load robot and scene into the empty world of `self.client`."""
        c = self.client
        pb.setPhysicsEngineParameter(**engine_parameters(scene.physics_dt), physicsClientId=c)
        pb.setGravity(0.0, 0.0, -scene.gravity, physicsClientId=c)
        body = self.body = pb.loadURDF(
            str(generate(robot).urdf), flags=pb.URDF_USE_INERTIA_FROM_FILE, physicsClientId=c
        )
        index = {}
        for j in range(pb.getNumJoints(body, physicsClientId=c)):
            info = pb.getJointInfo(body, j, physicsClientId=c)
            index[info[1].decode()] = j  # joint name -> index (= child link index)
            index["link:" + info[12].decode()] = j
        index["link:" + pb.getBodyInfo(body, physicsClientId=c)[0].decode()] = -1
        self._index = index
        self._joint_idx = [index[n] for n in robot.joint_names]
        self._link_idx = {link.name: index["link:" + link.name] for link in robot.links}
        self._link_name = {v: k for k, v in self._link_idx.items()}
        self._limb_link = np.array([self._link_idx[limb.link] for limb in robot.limbs])
        self._limb_frame = [index["link:" + limb.contact_frame] for limb in robot.limbs]
        self._imu = index["link:" + robot.imu_frame]
        for link in [-1, *range(pb.getNumJoints(body, physicsClientId=c))]:
            pb.changeDynamics(
                body,
                link,
                linearDamping=0.0,
                angularDamping=0.0,
                jointDamping=0.0,
                lateralFriction=1.0,
                spinningFriction=0.0,
                rollingFriction=0.0,
                restitution=0.0,
                physicsClientId=c,
            )
        pb.setJointMotorControlArray(
            body,
            self._joint_idx,
            pb.VELOCITY_CONTROL,
            forces=[0.0] * robot.n_joints,
            physicsClientId=c,
        )
        self._scene_bodies = []
        if scene.ground:
            shape = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=c)
            self._scene_bodies.append(pb.createMultiBody(0.0, shape, physicsClientId=c))
        for box in scene.boxes:
            shape = pb.createCollisionShape(
                pb.GEOM_BOX, halfExtents=list(box.half_extents), physicsClientId=c
            )
            self._scene_bodies.append(
                pb.createMultiBody(
                    0.0,
                    shape,
                    basePosition=list(box.center_world),
                    baseOrientation=_xyzw(box.orientation_world),
                    physicsClientId=c,
                )
            )
        self._moving = []
        for box in scene.moving_boxes:
            shape = pb.createCollisionShape(
                pb.GEOM_BOX, halfExtents=list(box.half_extents), physicsClientId=c
            )
            center, quaternion = box.pose_at(0.0)
            moving_body = pb.createMultiBody(
                0.0,
                shape,
                basePosition=center.tolist(),
                baseOrientation=_xyzw(quaternion),
                physicsClientId=c,
            )
            self._moving.append((moving_body, box))
            self._scene_bodies.append(moving_body)
        self._box_body = dict(
            zip(
                [box.name for box in (*scene.boxes, *scene.moving_boxes)],
                self._scene_bodies[1 if scene.ground else 0 :],
                strict=True,
            )
        )
        for scene_body in self._scene_bodies:
            pb.changeDynamics(
                scene_body,
                -1,
                lateralFriction=scene.friction,
                restitution=0.0,
                spinningFriction=0.0,
                rollingFriction=0.0,
                physicsClientId=c,
            )
        info = pb.getDynamicsInfo(body, -1, physicsClientId=c)
        self._base_com_in_link = np.array(info[3])
        self._base_inertial_rotation = quaternion_to_matrix(_wxyz(info[4]))
        w, x, y, z = _wxyz(info[4])
        self._base_inertial_conjugate = np.array([w, -x, -y, -z])
        self._grasp_constraint: dict[int, int] = {}  # limb number -> constraint id
        self._grasp_max_force = GRASP_MAX_FORCE_WEIGHTS * robot.total_mass * scene.gravity
        self._sensor_links = [*self._limb_frame, self._imu]  # read together every period
        self._layout = SensorLayout(robot.n_joints, len(robot.limbs))
        self._reset_caches()

    def _move_boxes(self, time: float) -> None:
        """Put every moving box at its prescribed pose and velocity (world) at `time` [s]."""
        c = self.client
        for body, box in self._moving:
            center, quaternion = box.pose_at(time)
            linear, angular = box.velocity_at(time)
            pb.resetBasePositionAndOrientation(
                body, center.tolist(), _xyzw(quaternion), physicsClientId=c
            )
            pb.resetBaseVelocity(body, linear.tolist(), angular.tolist(), physicsClientId=c)
        self._contact_cache = None
        self._checks_fresh = False

    def _make_grasp(self, limb: int, box: str) -> None:
        """A fixed constraint between the limb's link (parent) and the box's body (child), both
        frames at the palm centre and orientation now, given relative to each body's
        centre-of-mass frame (PyBullet's convention)."""
        c, body = self.client, self.body
        link = int(self._limb_link[limb])
        com, com_orientation = pb.getLinkState(
            body, link, computeForwardKinematics=1, physicsClientId=c
        )[:2]
        palm_state = pb.getLinkState(
            body, self._limb_frame[limb], computeForwardKinematics=1, physicsClientId=c
        )
        palm, palm_orientation = np.array(palm_state[4]), _wxyz(palm_state[5])
        box_body = self._box_body[box]
        box_position, box_orientation = pb.getBasePositionAndOrientation(
            box_body, physicsClientId=c
        )
        frames = []
        for position, orientation in ((com, com_orientation), (box_position, box_orientation)):
            w, x, y, z = _wxyz_tuple(orientation)
            frames.append(
                (
                    (quaternion_to_matrix((w, x, y, z)).T @ (palm - position)).tolist(),
                    _xyzw(quaternion_product((w, -x, -y, -z), palm_orientation)),
                )
            )
        (parent_position, parent_orientation), (child_position, child_orientation) = frames
        constraint = pb.createConstraint(
            body,
            link,
            box_body,
            -1,
            pb.JOINT_FIXED,
            [0.0, 0.0, 0.0],
            parentFramePosition=parent_position,
            childFramePosition=child_position,
            parentFrameOrientation=parent_orientation,
            childFrameOrientation=child_orientation,
            physicsClientId=c,
        )
        pb.changeConstraint(
            constraint, maxForce=self._grasp_max_force, erp=GRASP_ERP, physicsClientId=c
        )
        self._grasp_constraint[limb] = constraint

    def _drop_grasp(self, limb: int) -> None:
        pb.removeConstraint(self._grasp_constraint.pop(limb), physicsClientId=self.client)

    def scene_boxes_world(self) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Every box (static and moving) as Bullet holds it now: name -> (centre [m],
        orientation (w, x, y, z), half extents [m]): the body's base pose composed with its
        collision shape's local frame (the identity here), and the shape's extents (Bullet
        reports full extents). Bullet stores them in double precision; the composition is
        done here in float64 (pybullet's `multiplyTransforms` rounds to float32: 5e-8 m)."""
        c = self.client
        boxes = {}
        for name, body in self._box_body.items():
            base_position, base_orientation = pb.getBasePositionAndOrientation(
                body, physicsClientId=c
            )
            shape = pb.getCollisionShapeData(body, -1, physicsClientId=c)[0]
            base_quaternion = _wxyz(base_orientation)
            position = np.array(base_position) + quaternion_to_matrix(base_quaternion) @ shape[5]
            orientation = quaternion_product(base_quaternion, _wxyz(shape[6]))
            boxes[name] = (position, orientation, 0.5 * np.array(shape[3]))
        return boxes

    # PyBullet's base pose is its inertial frame; ours is the link frame.
    def _base_link_pose(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(link origin [m], link rotation, CoM [m], link quaternion (w, x, y, z), w >= 0)."""
        com, orn = pb.getBasePositionAndOrientation(self.body, physicsClientId=self.client)
        inertial = _wxyz_tuple(orn)
        rotation = quaternion_to_matrix(inertial) @ self._base_inertial_rotation.T
        position = np.array(com) - rotation @ self._base_com_in_link
        # the link's orientation: the inertial frame's times its offset's inverse
        quaternion = quaternion_product(inertial, self._base_inertial_conjugate)
        quaternion /= np.linalg.norm(quaternion)
        if quaternion[0] < 0:
            quaternion = -quaternion
        return position, rotation, np.array(com), quaternion

    def set_state(self, state: RobotState) -> None:
        c, body = self.client, self.body
        quaternion = state.base_orientation_world / np.linalg.norm(state.base_orientation_world)
        rotation = quaternion_to_matrix(quaternion)
        com = state.base_position_world + rotation @ self._base_com_in_link
        rotation_inertial = rotation @ self._base_inertial_rotation
        orn = Rotation.from_matrix(rotation_inertial).as_quat()  # x, y, z, w
        pb.resetBasePositionAndOrientation(body, com.tolist(), orn.tolist(), physicsClientId=c)
        omega = np.asarray(state.base_angular_velocity_world, dtype=float)
        v_com = state.base_linear_velocity_world + cross(omega, com - state.base_position_world)
        pb.resetBaseVelocity(body, v_com.tolist(), omega.tolist(), physicsClientId=c)
        for j, q, dq in zip(
            self._joint_idx, state.joint_position, state.joint_velocity, strict=True
        ):
            pb.resetJointState(body, j, float(q), float(dq), physicsClientId=c)
        self._joint_cache = None
        self._checks_fresh = False
        self._imu_velocity_before = self._imu_state()[2]
        self._contact_cache = None

    def ground_truth(self) -> RobotState:
        position, _, com, quaternion = self._base_link_pose()
        v_com, omega = pb.getBaseVelocity(self.body, physicsClientId=self.client)
        omega = np.array(omega)
        v_origin = np.array(v_com) + cross(omega, position - com)
        q, dq = self._joint_state()
        return RobotState(position, quaternion, v_origin, omega, q.copy(), dq.copy())

    def _joint_state(self) -> tuple[np.ndarray, np.ndarray]:
        """Read once per state: cached until the next physics step or `set_state` (callers
        must not modify the arrays)."""
        if self._joint_cache is None:
            states = pb.getJointStates(self.body, self._joint_idx, physicsClientId=self.client)
            # columns: positions, velocities, reaction forces, motor torques
            columns = zip(*states, strict=True)
            q, dq = np.array((next(columns), next(columns)))
            self._joint_cache = (q, dq)
        return self._joint_cache

    def _imu_state(self):
        s = pb.getLinkState(
            self.body,
            self._imu,
            computeLinkVelocity=1,
            computeForwardKinematics=1,
            physicsClientId=self.client,
        )
        return np.array(s[4]), _wxyz(s[5]), np.array(s[6]), np.array(s[7])

    def _physics_step(
        self, torque: np.ndarray, forces: list[tuple[str, np.ndarray]], last: bool
    ) -> None:
        c, body = self.client, self.body
        self._contact_cache = None
        self._joint_cache = None
        self._checks_fresh = False
        pb.setJointMotorControlArray(
            body, self._joint_idx, pb.TORQUE_CONTROL, forces=torque.tolist(), physicsClientId=c
        )
        for link, force in forces:  # cleared by PyBullet after every step
            index = self._link_idx[link]
            if index == -1:
                com = pb.getBasePositionAndOrientation(body, physicsClientId=c)[0]
            else:
                com = pb.getLinkState(body, index, computeForwardKinematics=1, physicsClientId=c)[0]
            pb.applyExternalForce(
                body, index, force.tolist(), list(com), pb.WORLD_FRAME, physicsClientId=c
            )
        if last:  # the accelerometer differences the IMU velocity over the last step
            self._imu_velocity_before = pb.getLinkState(
                body,
                self._imu,
                computeLinkVelocity=1,
                computeForwardKinematics=1,
                physicsClientId=c,
            )[6]
        start = time.perf_counter_ns()
        pb.stepSimulation(physicsClientId=c)
        self.engine_ns += time.perf_counter_ns() - start

    def _contacts(self) -> tuple[list[int], np.ndarray, np.ndarray]:
        """Touching contact points as (robot link indices, points world (n, 3) [m], forces on
        the robot world (n, 3) [N]). Read once per state: cached until the next physics step
        or `set_state`."""
        if self._contact_cache is not None:
            return self._contact_cache
        c = self.client
        links, points, forces = [], [], []
        for scene_body in self._scene_bodies:
            for p in pb.getContactPoints(bodyA=self.body, bodyB=scene_body, physicsClientId=c):
                if p[8] > 0.0 and p[9] <= 0.0:  # separated and carrying no force
                    continue
                links.append(p[3])
                points.append(p[6])
                # normal force along the normal (B -> A, on the robot), two friction directions
                forces.append([p[9], *p[7], p[10], *p[11], p[12], *p[13]])
        if forces:
            f = np.array(forces)
            on_robot = f[:, :1] * f[:, 1:4] + f[:, 4:5] * f[:, 5:8] + f[:, 8:9] * f[:, 9:12]
            self._contact_cache = (links, np.array(points), on_robot)
        else:
            self._contact_cache = ([], np.zeros((0, 3)), np.zeros((0, 3)))
        return self._contact_cache

    def _links_touching_scene(self) -> set[str]:
        return {self._link_name.get(link, f"link {link}") for link in self._contacts()[0]}

    def _read_sensors(self) -> Sensors:
        """One read of each kind per period (base pose and velocity, the limb frames and the
        IMU frame in one call, the joints, the contact points), converted and summed in one
        compiled kernel (`kernels.pybullet_sensors`); then each grasp's constraint force
        (`getConstraintState`) added to its limb's wrench."""
        assert self.robot is not None and self.scene is not None
        c, body = self.client, self.body
        com, orientation = pb.getBasePositionAndOrientation(body, physicsClientId=c)
        velocity, omega = pb.getBaseVelocity(body, physicsClientId=c)
        frames = pb.getLinkStates(
            body,
            self._sensor_links,
            computeLinkVelocity=1,
            computeForwardKinematics=1,
            physicsClientId=c,
        )
        values = [*com, *orientation, *velocity, *omega]
        for frame in frames[:-1]:
            values += frame[4]
            values += frame[5]
        imu = frames[-1]
        values += imu[5]
        values += imu[6]
        values += imu[7]
        values.extend(self._imu_velocity_before)
        rows = []
        for scene_body in self._scene_bodies:
            for p in pb.getContactPoints(bodyA=body, bodyB=scene_body, physicsClientId=c):
                rows.append((p[3], *p[6], p[8], p[9], *p[7], p[10], *p[11], p[12], *p[13]))
        q, dq = self._joint_state()
        buffer, checks = self._layout.buffer(), self._checks
        flags = pybullet_sensors(
            np.array(values),
            q,
            dq,
            self._last_torque,
            np.array(rows).reshape(-1, 17),
            self._limb_link,
            self._base_com_in_link,
            self._base_inertial_rotation,
            self._base_inertial_conjugate,
            self.scene.gravity,
            self.scene.physics_dt,
            buffer,
            checks,
        )
        self._checks_fresh = True
        sensors = self._layout.sensors(self.time, buffer, flags)
        for limb, constraint in self._grasp_constraint.items():
            # force on the limb (world axes), moment about the palm centre (palm axes)
            reaction = pb.getConstraintState(constraint, physicsClientId=c)
            rotation = quaternion_to_matrix(_wxyz_tuple(frames[limb][5]))
            sensors.contact_wrench_limb[limb, :3] += rotation.T @ np.array(reaction[:3])
            sensors.contact_wrench_limb[limb, 3:] += reaction[3:6]
            flags[limb] = True
        return sensors

    def mass_properties(self) -> MassProperties:
        c, body = self.client, self.body
        names, mass, com, inertia = [], [], [], []
        for link in [-1, *range(pb.getNumJoints(body, physicsClientId=c))]:
            info = pb.getDynamicsInfo(body, link, physicsClientId=c)
            if info[0] <= 0.0:
                continue  # massless frame links
            rotation = quaternion_to_matrix(_wxyz(info[4]))
            names.append(self._link_name[link])
            mass.append(info[0])
            com.append(np.array(info[3]))
            inertia.append(rotation @ np.diag(info[2]) @ rotation.T)
        joints = [
            pb.getJointInfo(body, j, physicsClientId=c)
            for j in range(pb.getNumJoints(body, physicsClientId=c))
        ]
        revolute = [j for j in joints if j[2] == pb.JOINT_REVOLUTE]
        return MassProperties(
            source="pybullet",
            body_names=tuple(names),
            mass=np.array(mass),
            com_in_body=np.array(com),
            inertia_at_com_in_body=np.array(inertia),
            joint_names=tuple(j[1].decode() for j in revolute),
            joint_lower=np.array([j[8] for j in revolute]),
            joint_upper=np.array([j[9] for j in revolute]),
        )

    def frame_positions_world(self, names: list[str]) -> np.ndarray:
        """World positions [m] of named frames by PyBullet's forward kinematics. A frame is a
        massless link whose inertial frame is at its origin (`robots.urdf`), so its
        `linkWorldPosition` (element 0, computed in double precision) is the frame's origin;
        `worldLinkFramePosition` (element 4) comes back rounded to float32 (errors up to
        1.1e-7 m measured, where the three-model test asks 1e-9 with rtol 0)."""
        states = pb.getLinkStates(
            self.body,
            [self._index["link:" + n] for n in names],
            computeForwardKinematics=1,
            physicsClientId=self.client,
        )
        return np.array([s[0] for s in states])
