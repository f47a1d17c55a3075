"""Sweep specs: a grid over controllers, simulators, scenarios, pushes, seeds and robot
variations, read from TOML (or CLI flags) and expanded to episodes.

A spec (every field but `controllers` and `sims` optional)::

    name = "main"
    controllers = ["preview_control+centroidal_feedback", "hold+posture"]   # or ["all"]
    sims = ["mujoco", "pybullet"]                                           # or ["all"]
    scenarios = ["walk"]        # episodes without a push, one per grid point
    seeds = [0]
    scales = [1.0]              # robot length scale (mass with its cube)
    frictions = [0.6]           # Coulomb coefficient of every contact
    estimator = "ground_truth"
    traces = ["walk"]           # scenarios whose per-period traces are stored

    [push]                      # the push-survival protocol (`bench.push_protocol`)
    phases = ["standing"]       # "standing", "walking" (mid single support)
    dv = [0.2, 0.3, 0.4]        # velocity change J / m [m/s] per level
    count = 20                  # pushes per level, directions uniform on the circle
    seed = 0                    # seed of the directions (the same for every controller)

Validation happens before anything runs: a wrong spec raises `SpecError`, one message naming
the field and what it accepts.
"""

from __future__ import annotations

import hashlib
import json
import tomllib
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from bench.controllers import CONTROLLERS, controller_spec
from bench.push_protocol import PHASES, PushProtocol, push_episodes, walking_push_time
from bench.runner import EpisodeSpec
from bench.scenarios import SCENARIOS
from robots.estimators import ESTIMATORS
from sims.base import SIMULATORS


class SpecError(ValueError):
    """A malformed sweep spec; the message names the field and the valid values."""


@dataclass(frozen=True)
class Episode:
    """One episode of a sweep: what to run plus the sweep's labels for it."""

    episode_id: str
    controller: str
    run: EpisodeSpec
    push_phase: str | None = None
    push_dv_mps: float | None = None
    push_index: int | None = None
    keep_trace: bool = False

    def labels(self) -> dict[str, Any]:
        push_time = self.run.push_time
        if push_time is None and self.run.push_step is not None:  # a walking push: its start
            push_time = walking_push_time(self.run.scale, self.run.push_step)
        return {
            "episode_id": self.episode_id,
            "controller": self.controller,
            "push_phase": self.push_phase,
            "push_dv_mps": self.push_dv_mps,
            "push_index": self.push_index,
            "push_time_s": push_time,
            "push_step": self.run.push_step,
            "push_impulse_Ns": self.run.push_impulse,
            "push_direction_deg": self.run.push_direction_deg,
        }


@dataclass(frozen=True)
class SweepSpec:
    controllers: tuple[str, ...]
    sims: tuple[str, ...]
    name: str = "sweep"
    scenarios: tuple[str, ...] = ()
    seeds: tuple[int, ...] = (0,)
    scales: tuple[float, ...] = (1.0,)
    frictions: tuple[float, ...] = (0.6,)
    estimator: str = "ground_truth"
    traces: tuple[str, ...] = ("walk",)
    push: PushProtocol | None = None
    duration: float | None = None  # [s] override for the plain scenarios
    extra: dict = field(default_factory=dict, compare=False, repr=False)

    def to_dict(self) -> dict[str, Any]:
        data = asdict(self)
        data.pop("extra")
        if self.push is None:
            data.pop("push")
        return data

    def digest(self) -> str:
        return hashlib.sha1(json.dumps(self.to_dict(), sort_keys=True).encode()).hexdigest()[:12]

    def episodes(self) -> list[Episode]:
        """Every episode of the grid, in a fixed order, each with a stable id."""
        result = []
        for controller in self.controllers:
            pair = controller_spec(controller)
            for sim in self.sims:
                for scale in self.scales:
                    for friction in self.frictions:
                        for seed in self.seeds:
                            common = dict(
                                planner=pair.planner,
                                stabilizer=pair.stabilizer,
                                sim=sim,
                                seed=seed,
                                estimator=self.estimator,
                                scale=scale,
                                friction=friction,
                            )
                            for scenario in self.scenarios:
                                run = EpisodeSpec(
                                    scenario=scenario, duration=self.duration, **common
                                )
                                result.append(
                                    _episode(controller, run, keep_trace=scenario in self.traces)
                                )
                            if self.push is not None:
                                for labels, run in push_episodes(self.push, common):
                                    result.append(
                                        _episode(
                                            controller,
                                            run,
                                            keep_trace=run.scenario in self.traces,
                                            **labels,
                                        )
                                    )
        return result


def _episode(controller: str, run: EpisodeSpec, keep_trace: bool, **labels) -> Episode:
    key = json.dumps({"controller": controller, **asdict(run), **labels}, sort_keys=True)
    episode_id = hashlib.sha1(key.encode()).hexdigest()[:16]
    return Episode(episode_id, controller, run, keep_trace=keep_trace, **labels)


# ---------------------------------------------------------------- parsing and validation

_TOP_FIELDS = {
    "name": "a string",
    "controllers": "a list of controller names",
    "sims": "a list of simulator names",
    "scenarios": "a list of scenario names",
    "seeds": "a list of integers",
    "scales": "a list of positive numbers",
    "frictions": "a list of positive numbers",
    "estimator": "an estimator name",
    "traces": "a list of scenario names",
    "duration": "a positive number of seconds",
    "push": "a table (see bench.push_protocol)",
}


