"""Kinematic check of a scenario: can the robot's joints follow its contact sequence at all?

The whole-body IK (`wholebody.ik.WholeBodyIK`, the one every controller here uses) alone
follows the CoM reference of Murooka et al.'s rule (Sec. V-C: `planners.reference.
com_reference`, smoothed: `SMOOTHING_S`; the base upright, a turning walk's base along its
support's heading) and
the limb targets of the scenario (`Scenario.limb_pose`: contacts, swings, waypoints), one IK
step per `dt`, with no dynamics, no planner and no feedback. Each configuration is put into
MuJoCo (`set_state`) and checked for what the runner counts as a fall by contact: a link
other than the limbs' (`Limb.link`, `Limb.touch_links`) touching the scene; and for the IK's
task errors and the joints at their limits. The scene's boxes are the same in PyBullet (a
test checks it), so one engine answers for both.

What it is for: a motion that fails here fails in every simulator with every controller,
whatever the gains, so its failure is the robot's geometry and the motion's targets, found in
seconds: the ladder (Fig. 4 C) first touches a rung with the thigh at 7.83 s here and falls
at 7.82 s in both simulators (docs/multi-contact.md). `centrobench check SCENARIO` prints it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from planners.reference import com_reference, height_offset, yaw_reference
from robots.model import RobotModel
from robots.types import RobotState, WholeBodyTargets
from sims.base import make_simulator
from wholebody.ik import WholeBodyIK

CHECK_PERIOD_S = 0.01
"""[s] one IK step per 10 ms of the scenario: the joints' speed limits bound each step (as at
the 2 ms control period, five times as far), so the check follows what the IK can reach in
time, at a fifth of the cost."""
SMOOTHING_S = 1.0
"""[s] the CoM reference (piecewise constant, Sec. V-C) is averaged over a centred window this
long before the IK follows it, as a stand-in for the planner's smooth trajectory (preview
control looks 2 s ahead): the raw steps would show as errors that are only the IK's lag."""
LIMIT_TOLERANCE_RAD = 1e-3
"""A joint within this of a limit counts as at it."""


@dataclass(frozen=True)
class PhaseCheck:
    """One contact phase: from `start` to `end` [s] with `limbs` in contact; the largest
    distance of the CoM from its reference and of a tracked limb's contact frame from its
    target [m]; the links (not the limbs') that touched the scene; the joints that reached a
    limit."""

    start: float
    end: float
    limbs: tuple[str, ...]
    com_error_max_m: float
    limb_error_max_m: float
    touching: tuple[str, ...]
    at_limit: tuple[str, ...]


@dataclass(frozen=True)
class KinematicCheck:
    """A scenario's check: per phase, and the first time [s] a link touched the scene (with
    the links), None if none did."""

    scenario: str
    phases: tuple[PhaseCheck, ...]
    first_touch: tuple[float, tuple[str, ...]] | None

    @property
    def feasible(self) -> bool:
        """No link touched the scene (the IK's errors are for the reader to judge)."""
        return self.first_touch is None


def check_scenario(model: RobotModel, scenario, dt: float = CHECK_PERIOD_S) -> KinematicCheck:
    """Follow `scenario` (a `robots.scene.Scenario`) kinematically with `model`'s robot; see
    the module docstring."""
    robot = model.robot
    start_state = model.standing_state()
    sim = make_simulator("mujoco")
    try:
        sim.reset(robot, scenario.scene, start_state)
        return _follow(model, scenario, start_state, sim, dt)
    finally:
        sim.close()


