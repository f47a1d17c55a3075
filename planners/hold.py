"""Planner `hold`: a constant reference, so the control loop can run before any paper's method.

The CoM reference is above the centre of the support (the mean of the foot contact positions of
the scenario's first phase) at the initial CoM height; the base orientation reference is level
with zero yaw; the planned state equals the reference with zero velocity and acceleration; the
planned resultant wrench is the weight, [0, 0, m g] with zero moment about the CoM, and needs no
projection; the planned ZMP is the support centre. Limb targets: contact limbs at their contact
poses; free limbs untracked (the whole-body posture task holds them).
"""

from __future__ import annotations

import time

import numpy as np

from centroidal.rotations import IDENTITY_WXYZ, from_matrix
from planners.base import PlannerSpec, register
from robots.limbs import FootstepSchedule, scheduled_footsteps
from robots.model import RobotModel
from robots.scene import Scenario
from robots.types import CentroidalPlan, RobotState


class HoldPlanner:
    name = "hold"
    projects_wrench = False

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
        self.com = np.array([support[0], support[1], com[2]])
        self.zmp = np.array([support[0], support[1], 0.0])
        self.wrench = np.zeros(6)
        poses = [robot.frame_pose(state, limb.contact_frame) for limb in limbs]
        self.start_position = np.array([p for p, _ in poses])
        self.start_orientation = np.array([from_matrix(r) for _, r in poses])
        self.limb_index = {limb.name: k for k, limb in enumerate(limbs)}

    def plan(self, t: float, state: RobotState) -> CentroidalPlan:
        start = time.perf_counter_ns()
        phase = self.scenario.phase_at(t)
        position = self.start_position.copy()
        orientation = self.start_orientation.copy()
        tracked = np.zeros(len(position), dtype=bool)
        for contact in phase.contacts:
            k = self.limb_index[contact.limb]
            position[k] = contact.position_world
            orientation[k] = contact.orientation_world
            tracked[k] = True
        zero = np.zeros(3)
        return CentroidalPlan(
            com_reference_world=self.com,
            com_planned_world=self.com,
            com_velocity_planned_world=zero,
            com_acceleration_planned_world=zero,
            base_orientation_planned_world=IDENTITY_WXYZ,
            base_angular_velocity_planned_world=zero,
            wrench_planned_world=self.wrench,
            wrench_projected_world=self.wrench,
            zmp_planned_world=self.zmp,
            contact_limbs=phase.limbs,
            footsteps=self.schedule.upcoming(t),
            limb_target_position_world=position,
            limb_target_orientation_world=orientation,
            timings_ns={"reference": time.perf_counter_ns() - start},
            limb_tracked=tracked,
        )


register(PlannerSpec("hold", HoldPlanner, "constant CoM reference above the support centre"))
