"""The `Simulator` protocol and the logic every backend shares.

A backend (MuJoCo, PyBullet) only supplies library primitives (read joints, apply torques and
forces, step the physics, read contacts). Everything that decides what the experiment is -- the
servo law, its rate, pushes, grasps, fall detection, the sensor contract -- lives here once, so
the two simulators run the same experiment by construction.

Grasps (`robots.scene.Grasp`, `SimulatorBase.grasp` / `release`): a hand that holds a rail or a
rung must be able to pull, which a hand pad's contact (unilateral, like every contact in both
engines) cannot. A grasp is an equality constraint that welds the limb's link (a hand's
`Limb.link`) to a scene box at the relative pose the two have when it is made, anchored at the
limb's contact frame (the palm centre): a MuJoCo weld equality (`mjEQ_WELD`, activated with
`MjData.eq_active`) and a PyBullet fixed constraint (`createConstraint(..., JOINT_FIXED)`,
removed at release); see each backend for its softness and force limit. Its force counts in
the limb's contact wrench with the same frame and sign as a contact's (the wrench the
environment applies on the limb, in its contact frame about its origin), and the limb counts
as in contact while it holds. The scene's grasps are made and released by `step`, before the
first physics step that starts at or after their times; `grasp` / `release` make and release
one at once (from the next physics step on).
"""

from __future__ import annotations

import abc
import importlib
import importlib.util
import math
import sys
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from robots.scene import Scene
from robots.spec import RobotDescription
from robots.types import JointCommand, MassProperties, RobotState, Sensors
from sims.kernels import servo_torque_kernel


class SimulatorError(RuntimeError):
    """The physics went wrong (non-finite state, solver failure). The runner records it as the
    episode's error; it never ends a sweep."""


class MissingDependencyError(ImportError):
    """An optional package is not installed; the message names the pip extra."""


class Simulator(Protocol):
    name: str
    engine_ns: int  # the engine's own work in the last step [ns] (`SimulatorBase.engine_ns`)

    def reset(self, robot: RobotDescription, scene: Scene, initial: RobotState) -> Sensors: ...
    def step(self, command: JointCommand) -> Sensors: ...
    def push(self, link: str, impulse_world: np.ndarray, duration: float) -> None: ...
    def grasp(self, limb: str, box: str) -> None: ...
    def release(self, limb: str) -> None: ...
    def ground_truth(self) -> RobotState: ...
    def set_state(self, state: RobotState) -> None: ...
    def fall_reason(self) -> str | None: ...
    def links_touching_scene(self) -> set[str]: ...
    def mass_properties(self) -> MassProperties: ...
    def frame_positions_world(self, names: list[str]) -> np.ndarray: ...
    def scene_boxes_world(self) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]: ...
    def close(self) -> None: ...


@dataclass
class _Push:
    link: str
    force_world: np.ndarray
    steps_left: int


def quaternion_to_matrix(quaternion_wxyz: np.ndarray) -> np.ndarray:
    """Rotation matrix of a unit quaternion (w, x, y, z) (Python-float arithmetic: the same
    IEEE results as numpy scalars', in a quarter of the time)."""
    if isinstance(quaternion_wxyz, np.ndarray):
        quaternion_wxyz = quaternion_wxyz.tolist()
    w, x, y, z = quaternion_wxyz
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def quaternion_product(a, b) -> np.ndarray:
    """Hamilton product a b of two quaternions (w, x, y, z) (scalar arithmetic: ~2 us)."""
    aw, ax, ay, az = a.tolist() if isinstance(a, np.ndarray) else a
    bw, bx, by, bz = b.tolist() if isinstance(b, np.ndarray) else b
    return np.array(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ]
    )


def contiguous(indices) -> slice | np.ndarray:
    """`indices` (ints) as a slice when they are consecutive and increasing (indexing with a
    slice gives a view and costs a sixth of fancy indexing), else as an index array."""
    index = np.asarray(indices, dtype=int)
    if len(index) and np.array_equal(index, np.arange(index[0], index[0] + len(index))):
        return slice(int(index[0]), int(index[0]) + len(index))
    return index


