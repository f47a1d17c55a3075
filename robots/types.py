"""The plain data objects that pass between stages (DESIGN.md, "The loop"). SI units; world
frame Z up; quaternions (w, x, y, z). Arrays are float64 numpy arrays; joint arrays follow
`RobotDescription.joints`, limb arrays follow `RobotDescription.limbs`."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np


def per_period(cls):
    """A frozen dataclass whose `__init__` writes the instance's dict directly instead of
    calling `object.__setattr__` per field (what frozen dataclasses do): three times faster for
    the objects built every control period. Fields, defaults, equality, immutability and
    `dataclasses.replace` stay the dataclass's (tests/robots/test_types.py)."""
    fields = dataclasses.fields(cls)
    if any(f.default_factory is not dataclasses.MISSING for f in fields):
        raise TypeError(f"{cls.__name__}: per_period does not support default factories")
    if hasattr(cls, "__post_init__"):
        raise TypeError(f"{cls.__name__}: per_period does not run __post_init__")
    parameters = ", ".join(
        f.name if f.default is dataclasses.MISSING else f"{f.name}=_default_{f.name}"
        for f in fields
    )
    body = "".join(f"    values[{f.name!r}] = {f.name}\n" for f in fields)
    source = f"def __init__(self, {parameters}):\n    values = self.__dict__\n{body}"
    namespace = {f"_default_{f.name}": f.default for f in fields}
    exec(source, namespace)  # generated from the dataclass's own field names
    namespace["__init__"].__qualname__ = f"{cls.__qualname__}.__init__"
    cls.__init__ = namespace["__init__"]
    return cls


@per_period
@dataclass(frozen=True)
class RobotState:
    """Floating-base state. The base is the root link's frame (not its centre of mass).

    base_position_world [m]; base_orientation_world (w, x, y, z); base_linear_velocity_world
    [m/s] of the base frame origin; base_angular_velocity_world [rad/s]; joint_position [rad];
    joint_velocity [rad/s].

    An estimator also fills: time [s]; com_position_world [m] and com_velocity_world [m/s];
    contact_wrench_limb (n_limbs, 6) measured force [N] and moment [N m] in each limb's
    contact frame about its origin, contact_flag_limb (n_limbs,) bool; zmp_world (3,) the
    measured ZMP on the ground plane z = 0 [m] (NaN without vertical contact force; an
    estimator without force sensors gives its own estimate, and passes the sensors' wrenches and
    flags through for the record only). A state
    from a simulator's ground truth leaves them None."""

    base_position_world: np.ndarray
    base_orientation_world: np.ndarray
    base_linear_velocity_world: np.ndarray
    base_angular_velocity_world: np.ndarray
    joint_position: np.ndarray
    joint_velocity: np.ndarray
    time: float = 0.0
    com_position_world: np.ndarray | None = None
    com_velocity_world: np.ndarray | None = None
    contact_wrench_limb: np.ndarray | None = None
    contact_flag_limb: np.ndarray | None = None
    zmp_world: np.ndarray | None = None
    com_acceleration_world: np.ndarray | None = None
    """[m/s^2] the CoM acceleration, from estimators that estimate it (Ficht & Behnke eq. 6)."""
    inertia_tilt: np.ndarray | None = None
    """(2,) [rad] the flywheel angle of a five-mass estimator: the projected angles (toward
    +x, toward +y; `centroidal.tilt`) of the principal z axis of inertia less those of the line
    from the feet's midpoint to the CoM (Ficht & Behnke eq. 5); None from other estimators."""
    inertia_tilt_rate: np.ndarray | None = None
    """(2,) [rad/s] their rates."""
    inertia_tilt_acceleration: np.ndarray | None = None
    """(2,) [rad/s^2] their accelerations (the tilt filter's third state)."""

    @staticmethod
    def at_rest(base_position_world, base_orientation_world, joint_position) -> RobotState:
        q = np.asarray(joint_position, dtype=float)
        return RobotState(
            base_position_world=np.asarray(base_position_world, dtype=float),
            base_orientation_world=np.asarray(base_orientation_world, dtype=float),
            base_linear_velocity_world=np.zeros(3),
            base_angular_velocity_world=np.zeros(3),
            joint_position=q,
            joint_velocity=np.zeros_like(q),
        )


