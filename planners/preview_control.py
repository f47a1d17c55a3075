"""Planner `preview_control`: 6-DoF centroidal preview control with wrench projection
(Murooka, Morisawa, Kanehiro, RA-L 2022, Sec. III; eqs. 1-10, Table I).

Each control period (dt = 2 ms here; the preview model is sampled at dtau = 5 ms, Table I):

1. reference (Sec. V-B, V-C; `planners.reference`): CoM at the support centre, piecewise
   constant, height a constant offset above the mean support height; base orientation zero;
   reference resultant force and moment zero. Precomputed at reset for the whole scenario.
2. preview (eqs. 3-5, 7): per axis, the optimal jerk from the cached gains
   (`centroidal.preview`); linear outputs [c, m c''], angular outputs [alpha, I_* alpha''] with I
   the constant diagonal approximation of I_base (eq. 6; `RobotModel.constant_inertia`). The
   planned state r^p is the state integrated over dt with that jerk, and the planned resultant
   wrench w-bar^p = [m c''^p; I alpha''^p].
3. projection (eqs. 9-10): w^p = w-bar^p + [m g; c^p x f^p] projected onto the cone of the
   current contacts; w-bar^p' = G lambda - [m g; c^p x f^p].
4. desired state (after eq. 10): eq. 1 integrated over dt from the current state with the
   projected wrench gives r^d, and the preview continues from r^d at the next period (r^d is
   "the desired centroidal state of the next control loop", Fig. 1) -- so a projection that
   changes the wrench also changes what the preview plans next.

Adaptations (our robot and framework, not the paper's): the contact polygons are the limb's
rectangle shrunk by a 10 mm margin (the paper uses "contact polygon vertices with inner
margins", Fig. 3, without a number); the friction coefficient is the scene's; the angle alpha
is the rotation vector of the base orientation (`centroidal.base_angle`: equal to the paper's
ZYX Euler angles to first order; the paper also neglects K_Euler, Sec. III-A4); the
preview's 1 % steady-state offset is removed by the tail correction of `centroidal.preview`
(tail_correction=False restores the paper's plain gains); the reference is computed once, at
reset (`planners.reference.com_reference`).
"""

from __future__ import annotations

import time

import numpy as np

from centroidal.base_angle import base_angle, base_orientation
from centroidal.preview import TripleIntegratorPreview, preview_gains
from centroidal.projection import DEFAULT_BACKEND, WrenchProjector, project_resultant
from centroidal.rotations import from_matrix
from centroidal.wrench import zmp_on_plane
from planners.base import PlannerSpec, register
from planners.reference import com_reference, height_offset, yaw_reference
from robots.limbs import (
    FootstepSchedule,
    PhaseContacts,
    limb_surfaces,
    limb_targets,
    scheduled_footsteps,
)
from robots.model import RobotModel
from robots.registry import MULTI_CONTACT
from robots.scene import Scenario
from robots.types import CentroidalPlan, RobotState

# Table I (Murooka et al. 2022): weights of eq. 4 and the preview discretisation.
TABLE_I = {
    "q_linear": (2e2, 5e-4),
    "r_linear": 1e-8,
    "q_angular": (1e2, 5e-3),
    "r_angular": 1e-8,
    "dtau": 0.005,
    "horizon": 400,
}


