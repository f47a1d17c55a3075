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

from planners.base import PLANNERS, planner_spec
from robots.registry import CAPABILITIES
from stabilizers.base import STABILIZERS, stabilizer_spec
from wholebody.base import DEFAULT_WHOLE_BODY, WHOLE_BODY_LAYERS


@dataclass(frozen=True)
class ControllerSpec:
    planner: str
    stabilizer: str
    description: str = ""
    whole_body: str = DEFAULT_WHOLE_BODY

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
    def name(self) -> str:
        pair = f"{self.planner}+{self.stabilizer}"
        return pair if self.whole_body == DEFAULT_WHOLE_BODY else f"{pair}+{self.whole_body}"


CONTROLLERS: dict[str, ControllerSpec] = {
    spec.name: spec
    for spec in (
        ControllerSpec("hold", "posture", "baseline: constant CoM above the support, posture PD"),
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


def controller_spec(name: str) -> ControllerSpec:
    """The registered controller `name`, or any "<planner>+<stabilizer>[+<whole-body
    layer>]" of registered parts. KeyError naming the valid choices otherwise."""
    if name in CONTROLLERS:
        return CONTROLLERS[name]
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
        f"unknown controller {name!r}; choose one of: {', '.join(CONTROLLERS)} "
        f"(or any <planner>+<stabilizer>[+<whole-body layer>] with planners "
        f"{', '.join(PLANNERS.names())}, stabilizers {', '.join(STABILIZERS.names())} and "
        f"whole-body layers {', '.join(WHOLE_BODY_LAYERS.names())})"
    )


def refusal(controller: ControllerSpec, scenario: str) -> str | None:
    """Why `controller` cannot run `scenario` (one line), or None if it can: the scenario asks
    for something neither its planner nor its stabilizer declares (`ScenarioSpec.requires`
    against `ControllerSpec.can`)."""
    from bench.scenarios import SCENARIOS

    missing = sorted(SCENARIOS[scenario].requires - controller.can)
    if not missing:
        return None
    return (
        f"{controller.name} cannot do {', '.join(missing)} "
        f"({'; '.join(CAPABILITIES[m] for m in missing)}), which {scenario} needs"
    )