@per_period
@dataclass(frozen=True)
class Sensors:
    """What the simulator reports after each control period.

    time [s]; joint_position [rad], joint_velocity [rad/s], joint_torque [N m] (applied by the
    servo during the last physics step, after clipping); ground-truth base pose and twist as in
    `RobotState`; IMU: imu_orientation_world (w, x, y, z), imu_angular_velocity_imu [rad/s],
    imu_linear_acceleration_imu [m/s^2] (specific force: reads +9.81 along the world's up
    direction at rest; the reading at reset, before any step, is no measurement: MuJoCo's reads
    0, the robot not yet touching the ground, PyBullet's +g whatever the state, and only the
    five-mass filter reads it, its horizontal part, 0 in both); contact_wrench_limb (n_limbs,
    6): force [N] then moment [N m] of the environment on the limb, expressed in the limb's
    contact frame (sole / palm centre) about its origin; contact_flag_limb (n_limbs,) bool."""

    time: float
    joint_position: np.ndarray
    joint_velocity: np.ndarray
    joint_torque: np.ndarray
    base_position_world: np.ndarray
    base_orientation_world: np.ndarray
    base_linear_velocity_world: np.ndarray
    base_angular_velocity_world: np.ndarray
    imu_orientation_world: np.ndarray
    imu_angular_velocity_imu: np.ndarray
    imu_linear_acceleration_imu: np.ndarray
    contact_wrench_limb: np.ndarray
    contact_flag_limb: np.ndarray

    def ground_truth(self) -> RobotState:
        return RobotState(
            self.base_position_world,
            self.base_orientation_world,
            self.base_linear_velocity_world,
            self.base_angular_velocity_world,
            self.joint_position,
            self.joint_velocity,
        )


@per_period
@dataclass(frozen=True)
class JointCommand:
    """Targets for the joint servo law tau = kp (q_d - q) + kd (dq_d - dq) + tau_ff, clipped to
    the torque limit. position [rad], velocity [rad/s], torque_feedforward [N m], kp [N m/rad],
    kd [N m s/rad]; all in joint order."""

    position: np.ndarray
    velocity: np.ndarray
    torque_feedforward: np.ndarray
    kp: np.ndarray
    kd: np.ndarray


@dataclass(frozen=True)
class MassProperties:
    """Mass properties as one library reports them, per massive body, in the body's link frame
    (the URDF link frame): mass [kg], centre of mass [m], inertia about the centre of mass
    [kg m^2]; plus the joint names and position limits [rad] in the library's own order."""

    source: str
    body_names: tuple[str, ...]
    mass: np.ndarray
    com_in_body: np.ndarray
    inertia_at_com_in_body: np.ndarray
    joint_names: tuple[str, ...]
    joint_lower: np.ndarray
    joint_upper: np.ndarray

    @property
    def total_mass(self) -> float:
        return float(self.mass.sum())


@dataclass(frozen=True)
class Footstep:
    """A contact a plan intends to make (DESIGN.md, adaptive footsteps): `limb` lifts off at
    `liftoff_time` [s] (in the past for a limb already moving) and touches down at
    `touchdown_time` [s] with its contact frame at `position_world` (3,) [m] and `yaw` [rad]
    (about the world Z axis), orientation `orientation_world` (w, x, y, z)."""

    limb: str
    position_world: np.ndarray
    yaw: float
    liftoff_time: float
    touchdown_time: float
    orientation_world: np.ndarray


