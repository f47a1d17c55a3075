"""The pinocchio model of a `RobotDescription`, built from the same generated URDF as PyBullet,
with a free-flyer root.

Conventions at this boundary: pinocchio's configuration stores the base quaternion as
(x, y, z, w) and its velocity holds the base twist in the base frame; `RobotState` uses
(w, x, y, z) and world-frame velocities. `configuration` and `velocity` convert.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pinocchio as pin

from robots.build import generate
from robots.spec import RobotDescription
from robots.types import JointCommand, MassProperties, RobotState


@functools.lru_cache(maxsize=8)
def cached_model(robot: RobotDescription) -> RobotModel:
    """The `RobotModel` of `robot`, built once per process (a sweep worker's episodes share
    it). Sharing is safe because its only state is pinocchio's scratch `data`, which every
    algorithm rewrites before reading (tests/bench/test_setup_cache.py: an episode after a fall
    equals the same episode run first); components take their own `model.createData()`."""
    return RobotModel(robot)


class RobotModel:
    """Kinematics and mass properties of one robot (pinocchio)."""

    def __init__(self, robot: RobotDescription) -> None:
        self.robot = robot
        self.model = pin.buildModelFromUrdf(str(generate(robot).urdf), pin.JointModelFreeFlyer())
        self.data = self.model.createData()
        self.frame_id = {f.name: i for i, f in enumerate(self.model.frames)}
        names = list(self.model.names)[2:]
        if names != list(robot.joint_names):
            raise RuntimeError(f"pinocchio joint order {names} differs from the description's")

    @property
    def total_mass(self) -> float:
        """[kg]"""
        return float(pin.computeTotalMass(self.model))

    def configuration(self, state: RobotState) -> np.ndarray:
        """pinocchio q: base position, base quaternion (x, y, z, w), joint positions."""
        quaternion = np.asarray(state.base_orientation_world, dtype=float)
        w, x, y, z = (quaternion / math.sqrt(quaternion @ quaternion)).tolist()
        return np.concatenate([state.base_position_world, (x, y, z, w), state.joint_position])

    def velocity(self, state: RobotState, q: np.ndarray | None = None) -> np.ndarray:
        """pinocchio v: base linear and angular velocity in the base frame, joint velocities;
        `q` is `configuration(state)` when the caller has it already."""
        if q is None:
            q = self.configuration(state)
        rotation_t = pin.Quaternion(q[6], q[3], q[4], q[5]).toRotationMatrix().T
        return np.concatenate(
            [
                rotation_t @ state.base_linear_velocity_world,
                rotation_t @ state.base_angular_velocity_world,
                state.joint_velocity,
            ]
        )

    def frame_positions_world(self, state: RobotState, names: list[str]) -> np.ndarray:
        """Positions [m] of named frames in the world for `state` (forward kinematics)."""
        pin.framesForwardKinematics(self.model, self.data, self.configuration(state))
        return np.array([self.data.oMf[self.frame_id[n]].translation.copy() for n in names])

    def com_position_world(self, state: RobotState) -> np.ndarray:
        """Centre of mass [m]."""
        return pin.centerOfMass(self.model, self.data, self.configuration(state)).copy()

    def com_state_world(self, state: RobotState) -> tuple[np.ndarray, np.ndarray]:
        """Centre of mass [m] and its velocity [m/s], in one pass."""
        q = self.configuration(state)
        com = pin.centerOfMass(self.model, self.data, q, self.velocity(state, q))
        return com.copy(), self.data.vcom[0].copy()

    def com_state_and_frame_position_world(
        self, state: RobotState, name: str
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Centre of mass [m], its velocity [m/s] and the position [m] of the named frame in
        the world, from the one forward-kinematics pass of `com_state_world` (the centre-of-mass
        pass places every joint; the frame is placed from its parent joint, no second pass)."""
        q = self.configuration(state)
        com = pin.centerOfMass(self.model, self.data, q, self.velocity(state, q))
        placement = pin.updateFramePlacement(self.model, self.data, self.frame_id[name])
        return com.copy(), self.data.vcom[0].copy(), placement.translation.copy()

    def com_velocity_world(self, state: RobotState) -> np.ndarray:
        """Centre-of-mass velocity [m/s]."""
        pin.centerOfMass(self.model, self.data, self.configuration(state), self.velocity(state))
        return self.data.vcom[0].copy()

    def static_torques(self, state: RobotState, contact_frames: list[str]) -> np.ndarray:
        """Joint torques [N m] that hold `state` at rest with the contact frames carrying the
        weight: tau = g_j(q) - J_c,j^T lambda, where the contact wrenches lambda (6 per frame,
        world-aligned at the frame) are the least-norm solution of the base rows
        g_b(q) = J_c,b^T lambda (static equilibrium of the floating base)."""
        q = self.configuration(state)
        gravity = pin.computeGeneralizedGravity(self.model, self.data, q)
        pin.computeJointJacobians(self.model, self.data, q)
        pin.framesForwardKinematics(self.model, self.data, q)
        jacobian = np.vstack(
            [
                pin.getFrameJacobian(
                    self.model, self.data, self.frame_id[f], pin.LOCAL_WORLD_ALIGNED
                )
                for f in contact_frames
            ]
        )
        wrenches = np.linalg.lstsq(jacobian[:, :6].T, gravity[:6], rcond=None)[0]
        return gravity[6:] - jacobian[:, 6:].T @ wrenches

    def hold_command(self, state: RobotState) -> JointCommand:
        """Servo targets that hold `state`'s posture with the description's gains and the
        static feed-forward torques of `static_torques` with the weight on the feet."""
        robot = self.robot
        feet = [limb.contact_frame for limb in robot.limbs if limb.name.endswith("foot")]
        return JointCommand(
            position=np.array(state.joint_position, dtype=float),
            velocity=np.zeros(robot.n_joints),
            torque_feedforward=self.static_torques(state, feet),
            kp=robot.array("kp"),
            kd=robot.array("kd"),
        )

    # ------------------------------------------------------------- centroidal quantities
    def centroidal_momentum_matrix(self, state: RobotState) -> np.ndarray:
        """A_G (6 x nv) with h_G = A_G v = [linear momentum; angular momentum about the CoM]
        (world axes), v in pinocchio's convention (see `velocity`)."""
        q = self.configuration(state)
        return pin.computeCentroidalMap(self.model, self.data, q).copy()

    def centroidal_momentum(self, state: RobotState) -> tuple[np.ndarray, np.ndarray]:
        """Linear momentum [kg m/s] and angular momentum about the CoM [kg m^2/s], world axes."""
        h = pin.computeCentroidalMomentum(
            self.model, self.data, self.configuration(state), self.velocity(state)
        )
        return h.linear.copy(), h.angular.copy()

    def inertia_all(self, state: RobotState) -> np.ndarray:
        """I_all of Murooka eq. 6 (3 x nv): L = I_all q-dot, the angular rows of A_G."""
        return self.centroidal_momentum_matrix(state)[3:]

    def inertia_base(self, state: RobotState) -> np.ndarray:
        """I_base of Murooka eq. 6 (3 x 3): the block of I_all for the base angular velocity,
        here mapping the world-frame base angular velocity (pinocchio's is in the base frame,
        hence the rotation)."""
        q = self.configuration(state)
        rotation = pin.Quaternion(q[6], q[3], q[4], q[5]).toRotationMatrix()
        return self.inertia_all(state)[:, 3:6] @ rotation.T

    def constant_inertia(self) -> np.ndarray:
        """I of Murooka eq. 6: a constant diagonal approximation of I_base, taken as the
        diagonal of I_base in the standing posture [kg m^2]."""
        return np.diag(np.diag(self.inertia_base(self.standing_state())))

    def frame_pose(self, state: RobotState, name: str) -> tuple[np.ndarray, np.ndarray]:
        """Position [m] and rotation matrix of a named frame in the world."""
        pin.framesForwardKinematics(self.model, self.data, self.configuration(state))
        placement = self.data.oMf[self.frame_id[name]]
        return placement.translation.copy(), placement.rotation.copy()

    def frame_jacobian(self, state: RobotState, name: str) -> np.ndarray:
        """6 x nv Jacobian of a named frame: [linear velocity of its origin; angular velocity],
        world axes, for pinocchio's v (see `velocity`)."""
        q = self.configuration(state)
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        return pin.getFrameJacobian(
            self.model, self.data, self.frame_id[name], pin.LOCAL_WORLD_ALIGNED
        ).copy()

    def standing_state(self) -> RobotState:
        """The nominal posture with the base upright and placed so that the lowest sole centre
        is on the ground (z = 0), the soles centred about x = 0."""
        posture = np.array(self.robot.nominal_posture)
        upright = RobotState.at_rest(np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0]), posture)
        soles = [limb.contact_frame for limb in self.robot.limbs if limb.name.endswith("foot")]
        positions = self.frame_positions_world(upright, soles)
        offset = np.array([-positions[:, 0].mean(), 0.0, -positions[:, 2].min()])
        return RobotState.at_rest(offset, upright.base_orientation_world, posture)

    def standing_height(self) -> float:
        """[m] the top of the robot's shapes in `standing_state` above the ground: the highest
        point of each shape's bounding sphere (boxes: half diagonal; capsules: half length
        plus radius), which is exact for the spheres and vertical capsules that top a
        humanoid (its head)."""
        state = self.standing_state()
        pin.framesForwardKinematics(self.model, self.data, self.configuration(state))
        top = 0.0
        for link in self.robot.links:
            placement = self.data.oMf[self.frame_id[link.name]]
            for shape in link.geometries:
                centre = placement.act(np.array(shape.position_in_link))
                if shape.kind == "box":
                    reach = float(np.linalg.norm(shape.size))
                elif shape.kind == "capsule":
                    reach = shape.size[0] + shape.size[1]
                else:
                    reach = shape.size[0]
                top = max(top, float(centre[2]) + reach)
        return top

    def mass_properties(self) -> MassProperties:
        """Per-joint-body mass properties (pinocchio merges the massless frame links into
        their parent body, which leaves exactly one body per link)."""
        model = self.model
        names, mass, com, inertia = [], [], [], []
        joint_to_link = {j.name: j.child for j in self.robot.joints}
        for i in range(1, model.njoints):
            body = model.inertias[i]
            names.append(self.robot.base_link if i == 1 else joint_to_link[model.names[i]])
            mass.append(body.mass)
            com.append(body.lever.copy())
            inertia.append(body.inertia.copy())
        joint_idx = slice(7, model.nq)
        return MassProperties(
            source="pinocchio",
            body_names=tuple(names),
            mass=np.array(mass),
            com_in_body=np.array(com),
            inertia_at_com_in_body=np.array(inertia),
            joint_names=tuple(list(model.names)[2:]),
            joint_lower=model.lowerPositionLimit[joint_idx].copy(),
            joint_upper=model.upperPositionLimit[joint_idx].copy(),
        )