def load_spec(path: str | Path) -> SweepSpec:
    """Read and validate a TOML sweep spec."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text())
    except FileNotFoundError:
        raise SpecError(f"sweep spec {path} does not exist") from None
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"sweep spec {path} is not valid TOML: {exc}") from None
    return spec_from_mapping(data)


def spec_from_mapping(data: dict[str, Any]) -> SweepSpec:
    """Validate a spec given as a mapping (parsed TOML, or built from CLI flags)."""
    if not isinstance(data, dict):
        raise SpecError("a sweep spec must be a table of fields")
    unknown = sorted(set(data) - set(_TOP_FIELDS))
    if unknown:
        raise SpecError(
            f"sweep spec: unknown field {unknown[0]!r}; valid fields: {', '.join(_TOP_FIELDS)}"
        )
    for required, valid in (("controllers", list(CONTROLLERS)), ("sims", list(SIMULATORS))):
        if required not in data:
            raise SpecError(
                f"sweep spec: missing field {required!r} ({_TOP_FIELDS[required]}: "
                f"{', '.join(valid)} or all)"
            )
    controllers = _names(
        "controllers", data["controllers"], list(CONTROLLERS), check=_check_controller
    )
    sims = _names("sims", data["sims"], list(SIMULATORS))
    scenarios = _names("scenarios", data.get("scenarios", []), list(SCENARIOS), allow_all=False)
    traces = _names("traces", data.get("traces", ["walk"]), list(SCENARIOS), allow_all=False)
    seeds = tuple(_integer(f"seeds[{k}]", v) for k, v in enumerate(_list("seeds", data, [0])))
    scales = tuple(_positive(f"scales[{k}]", v) for k, v in enumerate(_list("scales", data, [1.0])))
    frictions = tuple(
        _positive(f"frictions[{k}]", v) for k, v in enumerate(_list("frictions", data, [0.6]))
    )
    for label, values in (("seeds", seeds), ("scales", scales), ("frictions", frictions)):
        if not values:
            raise SpecError(f"sweep spec field {label!r} must not be empty")
    estimator = data.get("estimator", "ground_truth")
    if estimator not in ESTIMATORS:
        raise SpecError(
            f"sweep spec field 'estimator': unknown {estimator!r}; valid: {', '.join(ESTIMATORS)}"
        )
    name = data.get("name", "sweep")
    if not isinstance(name, str):
        raise SpecError(f"sweep spec field 'name' must be a string, got {type(name).__name__}")
    duration = data.get("duration")
    if duration is not None:
        duration = _positive("duration", duration)
    push = None
    if "push" in data:
        if not isinstance(data["push"], dict):
            raise SpecError("sweep spec field 'push' must be a table")
        try:
            push = PushProtocol.from_mapping(data["push"])
        except ValueError as exc:
            raise SpecError(f"sweep spec field 'push.{exc}") from None
    if not scenarios and push is None:
        raise SpecError(
            "sweep spec: no episodes; give 'scenarios' (one of: "
            f"{', '.join(SCENARIOS)}) or a 'push' table (phases: {', '.join(PHASES)})"
        )
    return SweepSpec(
        controllers=controllers,
        sims=sims,
        name=name,
        scenarios=scenarios,
        seeds=seeds,
        scales=scales,
        frictions=frictions,
        estimator=estimator,
        traces=traces,
        push=push,
        duration=duration,
    )


def _check_controller(name: str) -> None:
    controller_spec(name)


def _list(label: str, data: dict, default: list) -> list:
    value = data.get(label, default)
    if not isinstance(value, list):
        raise SpecError(
            f"sweep spec field {label!r} must be {_TOP_FIELDS[label]}, got {type(value).__name__}"
        )
    return value


def _names(
    label: str, value: Any, valid: list[str], allow_all: bool = True, check=None
) -> tuple[str, ...]:
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise SpecError(
            f"sweep spec field {label!r} must be a list of names; valid: {', '.join(valid)}"
        )
    if allow_all and value == ["all"]:
        return tuple(valid)
    if label in ("controllers", "sims") and not value:
        raise SpecError(f"sweep spec field {label!r} is empty; valid: {', '.join(valid)}, all")
    for name in value:
        try:
            if check is not None:
                check(name)
            elif name not in valid:
                raise KeyError(name)
        except KeyError as exc:
            detail = exc.args[0] if check is not None else f"unknown {name!r}"
            raise SpecError(
                f"sweep spec field {label!r}: {detail}"
                + ("" if check is not None else f"; valid: {', '.join(valid)}")
            ) from None
    if len(set(value)) != len(value):
        raise SpecError(f"sweep spec field {label!r} names something twice: {value}")
    return tuple(value)


def _integer(label: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise SpecError(f"sweep spec field {label!r} must be an integer, got {value!r}")
    return value


def _positive(label: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
        raise SpecError(f"sweep spec field {label!r} must be a positive number, got {value!r}")
    if value != value or value == float("inf"):
        raise SpecError(f"sweep spec field {label!r} must be finite, got {value!r}")
    return float(value)