class PreviewControlPlanner:
    name = "preview_control"
    projects_wrench = True
    tracks_hand_targets = False
    plans_com_trajectory = True

    def __init__(
        self,
        dt: float,
        projection_backend: str = DEFAULT_BACKEND,
        tail_correction: bool = True,
        horizon: int | None = None,
    ) -> None:
        self.dt = dt
        self.projector = WrenchProjector(projection_backend)
        self.tail_correction = tail_correction
        self.horizon = horizon or TABLE_I["horizon"]
        self.dtau = TABLE_I["dtau"]

    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None:
        self.schedule = FootstepSchedule(scheduled_footsteps(scenario))
        self.robot_model, self.scenario = robot, scenario
        description = robot.robot
        self.mass = description.total_mass
        self.inertia = np.diag(robot.constant_inertia())
        gains = [
            preview_gains(
                float(scale),
                *TABLE_I[f"q_{part}"],
                TABLE_I[f"r_{part}"],
                self.dtau,
                self.horizon,
                self.tail_correction,
            )
            for part, scale in zip(
                ("linear",) * 3 + ("angular",) * 3,
                (self.mass,) * 3 + tuple(self.inertia),
                strict=True,
            )
        ]
        # rows: CoM x, y, z (output scale m), base angle x, y, z (output scale I_x, I_y, I_z)
        self.preview = TripleIntegratorPreview(gains, self.dt)
        self.output_scale = np.r_[np.full(3, self.mass), self.inertia]
        com = np.asarray(state.com_position_world, dtype=float)
        self.preview.state[:3, 0] = com
        self.preview.state[:3, 1] = state.com_velocity_world
        self.preview.state[3:, 0] = base_angle(state.base_orientation_world)
        n_samples = int(np.ceil(scenario.duration / self.dtau)) + self.horizon + 2
        self.reference = com_reference(
            scenario, self.dtau, n_samples, height_offset(scenario, float(com[2]))
        )
        yaws = yaw_reference(scenario, self.dtau, n_samples)
        if yaws is not None:  # a turning walk: the base yaw reference too (angular row z)
            self.reference = np.column_stack([self.reference, np.zeros((n_samples, 2)), yaws])
        friction = scenario.scene.friction
        self.limbs = description.limbs
        self.surfaces = limb_surfaces(description, friction)
        self.start_pose = {}
        for limb in self.limbs:
            position, rotation = robot.frame_pose(state, limb.contact_frame)
            self.start_pose[limb.name] = (position, from_matrix(rotation))
        self._phase_contacts = PhaseContacts(self.surfaces)

    def plan(self, t: float, state: RobotState) -> CentroidalPlan:
        start = time.perf_counter_ns()
        index = int(t / self.dtau + 1e-9)
        window = self.reference[index + 1 : index + 1 + self.horizon]  # c_ref; f_ref = 0
        reference_now = self.reference[index, :3]
        after_reference = time.perf_counter_ns()

        # eq. 5 on all six axes; the angular references (angle, moment) are zero (Sec. V-B).
        now = self.preview.state
        planned = self.preview.planned_from_positions(window)
        wrench_planned = self.output_scale * planned[:, 2]
        after_preview = time.perf_counter_ns()

        phase = self.scenario.phase_at(t)
        contacts, height = self._phase_contacts(phase)
        com_planned = planned[:3, 0]
        wrench_projected, projected_contact = project_resultant(
            self.projector, contacts, self.mass, com_planned, wrench_planned
        )  # eqs. 9-10

        # r^d: eq. 1 over one period from the current state with the projected wrench (the
        # angular part through the constant inertia of eq. 6); the preview continues from it.
        dt = self.dt
        acceleration = wrench_projected / self.output_scale
        desired = np.empty((6, 3))
        desired[:, 0] = now[:, 0] + now[:, 1] * dt + 0.5 * dt * dt * acceleration
        desired[:, 1] = now[:, 1] + acceleration * dt
        desired[:, 2] = acceleration
        self.preview.state = desired
        zmp = zmp_on_plane(projected_contact, height)
        after_projection = time.perf_counter_ns()

        positions, orientations, tracked = limb_targets(
            self.scenario, self.limbs, self.start_pose, t
        )
        return CentroidalPlan(
            com_reference_world=reference_now,
            com_planned_world=com_planned,
            com_velocity_planned_world=planned[:3, 1],
            com_acceleration_planned_world=planned[:3, 2],
            base_orientation_planned_world=base_orientation(planned[3:, 0]),
            base_angular_velocity_planned_world=planned[3:, 1],
            wrench_planned_world=wrench_planned,
            wrench_projected_world=wrench_projected,
            zmp_planned_world=zmp,
            contact_limbs=phase.limbs,
            grasp_limbs=self._phase_contacts.grasps(phase),
            contact_surfaces=self._phase_contacts.phase_surfaces(phase),
            footsteps=self.schedule.upcoming(t),
            limb_target_position_world=positions,
            limb_target_orientation_world=orientations,
            timings_ns={
                "reference": after_reference - start,
                "preview": after_preview - after_reference,
                "projection": after_projection - after_preview,
            },
            com_desired_world=desired[:3, 0],
            com_velocity_desired_world=desired[:3, 1],
            base_orientation_desired_world=base_orientation(desired[3:, 0]),
            base_angular_velocity_desired_world=desired[3:, 1],
            limb_tracked=tracked,
        )


register(
    PlannerSpec(
        "preview_control",
        PreviewControlPlanner,
        "Murooka et al. 2022: 6-DoF centroidal preview control + projection",
        can=MULTI_CONTACT,
    )
)