_NEXT, _LAST = np.array([1, 2, 0]), np.array([2, 0, 1])  # component i of a x b: a_next b_last - ...


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b of two 3-vectors, or row by row of two (n, 3) stacks (numpy's `cross` costs
    ~40-100 us a call)."""
    if a.ndim == 1:
        return np.array(
            [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
        )
    # take() keeps the result C-ordered (fancy indexing would give an F-ordered stack)
    return a.take(_NEXT, axis=1) * b.take(_LAST, axis=1) - a.take(_LAST, axis=1) * b.take(
        _NEXT, axis=1
    )


def limb_wrenches(
    contact_owner: np.ndarray,
    points_world: np.ndarray,
    forces_world: np.ndarray,
    limb_owner: np.ndarray,
    frame_origin_world: np.ndarray,
    frame_rotation_world: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The contact wrench on each limb (k, 6), force [N] and moment [N m] about its frame's
    origin in its frame's axes, and whether the limb touches (k,): the contacts (n,) whose
    owner (body or link id) is the limb's, with points (n, 3) [m] and forces on the robot
    (n, 3) [N] in world; frames as origins (k, 3) [m] and rotations (k, 3, 3) in world."""
    n_limbs = len(limb_owner)
    if len(contact_owner) == 0:
        return np.zeros((n_limbs, 6)), np.zeros(n_limbs, dtype=bool)
    on_limb = np.asarray(limb_owner)[:, None] == np.asarray(contact_owner)[None, :]  # (k, n)
    selection = on_limb.astype(float)
    force = selection @ forces_world  # (k, 3), world
    moment = selection @ cross(points_world, forces_world) - cross(frame_origin_world, force)
    wrench = np.empty((n_limbs, 6))  # into each limb frame's axes: R_k^T
    wrench[:, :3] = np.einsum("kji,kj->ki", frame_rotation_world, force)
    wrench[:, 3:] = np.einsum("kji,kj->ki", frame_rotation_world, moment)
    return wrench, on_limb.any(axis=1)


def tilt_angle(quaternion_wxyz: np.ndarray) -> float:
    """Angle [rad] between the body's z axis and the world's z axis."""
    _, x, y, _ = (
        quaternion_wxyz.tolist() if isinstance(quaternion_wxyz, np.ndarray) else quaternion_wxyz
    )
    cos_tilt = 1.0 - 2.0 * (x * x + y * y)
    return math.acos(min(max(float(cos_tilt), -1.0), 1.0))


_NO_FORCES: list[tuple[str, np.ndarray]] = []  # no push this physics step (never modified)


