"""Planner `linear_mpc`: the constrained linear centroidal MPC that Murooka et al. 2022 compare
their preview control with (Sec. V-E, V-G; Audren et al. 2014). Model, cost and formulations:
`centroidal.mpc` and `centroidal.mpc_formulations`.

Each control period (dt = 2 ms):
1. reference: the horizon's samples t + k dtau (k = 0..N-1; default N = 20, dtau = 0.1 s,
   so 2 s like preview control; Murooka Sec. V-E gives Audren's as 3 s in 20 samples, 0.15 s:
   `MPC_HORIZON_SAMPLES`, `MPC_SAMPLE_S`); each sample's contacts from the scenario's phase at
   its start (ours: a double support shorter than a sample may fall between two samples);
   the output references c_ref (the same rules as preview control, Sec. V-B) and a zero base
   angle at t + (k+1) dtau.
2. preview (here: the MPC solve): the contact wrench of every horizon sample, G_k lambda_k
   (ridge formulations) or directly on the cone's faces (face formulations, the default); the
   first sample's is the planned wrench. It lies in the contact cone by construction.
3. projection: the planned resultant is still projected onto the current contacts (eqs. 9-10),
   exactly as for preview control, so that `projection_error` measures, rather than assumes,
   that the MPC's wrench is feasible (it comes out at solver tolerance).
4. desired state: eq. 1 integrated over dt from the planner's state with that wrench (the MPC
   continues from it, like preview control continues from r^d).

A solver failure (no solution, or no contact at the horizon's first sample) keeps the last
feasible plan: the contact wrench that the last solution planned for the current time (its
last sample once the time is past its horizon), or the weight alone before any solution; it
is counted in `CentroidalPlan.solver_failures` (the summary's `solver_failures`) and never
ends the episode by itself.
"""

from __future__ import annotations

import time

import numpy as np

from centroidal.base_angle import base_angle, base_orientation
from centroidal.mpc import GRAVITY, MpcModel, MpcProblem, MpcSolverError, MpcWeights
from centroidal.mpc_formulations import DEFAULT_FORMULATION, make_formulation
from centroidal.projection import DEFAULT_BACKEND, WrenchProjector, project_resultant
from centroidal.rotations import from_matrix
from centroidal.wrench import cross, zmp_on_plane
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

REFERENCE_DT = 0.005  # [s] grid on which the CoM reference is precomputed


MPC_HORIZON_SAMPLES = 20
MPC_SAMPLE_S = 0.1
"""The MPC's horizon, N samples of dtau [s]: Murooka Sec. V-E, "The MPC-based methods take 20 ms
for a 3 s horizon (20 sample points) [5]", so 0.15 s samples; ours: 20 samples of 0.1 s, a 2 s
horizon as Table I's preview control (400 x 5 ms), so that both planners see the same future."""


