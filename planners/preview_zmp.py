"""Planner `preview_zmp`: Kajita's ZMP preview control on the cart-table model (Kajita et al.,
ICRA 2003), the bipedal baseline whose output definition Murooka et al. compare theirs with
(Sec. III-A2: same state and input, but the ZMP as the output instead of [c, f-bar]).

Horizontal axes: state [x, x', x''], input the jerk, output the ZMP p = x - (z_c / g) x''
(cart-table with a constant CoM height z_c); cost sum Q (p - p_ref)^2 + R u^2 with Kajita's
weights Q = 1, R = 1e-6, discretised at 5 ms with a 2 s preview (Kajita uses 1.6 s; 2 s as in
Table I, so both planners see the same future). Ours: the cost is Murooka's eqs. 4-5 form (R on
the jerk, no integral of the ZMP error), where Kajita's preview servo puts R on the jerk's
increment and integrates the error; the authors' own CCC PreviewControlZmp uses this form. The
gains are designed on the 5 ms grid and applied every 2 ms control period, the preview
indexed on that grid (as Murooka's Table I). The ZMP reference is the support centre, by the
same piecewise-constant rule as `preview_control` (`planners.reference`), with each supporting
sole's point moved 2 cm toward the body's midline, as the authors' own implementation of this
baseline does (`zmp_reference`; in double support on parallel feet the two shifts cancel). The
height follows
the reference (a constant offset above the support; `follow_height`) and the base orientation
is level.

To give the stabilizers the same kind of plan as `preview_control`, the planned resultant
wrench [m x''; m z''; 0 moment about the CoM] (`cart_table_wrench`) goes through the same
projection (eqs. 9-10); its projection error then shows how far the cart-table plan is from
the contact constraints. Unlike `preview_control`, the desired state r^d is not integrated from
the projected wrench: the stabilizers take the cart-table's own state as c^d (the plan sets no
`com_desired_world`), with the projected wrench as their feed-forward.
The steady-state tail correction of `centroidal.preview` is used as for `preview_control`.
"""

from __future__ import annotations

import time

import numpy as np

from centroidal.preview import TripleIntegratorPreview, output_preview_gains
from centroidal.projection import DEFAULT_BACKEND, GRAVITY, WrenchProjector, project_resultant
from centroidal.rotations import IDENTITY_WXYZ, from_matrix, heading_quaternion, to_matrix
from centroidal.wrench import zmp_on_plane
from planners.base import PlannerSpec, register
from planners.reference import (
    com_reference,
    feet_heading,
    support_centre,
    yaw_reference,
)
from robots.limbs import (
    FootstepSchedule,
    PhaseContacts,
    limb_surfaces,
    limb_targets,
    scheduled_footsteps,
)
from robots.model import RobotModel
from robots.scene import Contact, Scenario
from robots.types import CentroidalPlan, RobotState

KAJITA = {"q": 1.0, "r": 1e-6, "dtau": 0.005, "horizon": 400}
BWC_ZMP_OFFSET_INWARD_M = 0.02
"""Murooka's BaselineWalkingController (isri-aist/BaselineWalkingController, the authors'
implementation of ZMP preview control with DCM feedback, the Appendix's baseline):
`FootManager.zmpOffset: [0, -0.02, 0]` "(positive for x-forward, y-outside)" in
etc/BaselineWalkingController.in.yaml, its default, for JVRC-1 and HRP-5P (HRP-2Kai: 0.03)."""


