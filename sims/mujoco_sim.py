"""MuJoCo backend: the generated MJCF loaded through `mujoco.MjSpec` (free joint at the root),
the scene added through the same MjSpec.

Physics settings (identical intent to `sims.pybullet_sim`; see docs/simulators.md):
- integrator Euler (semi-implicit, like Bullet), elliptic friction cone (Coulomb's circle, as
  Bullet's default cone friction) with `FRICTION_IMPRATIO`, condim 3 (no torsional or rolling
  friction: Bullet has none by default), friction = scene.friction;
- contact softness solref = (0.005 s, 1.0) (stiffer than MuJoCo's default 0.02 s, as fine as a
  1 ms step allows: timeconst >= 2 dt), solimp default; no joint armature, damping or friction.

Moving boxes (`robots.scene.MovingBox`): each is a body with a free joint whose position and
velocity are overwritten at every physics step with the prescribed motion (`_move_boxes`), not
a mocap body: MuJoCo gives mocap bodies no velocity in the constraint solver, so friction does
not carry what stands on them (measured: a cube on a mocap plate moving 20 mm sideways stayed
put, at x = 0 to 1e-5 m, while the plate moved under it). The free joint's velocity is in the
contact's relative velocity; its armature (`MOVING_BOX_ARMATURE`) makes the contact forces
unable to move it within a step, and gravity is compensated (`gravcomp`). The armature also
inflates `stat.meaninertia` (4.1 -> 4.8e4 in `moving_contacts`), which scales the solver's
tolerance: measured to change nothing (the robot holding its posture on the moving floors of
`moving_contacts` for 1.8 s is bit for bit the same with meaninertia set back to the robot's
value; the solver takes 1-4 iterations a step in both).

Grasps (`sims.base` docstring): a scene with boxes gets one weld equality (`mjEQ_WELD`) per
(limb, box) pair, `grasp_<limb>_<box>`, between the limb's link (body1) and the box's body
(body2: the world for a static box, the free body of a moving one), inactive: an inactive
equality makes no constraint row, so nothing changes until a grasp is made (a flat scene
compiles none). Making one writes its relative pose into `eq_data` (anchor: the palm centre, in
each body's frame; relative orientation body1^-1 body2, the current one) and sets
`MjData.eq_active`; the model is compiled once per process and shared, so the simulator first
takes its own copy of it (`_own_model`). A contact's time constant (`GRASP_SOLREF`) with a
nearly rigid impedance (`GRASP_SOLIMP`: see there why), and no force limit (MuJoCo's
equalities have none). Its force is in `cfrc_ext` (MuJoCo adds the weld's force to the
bodies' external forces), so the limb wrench includes it; when a push acts on the limb's body
the push is subtracted from it (`_read_sensors`). Both `grasp` and `release` make the next
physics step a full `mj_step`: constraint rows are built in the position stage.
"""

from __future__ import annotations

import copy
import functools
import time
from dataclasses import replace

import mujoco
import numpy as np

from robots.build import generate
from robots.scene import Scene
from robots.spec import RobotDescription
from robots.types import MassProperties, RobotState, Sensors
from sims.base import (
    SimulatorBase,
    SimulatorError,
    contiguous,
    cross,
    limb_wrenches,
    quaternion_product,
    quaternion_to_matrix,
)
from sims.kernels import mujoco_sensors
from sims.sensor_buffer import SensorLayout

