"""The controller registry: a controller is a (planner, stabilizer) pair with a name
(DESIGN.md, interfaces). Sweeps, the main job and the report iterate over `CONTROLLERS`.

A pair is named "<planner>+<stabilizer>". The registered pairs are the ones the papers
compare; any other combination of a registered planner and a registered stabilizer can still
be named the same way in a sweep spec (`controller_spec` builds it on the fly).
"""

from __future__ import annotations

from dataclasses import dataclass

from planners.base import PLANNERS
from stabilizers.base import STABILIZERS


@dataclass(frozen=True)
class ControllerSpec:
    planner: str
    stabilizer: str
    description: str = ""

    @property
    def name(self) -> str:
        return f"{self.planner}+{self.stabilizer}"


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
    """The registered pair `name`, or any "<planner>+<stabilizer>" of registered halves.
    KeyError naming the valid choices otherwise."""
    if name in CONTROLLERS:
        return CONTROLLERS[name]
    planner, plus, stabilizer = name.partition("+")
    if plus and planner in PLANNERS.names() and stabilizer in STABILIZERS.names():
        return ControllerSpec(planner, stabilizer, "unregistered combination")
    raise KeyError(
        f"unknown controller {name!r}; choose one of: {', '.join(CONTROLLERS)} "
        f"(or any <planner>+<stabilizer> with planners {', '.join(PLANNERS.names())} and "
        f"stabilizers {', '.join(STABILIZERS.names())})"
    )