def zmp_reference(
    scenario: Scenario,
    dtau: float,
    n_samples: int,
    height_offset: float,
    inward_m: float = BWC_ZMP_OFFSET_INWARD_M,
) -> np.ndarray:
    """The ZMP reference (n_samples, 3) [m] at times 0, dtau, ...: `com_reference`'s support
    centre (its third column the CoM height reference), with each supporting foot's point moved
    `inward_m` [m] along its sole's y axis toward the midline (left foot -y, right foot +y in
    the sole frame) before the mean, as the BaselineWalkingController's `calcZmpWithOffset`.

    Adaptation (not in Kajita et al., whose reference is the sole centre; taken from the
    authors' implementation of this baseline, `BWC_ZMP_OFFSET_INWARD_M`): measured on JVRC-1
    (stance 0.213 m, soles 0.08 m wide) in PyBullet at 4268572, the sole-centre reference left
    the DCM 20-27 mm outside its plan at every single support, the command ZMP saturated at the
    sole's outer edge and the walk fell at 8.72 s."""
    reference = com_reference(scenario, dtau, n_samples, height_offset)
    if inward_m == 0.0:
        return reference
    by_phase: dict[int, np.ndarray] = {}
    shift = np.zeros(2)  # a phase without contacts keeps the last supported phase's shift,
    for i in range(n_samples):  # as `support_centre` keeps its centre
        phase = scenario.phase_at(i * dtau)
        if id(phase) not in by_phase:
            by_phase[id(phase)] = (
                _inward_shift(phase.contacts, inward_m) if phase.contacts else shift
            )
        shift = by_phase[id(phase)]
        reference[i, :2] += shift
    return reference


def _inward_shift(contacts: tuple[Contact, ...], inward_m: float) -> np.ndarray:
    """Mean horizontal shift (2,) [m] of the supporting feet's points toward the midline, each
    along its sole's y axis (left feet -y, right feet +y); zero with no foot in contact (hands
    only: `support_centre`'s hands' centre unchanged)."""
    shifts = [
        to_matrix(c.orientation_world)[:2, 1]
        * (-inward_m if c.limb.startswith("left") else inward_m)
        for c in contacts
        if c.limb.endswith("foot")
    ]
    return np.mean(shifts, axis=0) if shifts else np.zeros(2)


class PreviewZmpPlanner:
    name = "preview_zmp"
    projects_wrench = True
    tracks_hand_targets = False
    plans_com_trajectory = True

    def __init__(self, dt: float, projection_backend: str = DEFAULT_BACKEND) -> None:
        self.dt = dt
        self.projector = WrenchProjector(projection_backend)
        self.dtau, self.horizon = KAJITA["dtau"], KAJITA["horizon"]

    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None:
        self.schedule = FootstepSchedule(scheduled_footsteps(scenario))
        self.scenario = scenario
        description = robot.robot
        self.mass = description.total_mass
        com = np.asarray(state.com_position_world, dtype=float)
        _, support_height = support_centre(scenario, 0.0)
        self.height = com[2] - support_height  # z_c of the cart-table
        self.omega = float(np.sqrt(GRAVITY[2] / self.height))  # its natural frequency [1/s]
        gains = output_preview_gains(
            ((1.0, 0.0, -self.height / GRAVITY[2]),),
            (KAJITA["q"],),
            KAJITA["r"],
            self.dtau,
            self.horizon,
        )
        self.horizontal = TripleIntegratorPreview(gains, self.dt, 2)
        self.horizontal.state[:, 0] = com[:2]
        self.horizontal.state[:, 1] = np.asarray(state.com_velocity_world)[:2]
        n_samples = int(np.ceil(scenario.duration / self.dtau)) + self.horizon + 2
        self.reference = zmp_reference(scenario, self.dtau, n_samples, self.height)
        self.window = np.zeros((self.horizon, 2, 1))
        self.limbs = description.limbs
        # a turning walk: the base heading follows the feet (`planners.reference`)
        self.turns = yaw_reference(scenario, self.dtau, n_samples) is not None
        self.surfaces = limb_surfaces(description, scenario.scene.friction)
        self._phase_contacts = PhaseContacts(self.surfaces)
        self.start_pose = {}
        for limb in self.limbs:
            position, rotation = robot.frame_pose(state, limb.contact_frame)
            self.start_pose[limb.name] = (position, from_matrix(rotation))
        self.height_state = np.array([com[2], 0.0])

    def plan(self, t: float, state: RobotState) -> CentroidalPlan:
        start = time.perf_counter_ns()
        index = int(t / self.dtau + 1e-9)
        self.window[:, :, 0] = self.reference[index + 1 : index + 1 + self.horizon, :2]
        reference_now = self.reference[index]
        after_reference = time.perf_counter_ns()

        self.horizontal.advance(self.horizontal.jerk(self.window))
        x = self.horizontal.state
        z_next, z_velocity, z_acceleration = follow_height(
            self.height_state, reference_now[2], self.omega, self.dt
        )
        self.height_state = np.array([z_next, z_velocity])
        com = np.array([x[0, 0], x[1, 0], z_next])
        velocity = np.array([x[0, 1], x[1, 1], z_velocity])
        acceleration = np.array([x[0, 2], x[1, 2], z_acceleration])
        wrench_planned = cart_table_wrench(self.mass, acceleration)
        after_preview = time.perf_counter_ns()

        phase = self.scenario.phase_at(t)
        contacts, height = self._phase_contacts(phase)
        wrench_projected, projected_contact = project_resultant(
            self.projector, contacts, self.mass, com, wrench_planned
        )  # eqs. 9-10
        zmp = zmp_on_plane(projected_contact, height)
        after_projection = time.perf_counter_ns()

        positions, orientations, tracked = limb_targets(
            self.scenario, self.limbs, self.start_pose, t
        )
        zero = np.zeros(3)
        heading = (
            heading_quaternion(feet_heading(self.limbs, orientations))
            if self.turns
            else IDENTITY_WXYZ
        )
        return CentroidalPlan(
            com_reference_world=reference_now,
            com_planned_world=com,
            com_velocity_planned_world=velocity,
            com_acceleration_planned_world=acceleration,
            base_orientation_planned_world=heading,
            base_angular_velocity_planned_world=zero,
            wrench_planned_world=wrench_planned,
            wrench_projected_world=wrench_projected,
            zmp_planned_world=zmp,
            contact_limbs=phase.limbs,
            footsteps=self.schedule.upcoming(t),
            limb_target_position_world=positions,
            limb_target_orientation_world=orientations,
            timings_ns={
                "reference": after_reference - start,
                "preview": after_preview - after_reference,
                "projection": after_projection - after_preview,
            },
            limb_tracked=tracked,
        )