@per_period
@dataclass(frozen=True)
class CentroidalPlan:
    """A planner's output for one control period (world frame, SI units).

    com_reference_world [m]: the reference r^ref (Murooka Fig. 1); com_planned_world [m],
    com_velocity_planned_world [m/s], com_acceleration_planned_world [m/s^2]: the planned
    state r^p; base_orientation_planned_world (w, x, y, z) and base_angular_velocity_planned
    _world [rad/s]; wrench_planned_world (6,): planned resultant force [N] and moment about the
    CoM [N m] before projection (w-bar^p = [m c''; L'], gravity apart: the contact wrenches
    carry w-bar + [m g; c x m g], Murooka eqs. 9-10, for every planner), wrench_projected_world
    (6,) after projection onto the
    contact constraints (w-bar^p'); zmp_planned_world (3,) [m] from the projected wrench;
    contact_limbs: names of the limbs in contact; limb_target_position_world /
    limb_target_orientation_world: per limb, where it should be (contact pose or swing
    trajectory), (n_limbs, 3) [m] and (n_limbs, 4) (w, x, y, z); timings_ns: sub-stage times
    of the planner (e.g. "reference", "preview", "projection") in ns.

    com_desired_world [m], com_velocity_desired_world [m/s], base_orientation_desired_world,
    base_angular_velocity_desired_world: the desired state r^d (Murooka eq. 10 and after: the
    planned state integrated one period with the projected wrench), which a stabilizer tracks;
    None means "the planned state"."""

    com_reference_world: np.ndarray
    com_planned_world: np.ndarray
    com_velocity_planned_world: np.ndarray
    com_acceleration_planned_world: np.ndarray
    base_orientation_planned_world: np.ndarray
    base_angular_velocity_planned_world: np.ndarray
    wrench_planned_world: np.ndarray
    wrench_projected_world: np.ndarray
    zmp_planned_world: np.ndarray
    contact_limbs: tuple[str, ...]
    limb_target_position_world: np.ndarray
    limb_target_orientation_world: np.ndarray
    timings_ns: dict[str, int]
    com_desired_world: np.ndarray | None = None
    com_velocity_desired_world: np.ndarray | None = None
    base_orientation_desired_world: np.ndarray | None = None
    base_angular_velocity_desired_world: np.ndarray | None = None
    limb_tracked: np.ndarray | None = None
    """(n_limbs,) bool: limbs with a pose target (in contact, or moving between contacts). An
    untracked limb's target is ignored and the whole-body posture task holds it; None: all."""
    solver_failures: int = 0
    """How many periods so far the planner's optimisation failed and it fell back on its last
    feasible plan (cumulative over the episode; always 0 for planners without a solver)."""
    footsteps: tuple[Footstep, ...] = ()
    """The contacts the plan intends to make next (touchdown after now), in touchdown order:
    a fixed-schedule planner's come from the scenario's contact sequence, an adaptive
    planner's from its own choice. The runner records the last version of each before its
    touchdown and compares it with the touchdown that happened (`bench.footsteps`)."""

    inertia_axes_reference_world: np.ndarray | None = None
    """(3, 3) the reference orientation R_I^ref of the principal axes of inertia (columns x,
    y, z; Ficht & Behnke eq. 5), for planners of a five-mass controller; None: not given."""
    step_remaining_s: float | None = None
    """[s] the nominal time left in the current step, t_r = (1 - mu) / f_g (Ficht & Behnke
    eq. 10), for planners that step by a gait phase; None: not stepping."""
    generalized_acceleration: np.ndarray | None = None
    """(nv,) the whole-body accelerations a planner decided (pinocchio's convention: base
    linear and angular acceleration in the base frame, then joints) [m/s^2, rad/s^2], for
    planners that solve the whole body's dynamics (Sherikov et al.); None: not given."""
    solver_iterations: int | None = None
    """Active-set iterations of the planner's solver this period (None: no such solver)."""
    grasp_limbs: tuple[str, ...] = ()
    """Those of `contact_limbs` that grasp (can pull: `robots.scene.Contact.grasp`)."""
    contact_surfaces: tuple | None = None
    """The `centroidal.contacts.ContactSurface` of each of `contact_limbs` (in its order) as the
    plan used it: the limb's, its grasp form, or a contact's own polygon (`robots.scene.
    Contact.support_in_frame`), in its own frame when it has one (`Contact.surface_pose_world`);
    None: each limb's whole surface in its contact frame (a grasp's with `grasp_limbs`)."""
    contact_wrench_limb: np.ndarray | None = None
    """(n_limbs, 6) contact wrenches such a planner decided: force [N] and moment [N m] of the
    environment on each limb, in its contact frame about its origin (zero off contact)."""

    def desired_state(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(c^d, c'^d, base orientation^d, omega^d), falling back to the planned state."""
        return (
            self.com_planned_world if self.com_desired_world is None else self.com_desired_world,
            self.com_velocity_planned_world
            if self.com_velocity_desired_world is None
            else self.com_velocity_desired_world,
            self.base_orientation_planned_world
            if self.base_orientation_desired_world is None
            else self.base_orientation_desired_world,
            self.base_angular_velocity_planned_world
            if self.base_angular_velocity_desired_world is None
            else self.base_angular_velocity_desired_world,
        )


@per_period
@dataclass(frozen=True)
class WholeBodyTargets:
    """A stabilizer's output: what the whole-body layer must realise.

    com_position_world [m] and base_orientation_world (w, x, y, z): kinematic targets for the
    IK; limb_position_world (n_limbs, 3) [m], limb_orientation_world (n_limbs, 4): limb-end
    (contact frame) targets; limb_in_contact (n_limbs,) bool: contact limbs are held, the others
    tracked; com_desired_world [m] and zmp_desired_world (3,) [m]: for the record;
    contact_wrench_desired_limb (n_limbs, 6) or None: desired contact wrenches in each limb's
    contact frame, the moment about its origin (the whole-body layer turns them into
    feed-forward torques); joint_torque
    (n_joints,) [N m] or None: extra feed-forward torques; timings_ns: sub-stage times."""

    com_position_world: np.ndarray
    base_orientation_world: np.ndarray
    limb_position_world: np.ndarray
    limb_orientation_world: np.ndarray
    limb_in_contact: np.ndarray
    com_desired_world: np.ndarray
    zmp_desired_world: np.ndarray
    contact_wrench_desired_limb: np.ndarray | None = None
    joint_torque: np.ndarray | None = None
    timings_ns: dict[str, int] | None = None
    wrench_desired_world: np.ndarray | None = None
    """w-bar^d (Murooka eq. 12): desired resultant force [N] and moment about the CoM [N m]."""
    limb_tracked: np.ndarray | None = None
    """(n_limbs,) bool, as in `CentroidalPlan.limb_tracked`; None: all limbs tracked."""
    wrench_distributed_world: np.ndarray | None = None
    """w-bar^d' : the resultant of the distributed contact wrenches minus [m g; c^a x f^d]; its
    difference from w-bar^d is the desired projection error (Sec. V-G)."""
    angular_momentum_world: np.ndarray | None = None
    """L^p [kg m^2/s] (3,), world: the plan's centroidal angular momentum about the CoM, I
    omega^p (Murooka eq. 6), the target of the IK's angular-momentum task (Sec. V-F, the
    `ik_angular_momentum` layer); None: zero."""
    inertia_axes_world: np.ndarray | None = None
    """(3, 3) the orientation R_I^set of the principal axes of inertia that a five-mass pose
    generator realises (Ficht & Behnke eq. 12); None: no such target."""
    generalized_acceleration: np.ndarray | None = None
    """(nv,) accelerations for an inverse-dynamics layer (as `CentroidalPlan.generalized
    _acceleration`), realised with `contact_wrench_desired_limb`; None: not given."""
