"""Stabilizer `centroidal_feedback` (Murooka, Morisawa, Kanehiro, RA-L 2022, Sec. IV; eqs.
11-16, Tables II and III).

Each control period:
1. centroidal feedback (eq. 11): Delta w-bar^d = [K_PL (c^d - c^a) + K_DL (c'^d - c'^a);
   K_PA log(R^d R^a') + K_DA (omega^d - omega^a)], with r^d the planner's desired state;
2. desired resultant wrench (eq. 12): w-bar^d = w-bar^p' + Delta w-bar^d;
3. distribution (eqs. 13-14): w^d = w-bar^d + [m g; c^a x f^d] (the actual CoM, as the paper
   recommends) onto the cone of the contacts; w_i^d = G_i lambda_i;
4. damping control of every limb end (eqs. 15-16, Table II): the compliance pose
   r^c = r^d + Delta r^c with K_d Delta r' + K_s Delta r = K_f (w^a - w^d), integrated as eq. 16;
   contact-phase parameters for limbs in contact, non-contact ones otherwise; with a single limb
   in contact its linear components use the non-contact values (Table II's note).
The whole-body layer gets the desired CoM and base orientation (r^d), the compliance poses,
and the desired contact wrenches (for its feed-forward torques).

Adaptation of the gains to our robot (Table III is for HRP-5P, m = 105 kg, omega^2 = 9.8 / 0.95):
by the Appendix relation K_PL = m omega^2 K_xi, K_DL = m omega K_xi (eq. 19), each of Table
III's linear gains is rescaled by the ratio of m omega^2 (resp. m omega) between our robot
(its mass and standing CoM height) and HRP-5P, which keeps the implied DCM gain K_xi of
Table III (1.85 for K_P, 1.98 for K_D). For the centrobench humanoid at scale 1 (58.4 kg, CoM at
0.826 m): K_PL = 1280 N/m and K_DL = 397 N s/m. Angular gains are zero, as in Table III.
Table II is used unchanged (its values are per limb end, not per robot mass).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from centroidal.contacts import contact_set
from centroidal.projection import DEFAULT_BACKEND, WrenchProjector
from centroidal.rotations import exp, from_matrix, log, rotation_error, to_matrix
from centroidal.wrench import cross, zmp_on_plane
from robots.limbs import limb_surfaces
from robots.model import RobotModel
from robots.scene import Scenario
from robots.types import CentroidalPlan, RobotState, WholeBodyTargets
from stabilizers.base import StabilizerSpec, register

GRAVITY = 9.81
HRP5P = {"mass": 105.0, "omega2": 9.8 / 0.95}
TABLE_III = {
    "kp": (2000.0, 2000.0, 2000.0, 0.0, 0.0, 0.0),
    "kd": (666.0, 666.0, 666.0, 0.0, 0.0, 0.0),
}
TABLE_II = {
    "contact": {
        "kd": (1e4, 1e4, 1e4, 100.0, 100.0, 100.0),
        "ks": (0, 0, 0, 0, 0, 2000.0),
        "kf": (1, 1, 1, 1, 1, 0),
    },
    "free": {
        "kd": (300.0, 300.0, 300.0, 40.0, 40.0, 40.0),
        "ks": (2250.0, 2250.0, 2250.0, 400.0, 400.0, 400.0),
        "kf": (0, 0, 0, 0, 0, 0),
    },
}


def _damping_parameters() -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """(K_d, K_s, K_f) arrays of Table II for a limb in contact, free, or the only one in
    contact (Table II's note: its linear components take the non-contact values)."""
    contact = [np.array(TABLE_II["contact"][x], dtype=float) for x in ("kd", "ks", "kf")]
    free = [np.array(TABLE_II["free"][x], dtype=float) for x in ("kd", "ks", "kf")]
    single = [c.copy() for c in contact]
    for s, f in zip(single, free, strict=True):
        s[:3] = f[:3]
    return {"contact": tuple(contact), "free": tuple(free), "single": tuple(single)}


_DAMPING = _damping_parameters()


def appendix_gains(mass: float, omega2: float, k_xi: float) -> tuple[float, float]:
    """K_PL = m omega^2 K_xi and K_DL = m omega K_xi (Murooka eq. 19)."""
    return mass * omega2 * k_xi, mass * np.sqrt(omega2) * k_xi


def scaled_table_iii(mass: float, com_height: float) -> tuple[np.ndarray, np.ndarray]:
    """Table III's K_P, K_D (6,) rescaled from HRP-5P to a robot of `mass` [kg] and CoM height
    [m] by eq. 19 (angular gains unchanged: zero)."""
    omega2 = GRAVITY / com_height
    kp, kd = np.array(TABLE_III["kp"]), np.array(TABLE_III["kd"])
    kp[:3] *= mass * omega2 / (HRP5P["mass"] * HRP5P["omega2"])
    kd[:3] *= mass * np.sqrt(omega2) / (HRP5P["mass"] * np.sqrt(HRP5P["omega2"]))
    return kp, kd


@dataclass
class _Compliance:
    """Delta r^c of one limb end: linear [m] and rotation vector [rad], world axes."""

    linear: np.ndarray
    angular: np.ndarray


class CentroidalFeedbackStabilizer:
    name = "centroidal_feedback"

    def __init__(self, dt: float, projection_backend: str = DEFAULT_BACKEND) -> None:
        self.dt = dt
        self.projector = WrenchProjector(projection_backend)

    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None:
        description = robot.robot
        self.mass = description.total_mass
        self.kp, self.kd = scaled_table_iii(self.mass, float(state.com_position_world[2]))
        self.limbs = description.limbs
        self.limb_names = description.limb_names
        friction = scenario.scene.friction
        self.surfaces = limb_surfaces(description, friction)
        self.compliance = {n: _Compliance(np.zeros(3), np.zeros(3)) for n in self.limb_names}
        self.gravity = np.array([0.0, 0.0, GRAVITY])
        self._cache_key, self._cache = None, None

    def _contact_set(self, contact_index, positions, orientations):
        """G of the contacts at their target poses, rebuilt only when they change (at contact
        switches, or when a target moves)."""
        key = (
            tuple(contact_index),
            positions[contact_index].tobytes(),
            orientations[contact_index].tobytes(),
        )
        if self._cache_key != key:
            self._cache = contact_set(
                [self.limb_names[k] for k in contact_index],
                [self.surfaces[self.limb_names[k]] for k in contact_index],
                [positions[k] for k in contact_index],
                [to_matrix(orientations[k]) for k in contact_index],
            )
            self._cache_key = key
        return self._cache

    def desired_wrench(self, plan: CentroidalPlan, state: RobotState) -> np.ndarray:
        """w-bar^d (eqs. 11-12): the projected planned wrench plus the centroidal PD."""
        com_d, velocity_d, orientation_d, omega_d = plan.desired_state()
        feedback = np.concatenate(
            [
                self.kp[:3] * (com_d - state.com_position_world)
                + self.kd[:3] * (velocity_d - state.com_velocity_world),
                self.kp[3:]
                * rotation_error(to_matrix(orientation_d), to_matrix(state.base_orientation_world))
                + self.kd[3:] * (omega_d - state.base_angular_velocity_world),
            ]
        )  # eq. 11
        return plan.wrench_projected_world + feedback  # eq. 12

    def stabilize(self, t: float, plan: CentroidalPlan, state: RobotState) -> WholeBodyTargets:
        start = time.perf_counter_ns()
        com_d, _, orientation_d, _ = plan.desired_state()
        com_a = state.com_position_world
        wrench_desired = self.desired_wrench(plan, state)
        after_feedback = time.perf_counter_ns()

        # eqs. 13-14: distribute over the contacts at their target poses.
        in_contact = [name in plan.contact_limbs for name in self.limb_names]
        contact_index = [k for k, c in enumerate(in_contact) if c]
        positions = plan.limb_target_position_world
        rotations = [to_matrix(q) for q in plan.limb_target_orientation_world]
        force_d = wrench_desired[:3] + self.mass * self.gravity
        offset = np.concatenate([self.mass * self.gravity, cross(com_a, force_d)])
        desired_limb = np.zeros((len(self.limbs), 6))
        distributed = np.zeros(6)
        if contact_index:
            contacts = self._contact_set(
                contact_index, positions, plan.limb_target_orientation_world
            )
            distributed, ridge = self.projector.project(contacts.matrix, wrench_desired + offset)
            for k in contact_index:
                w = contacts.wrench_of(self.limb_names[k], ridge)  # about the world origin
                moment_at_frame = w[3:] - cross(positions[k], w[:3])
                desired_limb[k, :3] = rotations[k].T @ w[:3]
                desired_limb[k, 3:] = rotations[k].T @ moment_at_frame
        after_distribution = time.perf_counter_ns()

        # eqs. 15-16: damping control of each limb end.
        single = len(contact_index) == 1
        compliant_position = np.empty_like(positions)
        compliant_orientation = np.empty((len(self.limbs), 4))
        for k, name in enumerate(self.limb_names):
            kd, ks, kf = _DAMPING[("single" if single else "contact") if in_contact[k] else "free"]
            measured = state.contact_wrench_limb[k]
            error = np.concatenate(
                [
                    rotations[k] @ (measured[:3] - desired_limb[k, :3]),
                    rotations[k] @ (measured[3:] - desired_limb[k, 3:]),
                ]
            )
            c = self.compliance[name]
            delta = np.concatenate([c.linear, c.angular])
            rate = -ks / kd * delta + kf / kd * error
            c.linear = c.linear + self.dt * rate[:3]
            c.angular = log(exp(self.dt * rate[3:]) @ exp(c.angular))
            compliant_position[k] = positions[k] + c.linear
            compliant_orientation[k] = from_matrix(exp(c.angular) @ rotations[k])
        end = time.perf_counter_ns()

        total_desired = np.zeros(6)
        for k in contact_index:
            total_desired += np.concatenate(
                [
                    rotations[k] @ desired_limb[k, :3],
                    rotations[k] @ desired_limb[k, 3:]
                    + cross(positions[k], rotations[k] @ desired_limb[k, :3]),
                ]
            )
        height = float(np.mean([positions[k][2] for k in contact_index])) if contact_index else 0.0
        return WholeBodyTargets(
            com_position_world=com_d,
            base_orientation_world=orientation_d,
            limb_position_world=compliant_position,
            limb_orientation_world=compliant_orientation,
            limb_in_contact=np.array(in_contact),
            com_desired_world=com_d,
            zmp_desired_world=zmp_on_plane(total_desired, height),
            contact_wrench_desired_limb=desired_limb,
            timings_ns={
                "feedback": after_feedback - start,
                "distribution": after_distribution - after_feedback,
                "damping": end - after_distribution,
            },
            wrench_desired_world=wrench_desired,
            limb_tracked=plan.limb_tracked,
            wrench_distributed_world=distributed - offset,
        )


register(
    StabilizerSpec(
        "centroidal_feedback",
        CentroidalFeedbackStabilizer,
        "Murooka et al. 2022: centroidal PD, wrench distribution, damping",
    )
)