CONTACT_SOLREF = (0.005, 1.0)
"""Every contact's solref (time constant [s], damping ratio): stiffer than MuJoCo's default
0.02 s (see the module); PyBullet's contacts are rigid with an ERP (`sims.pybullet_sim`)."""
FRICTION_CONE = mujoco.mjtCone.mjCONE_ELLIPTIC
FRICTION_IMPRATIO = 10.0
"""The friction law: Coulomb's cone |f_t| <= mu f_n (elliptic), as PyBullet's (its default
`enableConeFriction`); the friction constraint 10 times harder than the normal one
(`impratio`), so that a contact below the limit does not creep (Bullet's friction is a rigid
constraint). Measured (2026-11-27, a 30 kg box on a 25 deg incline, mu 0.6, pushed sideways
by r f_n, `tests/sims/test_agreement.py`): the slip threshold is the circle's r =
sqrt(0.6^2 - tan^2 25 deg) = 0.378 with this cone in MuJoCo and in PyBullet; with MuJoCo's
pyramidal cone, used before, it was 0.134 (the pyramid's edges along the sole's axes make the
cone a diamond, |f_x| + |f_y| <= mu f_n: 0.71 mu along a diagonal). The soft friction
constraint also lets a contact creep below the limit, in proportion to the load over the
friction's impedance: 0.27 mm/s for the box at impratio 1, 0.03 mm/s at 10; a stance sole on
Fig. 4 (A)'s board crept down it at 6 mm/s (26 mm per stance) at impratio 1 and 0.2 mm/s at 10
(both pyramidal). With the pyramidal cone at impratio 1, (A) as redesigned on 2026-11-27 fell
at 30.7 s (MuJoCo) against 54.9 s (PyBullet); with this cone and impratio, at 54.8 s."""
GRASP_SOLREF = CONTACT_SOLREF
"""A grasp's weld corrects its error with a contact's time constant (5 ms, critically damped:
as fast as a 1 ms step allows, timeconst >= 2 dt)."""
GRASP_SOLIMP = (0.999, 0.999, 0.001, 0.5, 2.0)
"""A grasp's weld impedance: nearly rigid, like PyBullet's fixed constraint. With the default
(0.9 to 0.95, a contact's) a constant load leaves an error (1 - d) / (d k) times the
unconstrained acceleration, a stiffness proportional to the effective inertia, which is small
in rotation: measured with a (40, -20, 100) N pull on the forearm of a hand grasping a bar, the
arm's servos took 1.5 % of the force and 35 % of the 2.1 N m moment about x, and the robot
swayed for 1 s; with 0.999 the grasp's wrench equals the load to 0.1 % and 1 % (the palm moves
1 um), as in PyBullet."""
GRASP_PREFIX = "grasp_"
"""Name prefix of the weld equalities: `grasp_<limb>_<box>`."""
SCENE_CONTYPE, SCENE_CONAFFINITY = 0, 1
MOVING_PREFIX = "moving_"
"""Name prefix of a moving box's body and free joint (its geom is `box_<name>`, as a static
box's)."""
MOVING_BOX_ARMATURE = 1.0e5
"""[kg, kg m^2] on each of a moving box's six degrees of freedom: a robot's 600 N moves it by
600 / 1e5 x dt^2 = 6e-9 m and 6e-6 m/s within a 1 ms step, before `_move_boxes` puts it back
on its path. Measured (the robot holding its posture 2 s on a plate moving 20 mm and 2 deg):
1e4, 1e5 and 1e6 give base paths within 0.005 mm of each other (1.03-1.06 solver iterations a
step); from 1e7 on MuJoCo's solver stops earlier (0.83 iterations a step at 1e7, 0.1 at 1e8)
and the path moves by 0.1 mm (1e7) to 0.8 mm (1e10)."""

# MuJoCo's warnings that mean the physics can no longer be trusted. On a bad acceleration,
# position or velocity MuJoCo resets the state to the model's default pose and carries on
# (the robot then lies on the ground and would count as fallen); a full contact or constraint
# buffer drops contacts. Each is checked every control period and ends the episode as an
# error (`SimulatorError`) with MuJoCo's message.
UNSTABLE_WARNINGS = (
    mujoco.mjtWarning.mjWARN_BADQACC,
    mujoco.mjtWarning.mjWARN_BADQVEL,
    mujoco.mjtWarning.mjWARN_BADQPOS,
    mujoco.mjtWarning.mjWARN_BADCTRL,
    mujoco.mjtWarning.mjWARN_CONTACTFULL,
    mujoco.mjtWarning.mjWARN_CNSTRFULL,
)
_UNSTABLE_INDEX = np.array([int(w) for w in UNSTABLE_WARNINGS])
_last_warning: list[str] = [""]


def _keep_warning(message: str) -> None:
    """MuJoCo's warning handler: keep the text for the error message instead of printing it
    on stdout (where it would break `centrobench run --json`)."""
    _last_warning[0] = " ".join(message.split())


mujoco.set_mju_user_warning(_keep_warning)


def set_physics_options(spec: mujoco.MjSpec, physics_dt: float, gravity: float) -> None:
    """The integrator, step [s], gravity [m/s^2] and friction law of every model here (see the
    module docstring, `FRICTION_CONE`)."""
    spec.option.timestep = physics_dt
    spec.option.gravity = [0.0, 0.0, -gravity]
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_EULER
    spec.option.cone = FRICTION_CONE
    spec.option.impratio = FRICTION_IMPRATIO


