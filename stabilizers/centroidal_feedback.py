"""Stabilizer `centroidal_feedback` (Murooka, Morisawa, Kanehiro, RA-L 2022, Sec. IV; eqs.
11-16, Tables II and III).

Each control period:
1. centroidal feedback (eq. 11): Delta w-bar^d = [K_PL (c^d - c^a) + K_DL (c'^d - c'^a);
   K_PA log(R^d R^a') + K_DA (omega^d - omega^a)], with r^d the planner's desired state (ours:
   the angular velocities omega for the paper's base-angle rates alpha', the same to first
   order in the angle);
2. desired resultant wrench (eq. 12): w-bar^d = w-bar^p' + Delta w-bar^d;
3. distribution (eqs. 13-14): w^d = w-bar^d + [m g; c^a x f^d] (the actual CoM, as the paper
   recommends) onto the cone of the contacts; w_i^d = G_i lambda_i;
4. damping control of every limb end (eqs. 15-16, Table II): the compliance pose
   r^c = r^d + Delta r^c with K_d Delta r' + K_s Delta r = K_f (w^a - w^d), integrated as eq. 16
   (compiled: `centroidal.kernels.damping_control`), per axis of each limb's contact frame, or
   of its contact surface's own frame where it has one (`ContactSurface.rotation_in_frame`: a
   hand resting on a rail; the surface then turns about its own origin);
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
import scipy.linalg

from centroidal.contacts import ContactSet, contact_set
from centroidal.gravity import GRAVITY
from centroidal.kernels import damping_control
from centroidal.projection import DEFAULT_BACKEND, WrenchProjector, gravity_offset
from centroidal.rotations import (
    from_matrix,
    quaternion_multiply,
    rotation_error,
    skew,
    to_matrices,
    to_matrix,
)
from centroidal.wrench import zmp_on_plane
from robots.limbs import grasp_surfaces, limb_surfaces
from robots.model import RobotModel
from robots.registry import MULTI_CONTACT
from robots.scene import Scenario
from robots.types import CentroidalPlan, RobotState, WholeBodyTargets
from stabilizers.base import StabilizerSpec, register

HRP5P = {"mass": 105.0, "omega2": 9.8 / 0.95}
TABLE_III = {
    "kp": (2000.0, 2000.0, 2000.0, 0.0, 0.0, 0.0),
    "kd": (666.0, 666.0, 666.0, 0.0, 0.0, 0.0),
}
TABLE_III_LADDER = {
    "kp": (3000.0, 3000.0, 3000.0, 1000.0, 1000.0, 1000.0),
    "kd": (1000.0, 1000.0, 1000.0, 333.0, 333.0, 333.0),
}
"""Table III's note: the gains "for climbing a vertical ladder in Fig. 4"."""
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