class SimulatorBase(abc.ABC):
    """The control period, pushes and fall detection; subclasses provide the primitives."""

    name: str = "base"

    def __init__(self) -> None:
        self.robot: RobotDescription | None = None
        self.scene: Scene | None = None
        self.time = 0.0
        self._pushes: list[_Push] = []
        self._fall_reason: str | None = None
        self._torque_limit = np.zeros(0)
        self._last_torque = np.zeros(0)
        self._limb_links: frozenset[str] = frozenset()
        self._substeps = 1
        self._moving_boxes = False  # the scene has moving boxes (`_move_boxes`)
        self._checks = np.zeros(4)
        """What a backend's sensor kernel found for the current state, when `_checks_fresh`:
        the base's `tilt_angle` [rad], the number of scene contacts on links that are not
        limbs, 1.0 if the joint and base positions are finite (else 0.0), and a backend's own
        count (MuJoCo: instability warnings)."""
        self._checks_fresh = False
        self._grasps: dict[str, str] = {}  # limb -> the box it holds
        self._grasp_events: list[tuple[float, int, str, str]] = []
        """The scene's grasps still to make or release: (time [s], 0 release / 1 grasp, limb,
        box), latest first (`step` pops them from the end)."""
        self.engine_ns = 0
        """[ns] the engine's own work in the last `step`: its physics steps and, for MuJoCo,
        the forward pass that computes the sensors (the rest of the step is ours: the servo
        law, pushes, reading and converting the sensors, fall checks)."""

    # ----------------------------------------------------------------- library primitives
    @abc.abstractmethod
    def _load(self, robot: RobotDescription, scene: Scene) -> None:
        """Build the world (robot + scene) with the scene's time step, gravity and friction."""

    @abc.abstractmethod
    def _joint_state(self) -> tuple[np.ndarray, np.ndarray]:
        """Joint positions [rad] and velocities [rad/s] in joint order."""

    @abc.abstractmethod
    def _physics_step(
        self, torque: np.ndarray, forces: list[tuple[str, np.ndarray]], last: bool
    ) -> None:
        """Advance one physics step with joint torques [N m] and external forces [N] (world
        frame) applied at the named links' centres of mass; `last`: the control period's last
        physics step (the one that finite-difference sensors span)."""

    def _move_boxes(self, time: float) -> None:
        """Put the scene's moving boxes at their prescribed pose and velocity at `time` [s]
        (`robots.scene.MovingBox.pose_at`, `velocity_at`); called after loading (time 0) and
        after every physics step, and only for a scene that has moving boxes."""
        raise NotImplementedError(f"{self.name} cannot move boxes")

    def _make_grasp(self, limb: int, box: str) -> None:
        """Weld the link of limb number `limb` to the scene box `box` at their current relative
        pose, anchored at the limb's contact frame, from the next physics step on."""
        raise NotImplementedError(f"{self.name} cannot grasp")

    def _drop_grasp(self, limb: int) -> None:
        """Remove limb number `limb`'s weld (`_make_grasp`) from the next physics step on."""
        raise NotImplementedError(f"{self.name} cannot grasp")

    @abc.abstractmethod
    def _read_sensors(self) -> Sensors:
        """Sensors for the current state (time, torques from `self`)."""

    @abc.abstractmethod
    def _links_touching_scene(self) -> set[str]:
        """Names of robot links in contact with the ground or a scene box."""

    def links_touching_scene(self) -> set[str]:
        """The robot's links other than its limbs' (`Limb.link`, `Limb.touch_links`) that
        touch the scene in the current state (after a step or `set_state`): those the fall
        check counts."""
        return self._links_touching_scene() - self._limb_links

    def _other_links_touching_scene(self) -> set[str]:
        """`_links_touching_scene` without the limbs' links; none when the sensor kernel
        counted none for the current state."""
        if self._checks_fresh and not self._checks[1]:
            return set()
        return self._links_touching_scene() - self._limb_links

    # ------------------------------------------------------------------------ protocol
    def reset(self, robot: RobotDescription, scene: Scene, initial: RobotState) -> Sensors:
        scene.validate()
        self.close()
        self.robot, self.scene = robot, scene
        self.time = 0.0
        self._pushes = []
        self._fall_reason = None
        self._torque_limit = robot.array("torque_limit")
        self._last_torque = np.zeros(robot.n_joints)
        self._limb_links = frozenset(
            link for limb in robot.limbs for link in (limb.link, *limb.touch_links)
        )
        self._substeps = scene.substeps
        self._moving_boxes = bool(scene.moving_boxes)
        self._grasps = {}
        for grasp in scene.grasps:
            robot.limb(grasp.limb)  # raises for an unknown limb
        self._grasp_events = sorted(
            [(g.start, 1, g.limb, g.box) for g in scene.grasps]
            + [(g.end, 0, g.limb, g.box) for g in scene.grasps if math.isfinite(g.end)],
            reverse=True,
        )
        self._load(robot, scene)
        if self._moving_boxes:
            self._move_boxes(0.0)
        self.set_state(initial)
        return self._read_sensors()

    def step(self, command: JointCommand) -> Sensors:
        """Advance one control period: the servo law and pushes at every physics step, and
        after each physics step the moving boxes put at their pose at the new time (so that
        the engine always holds the boxes' pose at `self.time`)."""
        assert self.robot is not None and self.scene is not None, "reset() first"
        substeps, physics_dt = self._substeps, self.scene.physics_dt
        servo = (
            command.position,
            command.velocity,
            command.torque_feedforward,
            command.kp,
            command.kd,
        )
        self.engine_ns = 0
        joint_state, physics_step, limit = self._joint_state, self._physics_step, self._torque_limit
        last, moving, events = substeps - 1, self._moving_boxes, self._grasp_events
        for substep in range(substeps):
            if events and events[-1][0] <= self.time + 0.5 * physics_dt:
                self._grasp_events_due()
            q, dq = joint_state()
            torque = servo_torque_kernel(*servo, q, dq, limit)  # `servo_torque`
            if self._pushes:
                forces = [(p.link, p.force_world) for p in self._pushes if p.steps_left > 0]
                physics_step(torque, forces, substep == last)
                for p in self._pushes:
                    p.steps_left -= 1
                self._pushes = [p for p in self._pushes if p.steps_left > 0]
            else:
                physics_step(torque, _NO_FORCES, substep == last)
            self._last_torque = torque
            self.time += physics_dt
            if moving:
                self._move_boxes(self.time)
        sensors = self._read_sensors()
        if not self._state_finite(sensors):
            raise SimulatorError(f"{self.name}: non-finite state at t = {self.time:.3f} s")
        if self._fall_reason is None:
            self._fall_reason = self._detect_fall(sensors)
        return sensors

    def push(self, link: str, impulse_world: np.ndarray, duration: float) -> None:
        """Apply a constant force impulse/duration [N] at `link`'s centre of mass for
        `duration` [s], starting with the next physics step. The duration is rounded to whole
        physics steps and the force set so that the impulse [N s] is exact."""
        assert self.robot is not None and self.scene is not None, "reset() first"
        self.robot.link(link)  # raises for an unknown link
        impulse = np.asarray(impulse_world, dtype=float)
        if impulse.shape != (3,) or not np.all(np.isfinite(impulse)):
            raise ValueError("impulse_world must be 3 finite numbers [N s]")
        if duration <= 0:
            raise ValueError(f"push duration must be positive, got {duration} s")
        steps = max(1, round(duration / self.scene.physics_dt))
        force = impulse / (steps * self.scene.physics_dt)
        self._pushes.append(_Push(link, force, steps))

    def grasp(self, limb: str, box: str) -> None:
        """Make `limb` (a robot limb's name) grasp the scene box `box` (a `Box` or `MovingBox`
        name): weld the limb's link to the box at their current relative pose, from the next
        physics step on, until `release` (see the module docstring)."""
        assert self.robot is not None and self.scene is not None, "reset() first"
        limb_number = self.robot.limbs.index(self.robot.limb(limb))  # raises for an unknown limb
        boxes = [b.name for b in (*self.scene.boxes, *self.scene.moving_boxes)]
        if box not in boxes:
            raise KeyError(f"no box {box!r}; boxes: {', '.join(boxes)}")
        if limb in self._grasps:
            raise ValueError(f"{limb!r} already grasps {self._grasps[limb]!r}: release it first")
        self._make_grasp(limb_number, box)
        self._grasps[limb] = box

    def release(self, limb: str) -> None:
        """End `limb`'s grasp from the next physics step on (nothing if it holds nothing)."""
        assert self.robot is not None, "reset() first"
        limb_number = self.robot.limbs.index(self.robot.limb(limb))  # raises for an unknown limb
        if self._grasps.pop(limb, None) is not None:
            self._drop_grasp(limb_number)

    def grasping(self) -> dict[str, str]:
        """The grasps that hold now: limb -> box."""
        return dict(self._grasps)

    def _grasp_events_due(self) -> None:
        """Release, then make, the scene's grasps whose time has come (to half a physics
        step)."""
        assert self.scene is not None
        events, due = self._grasp_events, self.time + 0.5 * self.scene.physics_dt
        while events and events[-1][0] <= due:
            _, kind, limb, box = events.pop()
            if kind == 0:
                self.release(limb)
            else:
                self.grasp(limb, box)

    def fall_reason(self) -> str | None:
        """Why the robot counts as fallen (first cause seen), or None."""
        return self._fall_reason

    def _state_finite(self, sensors: Sensors) -> bool:
        """The joint positions and the base position of `sensors` are finite."""
        if self._checks_fresh:
            return bool(self._checks[2])
        return math.isfinite(
            float(sensors.joint_position.sum()) + float(sensors.base_position_world.sum())
        )

    def _tilt(self, sensors: Sensors) -> float:
        """`tilt_angle` of the base."""
        if self._checks_fresh:
            return float(self._checks[0])
        return tilt_angle(sensors.base_orientation_world)

    def _detect_fall(self, sensors: Sensors) -> str | None:
        assert self.robot is not None and self.scene is not None
        tilt = self._tilt(sensors)
        if tilt > self.scene.max_tilt:
            return (
                f"base tilt {np.rad2deg(tilt):.1f} deg above {np.rad2deg(self.scene.max_tilt):.0f}"
            )
        height = sensors.base_position_world[2]
        fall_height = (
            self.robot.fall_height if self.scene.fall_height is None else self.scene.fall_height
        )
        if height < fall_height:
            return f"base height {height:.3f} m below {fall_height:.3f} m"
        touching = self._other_links_touching_scene()
        if touching:
            return f"{', '.join(sorted(touching))} touching the scene"
        return None

    def close(self) -> None:  # noqa: B027 - optional hook
        """Release the library's resources."""