@functools.lru_cache(maxsize=8)
def build_model(robot: RobotDescription, scene: Scene) -> mujoco.MjModel:
    """Compile robot + scene into an MjModel with the scene's physics settings. Cached per
    process (the simulator never changes its model; each episode gets a new MjData)."""
    spec = mujoco.MjSpec.from_file(str(generate(robot).mjcf))
    set_physics_options(spec, scene.physics_dt, scene.gravity)
    for geom in spec.geoms:
        geom.friction = [scene.friction, 0.0, 0.0]
        geom.condim = 3
        geom.solref = list(CONTACT_SOLREF)
    world = spec.worldbody
    scene_geoms = []
    if scene.ground:
        scene_geoms.append(
            world.add_geom(name="ground", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1.0])
        )
    for box in scene.boxes:
        scene_geoms.append(
            world.add_geom(
                name=f"box_{box.name}",
                type=mujoco.mjtGeom.mjGEOM_BOX,
                size=list(box.half_extents),
                pos=list(box.center_world),
                quat=list(box.orientation_world),
            )
        )
    for box in scene.moving_boxes:
        center, quaternion = box.pose_at(0.0)
        body = world.add_body(
            name=MOVING_PREFIX + box.name, pos=center.tolist(), quat=quaternion.tolist()
        )
        # 1 kg of uniform box (the armature dominates), weight compensated
        hx, hy, hz = box.half_extents
        body.explicitinertial = True
        body.mass = 1.0
        body.inertia = [(hy * hy + hz * hz) / 3, (hx * hx + hz * hz) / 3, (hx * hx + hy * hy) / 3]
        body.gravcomp = 1.0
        joint = body.add_freejoint(name=MOVING_PREFIX + box.name)
        joint.armature = MOVING_BOX_ARMATURE
        scene_geoms.append(
            body.add_geom(
                name=f"box_{box.name}",
                type=mujoco.mjtGeom.mjGEOM_BOX,
                size=list(box.half_extents),
            )
        )
    for geom in scene_geoms:
        geom.contype, geom.conaffinity = SCENE_CONTYPE, SCENE_CONAFFINITY
        geom.friction = [scene.friction, 0.0, 0.0]
        geom.condim = 3
        geom.solref = list(CONTACT_SOLREF)
    for limb in robot.limbs:  # the grasps' welds, inactive (`MujocoSimulator._make_grasp`)
        for box in scene.boxes:
            _add_grasp_weld(spec, limb.name, limb.link, box.name, "world")
        for box in scene.moving_boxes:
            _add_grasp_weld(spec, limb.name, limb.link, box.name, MOVING_PREFIX + box.name)
    return spec.compile()


def _add_grasp_weld(spec: mujoco.MjSpec, limb: str, link: str, box: str, body: str) -> None:
    spec.add_equality(
        name=f"{GRASP_PREFIX}{limb}_{box}",
        type=mujoco.mjtEq.mjEQ_WELD,
        objtype=mujoco.mjtObj.mjOBJ_BODY,
        name1=link,
        name2=body,
        active=False,
        solref=list(GRASP_SOLREF),
        solimp=list(GRASP_SOLIMP),
    )


def clear_cache() -> None:
    """Forget the compiled models (`sims.base.clear_backend_caches`)."""
    build_model.cache_clear()