def scaled_table_iii(
    mass: float, com_height: float, ladder: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """Table III's K_P, K_D (6,) (its ladder row if `ladder`) rescaled from HRP-5P to a robot
    of `mass` [kg] and CoM height [m]: the linear gains by eq. 19, the angular gains (the
    ladder's only; zero otherwise) by `angular_gain_ratio`."""
    omega2 = GRAVITY / com_height
    table = TABLE_III_LADDER if ladder else TABLE_III
    kp, kd = np.array(table["kp"]), np.array(table["kd"])
    kp[:3] *= mass * omega2 / (HRP5P["mass"] * HRP5P["omega2"])
    kd[:3] *= mass * np.sqrt(omega2) / (HRP5P["mass"] * np.sqrt(HRP5P["omega2"]))
    ratio = angular_gain_ratio(mass, com_height)
    kp[3:] *= ratio
    kd[3:] *= ratio
    return kp, kd


def angular_gain_ratio(mass: float, com_height: float) -> float:
    """Adaptation of Table III's angular gains (N m/rad, N m s/rad) to our robot: the ratio of
    the robots' inertia scales m h^2 (h the CoM height; HRP-5P: 105 kg, 9.8 / omega^2 = 0.95
    m), which keeps the angular loop's natural frequency sqrt(K_PA / I) and damping ratio of
    Table III, as eq. 19 keeps the linear loop's DCM gain. The paper prints no relation."""
    hrp_height = 9.8 / HRP5P["omega2"]
    return mass * com_height**2 / (HRP5P["mass"] * hrp_height**2)


@dataclass(frozen=True)
class _ContactConfiguration:
    """What the distribution and damping need for one set of contacts at given target poses:
    built once per contact switch (or target move), reused every period in between."""

    contacts: ContactSet  # G of eq. 13
    index: np.ndarray  # limb indices in contact
    in_contact: np.ndarray  # (limbs,) bool: the same as a mask
    to_limb_frames: np.ndarray  # (6 n_c, n): lambda -> each contact's w_i in its own frame
    height: float  # mean contact height [m], the plane of the desired ZMP
    kd: np.ndarray  # (limbs, 6) Table II parameters per limb for this configuration
    ks: np.ndarray
    kf: np.ndarray
    axes: np.ndarray | None = None
    """(limbs, 3, 3) the damping's axes per limb in its contact frame: a contact surface's own
    frame (`ContactSurface.rotation_in_frame`: a hand resting on a rail, whose normal is not
    the hand frame's z), identity elsewhere; None when every limb's are its contact frame's."""
    axes_origin: np.ndarray | None = None
    """(limbs, 3) [m] that frame's origin in the contact frame (moments are taken about it)."""
    axes_quaternions: tuple[np.ndarray, np.ndarray] | None = None
    """(limbs, 4) the axes as quaternions (w, x, y, z), and their inverses."""
    axes_wrench: np.ndarray | None = None
    """(limbs, 6, 6) a limb-frame wrench (f, m about the contact frame's origin) to the damping
    axes: [R^T, 0; -R^T [o]x, R^T] (the moment about o)."""


class CentroidalFeedbackStabilizer:
    name = "centroidal_feedback"

    def __init__(self, dt: float, projection_backend: str = DEFAULT_BACKEND) -> None:
        self.dt = dt
        self.projector = WrenchProjector(projection_backend)

    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None:
        description = robot.robot
        self.mass = description.total_mass
        self.inertia = robot.constant_inertia()  # I of eq. 6 [kg m^2], as the planners'
        com_height = float(state.com_position_world[2])  # every scenario starts at z = 0
        self.kp, self.kd = scaled_table_iii(self.mass, com_height, scenario.ladder_gains)
        self.hand_kd_linear = scenario.hand_contact_kd_linear
        self.limbs = description.limbs
        self.limb_names = description.limb_names
        friction = scenario.scene.friction
        self.surfaces = limb_surfaces(description, friction)
        self.grasping = grasp_surfaces(self.surfaces)
        # Delta r^c of every limb end (eq. 15): linear [m] and rotation vector [rad], in each
        # limb's damping axes (its contact frame's, or its contact surface's own: `axes`).
        self.compliance_linear = np.zeros((len(self.limbs), 3))
        self.compliance_angular = np.zeros((len(self.limbs), 3))
        self._cache_key, self._cache = None, None
        self._index_of: dict[tuple[str, ...], np.ndarray] = {}
        self._damping_axes: np.ndarray | None = None  # the compliances' axes (None: frames')

    def _configuration(self, plan: CentroidalPlan) -> _ContactConfiguration:
        """G and the per-limb data of the plan's contacts at their target poses (cached)."""
        positions = plan.limb_target_position_world
        orientations = plan.limb_target_orientation_world
        index = self._index_of.get(plan.contact_limbs)
        if index is None:
            index = self._index_of[plan.contact_limbs] = np.array(
                [k for k, name in enumerate(self.limb_names) if name in plan.contact_limbs],
                dtype=int,
            )
        key = (
            plan.contact_limbs,
            plan.grasp_limbs,
            id(plan.contact_surfaces),
            positions[index].tobytes(),
            orientations[index].tobytes(),
        )
        if self._cache_key == key:
            return self._cache
        rotations = to_matrices(orientations[index]) if len(index) else np.zeros((0, 3, 3))
        if plan.contact_surfaces is not None:  # the planner's, in contact_limbs' order
            surface_of = dict(zip(plan.contact_limbs, plan.contact_surfaces, strict=True))
        else:
            surface_of = {
                name: (self.grasping if name in plan.grasp_limbs else self.surfaces)[name]
                for name in plan.contact_limbs
            }
        contacts = contact_set(
            [self.limb_names[k] for k in index],
            [surface_of[self.limb_names[k]] for k in index],
            [positions[k] for k in index],
            list(rotations),
        )
        blocks = []
        for j, k in enumerate(index):
            # world wrench about the origin -> the limb frame about its origin
            transpose = rotations[j].T
            shift = np.eye(6)
            shift[3:, :3] = -skew(positions[k])
            to_frame = np.kron(np.eye(2), transpose) @ shift
            blocks.append(to_frame @ contacts.matrix[:, contacts.slices[j]])
        to_limb_frames = (
            scipy.linalg.block_diag(*blocks) if blocks else np.zeros((0, contacts.matrix.shape[1]))
        )
        mode = "single" if len(index) == 1 else "contact"
        parameters = [_DAMPING[mode if k in index else "free"] for k in range(len(self.limb_names))]
        kd, ks, kf = (np.array([p[i] for p in parameters]) for i in range(3))
        if self.hand_kd_linear is not None and mode == "contact":  # Table II's note
            for k in index:
                if self.limb_names[k].endswith("hand"):
                    kd[k, :3] = self.hand_kd_linear
        height = float(positions[index, 2].mean()) if len(index) else 0.0
        in_contact = np.zeros(len(self.limb_names), dtype=bool)
        in_contact[index] = True
        axes = axes_origin = None
        for k in index:
            surface = surface_of[self.limb_names[k]]
            if surface.rotation_in_frame is not None or surface.origin_in_frame is not None:
                if axes is None:
                    axes = np.tile(np.eye(3), (len(self.limb_names), 1, 1))
                    axes_origin = np.zeros((len(self.limb_names), 3))
                if surface.rotation_in_frame is not None:
                    axes[k] = surface.rotation_in_frame
                if surface.origin_in_frame is not None:
                    axes_origin[k] = surface.origin_in_frame
        quaternions = to_axes = None
        if axes is not None:
            turn = np.array([from_matrix(r) for r in axes])
            quaternions = (turn, turn * np.array([1.0, -1.0, -1.0, -1.0]))
            to_axes = np.zeros((len(self.limb_names), 6, 6))
            for k, (r, o) in enumerate(zip(axes, axes_origin, strict=True)):
                to_axes[k, :3, :3] = to_axes[k, 3:, 3:] = r.T
                to_axes[k, 3:, :3] = -r.T @ skew(o)
        self._cache = _ContactConfiguration(
            contacts,
            index,
            in_contact,
            to_limb_frames,
            height,
            kd,
            ks,
            kf,
            axes,
            axes_origin,
            quaternions,
            to_axes,
        )
        self._cache_key = key
        return self._cache

    def _change_damping_axes(self, axes: np.ndarray | None) -> None:
        """The compliances are vectors in each limb's damping axes; when a limb's axes change
        (its contact surface's frame comes or goes), its compliance is re-expressed in the new
        ones (the same displacement and rotation of the limb end)."""
        old = self._damping_axes
        if old is axes:  # the same configuration (or none with axes of their own)
            return
        eye = np.eye(3)
        for k in range(len(self.limb_names)):
            before = eye if old is None else old[k]
            after = eye if axes is None else axes[k]
            if not np.array_equal(before, after):
                change = after.T @ before
                self.compliance_linear[k] = change @ self.compliance_linear[k]
                self.compliance_angular[k] = change @ self.compliance_angular[k]
        self._damping_axes = axes

    def desired_wrench(self, plan: CentroidalPlan, state: RobotState) -> np.ndarray:
        """w-bar^d (eqs. 11-12): the projected planned wrench plus the centroidal PD."""
        com_d, velocity_d, orientation_d, omega_d = plan.desired_state()
        linear = self.kp[:3] * (com_d - state.com_position_world) + self.kd[:3] * (
            velocity_d - state.com_velocity_world
        )
        if self.kp[3:].any() or self.kd[3:].any():
            angular = self.kp[3:] * rotation_error(
                to_matrix(orientation_d), to_matrix(state.base_orientation_world)
            ) + self.kd[3:] * (omega_d - state.base_angular_velocity_world)
        else:  # Table III: no angular feedback
            angular = np.zeros(3)
        return plan.wrench_projected_world + np.concatenate([linear, angular])  # eqs. 11-12

    def stabilize(self, t: float, plan: CentroidalPlan, state: RobotState) -> WholeBodyTargets:
        start = time.perf_counter_ns()
        com_d, _, orientation_d, _ = plan.desired_state()
        wrench_desired = self.desired_wrench(plan, state)
        after_feedback = time.perf_counter_ns()

        # eqs. 13-14: distribute over the contacts at their target poses, with the actual CoM.
        configuration = self._configuration(plan)
        n_limbs = len(self.limbs)
        offset = gravity_offset(self.mass, state.com_position_world, wrench_desired)
        desired_limb = np.zeros((n_limbs, 6))
        distributed = np.zeros(6)
        if len(configuration.index):
            distributed, ridge = self.projector.project(
                configuration.contacts.matrix, wrench_desired + offset
            )
            desired_limb[configuration.index] = (configuration.to_limb_frames @ ridge).reshape(
                -1, 6
            )
        after_distribution = time.perf_counter_ns()

        # eqs. 15-16: damping control of every limb end at once, per axis of each contact's
        # frame (of its surface's own frame where it has one: `_surface_axes`).
        c = configuration
        self._change_damping_axes(c.axes)
        targets, measured, desired = (
            plan.limb_target_orientation_world,
            state.contact_wrench_limb,
            desired_limb,
        )
        if c.axes is not None:
            targets, measured, desired = _surface_axes(c, targets, measured, desired)
        compliant_position, compliant_orientation = damping_control(
            plan.limb_target_position_world,
            targets,
            measured,
            desired,
            c.kd,
            c.ks,
            c.kf,
            self.dt,
            self.compliance_linear,
            self.compliance_angular,
        )
        if c.axes is not None:  # back to the limbs' contact frames: R_c R_s exp(p) R_s^T
            compliant_orientation = quaternion_multiply(
                compliant_orientation, c.axes_quaternions[1]
            )
            # the surface's frame turns about its own origin o: the limb frame's origin moves
            # by (R_c - R_limb) o (zero for limbs with o = 0)
            turn = to_matrices(plan.limb_target_orientation_world) - to_matrices(
                compliant_orientation
            )
            compliant_position = compliant_position + (turn @ c.axes_origin[:, :, None])[:, :, 0]
        end = time.perf_counter_ns()

        return WholeBodyTargets(
            com_position_world=com_d,
            base_orientation_world=orientation_d,
            limb_position_world=compliant_position,
            limb_orientation_world=compliant_orientation,
            limb_in_contact=configuration.in_contact.copy(),
            com_desired_world=com_d,
            zmp_desired_world=zmp_on_plane(distributed, configuration.height),
            contact_wrench_desired_limb=desired_limb,
            timings_ns={
                "feedback": after_feedback - start,
                "distribution": after_distribution - after_feedback,
                "damping": end - after_distribution,
            },
            wrench_desired_world=wrench_desired,
            limb_tracked=plan.limb_tracked,
            wrench_distributed_world=distributed - offset,
            angular_momentum_world=self.inertia @ plan.base_angular_velocity_planned_world,
        )


def _surface_axes(
    c: _ContactConfiguration, targets: np.ndarray, measured: np.ndarray, desired: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The damping's inputs in each limb's damping axes (`_ContactConfiguration.axes`, R_s,
    origin o in the contact frame): target orientations R_c R_s, and the measured and desired
    wrenches (force f, moment m about the contact frame's origin, contact-frame axes) as
    R_s^T f and R_s^T (m - o x f), so that Table II's normal and tangential entries act along
    the surface's normal and tangents, as eq. 15 is written."""
    turned = quaternion_multiply(np.asarray(targets, dtype=float), c.axes_quaternions[0])
    both = c.axes_wrench @ np.stack([measured, desired], axis=2)  # (limbs, 6, 2)
    return turned, both[:, :, 0], both[:, :, 1]


register(
    StabilizerSpec(
        "centroidal_feedback",
        CentroidalFeedbackStabilizer,
        "Murooka et al. 2022: centroidal PD, wrench distribution, damping",
        can=MULTI_CONTACT,
        needs=frozenset({"force_torque_sensors"}),
    )
)
