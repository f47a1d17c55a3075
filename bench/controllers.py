"""The controller registry: a controller is a (planner, stabilizer, whole-body layer) triple
with a name (DESIGN.md, interfaces). Sweeps, the main job and the report iterate over
`CONTROLLERS`.

A triple is named "<planner>+<stabilizer>" when its whole-body layer is the default (`ik`:
joint positions from the IK, what Murooka et al.'s robot does), else
"<planner>+<stabilizer>+<whole-body layer>". The registered triples
are the ones the papers compare; any other combination of registered parts can still be named
the same way in a sweep spec (`controller_spec` builds it on the fly).
"""

from __future__ import annotations

from dataclasses import dataclass

from estimators import DEFAULT_ESTIMATOR
from planners.base import PLANNERS, planner_spec
from robots.registry import CAPABILITIES, STATE
from stabilizers.base import STABILIZERS, stabilizer_spec
from wholebody.base import DEFAULT_WHOLE_BODY, WHOLE_BODY_LAYERS


@dataclass(frozen=True)
class ControllerSpec:
    planner: str
    stabilizer: str
    description: str = ""
    whole_body: str = DEFAULT_WHOLE_BODY
    alias: str | None = None
    """A name of its own (a method whose parts only make sense together); None: the parts'."""
    estimator: str | None = None
    """The estimator the method comes with (None: `estimators.DEFAULT_ESTIMATOR`), used
    wherever an episode or a sweep does not name another."""

    @property
    def can(self) -> frozenset[str]:
        """What the controller can do (`robots.registry.CAPABILITIES`): what both its planner
        and its stabilizer can."""
        return planner_spec(self.planner).can & stabilizer_spec(self.stabilizer).can

    @property
    def needs(self) -> frozenset[str]:
        """What it needs of the robot (`robots.registry.NEEDS`): what either part needs."""
        return planner_spec(self.planner).needs | stabilizer_spec(self.stabilizer).needs

    @property
    def needs_state(self) -> frozenset[str]:
        """What it reads of the estimator's state beyond what every estimator gives
        (`robots.registry.STATE`): what either part reads."""
        return planner_spec(self.planner).needs_state | stabilizer_spec(self.stabilizer).needs_state

    @property
    def episode_estimator(self) -> str:
        """The estimator its episodes run with unless told otherwise."""
        return self.estimator or DEFAULT_ESTIMATOR

    @property
    def name(self) -> str:
        if self.alias is not None:
            return self.alias
        pair = f"{self.planner}+{self.stabilizer}"
        return pair if self.whole_body == DEFAULT_WHOLE_BODY else f"{pair}+{self.whole_body}"


CONTROLLERS: dict[str, ControllerSpec] = {
    spec.name: spec
    for spec in (
        ControllerSpec("hold", "posture", "baseline: CoM settling above the support, posture PD"),
        ControllerSpec(
            "preview_control",
            "centroidal_feedback",
            "Murooka et al. 2022: 6-DoF centroidal preview control and stabilization",
        ),
        ControllerSpec(
            "preview_control",
            "centroidal_feedback",
            "Murooka et al. 2022 with IK feed-forward torques g(q) - J_c^T w^d (our variant)",
            "ik_feedforward",
        ),
        ControllerSpec(
            "preview_zmp", "dcm", "ZMP preview control (Kajita) with DCM feedback (Appendix)"
        ),
        ControllerSpec(
            "linear_mpc",
            "centroidal_feedback",
            "Audren et al. 2014 constrained linear MPC with Murooka's stabilization (Sec. V-E)",
        ),
    )
}

