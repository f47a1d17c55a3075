"""A registry of named components (planners, stabilizers): filled when their modules are
imported, and answering an unknown name with the list of known ones (DESIGN.md, registries)."""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

# What a controller's parts can do (`ComponentSpec.can`) and what a scenario asks for
# (`bench.scenarios.ScenarioSpec.requires`); `needs` names what a part needs of the robot.
CAPABILITIES = {
    "flat_ground": "standing and walking with the feet on flat ground",
    "multi_contact": "contacts of any limb on any surface (hands on walls, rails, rungs)",
    "turning": "walking paths that turn (footholds and soles yawed along the path)",
}
NEEDS = {"force_torque_sensors": "6-axis force/torque sensors at the feet and hands"}
# What of a `RobotState` beyond the base, joints, CoM, wrenches and ZMP an estimator gives
# (`ComponentSpec.gives`) and a stabilizer reads (`ComponentSpec.needs_state`)
STATE = {
    "inertia_tilt": "the tilt of the inertia's principal axes and its acceleration "
    "(RobotState.inertia_tilt, Ficht & Behnke eqs. 12-15)"
}
FLAT_GROUND = frozenset({"flat_ground"})  # what a scenario asks for by default
WALKING = frozenset({"flat_ground", "turning"})  # what a component can by default
MULTI_CONTACT = WALKING | {"multi_contact"}


@dataclass(frozen=True)
class ComponentSpec:
    """A registered component: `factory(dt)` builds one for control period dt [s];
    `pairs_with` names the only counterparts it makes sense with (empty: any); `can` what it
    can do (`CAPABILITIES`), `needs` what it needs of the robot (`NEEDS`); an estimator's
    `gives` what of `STATE` it gives, a stabilizer's `needs_state` what of it it reads."""

    name: str
    factory: Callable[[float], Any]
    description: str
    pairs_with: tuple[str, ...] = ()
    can: frozenset[str] = WALKING
    needs: frozenset[str] = frozenset()
    gives: frozenset[str] = frozenset()
    needs_state: frozenset[str] = frozenset()


class Registry:
    """Named `ComponentSpec`s of one kind. `modules` are imported on first lookup, which
    registers the built-in components."""

    def __init__(self, kind: str, modules: tuple[str, ...]) -> None:
        self.kind = kind
        self.modules = modules
        self.specs: dict[str, ComponentSpec] = {}
        self._loaded = False

    def register(self, spec: ComponentSpec) -> ComponentSpec:
        if spec.name in self.specs:
            raise ValueError(f"{self.kind} {spec.name!r} registered twice")
        self.specs[spec.name] = spec
        return spec

    def _load(self) -> None:
        if not self._loaded:
            self._loaded = True
            for module in self.modules:
                importlib.import_module(module)

    def names(self) -> list[str]:
        self._load()
        return sorted(self.specs)

    def get(self, name: str) -> ComponentSpec:
        """The spec `name`; unknown names raise KeyError listing the known ones."""
        self._load()
        if name not in self.specs:
            known = ", ".join(sorted(self.specs))
            raise KeyError(f"unknown {self.kind} {name!r}; choose one of: {known}")
        return self.specs[name]