class MujocoSimulator(SimulatorBase):
    name = "mujoco"

    def _load(self, robot: RobotDescription, scene: Scene) -> None:
        # the grasps are events, not the model: one compiled model for every schedule
        m = self.model = build_model(robot, replace(scene, grasps=()) if scene.grasps else scene)
        self._model_owned = False  # `_own_model`
        self.data = mujoco.MjData(m)
        _last_warning[0] = ""

        def jid(name: str) -> int:
            return mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, name)

        def bid(name: str) -> int:
            return mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, name)

        def sid(name: str) -> int:
            return mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, name)

        joint_ids = [jid(n) for n in robot.joint_names]
        # index arrays, as slices where contiguous (a view: 6x cheaper than fancy indexing)
        self._qpos_idx = contiguous([m.jnt_qposadr[j] for j in joint_ids])
        self._dof_idx = contiguous([m.jnt_dofadr[j] for j in joint_ids])
        actuator_ids = [
            mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, n) for n in robot.joint_names
        ]
        self._actuator_idx = contiguous(actuator_ids)
        self._root_qpos = m.jnt_qposadr[jid("root")]
        self._root_dof = m.jnt_dofadr[jid("root")]
        self._body_id = {link.name: bid(link.name) for link in robot.links}
        self._body_name = {v: k for k, v in self._body_id.items()}
        self._limb_body = np.array([self._body_id[limb.link] for limb in robot.limbs])
        # cfrc_ext is a spatial force about the subtree CoM of each body's root body
        self._limb_root = m.body_rootid[self._limb_body]
        self._limb_body_set = frozenset(self._limb_body.tolist())
        self._limb_body_mask = np.zeros(m.nbody, dtype=bool)
        self._limb_body_mask[self._limb_body] = True
        self._limb_pushed = False  # a push acts on a limb's body (see `_limb_wrenches`)
        self._limb_site = np.array([sid(limb.contact_frame) for limb in robot.limbs])
        self._site_id = {f.name: sid(f.name) for f in robot.frames}
        moving_joints = [jid(MOVING_PREFIX + box.name) for box in scene.moving_boxes]
        self._moving = [
            (box, int(m.jnt_qposadr[j]), int(m.jnt_dofadr[j]))
            for box, j in zip(scene.moving_boxes, moving_joints, strict=True)
        ]
        scene_bodies = {0, *(int(m.jnt_bodyid[j]) for j in moving_joints)}
        self._scene_geom = np.array(
            [
                m.geom_contype[g] == SCENE_CONTYPE
                and m.geom_conaffinity[g] == SCENE_CONAFFINITY
                and int(m.geom_bodyid[g]) in scene_bodies
                for g in range(m.ngeom)
            ]
        )
        self._box_geom = {
            box.name: mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, f"box_{box.name}")
            for box in (*scene.boxes, *scene.moving_boxes)
        }
        self._grasp_weld = {
            (k, box): mujoco.mj_name2id(
                m, mujoco.mjtObj.mjOBJ_EQUALITY, f"{GRASP_PREFIX}{limb.name}_{box}"
            )
            for k, limb in enumerate(robot.limbs)
            for box in self._box_geom
        }
        self._grasp_active: dict[int, int] = {}  # limb number -> its active weld

        def sensor(name: str) -> slice:
            i = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SENSOR, name)
            return slice(m.sensor_adr[i], m.sensor_adr[i] + m.sensor_dim[i])

        self._imu_quat, self._imu_gyro, self._imu_accel = (
            sensor("imu_quat"),
            sensor("imu_gyro"),
            sensor("imu_accel"),
        )
        self._geom_body = m.geom_bodyid.copy()
        # numpy views of MjData's buffers (fixed for its lifetime), taken once: every attribute
        # access through the bindings costs about 1 us per period once the control stages have
        # evicted the bindings' code from the caches
        d = self.data
        self._qpos, self._qvel, self._ctrl = d.qpos, d.qvel, d.ctrl
        self._sensordata, self._warnings = d.sensordata, d.warning.number
        if isinstance(self._qpos_idx, slice) and isinstance(self._dof_idx, slice):
            joint_views = (d.qpos[self._qpos_idx], d.qvel[self._dof_idx])
            self._joint_views: tuple[np.ndarray, np.ndarray] | None = joint_views
        else:
            self._joint_views = None
        self._layout = SensorLayout(robot.n_joints, len(robot.limbs))
        self._joint_qpos = np.array([m.jnt_qposadr[j] for j in joint_ids])
        self._joint_dof = np.array([m.jnt_dofadr[j] for j in joint_ids])
        self._root_and_imu = np.array(
            [
                self._root_qpos,
                self._root_dof,
                self._imu_quat.start,
                self._imu_gyro.start,
                self._imu_accel.start,
            ]
        )
        self._spatial_inputs = (d.cfrc_ext, d.subtree_com, d.site_xpos, d.site_xmat)
        self._limb_inputs = (self._limb_body, self._limb_root, self._limb_site)
        self._contact_cache: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        self._touching_cache: np.ndarray | None = None
        self._pushing = False  # xfrc_applied holds a push
        self._forwarded = False  # mj_forward has run on the current state

    def _move_boxes(self, time: float) -> None:
        """Put every moving box at its prescribed pose and velocity at `time` [s]: the free
        joint's position, quaternion, linear velocity (world) and angular velocity (in the
        box's frame, MuJoCo's convention)."""
        qpos, qvel = self._qpos, self._qvel
        for box, q, v in self._moving:
            center, quaternion = box.pose_at(time)
            linear, angular = box.velocity_at(time)
            qpos[q : q + 3] = center
            qpos[q + 3 : q + 7] = quaternion
            qvel[v : v + 3] = linear
            qvel[v + 3 : v + 6] = quaternion_to_matrix(quaternion).T @ angular
        self._forwarded = False
        self._contact_cache = self._touching_cache = None
        self._checks_fresh = False

    def _own_model(self) -> mujoco.MjModel:
        """The simulator's own copy of the model, taken at its first grasp (`build_model`'s
        are shared by every simulator of the process; a grasp writes into `eq_data`)."""
        if not self._model_owned:
            self.model = copy.copy(self.model)
            self._model_owned = True
        return self.model

    def _make_grasp(self, limb: int, box: str) -> None:
        """Activate the (limb, box) weld with the current relative pose: anchor at the palm
        centre in body2's frame (eq_data[0:3]) and in body1's (eq_data[3:6]), orientation
        body1^-1 body2 (eq_data[6:10], w x y z)."""
        m, d = self._own_model(), self.data
        weld = self._grasp_weld[(limb, box)]
        mujoco.mj_kinematics(m, d)  # the current state's poses (recomputed: unchanged)
        body1, body2 = int(m.eq_obj1id[weld]), int(m.eq_obj2id[weld])
        palm = d.site_xpos[self._limb_site[limb]]
        m.eq_data[weld, 0:3] = d.xmat[body2].reshape(3, 3).T @ (palm - d.xpos[body2])
        m.eq_data[weld, 3:6] = d.xmat[body1].reshape(3, 3).T @ (palm - d.xpos[body1])
        w, x, y, z = d.xquat[body1].tolist()
        relative = quaternion_product((w, -x, -y, -z), d.xquat[body2])
        m.eq_data[weld, 6:10] = relative / np.linalg.norm(relative)
        d.eq_active[weld] = 1
        self._grasp_active[limb] = weld
        self._forwarded = False  # constraint rows are made in mj_step1's position stage

    def _drop_grasp(self, limb: int) -> None:
        self.data.eq_active[self._grasp_active.pop(limb)] = 0
        self._forwarded = False

    def _push_wrench(self, limb: int) -> np.ndarray:
        """The push on limb number `limb`'s body (`xfrc_applied`, at its centre of mass) as a
        wrench in its contact frame about its origin, as `cfrc_ext` counts it."""
        d, body, site = self.data, self._limb_body[limb], self._limb_site[limb]
        force = d.xfrc_applied[body, :3]
        moment = d.xfrc_applied[body, 3:] + cross(d.xipos[body] - d.site_xpos[site], force)
        rotation = d.site_xmat[site].reshape(3, 3)
        return np.concatenate([rotation.T @ force, rotation.T @ moment])

    def scene_boxes_world(self) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Every box (static and moving) as MuJoCo holds it now: name -> (centre [m],
        orientation (w, x, y, z), half extents [m]), from the geoms' world poses after a
        kinematics pass (which recomputes the current state's poses, changing nothing) and
        their sizes."""
        m, d = self.model, self.data
        mujoco.mj_kinematics(m, d)
        boxes = {}
        for name, g in self._box_geom.items():
            quaternion = np.empty(4)
            mujoco.mju_mat2Quat(quaternion, d.geom_xmat[g])
            boxes[name] = (d.geom_xpos[g].copy(), quaternion, m.geom_size[g].copy())
        return boxes

    def set_state(self, state: RobotState) -> None:
        d, r, v = self.data, self._root_qpos, self._root_dof
        d.qpos[r : r + 3] = state.base_position_world
        d.qpos[r + 3 : r + 7] = state.base_orientation_world / np.linalg.norm(
            state.base_orientation_world
        )
        d.qpos[self._qpos_idx] = state.joint_position
        rotation = quaternion_to_matrix(d.qpos[r + 3 : r + 7])
        # Free joint velocity: linear of the body origin in world, angular in the body frame.
        d.qvel[v : v + 3] = state.base_linear_velocity_world
        d.qvel[v + 3 : v + 6] = rotation.T @ state.base_angular_velocity_world
        d.qvel[self._dof_idx] = state.joint_velocity
        d.qacc_warmstart[:] = 0.0
        mujoco.mj_forward(self.model, d)
        self._forwarded = True
        self._contact_cache = self._touching_cache = None
        self._checks_fresh = False

    def ground_truth(self) -> RobotState:
        d, r, v = self.data, self._root_qpos, self._root_dof
        quat = d.qpos[r + 3 : r + 7].copy()
        return RobotState(
            base_position_world=d.qpos[r : r + 3].copy(),
            base_orientation_world=quat,
            base_linear_velocity_world=d.qvel[v : v + 3].copy(),
            base_angular_velocity_world=quaternion_to_matrix(quat) @ d.qvel[v + 3 : v + 6],
            joint_position=d.qpos[self._qpos_idx].copy(),
            joint_velocity=d.qvel[self._dof_idx].copy(),
        )

    def _joint_state(self) -> tuple[np.ndarray, np.ndarray]:
        if self._joint_views is not None:
            return self._joint_views
        return self._qpos[self._qpos_idx], self._qvel[self._dof_idx]

    def _physics_step(
        self, torque: np.ndarray, forces: list[tuple[str, np.ndarray]], last: bool
    ) -> None:
        d = self.data
        self._contact_cache = self._touching_cache = None
        self._checks_fresh = False
        self._ctrl[self._actuator_idx] = torque
        if forces or self._pushing:
            d.xfrc_applied[:] = 0.0
            self._limb_pushed = False
            for link, force in forces:  # xfrc_applied acts at the body's centre of mass
                body = self._body_id[link]
                d.xfrc_applied[body, :3] += force
                self._limb_pushed |= body in self._limb_body_set
            self._pushing = bool(forces)
        start = time.perf_counter_ns()
        if self._forwarded:
            # mj_step = mj_step1 (positions, velocities: independent of ctrl and xfrc_applied)
            # + mj_step2 (actuation, acceleration, constraints, integration); the state's
            # mj_forward (after the last period, or set_state) already did mj_step1's part.
            mujoco.mj_step2(self.model, d)
            self._forwarded = False
        else:
            mujoco.mj_step(self.model, d)
        self.engine_ns += time.perf_counter_ns() - start

    def _contacts(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Active contacts between a robot geom and a scene geom, as arrays over the contacts:
        robot body ids (n,), contact points world (n, 3) [m], forces on the robot world
        (n, 3) [N]. Read once per state: cached until the next physics step or `set_state`."""
        if self._contact_cache is not None:
            return self._contact_cache
        m, d = self.model, self.data
        contact = d.contact
        geom1, geom2 = contact.geom1[: d.ncon], contact.geom2[: d.ncon]
        scene1, scene2 = self._scene_geom[geom1], self._scene_geom[geom2]
        keep = np.flatnonzero(scene1 != scene2)
        forces = np.empty((len(keep), 6))
        for j, i in enumerate(keep.tolist()):
            mujoco.mj_contactForce(m, d, i, forces[j])
        frames = contact.frame[keep].reshape(-1, 3, 3)  # rows: normal (geom1 -> geom2), tangents
        force_on_geom2 = np.einsum("kji,kj->ki", frames, forces[:, :3])
        robot_is_2 = scene1[keep]
        bodies = np.where(robot_is_2, m.geom_bodyid[geom2[keep]], m.geom_bodyid[geom1[keep]])
        on_robot = np.where(robot_is_2[:, None], force_on_geom2, -force_on_geom2)
        self._contact_cache = (bodies, contact.pos[keep].copy(), on_robot)
        return self._contact_cache

    def _touching_bodies(self) -> np.ndarray:
        """Robot body ids (n,) of the active contacts between a robot geom and a scene geom
        (as `_contacts`, without the forces). Cached until the next physics step."""
        if self._touching_cache is None:
            d = self.data
            geoms = d.contact.geom[: d.ncon]  # (n, 2)
            scene = self._scene_geom[geoms]
            robot_geom = np.where(scene[:, 0], geoms[:, 1], geoms[:, 0])
            self._touching_cache = self._geom_body[robot_geom[scene[:, 0] != scene[:, 1]]]
        return self._touching_cache

    def _links_touching_scene(self) -> set[str]:
        return {self._body_name[b] for b in self._touching_bodies().tolist()}

    def _check_warnings(self) -> None:
        """SimulatorError when MuJoCo has raised an instability warning (`UNSTABLE_WARNINGS`)."""
        counts = self._warnings
        if counts.any() and counts[_UNSTABLE_INDEX].any():
            names = [w.name for w in UNSTABLE_WARNINGS if counts[int(w)]]
            detail = _last_warning[0] or ", ".join(names)
            raise SimulatorError(f"mujoco: unstable simulation at t = {self.time:.3f} s: {detail}")

    def _read_sensors(self) -> Sensors:
        """The state, the IMU and the contacts after the forward pass (`kernels.mujoco_sensors`).
        The limb wrenches come from MuJoCo's `cfrc_ext`: the external spatial force (moment,
        force) on each body about the subtree CoM of its root body, in world axes, which the
        forward pass computes for the accelerometer (its contacts summed in C; equal to the sum
        of `mj_contactForce` over each body's contacts to 1e-12 N: a test), and the force of a
        grasp's weld. A push on a limb's body is in `cfrc_ext` too: then the contacts are summed
        one by one (`_contacts`), and a grasping limb's wrench is `cfrc_ext`'s without the
        push."""
        m, d = self.model, self.data
        start = time.perf_counter_ns()
        mujoco.mj_forward(m, d)  # sensors, contacts and poses of the state after the step
        self.engine_ns += time.perf_counter_ns() - start
        self._forwarded = True
        self._contact_cache = None
        buffer, checks = self._layout.buffer(), self._checks
        flags, self._touching_cache = mujoco_sensors(
            self._qpos,
            self._qvel,
            self._sensordata,
            self._last_torque,
            self._joint_qpos,
            self._joint_dof,
            self._root_and_imu,
            *self._spatial_inputs,
            *self._limb_inputs,
            d.contact.geom[: d.ncon],
            self._scene_geom,
            self._geom_body,
            self._limb_body_mask,
            self._warnings,
            _UNSTABLE_INDEX,
            buffer,
            checks,
        )
        if checks[3]:  # an instability warning (in the step or this forward pass)
            self._check_warnings()
        self._checks_fresh = True
        sensors = self._layout.sensors(self.time, buffer, flags)
        if self._grasp_active:
            flags[list(self._grasp_active)] = True
        if self._limb_pushed:
            holding = {
                limb: sensors.contact_wrench_limb[limb] - self._push_wrench(limb)
                for limb in self._grasp_active
            }
            bodies, points, forces = self._contacts()
            sensors.contact_wrench_limb[:] = limb_wrenches(
                bodies,
                points,
                forces,
                self._limb_body,
                d.site_xpos[self._limb_site],
                d.site_xmat[self._limb_site].reshape(-1, 3, 3),
            )[0]
            for limb, wrench in holding.items():
                sensors.contact_wrench_limb[limb] = wrench
        return sensors

    def mass_properties(self) -> MassProperties:
        m = self.model
        assert self.robot is not None
        bodies = [self._body_id[link.name] for link in self.robot.links]
        inertia = []
        for b in bodies:
            rotation = quaternion_to_matrix(m.body_iquat[b])
            inertia.append(rotation @ np.diag(m.body_inertia[b]) @ rotation.T)
        joint_ids = [
            mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, n)
            for n in (mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) for j in range(m.njnt))
            if n != "root" and not n.startswith(MOVING_PREFIX)
        ]
        return MassProperties(
            source="mujoco",
            body_names=tuple(self._body_name[b] for b in bodies),
            mass=m.body_mass[bodies].copy(),
            com_in_body=m.body_ipos[bodies].copy(),
            inertia_at_com_in_body=np.array(inertia),
            joint_names=tuple(
                mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) for j in joint_ids
            ),
            joint_lower=m.jnt_range[joint_ids, 0].copy(),
            joint_upper=m.jnt_range[joint_ids, 1].copy(),
        )

    def frame_positions_world(self, names: list[str]) -> np.ndarray:
        mujoco.mj_kinematics(self.model, self.data)
        return np.array([self.data.site_xpos[self._site_id[n]] for n in names])