DIRECT_CENTROIDAL = "Ficht & Behnke 2021: direct centroidal control with a five-mass model"
DIRECT_CENTROIDAL_ROWS = (
    # Table 1's rows in the paper's order: (row, planner, stabilizer, whole-body layer); each
    # adds a component to the row before, the last drops the inertia controller again
    ("open_loop", "five_mass_gait_fixed", "direct_centroidal_open_loop", "five_mass_pose_bent"),
    ("straight_leg", "five_mass_gait_fixed", "direct_centroidal_open_loop", "five_mass_pose"),
    ("closed_loop", "five_mass_gait_fixed", "direct_centroidal_integrator", "five_mass_pose"),
    ("leaky", "five_mass_gait_fixed", "direct_centroidal_leaky", "five_mass_pose"),
    ("extended", "five_mass_gait_fixed", "direct_centroidal_no_inertia", "five_mass_pose"),
    ("inertia", "five_mass_gait_fixed", "direct_centroidal", "five_mass_pose"),
    ("step_timing", "five_mass_gait_timing", "direct_centroidal", "five_mass_pose"),
    ("step_size", "five_mass_gait", "direct_centroidal", "five_mass_pose"),
    ("no_inertia", "five_mass_gait", "direct_centroidal_no_inertia", "five_mass_pose"),
    # ours, not a row of the paper: without the straight-support-leg constraint as well, which
    # survives more walking pushes on our robot (docs/ficht-behnke.md)
    ("bent_no_inertia", "five_mass_gait", "direct_centroidal_no_inertia", "five_mass_pose_bent"),
    # ours: the same with the free limbs' gravity torques, part of the model feed-forward of the
    # authors' platform software (`wholebody.five_mass_pose.FreeLimbGravity`)
    (
        "bent_no_inertia_feedforward",
        "five_mass_gait",
        "direct_centroidal_no_inertia",
        "five_mass_pose_bent_feedforward",
    ),
    # ours: every component, the inertia controller's set tilt through a first-order lag, with
    # which it stands (`stabilizers.direct_centroidal.tilt_lag_time_constant`)
    ("lagged_inertia", "five_mass_gait", "direct_centroidal_lagged_inertia", "five_mass_pose"),
    # ours: the same with the set tilt bounded (`stabilizers.direct_centroidal.TILT_LIMIT_RAD`),
    # with which it walks
    ("bounded_inertia", "five_mass_gait", "direct_centroidal_bounded_inertia", "five_mass_pose"),
    # ours: the two rows without inertia control at CoM gains nearer omega, inside Choi's
    # condition (`stabilizers.direct_centroidal.choi_gains`; measured, not the default)
    (
        "no_inertia_near_omega",
        "five_mass_gait",
        "direct_centroidal_no_inertia_near_omega",
        "five_mass_pose",
    ),
    (
        "bent_no_inertia_near_omega",
        "five_mass_gait",
        "direct_centroidal_no_inertia_near_omega",
        "five_mass_pose_bent",
    ),
)
OURS = {
    "bent_no_inertia": "ours: bent knees, no inertia control",
    "bent_no_inertia_feedforward": "ours: bent knees, no inertia control, the free limbs' "
    "gravity feed-forward",
    "lagged_inertia": "ours: every component, the inertia controller's set tilt through a "
    "first-order lag",
    "bounded_inertia": "ours: every component, the inertia controller's set tilt through a "
    "first-order lag and within 0.02 rad",
    "no_inertia_near_omega": "ours: every component but inertia control, K_com = 1.5 omega "
    "and K_zmp = 0.8 omega",
    "bent_no_inertia_near_omega": "ours: bent knees, no inertia control, K_com = 1.5 omega "
    "and K_zmp = 0.8 omega",
}
"""The rows of `DIRECT_CENTROIDAL_ROWS` that are not the paper's, and how they differ."""
OURS_CONTROLLERS = frozenset(f"direct_centroidal/{row}" for row in OURS)
"""The registered controllers that are our variants of a paper's method, not a row of it: the
report tags them "(ours)" (`reports.build.label_ours`)."""


def _direct_centroidal(row: str, planner: str, stabilizer: str, layer: str) -> ControllerSpec:
    """Table 1's `row` as a controller: "step_size" (every component) is `direct_centroidal`,
    the others `direct_centroidal/<row>`; all with their own estimator (IMU and encoders)."""
    return ControllerSpec(
        planner,
        stabilizer,
        f"{DIRECT_CENTROIDAL} ("
        + (OURS[row] if row in OURS else "Table 1: " + row.replace("_", " "))
        + ")",
        layer,
        alias="direct_centroidal" if row == "step_size" else f"direct_centroidal/{row}",
        estimator="five_mass_kalman",
    )