class LinearMpcPlanner:
    name = "linear_mpc"
    projects_wrench = True
    tracks_hand_targets = False
    plans_com_trajectory = True

    def __init__(
        self,
        dt: float,
        formulation: str = DEFAULT_FORMULATION,
        horizon: int = MPC_HORIZON_SAMPLES,
        dtau: float = MPC_SAMPLE_S,
        weights: MpcWeights | None = None,
        ridge_upper: float | None = None,
        projection_backend: str = DEFAULT_BACKEND,
    ) -> None:
        if ridge_upper is not None and not ridge_upper > 0:
            raise ValueError(f"ridge_upper must be a positive force [N] or None, got {ridge_upper}")
        if ridge_upper is not None and formulation.startswith("face:"):
            raise ValueError(
                f"ridge_upper bounds ridge forces, which {formulation!r} does not have: "
                "choose a ridge formulation (dense:, sparse:, cvxpy:, casadi: or native:)"
            )
        self.dt, self.horizon, self.dtau = dt, int(horizon), float(dtau)
        self.formulation_name = formulation
        self.weights = weights or MpcWeights()
        self.ridge_upper = ridge_upper
        self.projector = WrenchProjector(projection_backend)

    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None:
        self.schedule = FootstepSchedule(scheduled_footsteps(scenario))
        description = robot.robot
        self.scenario = scenario
        self.mass = description.total_mass
        self.inertia = np.diag(robot.constant_inertia())
        self.model = MpcModel(self.mass, self.inertia, self.dtau, self.horizon, self.weights)
        self.limbs = description.limbs
        self.surfaces = limb_surfaces(description, scenario.scene.friction)
        max_ridges = sum(s.n_ridges for s in self.surfaces.values())
        self.formulation = make_formulation(self.formulation_name, self.model, max_ridges)
        com = np.asarray(state.com_position_world, dtype=float)
        self.x = np.concatenate(
            [
                com,
                np.asarray(state.com_velocity_world, dtype=float),
                base_angle(state.base_orientation_world),
                np.zeros(3),
            ]
        )
        span = scenario.duration + (self.horizon + 2) * self.dtau
        n_reference = int(np.ceil(span / REFERENCE_DT)) + 2
        self.reference = com_reference(
            scenario, REFERENCE_DT, n_reference, height_offset(scenario, float(com[2]))
        )
        self.yaw_reference = yaw_reference(scenario, REFERENCE_DT, n_reference)
        self.start_pose = {}
        for limb in self.limbs:
            position, rotation = robot.frame_pose(state, limb.contact_frame)
            self.start_pose[limb.name] = (position, from_matrix(rotation))
        self._phase_contacts = PhaseContacts(self.surfaces)
        faces_of = getattr(self.formulation, "faces_of", None)
        if faces_of is not None:  # the face form: every phase's faces now, not mid-episode
            for phase in scenario.phases:
                contacts, _ = self._phase_contacts(phase)
                faces_of(contacts.matrix)
        self._prediction: tuple[np.ndarray, np.ndarray] | None = None  # (times, CoM)
        self._last_plan: tuple[float, np.ndarray] | None = None  # (start, contact wrenches)
        self.solver_failures = 0
        self.last_error: str | None = None

    def _reference_at(self, times: np.ndarray) -> np.ndarray:
        return self.reference[self._reference_index(times)]

    def _reference_index(self, times: np.ndarray) -> np.ndarray:
        return np.minimum(np.round(times / REFERENCE_DT).astype(int), len(self.reference) - 1)

    def _linearisation_points(self, times: np.ndarray) -> np.ndarray:
        """c-hat_k: the CoM the previous solution predicted at `times` (the reference before
        the first solution)."""
        if self._prediction is None:
            return self._reference_at(times)
        known_times, known = self._prediction
        return np.column_stack([np.interp(times, known_times, known[:, i]) for i in range(3)])

    def _fallback(self, t: float) -> np.ndarray:
        """The last feasible plan's contact wrench (about the origin) for time t."""
        if self._last_plan is None:
            com = self.x[:3]
            weight = np.array([0.0, 0.0, self.mass * GRAVITY])
            return np.concatenate([weight, cross(com, weight)])
        start, wrenches = self._last_plan
        k = min(int((t - start) / self.dtau + 1e-9), len(wrenches) - 1)
        return wrenches[k]

    def plan(self, t: float, state: RobotState) -> CentroidalPlan:
        start = time.perf_counter_ns()
        samples = t + self.dtau * np.arange(self.horizon)
        phases = [self.scenario.phase_at(s) for s in samples]
        per_sample = [self._phase_contacts(phase) for phase in phases]
        y_reference = np.zeros((self.horizon, 6))
        y_reference[:, :3] = self._reference_at(samples + self.dtau)
        if self.yaw_reference is not None:  # a turning walk (`planners.reference`)
            y_reference[:, 5] = self.yaw_reference[self._reference_index(samples + self.dtau)]
        phase = phases[0]
        contacts_now, height = per_sample[0]
        after_reference = time.perf_counter_ns()

        generators = [c.matrix for c, _ in per_sample]
        points = self._linearisation_points(samples)
        maps = (
            self.model.wrench_maps(generators, points)
            if getattr(self.formulation, "needs_maps", True)
            else None
        )
        upper = (
            None
            if self.ridge_upper is None
            else [np.full(g.shape[1], self.ridge_upper) for g in generators]
        )
        problem = MpcProblem(maps, self.x.copy(), y_reference, upper, generators, points)
        try:
            if generators[0].shape[1] == 0:
                raise MpcSolverError("no contact at the horizon's first sample")
            inputs = self.formulation.solve(problem)  # (N, 6), moments about c-hat_k
            contact_wrenches = inputs.copy()  # moments about the origin: n + c-hat_k x f
            contact_wrenches[:, 3:] += cross(points, inputs[:, :3])
            predicted = self.model.predict_outputs(self.x, inputs)
            self._prediction = (
                np.concatenate([[t], samples + self.dtau]),
                np.vstack([self.x[:3], predicted[:, :3]]),
            )
            self._last_plan = (t, contact_wrenches)
            planned_contact = contact_wrenches[0]
        except MpcSolverError as exc:
            self.solver_failures += 1
            self.last_error = str(exc)
            planned_contact = self._fallback(t)
        after_solve = time.perf_counter_ns()

        # the planned resultant about the planner's CoM (eq. 2), then eqs. 9-10 as a check
        com = self.x[:3]
        force = planned_contact[:3]
        wrench_planned = np.concatenate(
            [
                force - np.array([0.0, 0.0, self.mass * GRAVITY]),
                planned_contact[3:] - cross(com, force),
            ]
        )
        if contacts_now.matrix.shape[1]:
            wrench_projected, projected_contact = project_resultant(
                self.projector, contacts_now, self.mass, com, wrench_planned
            )
        else:
            wrench_projected, projected_contact = wrench_planned, planned_contact
        dt = self.dt
        acceleration = np.concatenate(
            [wrench_projected[:3] / self.mass, wrench_projected[3:] / self.inertia]
        )
        x = self.x
        position = np.concatenate([x[:3], x[6:9]])
        velocity = np.concatenate([x[3:6], x[9:12]])
        position = position + velocity * dt + 0.5 * acceleration * dt * dt
        velocity = velocity + acceleration * dt
        self.x = np.concatenate([position[:3], velocity[:3], position[3:], velocity[3:]])
        zmp = zmp_on_plane(projected_contact, height)
        after_projection = time.perf_counter_ns()

        positions, orientations, tracked = limb_targets(
            self.scenario, self.limbs, self.start_pose, t
        )
        orientation = base_orientation(self.x[6:9])
        return CentroidalPlan(
            com_reference_world=self._reference_at(np.array([t]))[0],
            com_planned_world=self.x[:3].copy(),
            com_velocity_planned_world=self.x[3:6].copy(),
            com_acceleration_planned_world=acceleration[:3],
            base_orientation_planned_world=orientation,
            base_angular_velocity_planned_world=self.x[9:12].copy(),
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
                "preview": after_solve - after_reference,
                "projection": after_projection - after_solve,
            },
            limb_tracked=tracked,
            solver_failures=self.solver_failures,
        )


register(
    PlannerSpec(
        "linear_mpc",
        LinearMpcPlanner,
        "constrained linear centroidal MPC over the contact wrenches (Audren et al. 2014)",
        can=MULTI_CONTACT,
    )
)
