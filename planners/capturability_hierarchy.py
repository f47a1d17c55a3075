"""Planner `capturability_hierarchy`: Sherikov, Dimitrov & Wieber, "Whole body motion controller
with long-term balance constraints" (Humanoids 2014). One hierarchical least-squares problem per
control period decides the joint and base accelerations, the contact wrenches, the previewed
CoP and the next footsteps (Sec. VI); there is no separate planning stage, so this "planner" is
the whole method, and its plan carries the accelerations and wrenches that the `passthrough`
stabilizer hands to the `inverse_dynamics` layer (torques, eq. 1).

Decision variables x (`Layout`): q'' (nv; pinocchio's convention), per foot the friction-pyramid
coefficients lambda (4) and the moment mu_c (3) at the sole centre (eqs. 3-4; both in units of
the robot's weight m g, and m g x 1 m, so that every variable is of order one), the CoM
acceleration c''_0 (x, y), the previewed CoP Z (N per axis) and the displacements of the next
K footsteps from the foothold before each (eq. 12's rectangles as bounds on them).

Levels (Sec. VI):
1. dynamics of the floating base (eq. 2), lambda >= 0 (5), torsional friction (6), CoP in the
   sole (7), no stance-foot acceleration (8), joint limits over a horizon T (9), CoM coupling
   (15), swing-foot coupling (16), previewed CoP in the previewed footholds (11), footstep
   rectangles (12); a foot in the air has lambda = mu = 0;
2. the terminal capturability constraint (14);
3. weighted objectives: hand (17), torso orientation (18), joint PD (19), CoP centring (21),
   CoP velocity (22), swing-foot jerk (20), and (ours, after the paper's [3]) a CoM velocity
   objective for walking on a gait command.

The paper's numbers used as printed: a preview of two steps of 0.8 s at 100 ms (N = 16, K = 2),
fixed step timing with free footstep positions (a gait command's own step period is not
used: its speed is the velocity objective's reference, and its number of steps becomes as many
0.8 s steps as fit in its duration). What the paper leaves open, chosen here and named as
constants below: the objectives' weights and gains, the joint-limit horizon T, the
torsional friction coefficient, the footstep rectangles, the swing's vertical profile, the
split of a step into 0.7 s single and 0.1 s double support (Herdt et al.'s), and when a
standing robot starts to step (ours: its capture point 3 cm off the feet's middle; the paper's
robot walks from the start of its tests), and, to make it stand and step on our robot in a
simulator (each measured, docs/sherikov.md): the current CoP z_0 bounded too, a 1 cm margin
inside the soles, a least load on every contact sole, contact-velocity damping in eq. 8, a
CoM-height objective, the swing's orientation held by a PD, the footstep kept in the last
0.1 s of a swing, the "both feet" support as the box around both soles (exact for feet
side by side), and the preview's samples after a walk's end on both feet
(`_standing_after_walk`; the paper's robot never stops). The preview's first interval is
shortened to the step grid, so that its samples fall on the lift-offs, touchdowns and double
supports' ends (as the authors' humoto does, module `wpg04`; the paper says only "at 100
ms").
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from centroidal.capture_preview import capture_velocity_row, preview, swing_cubic
from centroidal.gravity import GRAVITY
from centroidal.hierarchy import HierarchyError, Level, solve_hierarchy
from centroidal.whole_body_rows import WholeBodyTerms, whole_body_terms
from planners.base import PlannerSpec, register
from planners.step_schedule import FEET, StepSchedule, other_foot
from robots.model import RobotModel
from robots.registry import FLAT_GROUND
from robots.scene import Scenario
from robots.similarity import froude_time_scale
from robots.types import CentroidalPlan, Footstep, RobotState

HAND = "right_hand"  # the hand of eq. 17 (the paper drives the right hand)
PREVIEW_INTERVALS = 16  # N: two steps of 0.8 s at 100 ms (Sec. VII)
PREVIEW_PERIOD_S = 0.1
FOOTSTEPS = 2  # K
SINGLE_SUPPORT_S, DOUBLE_SUPPORT_S = 0.7, 0.1  # one step of 0.8 s (Herdt et al.'s split)
JOINT_LIMIT_HORIZON_S = 0.1  # T of eq. 9 (ours)
STEP_LENGTH_MAX_M = 0.3  # eq. 12's rectangle: +-0.3 m forward (ours, at scale 1)
STEP_WIDTH_EXTRA_M = (-0.05, 0.2)  # lateral: the standing width -0.05 ... +0.2 m (ours)
# Objectives (level 3) and their gains (ours: the paper gives none). A weight multiplies the
# squared residual of rows scaled so that the block's largest row has unit norm (`_Rows.add`;
# the velocity objective: every row), so it compares residuals in units of that row, not in
# the physical units of the task.
# Eq. 19 "is used for two purposes: damping (Kd > 0, Kp = 0) and maintaining reference
# configuration q'_ref (Kd > 0, Kp > 0)": ours is one objective, the second (which damps too),
# on every joint.
POSTURE_KP, POSTURE_KD, POSTURE_WEIGHT = 10.0, 2 * math.sqrt(10.0), 1e-3  # eq. 19 [1/s^2, 1/s]
# eq. 18 on the robot's base link (`RobotDescription.base_link`): the humanoid's torso, but
# JVRC-1's pelvis, below its waist joints (its chest is then free)
TORSO_KP, TORSO_KD, TORSO_WEIGHT = 100.0, 20.0, 1.0  # eq. 18
HAND_KP, HAND_KD, HAND_ERROR_MAX, HAND_WEIGHT = 10.0, 3.0, 0.05, 10.0  # eq. 17 (m: saturation)
COP_WEIGHT = 1e5  # eq. 21 (see below)
"""Eq. 21's weight, 1e4 times the hand's. The current CoM acceleration c''_0 is shared by the
whole-body rows (eq. 15) and the preview, which prices it only through the previewed CoPs
(bounded at level 1, centred by eq. 21, smoothed by eq. 22) and eq. 14; while walking, the free
footsteps let the preview follow almost any c''_0. At weight 10 the whole-body objectives
decided it: in `reach_push` 0.3 s after the first push, c''_0 came out +1.28 m/s^2 forward
and, with one objective left out of the same problem, -0.79 (hand), -0.76 (joint PD, weight
1e-3), 0.00 (CoM height), +0.55 (torso), and the robot ran forward onto its rectangles' limit
and fell. At 1e5 they still move it (by up to 0.8 m/s^2 in a later state): the weight is
chosen by its results on the standing push protocol (20 pushes at 0.4 m/s, MuJoCo,
2026-11-27): weight 10: 8 survived, 1e3: 8, 1e4: 12, 1e5: 15, 1e6: 14 (docs/sherikov.md)."""
COP_VELOCITY_WEIGHT = 1.0  # eq. 22
JERK_WEIGHT = 10.0  # eq. 20
JERK_TIME_FLOOR_S = 0.2  # [s] eq. 20's remaining time no shorter (row norms within 2e3)
ADAPTATION_BLOCK_S = 0.1  # [s] the footstep is kept in the last 0.1 s of a swing (ours)
VELOCITY_WEIGHT = 100.0  # CoM velocity objective over the preview (ours, after [3])
HEIGHT_KP, HEIGHT_KD, HEIGHT_WEIGHT = 100.0, 20.0, 10.0  # CoM height held (ours)
SWING_ORIENTATION_KP, SWING_ORIENTATION_KD = 100.0, 20.0  # eq. 16's constant orientation, held
SWING_TIME_FLOOR_S = 0.05  # [s] the cubics' remaining time no shorter (ours: see _swing_rows)
CONTACT_DAMPING = 20.0  # [1/s] eq. 8 as J q'' + J' q' = -K J q' (ours, see _levels)
SOLE_MARGIN_M = 0.01  # [m] eqs. 7, 11 keep the CoP this far inside the sole (ours: see below)
"""The paper bounds the CoP by the sole itself (eqs. 7, 11). Ours: 1 cm inside it. At 0 the
hierarchy's cascade fails at the end of the MuJoCo `walk` (18 failures, then an error at
10.25 s; 2026-12-01); with the preview aligned to the steps (`StepSchedule.first_interval`)
`reach_push` passes at 0 and 1 cm in both simulators and falls at 1.5 cm (4.56 s) and 2 cm
(3.85 s, MuJoCo; these two measured with an audit's patch of the same rule), 2 cm being the
margin until 2026-12-01 (docs/sherikov.md)."""
MIN_NORMAL_FORCE = 0.05  # a contact sole's least normal force, in units of m g (ours)
REACH_FIRST_STEP_S, REACH_FIRST_SWING = 0.8, "left_foot"
"""A reach's walk starts 0.8 s after the first hand target (s, times sqrt(scale)), left foot
first: the phase of a walk of 0.8 s steps from t = 0 with the right foot first (the paper's
robot "starts walking since the target is initially unreachable"; it gives no start time or
first foot), so that the left foot is 0.1 s into its swing at Test 2's first push (2.5 s, not
scaled; at scale 1 only), our reading of the paper's "forcing the robot to make a step to the
left" and "adjusting footsteps in mid-air". (Until 2026-11-27: after 1.0 s, right foot first,
so that the push came as the left foot landed and the right one, which cannot step left,
swung next.)"""
STEP_TRIGGER_M = 0.03  # [m] capture point off the feet's middle that makes it step (ours)
HOLD_PERIODS_MAX = 5  # a hierarchy no solver solves: the last answer held this long (ours)
STOP_MARGIN_M, STOP_SPEED = 0.02, 0.1  # a push-started walk stops when capture point is inside


def torsional_friction(friction: float, half_extents: tuple[float, float]) -> float:
    """gamma of eq. 6 [m] (the paper cites [23] without a value): the torsional moment a
    rectangular sole can hold under a uniform pressure, mu F times the mean distance of its
    points from the centre, approximated from below as mu (a + b) / 3 for half extents a, b
    (a square's mean distance is 0.765 a, this gives 0.667 a; ours)."""
    a, b = half_extents
    return friction * (a + b) / 3.0


def weight_shift_support(
    anchor: np.ndarray,
    foot_box: tuple[np.ndarray, np.ndarray],
    both_feet_box: tuple[np.ndarray, np.ndarray],
    lifted_off: bool,
) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """(eq. 21's centring target [m], eq. 11's CoP box about it) for a preview sample in the
    support before a walk's first step. Ours: the paper's robot walks from its first sample, and
    eq. 21 centres the CoP on "the center of the footsteps"; standing on both feet before the
    first lift-off, the CoP may range over the box about both feet (`both_feet_box`, about
    the first stance foot `anchor`) while eq. 21 pulls it to the first stance foot (the
    weight shift); from the lift-off on, the stance foot's own box (`foot_box`)."""
    return (anchor, foot_box) if lifted_off else (anchor, both_feet_box)


def friction_pyramid(friction: float) -> np.ndarray:
    """G of eq. 4 (3, 4): unit vectors along the edges of the linearised friction cone, in the
    contact frame (z normal): (+-mu, 0, 1) and (0, +-mu, 1), normalised."""
    edges = np.array([[friction, 0, 1], [-friction, 0, 1], [0, friction, 1], [0, -friction, 1]])
    return (edges / np.linalg.norm(edges, axis=1)[:, None]).T


@dataclass(frozen=True)
class Layout:
    """Where each decision variable sits in x (see the module)."""

    nv: int
    samples: int
    steps: int

    @property
    def qdd(self) -> slice:
        return slice(0, self.nv)

    def force(self, foot: int) -> slice:
        start = self.nv + 7 * foot
        return slice(start, start + 4)

    def moment(self, foot: int) -> slice:
        start = self.nv + 7 * foot + 4
        return slice(start, start + 3)

    @property
    def cdd(self) -> slice:
        start = self.nv + 14
        return slice(start, start + 2)

    def cop(self, axis: int) -> slice:
        start = self.nv + 16 + axis * self.samples
        return slice(start, start + self.samples)

    def step(self, j: int) -> slice:
        """Displacement (x, y) of footstep j >= 1 from the foothold before it."""
        start = self.nv + 16 + 2 * self.samples + 2 * (j - 1)
        return slice(start, start + 2)

    @property
    def size(self) -> int:
        return self.nv + 16 + 2 * self.samples + 2 * self.steps


def _per_row(value, m: int) -> np.ndarray:
    """A bound given as a scalar or per row, as an (m,) float array."""
    value = np.asarray(value, dtype=float)
    return np.full(m, float(value)) if value.ndim == 0 else value.reshape(m)


class _Rows:
    """Rows of one level: lower <= A x <= upper, appended block by block.

    `cache` (the planner's, for one episode): the scaled rows of blocks whose A is fixed by a
    `key` (`add`), built and scaled once; the same floating-point operations on the same
    values, so a period's levels are bit-identical with or without it (a test holds this)."""

    def __init__(self, n: int, cache: dict | None = None) -> None:
        self.n = n
        self.cache = cache
        self.blocks: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
        self.names: list[str] = []  # per row, for reports of which rows are violated

    def add(
        self,
        a,
        lower,
        upper,
        weight: float = 1.0,
        name: str = "",
        rowwise: bool = False,
        key=None,
    ) -> None:
        """Append lower <= a x <= upper, scaled (`_scaled_rows`). `key`: a hashable value that
        determines `a` for the rest of the episode (for example ("air", foot)); `a` may then
        be a function of no arguments that builds it, called only when the block is not
        cached yet."""
        entry = None if key is None or self.cache is None else (key, weight, rowwise)
        cached = None if entry is None else self.cache.get(entry)
        if cached is None:
            cached = _scaled_rows(np.atleast_2d(a() if callable(a) else a), weight, rowwise)
            if entry is not None:
                cached[0].flags.writeable = False
                self.cache[entry] = cached
        scaled, scale = cached
        m = scaled.shape[0]
        self.names.extend([name] * m)
        self.blocks.append((scaled, _per_row(lower, m) * scale, _per_row(upper, m) * scale))

    def equal(
        self,
        a,
        value,
        weight: float = 1.0,
        name: str = "",
        rowwise: bool = False,
        key=None,
    ) -> None:
        self.add(a, value, value, weight, name, rowwise, key)

    def level(self, name: str) -> Level:
        if not self.blocks:
            return Level(np.zeros((0, self.n)), np.zeros(0), np.zeros(0), name)
        a = np.vstack([b[0] for b in self.blocks])
        lower = np.concatenate([b[1] for b in self.blocks])
        upper = np.concatenate([b[2] for b in self.blocks])
        return Level(a, lower, upper, name)


def _scaled_rows(a: np.ndarray, weight: float, rowwise: bool) -> tuple[np.ndarray, object]:
    """(a times its scale, the scale (a float, or one per row)): each block scaled to a largest
    row norm of one, then weighted, so that the rows' norms within a level stay near the
    weights' ratio (DAQP's accuracy and speed fall with that ratio: centroidal.hierarchy); a
    block keeps its rows' relative weights. `rowwise`: every row to unit norm, for blocks whose
    rows' norms span decades."""
    if rowwise:
        norms = np.sqrt(np.einsum("ij,ij->i", a, a))
        norms[norms == 0.0] = 1.0
        scale = math.sqrt(weight) / norms
        return a * scale[:, None], scale
    largest = math.sqrt(float(np.einsum("ij,ij->i", a, a).max())) if a.size else 0.0
    scale = math.sqrt(weight) / (largest if largest > 0.0 else 1.0)
    return a * scale, scale


class CapturabilityHierarchyPlanner:
    name = "capturability_hierarchy"
    projects_wrench = False
    tracks_hand_targets = True
    plans_com_trajectory = False

    def __init__(self, dt: float) -> None:
        self.dt = dt

    # ------------------------------------------------------------------ set-up
    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None:
        self.robot_model = robot
        self.model = robot.model
        self.data = self.model.createData()
        description = robot.robot
        self.scale = description.scale
        self.limb_names = description.limb_names
        limbs = {limb.name: limb for limb in description.limbs}
        self.foot_frames = [robot.frame_id[limbs[f].contact_frame] for f in FEET]
        self.hand_frame = robot.frame_id[limbs[HAND].contact_frame]
        self.base_frame = robot.frame_id[description.base_link]
        self.limb_frames = [robot.frame_id[limb.contact_frame] for limb in description.limbs]
        # every limb's frame (the plan's limb targets) and the base (eq. 18), once each
        self.frames = list(dict.fromkeys([*self.limb_frames, self.base_frame]))
        self.half_extents = np.array(limbs[FEET[0]].half_extents[:2], dtype=float)
        # eqs. 7 and 11 on the sole less a margin (ours: a CoP on the very edge tips the foot)
        self.cop_extents = self.half_extents - SOLE_MARGIN_M * description.scale
        self.weight = robot.total_mass * GRAVITY
        friction = scenario.scene.friction
        self.pyramid = friction_pyramid(friction)
        self.gamma = torsional_friction(friction, tuple(self.half_extents))
        self.lower = description.array("lower")
        self.upper = description.array("upper")
        self.nominal = np.array(description.nominal_posture)
        self.layout = Layout(self.model.nv, PREVIEW_INTERVALS, FOOTSTEPS)
        q = robot.configuration(state)
        pin.framesForwardKinematics(self.model, self.data, q)
        soles = [self.data.oMf[f].translation.copy() for f in self.foot_frames]
        self.ground = float(np.mean([s[2] for s in soles]))
        self.foothold = {foot: soles[i][:2].copy() for i, foot in enumerate(FEET)}
        self.standing_width = float(abs(soles[0][1] - soles[1][1]))
        com = pin.centerOfMass(self.model, self.data, q)
        self.height = float(com[2] - self.ground)
        self.omega = math.sqrt(GRAVITY / self.height)
        self.period_s = PREVIEW_PERIOD_S * froude_time_scale(self.scale)
        for phase_s in (SINGLE_SUPPORT_S, DOUBLE_SUPPORT_S):  # `_use_preview`'s alignment
            if abs(phase_s / PREVIEW_PERIOD_S - round(phase_s / PREVIEW_PERIOD_S)) > 1e-9:
                raise ValueError(
                    f"step phases must be multiples of the preview's {PREVIEW_PERIOD_S} s, "
                    f"got {phase_s} s"
                )
        self._previews: dict[int, tuple] = {}  # the aligned previews by first interval [us]
        self._use_preview(self.period_s)
        self.schedule = StepSchedule(
            SINGLE_SUPPORT_S * froude_time_scale(self.scale),
            DOUBLE_SUPPORT_S * froude_time_scale(self.scale),
        )
        self.base_orientation_reference = np.array(state.base_orientation_world, dtype=float)
        self.velocity_reference = None
        self.walk_by_push = False
        self.swing_height = scenario.swing_height
        gait = scenario.gait
        if gait is not None and gait.turn_per_step(self.scale) != 0.0:
            raise ValueError(
                f"{self.name} cannot turn: its footstep rectangles and CoP boxes (eqs. 11-12) "
                "and the swing foot's orientation are in world axes (ours), so it walks "
                f"straight paths only; got {gait.turn_per_step(self.scale):.3g} rad per step"
            )
        if gait is not None:
            forward, lateral = gait.step_length_for(self.scale)
            period = gait.step_period * froude_time_scale(self.scale)
            self.velocity_reference = np.array([forward, lateral]) / period
            first = FEET[0] if lateral > 0 else FEET[1]
            duration = gait.steps * gait.step_period * froude_time_scale(self.scale)
            self.schedule.start(
                gait.start_double_support * froude_time_scale(self.scale),
                first,
                max(1, round(duration / self.schedule.period_s)),
            )
            self.swing_height = gait.swing_height * self.scale
        self.scenario = scenario
        self.hand_target = None
        if scenario.hand_targets and not self.schedule.walking:
            # the paper's robot walks from the start, in place when nothing drives it (Sec.
            # VII-B: "exclusion of (17) from the hierarchy results in walking in place")
            first = min(target.time for target in scenario.hand_targets)
            start = first + REACH_FIRST_STEP_S * froude_time_scale(self.scale)
            self.schedule.start(start, REACH_FIRST_SWING)
        self.warm = None
        self.last_phase = self.schedule.phase(0.0)
        self.solver_failures = 0
        self.last_solution = None  # (rows' signature, HierarchySolution) of the last period
        self.held = 0  # periods in a row that held the last solution
        self.last_step: np.ndarray | None = None
        self._row_cache: dict | None = {}  # `_Rows`: the rows fixed for the episode, scaled

    def _use_preview(self, first_s: float) -> None:
        """The preview of eq. 10 whose first interval lasts `first_s` [s]
        (`StepSchedule.first_interval`, with the step times multiples of the preview's
        period, so that every lift-off, touchdown and double support's end in the horizon is
        a sample), with eq. 14's row; built once per first interval."""
        grid = round(first_s * 1e6)
        if grid not in self._previews:
            pre = preview(self.height, self.period_s, PREVIEW_INTERVALS, first_s=first_s)
            self._previews[grid] = (pre, capture_velocity_row(pre))
        self._grid = grid
        self.preview, self.capture_row = self._previews[grid]

    # ------------------------------------------------------------------ one period
    def plan(self, t: float, state: RobotState) -> CentroidalPlan:
        start_ns = time.perf_counter_ns()
        robot = self.robot_model
        q = robot.configuration(state)
        v = robot.velocity(state, q)
        frames = self.frames
        terms = whole_body_terms(self.model, self.data, q, v, frames)
        self._velocities = {f: terms.jacobian[f] @ v for f in frames}
        phase = self._advance(t, terms)
        self._t = t
        self.hand_target = self.scenario.hand_target_at(HAND, t)  # eq. 17's target, if any
        terms_ns = time.perf_counter_ns()
        levels, context = self._levels(t, q, v, terms, phase)
        build_ns = time.perf_counter_ns()
        # hot start (Sec. VII) from the last period's active set when the rows are the same
        signature = (phase.swing, tuple(level.a.shape[0] for level in levels))
        warm = self.warm[1] if self.warm is not None and self.warm[0] == signature else None
        held = False
        try:
            solution = solve_hierarchy(levels, self.layout.size, warm_start=warm)
        except HierarchyError:
            # DAQP gave up (measured: rows' norm ratio beyond its limit, or its exitflag 3):
            # the same hierarchy through the reference cascade of QPs, counted as a failure
            self.solver_failures += 1
            try:
                solution = solve_hierarchy(levels, self.layout.size, solver="cascade")
            except HierarchyError:
                # ours: the last period's answer held (the same rows), as a controller keeps
                # its last command, for at most `HOLD_PERIODS_MAX` periods in a row
                last = self.last_solution
                if last is None or last[0] != signature or self.held >= HOLD_PERIODS_MAX:
                    raise
                solution, held = last[1], True
        solve_ns = time.perf_counter_ns()
        x = solution.x
        if not np.all(np.isfinite(x)):
            raise RuntimeError(f"hierarchy solver failed (exitflag {solution.exitflag})")
        self.held = self.held + 1 if held else 0
        self.last_solution = (signature, solution)
        self.warm = (signature, solution.active)
        if not held:
            self.last_step = x[self.layout.step(1)].copy() if phase.swing is not None else None
        if not self.schedule.walking:
            self._maybe_step(t, terms)
        timings = {
            "terms": terms_ns - start_ns,
            "rows": build_ns - terms_ns,
            "hierarchy": solve_ns - build_ns,
        }
        plan = self._plan(t, x, terms, phase, context, timings, solution.iterations)
        timings["plan"] = time.perf_counter_ns() - solve_ns
        return plan

    def _advance(self, t: float, terms: WholeBodyTerms):
        """The schedule's phase at t; at a touchdown the landed foot's foothold is where it
        is; a push-started walk stops when the robot can stand again."""
        phase = self.schedule.phase(t)
        last = self.last_phase
        if last.swing is not None and phase.swing != last.swing:  # a touchdown
            frame = self.foot_frames[FEET.index(last.swing)]
            self.foothold[last.swing] = terms.placement[frame][0][:2].copy()
        if self.walk_by_push and phase.swing is None and phase.step >= 1:
            capture = terms.com_position[:2] + terms.com_velocity[:2] / self.omega
            low, high = self._both_feet_box()
            inside = np.all(capture > low + STOP_MARGIN_M) and np.all(
                capture < high - STOP_MARGIN_M
            )
            if inside and np.linalg.norm(terms.com_velocity[:2]) < STOP_SPEED:
                self.schedule.stop_after(phase.step)
                self.walk_by_push = False
                phase = self.schedule.phase(t)
        self.last_phase = phase
        return phase

    def _maybe_step(self, t: float, terms: WholeBodyTerms) -> None:
        """Ours (the paper's robot always walks, in place when nothing drives it): a standing
        robot starts to step when its capture point c + c'/omega is more than
        `STEP_TRIGGER_M` from the middle of its feet along x or y, after one double support."""
        capture = terms.com_position[:2] + terms.com_velocity[:2] / self.omega
        middle = (self.foothold[FEET[0]] + self.foothold[FEET[1]]) / 2
        if np.max(np.abs(capture - middle)) <= STEP_TRIGGER_M * self.scale:
            return
        # the foot away from the capture point swings first: it is the unloaded one (the
        # loaded one cannot be lifted in one double support), and K = 2 steps recover
        first = FEET[1] if capture[1] > middle[1] else FEET[0]
        self.schedule.start(t + self.schedule.double_s, first)
        self.walk_by_push = True

    def _both_feet_box(self) -> tuple[np.ndarray, np.ndarray]:
        points = np.array([self.foothold[f] for f in FEET])
        return points.min(axis=0) - self.cop_extents, points.max(axis=0) + self.cop_extents

    # ------------------------------------------------------------------ the hierarchy
    def _levels(self, t, q, v, terms: WholeBodyTerms, phase):
        lay, n = self.layout, self.layout.size
        cache = self._row_cache
        first, second, third = _Rows(n, cache), _Rows(n, cache), _Rows(n, cache)
        stance = [f for f in FEET if f != phase.swing]
        weight = self.weight
        # eq. 2: the base rows of H q'' + h = J_c^T f, scaled by 1 / (m g)
        dynamics = np.zeros((6, n))
        dynamics[:, lay.qdd] = terms.mass_matrix[:6] / weight
        for i, foot in enumerate(FEET):
            frame = self.foot_frames[i]
            jacobian, rotation = terms.jacobian[frame], terms.placement[frame][1]
            if foot in stance:
                # J_lwa^T [R f; R m] with f = m g G lambda, m = m g mu
                dynamics[:, lay.force(i)] = -jacobian[:3, :6].T @ rotation @ self.pyramid
                dynamics[:, lay.moment(i)] = -jacobian[3:, :6].T @ rotation
                self._contact_rows(first, i)
                # eq. 8: the stance sole does not accelerate (ours: its velocity damped)
                a = np.zeros((6, n))
                a[:, lay.qdd] = jacobian
                first.equal(
                    a, -terms.drift[frame] - CONTACT_DAMPING * self._velocities[frame], name="eq8"
                )
            else:  # in the air: no force
                first.equal(lambda i=i: self._air_rows(i), 0.0, name="air", key=("air", i))
        first.equal(dynamics, -terms.bias[:6] / weight, name="dynamics")
        # eq. 9: joint limits over the horizon T
        horizon = JOINT_LIMIT_HORIZON_S
        joints, rates = q[7:], v[6:]
        first.add(
            self._joint_rows,
            2 * (self.lower - joints - horizon * rates) / horizon**2,
            2 * (self.upper - joints - horizon * rates) / horizon**2,
            name="joint_limits",
            key="joints",
        )
        # eq. 15: the CoM acceleration is the preview's initial one
        a = np.zeros((2, n))
        a[:, lay.qdd] = terms.com_jacobian[:2]
        a[:, lay.cdd] = -np.eye(2)
        first.equal(a, -terms.com_drift[:2], name="com_coupling")
        # the footholds and eqs. 11, 12, 16, 20, 21
        self._use_preview(self.schedule.first_interval(t, self.period_s))
        supports = self.schedule.sample_supports(t, self.period_s, lay.samples)
        context = self._preview_rows(first, second, third, terms, phase, supports)
        # level 3: eqs. 18, 19 (and 17 when a hand target is set)
        base = self.base_frame
        rotation = terms.placement[base][1]
        reference = pin.Quaternion(*self.base_orientation_reference).toRotationMatrix()
        error = pin.log3(reference @ rotation.T)
        omega = terms.jacobian[base][3:] @ v
        a = np.zeros((3, n))
        a[:, lay.qdd] = terms.jacobian[base][3:]
        third.equal(
            a, TORSO_KP * error - TORSO_KD * omega - terms.drift[base][3:], TORSO_WEIGHT, "torso"
        )
        third.equal(
            self._joint_rows,
            POSTURE_KP * (self.nominal - joints) - POSTURE_KD * rates,
            POSTURE_WEIGHT,
            "posture",
            key="joints",
        )
        if self.hand_target is not None:
            hand = self.hand_frame
            position = terms.placement[hand][0]
            velocity = terms.jacobian[hand][:3] @ v
            error = self.hand_target - position
            norm = np.linalg.norm(error)
            if norm > HAND_ERROR_MAX:
                error *= HAND_ERROR_MAX / norm
            a = np.zeros((3, n))
            a[:, lay.qdd] = terms.jacobian[hand][:3]
            third.equal(
                a, HAND_KP * error - HAND_KD * velocity - terms.drift[hand][:3], HAND_WEIGHT, "hand"
            )
        # ours: the CoM height held (the point-mass model's constant c_z, Sec. III-A)
        a = np.zeros((1, n))
        a[0, lay.qdd] = terms.com_jacobian[2]
        height_error = self.ground + self.height - terms.com_position[2]
        third.equal(
            a,
            HEIGHT_KP * height_error - HEIGHT_KD * terms.com_velocity[2] - terms.com_drift[2],
            HEIGHT_WEIGHT,
            "com_height",
        )
        self.row_names = (first.names, second.names, third.names)
        levels = [
            first.level("constraints"),
            second.level("capturability"),
            third.level("objectives"),
        ]
        return levels, context

    def _contact_rows(self, rows: _Rows, foot: int) -> None:
        """Eqs. 5-7 for a foot in contact, in units of m g: lambda >= 0, |mu_z| <= gamma f_z,
        the CoP (-mu_y / f_z, mu_x / f_z) inside the sole's half extents."""
        lay, n = self.layout, self.layout.size
        normal = self.pyramid[2]  # f_z per unit lambda

        def lambdas() -> np.ndarray:
            a = np.zeros((4, n))
            a[:, lay.force(foot)] = np.eye(4)
            return a

        rows.add(lambdas, 0.0, np.inf, name="lambda", key=("lambda", foot))

        def load() -> np.ndarray:
            a = np.zeros((1, n))
            a[0, lay.force(foot)] = normal
            return a

        # ours: every foot in contact carries a minimum load (an unloaded sole drifts away)
        rows.add(load, MIN_NORMAL_FORCE, np.inf, name="min_force", key=("min_force", foot))

        def sole() -> np.ndarray:
            half_x, half_y = self.cop_extents
            moment = lay.moment(foot).start
            a = np.zeros((6, n))
            for r, (index, sign, bound) in enumerate(
                [
                    (2, 1, self.gamma),
                    (2, -1, self.gamma),
                    (1, -1, half_x),
                    (1, 1, half_x),
                    (0, 1, half_y),
                    (0, -1, half_y),
                ]
            ):
                a[r, moment + index] = sign
                a[r, lay.force(foot)] = -bound * normal
            return a

        rows.add(sole, -np.inf, 0.0, name="cop_sole", key=("cop_sole", foot))

    def _air_rows(self, foot: int) -> np.ndarray:
        """A foot in the air: its lambda and moment rows (= 0)."""
        lay = self.layout
        a = np.zeros((7, lay.size))
        a[:4, lay.force(foot)] = np.eye(4)
        a[4:, lay.moment(foot)] = np.eye(3)
        return a

    def _joint_rows(self) -> np.ndarray:
        """The joints' accelerations q''_j (eqs. 9 and 19)."""
        lay = self.layout
        a = np.zeros((lay.nv - 6, lay.size))
        a[:, 6 : lay.nv] = np.eye(lay.nv - 6)
        return a

    def _step_rows(self, j: int) -> np.ndarray:
        """The j-th footstep displacement d_j (eq. 12)."""
        a = np.zeros((2, self.layout.size))
        a[:, self.layout.step(j)] = np.eye(2)
        return a

    def _preview_rows(self, first, second, third, terms, phase, supports):
        """Eqs. 11, 12, 14, 16, 20, 21, 22 and the velocity objective; returns the footholds
        (index 0: now) as (known part (2,), footstep count) for the plan."""
        lay = self.layout
        pre = self.preview
        c0, dc0 = terms.com_position[:2], terms.com_velocity[:2]
        walking = self.schedule.walking and phase.step >= 0
        starting = self.schedule.starting(self._t)
        # the current support (index 0): its centre and CoP box; the anchor the footsteps
        # are chained from (p_1 = anchor + d_1, p_j = p_{j-1} + d_j)
        if not walking:
            low, high = self._both_feet_box()
            current = (low + high) / 2
            box = (low - current, high - current)
            feet_next = []
            anchor = current
            if starting:  # the double support before a walk's first step
                first_swing = self.schedule.swing_of(0)
                anchor = self.foothold[other_foot(first_swing)]
                feet_next = [first_swing, other_foot(first_swing)][: lay.steps]
        else:
            current = anchor = self.foothold[phase.stance]
            box = (-self.cop_extents, self.cop_extents)
            # the feet of the next K footsteps: the swing foot (or the other one in double
            # support), then alternating
            next_foot = phase.swing if phase.swing is not None else other_foot(phase.stance)
            feet_next = [next_foot, other_foot(next_foot)][: lay.steps]
        foot_box = (-self.cop_extents, self.cop_extents)

        def box_about(point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            """The both-feet box as bounds about `point`."""
            return box[0] + current - point, box[1] + current - point

        # eq. 12: the rectangles (bounds on the displacements); standing: no footstep
        length = STEP_LENGTH_MAX_M * self.scale
        w_low = self.standing_width + STEP_WIDTH_EXTRA_M[0] * self.scale
        w_high = self.standing_width + STEP_WIDTH_EXTRA_M[1] * self.scale
        for j in range(1, lay.steps + 1):
            a = functools.partial(self._step_rows, j)
            if j == 1 and self._step_kept(phase):
                continue  # `_swing_rows` holds it where it was (inside its rectangle)
            if j <= len(feet_next):
                side = 1.0 if feet_next[j - 1] == FEET[0] else -1.0
                y_range = sorted((side * w_low, side * w_high))
                first.add(
                    a,
                    [-length, y_range[0]],
                    [length, y_range[1]],
                    name="footstep_box",
                    key=("step", j),
                )
            else:
                first.equal(a, 0.0, name="no_footstep", key=("step", j))
        # per preview sample: its foothold index (the K-th after K landings), the centre of
        # its CoP box (eq. 11) and centring target (eq. 21), and the box about that centre
        footholds = np.minimum(supports[: lay.samples], lay.steps)
        centres = np.empty((lay.samples, 2))
        lows, highs = np.empty((lay.samples, 2)), np.empty((lay.samples, 2))
        for k in range(lay.samples):
            centre, bounds = (current, box) if footholds[k] == 0 else (anchor, foot_box)
            if starting and footholds[k] == 0:  # before the first step: the weight shift
                sample = self._t + pre.first_s + k * self.period_s
                lift_off = sample >= self.schedule.walk_start - 1e-9
                centre, bounds = weight_shift_support(anchor, foot_box, box_about(anchor), lift_off)
            centres[k] = centre
            lows[k], highs[k] = bounds[0] + centre, bounds[1] + centre
        # the samples after a walk's end stand on both feet (`_standing_after_walk`)
        coefficients = (footholds[:, None] >= np.arange(1, lay.steps + 1)).astype(float)
        after = np.zeros(lay.samples, dtype=bool)
        if walking or starting:
            after = self.schedule.samples_after_walk(self._t, self.period_s, lay.samples)
        pairs = self._standing_after_walk(
            after, footholds, coefficients, centres, lows, highs, anchor, phase, feet_next
        )
        for axis in range(2):
            # eq. 11 now too: the preview's CoP z_0 = c_0 - c''_0 / omega^2 in the current
            # support (else the point mass could lean on a CoP that only angular momentum of
            # the whole body would realise)
            # (ours; in a double support between steps on both feet, so that the CoP can move
            # onto the landed foot during it)
            now_low, now_high = (box[0] + current, box[1] + current)
            if walking and phase.swing is None:
                now_low, now_high = self._both_feet_box()
            first.add(
                functools.partial(self._cop_now_row, axis),
                now_low[axis] - c0[axis],
                now_high[axis] - c0[axis],
                name="cop_now",
                key=("cop_now", axis),
            )
            # eqs. 11 and 21 for the samples, one row each (scaled row by row, as separate
            # blocks would be): z_k - p_j(k), p_j = anchor + sum_{i <= j} d_i
            a = functools.partial(self._cop_preview_rows, axis, coefficients)
            key = ("cop_preview", axis, coefficients.tobytes())
            first.add(a, lows[:, axis], highs[:, axis], name="cop_preview", rowwise=True, key=key)
            third.equal(a, centres[:, axis], COP_WEIGHT, "cop", rowwise=True, key=key)
            if pairs is not None:  # eq. 11 on both feet after the walk: z_k - p_j, j = L-1, L
                rows, pair_coefficients, pair_lows, pair_highs = pairs
                first.add(
                    functools.partial(self._cop_preview_rows, axis, pair_coefficients, rows),
                    pair_lows[:, axis],
                    pair_highs[:, axis],
                    name="cop_after_walk",
                    rowwise=True,
                    key=("cop_after_walk", axis, rows.tobytes(), pair_coefficients.tobytes()),
                )
            # eq. 14 at level 2
            row_known = self.capture_row[0]
            second.equal(
                functools.partial(self._capture_row, axis),
                -row_known @ np.array([c0[axis], dc0[axis]]),
                name="capture",
                key=("capture", axis, self._grid),
            )
            # eq. 22: CoP velocity
            third.equal(
                functools.partial(self._cop_velocity_rows, axis),
                -pre.d_known @ np.array([c0[axis], dc0[axis]]),
                COP_VELOCITY_WEIGHT,
                "cop_velocity",
                key=("cop_velocity", axis, self._grid),
            )
            # velocity objective (ours, after [3]): the previewed CoM velocity
            if self.velocity_reference is not None:
                target = self.velocity_reference[axis] if walking else 0.0
                third.equal(
                    functools.partial(self._com_velocity_rows, axis),
                    target - pre.s_known[:, 1, :] @ np.array([c0[axis], dc0[axis]]),
                    VELOCITY_WEIGHT,
                    "com_velocity",
                    rowwise=True,
                    key=("com_velocity", axis, self._grid),
                )
        # eq. 16 (and 20): the swing foot
        if phase.swing is not None:
            self._swing_rows(first, third, terms, phase, anchor)
        return anchor

    def _cop_now_row(self, axis: int) -> np.ndarray:
        """The preview's CoP now, z_0 - c_0 = -c''_0 / omega^2, along `axis` (eq. 11)."""
        a = np.zeros(self.layout.size)
        a[self.layout.cdd.start + axis] = -1.0 / self.omega**2
        return a

    def _cop_preview_rows(
        self, axis: int, coefficients: np.ndarray, samples: np.ndarray | None = None
    ) -> np.ndarray:
        """z_k - sum_i w_i d_i along `axis` for the samples k (eqs. 11 and 21): with w_i = 1
        for i <= j(k) the CoP less the foothold p_j = anchor + sum_{i <= j} d_i; `coefficients`
        the w (one row per row, K columns), `samples` the k of each row (None: every sample,
        in order)."""
        lay = self.layout
        samples = np.arange(lay.samples) if samples is None else samples
        a = np.zeros((len(samples), lay.size))
        a[np.arange(len(samples)), lay.cop(axis).start + samples] = 1.0
        for i in range(1, lay.steps + 1):
            a[:, lay.step(i).start + axis] = -coefficients[:, i - 1]
        return a

    def _standing_after_walk(
        self, after, footholds, coefficients, centres, lows, highs, anchor, phase, feet_next
    ):
        """Ours: the preview samples after the walk's end (`after`) stand on both feet, as the
        robot will, instead of on the last foothold alone (until 2026-12-04; the paper's robot
        never stops). A sample on the footholds L-1 and L (L = j(k), index 0 the current one):
        eq. 21 centres its CoP on their midpoint (w_L = 1/2 in `coefficients`, changed in
        place) and eq. 11 bounds it by both soles, for feet side by side: along x within each
        sole's extent, along y between the right sole's outer edge and the left's (the rows
        returned). The x rows are the linear part of the soles' hull that holds for any
        stagger (the hull itself is bilinear in the footsteps): they cap the last step's
        stagger at the CoP box's length, 2 (a - margin) (0.20 m on the humanoid, 0.18 m on
        JVRC-1; measured binding in `walk`, docs/sherikov.md). At L = 0 (the last double
        support) the feet are known: the both-feet box and its middle, in `centres`, `lows`,
        `highs` (changed in place). Returns (samples, coefficients, lows, highs) of the two
        rows per sample at L >= 1, or None."""
        lay = self.layout
        if not after.any():
            return None
        low_both, high_both = self._both_feet_box()
        rows, pair_coefficients, pair_lows, pair_highs = [], [], [], []
        stance = phase.stance if phase.stance is not None else other_foot(feet_next[0])
        half_x, half_y = self.cop_extents
        for k in np.flatnonzero(after):
            last = int(footholds[k])
            if last == 0:
                centres[k] = (low_both + high_both) / 2
                lows[k], highs[k] = low_both, high_both
                continue
            coefficients[k, last - 1] = 0.5
            lows[k], highs[k] = -np.inf, np.inf  # its bounds are the two rows below
            centres[k] = anchor
            for j in (last - 1, last):
                foot = stance if j == 0 else feet_next[j - 1]
                left = foot == FEET[0]
                rows.append(k)
                pair_coefficients.append(np.arange(1, lay.steps + 1) <= j)
                pair_lows.append(anchor + np.array([-half_x, -np.inf if left else -half_y]))
                pair_highs.append(anchor + np.array([half_x, half_y if left else np.inf]))
        if not rows:
            return None
        return (
            np.array(rows),
            np.array(pair_coefficients, dtype=float),
            np.array(pair_lows),
            np.array(pair_highs),
        )

    def _capture_row(self, axis: int) -> np.ndarray:
        """Eq. 14's capture-point velocity along `axis`, in c''_0 and the CoPs."""
        _, row_acc, row_cop = self.capture_row
        a = np.zeros(self.layout.size)
        a[self.layout.cdd.start + axis] = row_acc
        a[self.layout.cop(axis)] = row_cop
        return a

    def _cop_velocity_rows(self, axis: int) -> np.ndarray:
        """Eq. 22's CoP velocities along `axis`, in c''_0 and the CoPs."""
        lay, pre = self.layout, self.preview
        a = np.zeros((lay.samples, lay.size))
        a[:, lay.cdd.start + axis] = pre.d_acc
        a[:, lay.cop(axis)] = pre.d_cop
        return a

    def _com_velocity_rows(self, axis: int) -> np.ndarray:
        """The previewed CoM velocities along `axis` (the velocity objective), in c''_0 and
        the CoPs."""
        lay, pre = self.layout, self.preview
        a = np.zeros((lay.samples, lay.size))
        a[:, lay.cdd.start + axis] = pre.s_acc[:, 1]
        a[:, lay.cop(axis)] = pre.s_cop[:, 1, :]
        return a

    def _step_kept(self, phase) -> bool:
        """The next footstep is held where the last period put it (the last
        `ADAPTATION_BLOCK_S` of a swing). Its rectangle (eq. 12) is then left out: the held
        value lies on it whenever the step was pressed against it, and the two rows together
        are degenerate (measured: DAQP's exitflag 3 and every cascade QP solver failing)."""
        return (
            phase.swing is not None
            and phase.remaining_s < ADAPTATION_BLOCK_S
            and self.last_step is not None
        )

    def _swing_rows(self, first, third, terms, phase, current) -> None:
        """Eq. 16: the swing sole's acceleration from cubics through the next footstep
        (horizontal) and to the apex, then the ground (vertical, ours), with its orientation
        held flat; eq. 20: the horizontal jerk. The cubics' remaining time is floored at
        `SWING_TIME_FLOOR_S`: their rows grow as 1 / t_f^2 (and t_f^3), and the paper's own
        remedy for "violent position changes near the end of a step" is to penalise jerk or
        block the adaptation near the ground."""
        lay, n = self.layout, self.layout.size
        frame = self.foot_frames[FEET.index(phase.swing)]
        jacobian = terms.jacobian[frame]
        position, rotation = terms.placement[frame]
        linear = jacobian[:3]
        v_now = self._velocities[frame]
        rows = swing_cubic(phase.remaining_s, floor_s=SWING_TIME_FLOOR_S)
        jerk_rows = swing_cubic(phase.remaining_s, floor_s=JERK_TIME_FLOOR_S)
        if self._step_kept(phase):
            # the paper's "straightforward workaround": no footstep change near the ground
            first.equal(
                functools.partial(self._step_rows, 1),
                self.last_step,
                name="footstep_kept",
                key=("step", 1),
            )
        a = np.zeros((2, n))
        a[:, lay.qdd] = linear[:2]
        a[:, lay.step(1)] = -rows.acc_p * np.eye(2)
        rhs = rows.acc_p * current + rows.acc_s0 * position[:2] + rows.acc_ds0 * v_now[:2]
        first.equal(a, rhs - terms.drift[frame][:2], name="swing_xy")
        # eq. 20: the swing jerk, linear in the footstep
        a = np.zeros((2, n))
        a[:, lay.step(1)] = jerk_rows.jerk_p * np.eye(2)
        third.equal(
            a,
            -(
                jerk_rows.jerk_p * current
                + jerk_rows.jerk_s0 * position[:2]
                + jerk_rows.jerk_ds0 * v_now[:2]
            ),
            JERK_WEIGHT,
            "swing_jerk",
        )
        # the vertical profile (ours): to the apex by mid-swing, then down to the ground
        single = self.schedule.single_s
        elapsed = single - phase.remaining_s
        if elapsed < single / 2:
            target, remaining = self.ground + self.swing_height, single / 2 - elapsed
        else:
            target, remaining = self.ground, phase.remaining_s
        vertical = swing_cubic(remaining, floor_s=SWING_TIME_FLOOR_S)
        z_acc = (
            vertical.acc_p * target + vertical.acc_s0 * position[2] + vertical.acc_ds0 * v_now[2]
        )
        a = np.zeros((1, n))
        a[0, lay.qdd] = linear[2]
        first.equal(a, z_acc - terms.drift[frame][2], name="swing_z")
        # constant (flat) orientation, held with a PD against drift (ours)
        error = pin.log3(rotation.T)  # log(R_ref R^T) with R_ref = I (the standing sole)
        a = np.zeros((3, n))
        a[:, lay.qdd] = jacobian[3:]
        first.equal(
            a,
            SWING_ORIENTATION_KP * error
            - SWING_ORIENTATION_KD * v_now[3:]
            - terms.drift[frame][3:],
            name="swing_rotation",
        )

    # ------------------------------------------------------------------ the plan
    def _plan(self, t, x, terms, phase, anchor, timings, iterations) -> CentroidalPlan:
        lay = self.layout
        weight = self.weight
        n_limbs = len(self.limb_names)
        wrenches = np.zeros((n_limbs, 6))
        contacts = []
        for i, foot in enumerate(FEET):
            limb = self.limb_names.index(foot)
            if foot != phase.swing:
                contacts.append(foot)
                wrenches[limb, :3] = weight * self.pyramid @ x[lay.force(i)]
                wrenches[limb, 3:] = weight * x[lay.moment(i)]
        cdd = x[lay.cdd]
        com = terms.com_position
        zmp = np.array([*(com[:2] - cdd / self.omega**2), self.ground])
        # footsteps: P_j = current + sum d_i
        footsteps = []
        limb_position = np.array([terms.placement[f][0] for f in self.limb_frames])
        limb_orientation = np.tile([1.0, 0.0, 0.0, 0.0], (n_limbs, 1))
        starting = self.schedule.starting(t)
        if (self.schedule.walking and phase.step >= 0) or starting:
            if starting:
                foot = self.schedule.swing_of(0)
                touchdown = self.schedule.walk_start + self.schedule.single_s
            else:
                foot = phase.swing if phase.swing is not None else other_foot(phase.stance)
                touchdown = phase.touchdown_s
                if touchdown is None:
                    touchdown = t + phase.remaining_s + self.schedule.single_s
            point = np.array(anchor, dtype=float)
            for j in range(1, lay.steps + 1):
                point = point + x[lay.step(j)]
                footsteps.append(
                    Footstep(
                        foot,
                        np.array([point[0], point[1], self.ground]),
                        0.0,
                        touchdown - self.schedule.single_s,
                        touchdown,
                        np.array([1.0, 0.0, 0.0, 0.0]),
                    )
                )
                if j == 1 and phase.swing is not None:
                    limb_position[self.limb_names.index(foot)] = footsteps[-1].position_world
                foot = other_foot(foot)
                touchdown += self.schedule.period_s
        # the resultant w-bar, gravity apart as every planner's (`CentroidalPlan`): the contact
        # forces' sum less the weight; its moment is left at zero (for the record only)
        wrench = np.zeros(6)
        wrench[:3] = wrenches[:, :3].sum(axis=0) - [0.0, 0.0, self.weight]
        return CentroidalPlan(
            com_reference_world=com.copy(),
            com_planned_world=com.copy(),
            com_velocity_planned_world=terms.com_velocity.copy(),
            com_acceleration_planned_world=np.array([cdd[0], cdd[1], 0.0]),
            base_orientation_planned_world=self.base_orientation_reference,
            base_angular_velocity_planned_world=np.zeros(3),
            wrench_planned_world=wrench,
            wrench_projected_world=wrench,
            zmp_planned_world=zmp,
            contact_limbs=tuple(contacts),
            limb_target_position_world=limb_position,
            limb_target_orientation_world=limb_orientation,
            timings_ns=timings,
            solver_iterations=iterations,
            footsteps=tuple(footsteps),
            generalized_acceleration=x[lay.qdd].copy(),
            contact_wrench_limb=wrenches,
            solver_failures=self.solver_failures,
        )


register(
    PlannerSpec(
        "capturability_hierarchy",
        CapturabilityHierarchyPlanner,
        "Sherikov et al. 2014: whole-body inverse dynamics with K-step capturability (3 levels)",
        pairs_with=("passthrough",),
        can=FLAT_GROUND,  # not turning: eqs. 11-12's boxes and the swing sole in world axes
    )
)