def _follow(model: RobotModel, scenario, start_state: RobotState, sim, dt: float):
    robot = model.robot
    ik = WholeBodyIK(model, dt)
    ik.reset(start_state)
    n_periods = round(scenario.duration / dt)
    com_start = model.com_position_world(start_state)
    reference = smoothed(
        com_reference(scenario, dt, n_periods + 1, height_offset(scenario, float(com_start[2]))),
        round(SMOOTHING_S / dt),
    )
    yaws = yaw_reference(scenario, dt, n_periods + 1)
    names = [limb.name for limb in robot.limbs]
    frames = [model.frame_id[limb.contact_frame] for limb in robot.limbs]
    start_pose = {}
    for limb in robot.limbs:
        position, _ = model.frame_pose(start_state, limb.contact_frame)
        start_pose[limb.name] = position
    data = model.model.createData()
    lower, upper = robot.array("lower"), robot.array("upper")
    joint_names = [joint.name for joint in robot.joints]
    rows: dict[int, list] = {}  # id(phase) -> [phase, com error, limb error, touching, limits]
    first_touch = None
    positions = np.empty((len(names), 3))
    orientations = np.empty((len(names), 4))
    for i in range(n_periods):
        t = i * dt
        phase = scenario.phase_at(t)
        tracked = np.zeros(len(names), dtype=bool)
        for k, name in enumerate(names):
            pose = scenario.limb_pose(name, t)
            tracked[k] = pose is not None
            if pose is None:
                positions[k], orientations[k] = start_pose[name], (1.0, 0.0, 0.0, 0.0)
            else:
                positions[k], orientations[k] = pose
        in_contact = np.array([name in phase.limbs for name in names])
        yaw = 0.0 if yaws is None else float(yaws[i])
        base = np.array([np.cos(0.5 * yaw), 0.0, 0.0, np.sin(0.5 * yaw)])
        com_target = reference[i]
        ik.solve(
            WholeBodyTargets(
                com_target,
                base,
                positions,
                orientations,
                in_contact,
                com_target,
                com_target,
                limb_tracked=tracked,
            )
        )
        q = ik.q
        com = pin.centerOfMass(model.model, data, q)
        pin.framesForwardKinematics(model.model, data, q)
        limb_error = max(
            (
                float(np.linalg.norm(data.oMf[frames[k]].translation - positions[k]))
                for k in range(len(names))
                if tracked[k]
            ),
            default=0.0,
        )
        sim.set_state(RobotState.at_rest(q[:3], np.array([q[6], q[3], q[4], q[5]]), q[7:].copy()))
        touching = sim.links_touching_scene()
        joints = q[7:]
        limits = {
            joint_names[j]
            for j in np.flatnonzero(
                (joints <= lower + LIMIT_TOLERANCE_RAD) | (joints >= upper - LIMIT_TOLERANCE_RAD)
            )
        }
        row = rows.setdefault(id(phase), [phase, 0.0, 0.0, set(), set()])
        row[1] = max(row[1], float(np.linalg.norm(com - com_target)))
        row[2] = max(row[2], limb_error)
        row[3] |= touching
        row[4] |= limits
        if touching and first_touch is None:
            first_touch = (round(t, 9), tuple(sorted(touching)))
    phases = tuple(
        PhaseCheck(
            phase.start,
            phase.end,
            phase.limbs,
            com_error,
            limb_error,
            tuple(sorted(touching)),
            tuple(sorted(limits)),
        )
        for phase, com_error, limb_error, touching, limits in rows.values()
    )
    return KinematicCheck(scenario.name, phases, first_touch)


def smoothed(samples: np.ndarray, window: int) -> np.ndarray:
    """The centred moving average of `samples` (n, d) over `window` samples, the ends held
    (padded with the first and last sample)."""
    if window < 2:
        return samples
    before, after = window // 2, window - 1 - window // 2
    padded = np.concatenate(
        [np.repeat(samples[:1], before, axis=0), samples, np.repeat(samples[-1:], after, axis=0)]
    )
    sums = np.cumsum(np.vstack([np.zeros((1, samples.shape[1])), padded]), axis=0)
    return (sums[window:] - sums[:-window]) / window


def format_check(check: KinematicCheck) -> str:
    """The check as a text table, one line per phase, and its verdict."""
    lines = [
        f"kinematic check of {check.scenario}: the IK alone on the CoM reference and the limb "
        "targets (no dynamics)",
        f"{'start':>7} {'end':>7}  {'contacts':<44} {'CoM err':>8} {'limb err':>9}  "
        "touching / at a limit",
    ]
    for p in check.phases:
        contacts = ",".join(p.limbs)
        notes = []
        if p.touching:
            notes.append("touching: " + ", ".join(p.touching))
        if p.at_limit:
            notes.append("at limit: " + ", ".join(p.at_limit))
        lines.append(
            f"{p.start:7.2f} {p.end:7.2f}  {contacts:<44} {1000 * p.com_error_max_m:6.0f} mm "
            f"{1000 * p.limb_error_max_m:6.0f} mm  {'; '.join(notes)}"
        )
    if check.first_touch is None:
        lines.append("no link other than the limbs' touches the scene")
    else:
        time, links = check.first_touch
        lines.append(f"first touch at {time:.2f} s: {', '.join(links)}")
    return "\n".join(lines)