# ---------------------------------------------------------------------------- registry
@dataclass(frozen=True)
class SimulatorSpec:
    name: str
    module: str
    cls: str
    package: str
    extra: str

    def create(self) -> Simulator:
        if importlib.util.find_spec(self.package) is None:
            raise MissingDependencyError(
                f"simulator {self.name!r} needs the package {self.package!r}, which is not "
                f"installed: pip install 'centrobench[{self.extra}]'"
            )
        return getattr(importlib.import_module(self.module), self.cls)()


SIMULATORS: dict[str, SimulatorSpec] = {
    "mujoco": SimulatorSpec("mujoco", "sims.mujoco_sim", "MujocoSimulator", "mujoco", "mujoco"),
    "pybullet": SimulatorSpec(
        "pybullet", "sims.pybullet_sim", "PybulletSimulator", "pybullet", "pybullet"
    ),
}


def clear_backend_caches() -> None:
    """Forget the per-process set-up caches of the backends loaded in this process (each
    backend module's `clear_cache`)."""
    for spec in SIMULATORS.values():
        module = sys.modules.get(spec.module)
        if module is not None:
            module.clear_cache()


def make_simulator(name: str) -> Simulator:
    """A new simulator by name. Unknown names raise KeyError listing the known ones; a missing
    package raises MissingDependencyError naming the pip extra."""
    if name not in SIMULATORS:
        raise KeyError(f"unknown simulator {name!r}; choose one of: {', '.join(SIMULATORS)}")
    return SIMULATORS[name].create()