ABLATIONS: dict[str, ControllerSpec] = {
    spec.name: spec for spec in (_direct_centroidal(*row) for row in DIRECT_CENTROIDAL_ROWS)
}
"""Controllers named like any controller but not in `CONTROLLERS`, so that a sweep of "all"
and the main job leave them out: the ablations that take a method apart (Ficht & Behnke's
Table 1; the Table 1 protocol runs them) and methods not yet in the main job."""
ABLATIONS["capturability_hierarchy"] = ControllerSpec(
    "capturability_hierarchy",
    "passthrough",
    "Sherikov et al. 2014: whole-body inverse dynamics with K-step capturability, automatic "
    "footsteps (3-level hierarchy, torque control)",
    "inverse_dynamics",
    alias="capturability_hierarchy",
    estimator="ground_truth",  # the paper: "perfect model and perfect inertial measurement"
)
"""Named and runnable, but out of "all": the main job names it where its budget holds it (the
reaching tests and the standing pushes, issue 22); about 2.1 ms of planner per 2 ms period in
`reach` (2026-11-29, docs/sherikov.md)."""
CONTROLLERS["direct_centroidal"] = ABLATIONS["direct_centroidal"]
CONTROLLERS["direct_centroidal/no_inertia"] = ABLATIONS["direct_centroidal/no_inertia"]


def controller_spec(name: str) -> ControllerSpec:
    """The registered controller `name`, or any "<planner>+<stabilizer>[+<whole-body
    layer>]" of registered parts. KeyError naming the valid choices otherwise."""
    if name in CONTROLLERS:
        return CONTROLLERS[name]
    if name in ABLATIONS:
        return ABLATIONS[name]
    parts = name.split("+")
    if len(parts) == 2:
        parts.append(DEFAULT_WHOLE_BODY)
    if (
        len(parts) == 3
        and parts[0] in PLANNERS.names()
        and parts[1] in STABILIZERS.names()
        and parts[2] in WHOLE_BODY_LAYERS.names()
    ):
        for spec in CONTROLLERS.values():  # a registered triple named with its layer
            if (spec.planner, spec.stabilizer, spec.whole_body) == tuple(parts):
                return spec
        return ControllerSpec(parts[0], parts[1], "unregistered combination", parts[2])
    raise KeyError(
        f"unknown controller {name!r}; choose one of: {', '.join(CONTROLLERS)}, "
        f"{', '.join(n for n in ABLATIONS if n not in CONTROLLERS)} "
        f"(or any <planner>+<stabilizer>[+<whole-body layer>] with planners "
        f"{', '.join(PLANNERS.names())}, stabilizers {', '.join(STABILIZERS.names())} and "
        f"whole-body layers {', '.join(WHOLE_BODY_LAYERS.names())})"
    )


def refusal(controller: ControllerSpec, scenario: str, estimator: str | None = None) -> str | None:
    """Why `controller` cannot run `scenario` with `estimator` (one line), or None if it can:
    the scenario asks for something neither its planner nor its stabilizer declares
    (`ScenarioSpec.requires` against `ControllerSpec.can`), or the controller reads a state the
    estimator does not give (`ControllerSpec.needs_state` against the estimator's `gives`;
    None: the estimator is not checked)."""
    from bench.scenarios import SCENARIOS

    missing = sorted(SCENARIOS[scenario].requires - controller.can)
    if missing:
        return (
            f"{controller.name} cannot do {', '.join(missing)} "
            f"({'; '.join(CAPABILITIES[m] for m in missing)}), which {scenario} needs"
        )
    return estimator_refusal(controller, estimator) if estimator is not None else None


def estimator_refusal(controller: ControllerSpec, estimator: str) -> str | None:
    """Why `controller` cannot run with `estimator` (one line, naming the estimators that
    would do), or None if it can."""
    from estimators.base import ESTIMATORS

    missing = sorted(controller.needs_state - ESTIMATORS.get(estimator).gives)
    if not missing:
        return None
    givers = [n for n in ESTIMATORS.names() if set(missing) <= ESTIMATORS.get(n).gives]
    return (
        f"{controller.name} cannot run with the estimator {estimator}: it reads "
        f"{', '.join(missing)} ({'; '.join(STATE[m] for m in missing)}), which only "
        f"{', '.join(givers) or 'no registered estimator'} give"
    )