register(
    PlannerSpec(
        "preview_zmp",
        PreviewZmpPlanner,
        "Kajita et al. 2003: ZMP preview control on the cart-table model",
    )
)


def cart_table_wrench(mass: float, acceleration: np.ndarray) -> np.ndarray:
    """The planned resultant wrench w-bar^p (6,) of a cart-table plan, gravity excluded: the
    force m c'' [N] and no moment about the CoM [N m].

    Adaptation: Kajita's cart-table plan is a CoM trajectory only, its force through the CoM
    (the ZMP is where that line meets the floor); this is the wrench that `preview_zmp` gives
    the stabilizers, in the convention of Murooka et al.'s w-bar^p (eqs. 3, 9-10), so that it
    goes through the same projection as `preview_control`'s plan and its projection error
    shows how far the cart-table plan is from the contact constraints."""
    return np.concatenate([mass * np.asarray(acceleration, dtype=float), np.zeros(3)])


def follow_height(
    state: np.ndarray, reference: float, omega: float, dt: float
) -> tuple[float, float, float]:
    """One period of a critically damped follower of the reference height, z'' = omega^2
    (z_ref - z) - 2 omega z', from `state` = (z [m], z' [m/s]) by semi-implicit Euler over dt
    [s]: (z, z') after the period and the z'' [m/s^2] applied over it.

    Adaptation: Kajita's cart-table holds the height constant; our reference height is the
    supporting soles' mean height plus a constant, which steps when the support changes. The
    earlier rule differentiated it twice per period, so a step of 0.05 mm (JVRC-1's soles stand
    0.1 mm apart) planned 12 m/s^2 down and up again: a planned vertical force below zero, a ZMP
    of NaN, and the episode's end. Following at the cart-table's own omega plans 6e-4 m/s^2 for
    that step. A constant reference equal to the height (the humanoid's walks) plans z'' = 0
    exactly, as before."""
    z, velocity = float(state[0]), float(state[1])
    acceleration = omega * omega * (reference - z) - 2.0 * omega * velocity
    velocity += acceleration * dt
    return z + velocity * dt, velocity, acceleration
