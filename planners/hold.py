"""Planner `hold`: a reference that stands still, so the control loop can run before any paper's
method.

The CoM reference starts at the robot's CoM and settles critically damped, at the LIP's rate
omega = sqrt(g / h), above the centre of the support (the mean of the foot contact positions of
the scenario's first phase) at the initial CoM height (`centroidal.lipm.critically_damped`);
the base orientation reference is level with zero yaw; the planned state equals the reference;
the planned resultant wrench is m c'' with zero moment about the CoM (gravity apart, as every
planner's) and needs no projection; the planned ZMP is the LIP's, c - c'' / omega^2, on the
ground (it starts as far beyond the start CoM as that is from the support centre, 2 x 19.8 mm
behind the centre on JVRC-1, inside its 0.2 m soles, and moves onto the centre). Limb targets:
contact limbs at their contact poses; free limbs untracked (the whole-body posture task holds
them).

Why the settling (measured 2026-11-27): JVRC-1's half-sitting CoM is 19.8 mm behind its feet's
midpoint; a reference there from t = 0 asked the IK for a 2 cm CoM step in one period, and
`hold` + `posture` fell standing at 1.29 s in MuJoCo and 3.56 s in PyBullet. The humanoid's CoM
starts within 0.1 mm of it.
"""

from __future__ import annotations

import math

import numpy as np

from centroidal.lipm import critically_damped
from centroidal.projection import GRAVITY
from centroidal.rotations import IDENTITY_WXYZ, from_matrix
from planners.base import PlannerSpec, register
from robots.limbs import FootstepSchedule, scheduled_footsteps
from robots.model import RobotModel
from robots.scene import Scenario
from robots.types import CentroidalPlan, RobotState


class HoldPlanner:
    name = "hold"
    projects_wrench = False
    tracks_hand_targets = False
    plans_com_trajectory = True

    def __init__(self, dt: float) -> None:
        self.dt = dt

    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None:
        self.schedule = FootstepSchedule(scheduled_footsteps(scenario))
        self.robot = robot
        self.scenario = scenario
        limbs = robot.robot.limbs
        first = scenario.phases[0]
        feet = [c.position_world for c in first.contacts if c.limb.endswith("foot")]
        support = np.mean(feet, axis=0) if feet else np.asarray(state.base_position_world)
        com = robot.com_position_world(state)
        self.com_start = com[:2].copy()
        self.com_target = np.array([support[0], support[1]])
        self.height = float(com[2])
        self.ground = float(support[2]) if feet else 0.0
        self.omega = math.sqrt(float(GRAVITY[2]) / (self.height - self.ground))
        self.mass = robot.total_mass
        poses = [robot.frame_pose(state, limb.contact_frame) for limb in limbs]
        self.start_position = np.array([p for p, _ in poses])
        self.start_orientation = np.array([from_matrix(r) for _, r in poses])
        self.limb_index = {limb.name: k for k, limb in enumerate(limbs)}

    def plan(self, t: float, state: RobotState) -> CentroidalPlan:
        phase = self.scenario.phase_at(t)
        position = self.start_position.copy()
        orientation = self.start_orientation.copy()
        tracked = np.zeros(len(position), dtype=bool)
        for contact in phase.contacts:
            k = self.limb_index[contact.limb]
            position[k] = contact.position_world
            orientation[k] = contact.orientation_world
            tracked[k] = True
        xy, xy_velocity, xy_acceleration = critically_damped(
            self.com_start, 0.0, self.com_target, self.omega, t
        )
        com = np.array([xy[0], xy[1], self.height])
        velocity = np.array([xy_velocity[0], xy_velocity[1], 0.0])
        acceleration = np.array([xy_acceleration[0], xy_acceleration[1], 0.0])
        zmp = np.array([*(xy - xy_acceleration / self.omega**2), self.ground])
        wrench = np.concatenate([self.mass * acceleration, np.zeros(3)])
        zero = np.zeros(3)
        return CentroidalPlan(
            com_reference_world=com,
            com_planned_world=com,
            com_velocity_planned_world=velocity,
            com_acceleration_planned_world=acceleration,
            base_orientation_planned_world=IDENTITY_WXYZ,
            base_angular_velocity_planned_world=zero,
            wrench_planned_world=wrench,
            wrench_projected_world=wrench,
            zmp_planned_world=zmp,
            contact_limbs=phase.limbs,
            footsteps=self.schedule.upcoming(t),
            limb_target_position_world=position,
            limb_target_orientation_world=orientation,
            # no sub-stages: the runner's planner stage is the whole plan (it has none of
            # Murooka Table IV's, whose "calculate reference" row it was once shown as)
            timings_ns={},
            limb_tracked=tracked,
        )


register(
    PlannerSpec("hold", HoldPlanner, "CoM reference settling above the support centre, then still")
)
