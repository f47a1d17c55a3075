"""Sweep specs: a grid over controllers, simulators, scenarios, pushes, seeds and robot
variations, read from TOML (or CLI flags) and expanded to episodes.

A spec (every field but `controllers` and `sims` optional)::

    name = "main"
    controllers = ["preview_control+centroidal_feedback", "hold+posture"]   # or ["all", ...]
    sims = ["mujoco", "pybullet"]                                           # or ["all"]
    scenarios = ["walk"]        # episodes without a push, one per grid point
    speeds = [0.1, 0.2]         # forward speeds [m/s] of walk / walk_push (default: their own)
    seeds = [0]
    robots = ["centrobench_humanoid"]   # `robots.robot_registry` names, or ["all"]
    scales = [1.0]              # robot length scale (mass with its cube): scalable robots only
    frictions = [0.6]           # Coulomb coefficient of every contact
    estimator = "ground_truth"  # for every controller (default: each one's own, else
                                # kinematic_inertial, which reaches a controller that has its
    estimator_for_every_controller = false  # own only with this set to true)
    traces = ["walk"]           # scenarios whose per-period traces are stored
    timeout_base_s = 60.0       # wall-clock budget of an episode [s]: base + per_sim_s x its
    timeout_per_sim_s = 10.0    # simulated duration; past it the episode ends as "timeout"

    [push]                      # the push-survival protocol (`bench.push_protocol`)
    phases = ["standing"]       # "standing", "walking" (mid single support)
    dv = [0.2, 0.3, 0.4]        # velocity change J / m [m/s] per level
    count = 20                  # pushes per level, directions uniform on the circle
    seed = 0                    # seed of the directions (the same for every controller)
    replicas = 1                # trials of every push (robust threshold: 4 of 5)
    swing_fractions = [0.5]     # walking pushes: where in the single support
    directions = ["random"]     # walking pushes: and/or inward, outward, forward, backward

    [robustness]                # one dimension at a time around the nominal episode
    noise = [1, 2]              # (`bench.robustness`: noise, delay, payload_kg, com_offset_m,
    delay = [1]                 #  mass_error, torque_scale, gain_scale, ground_height_m,
                                #  slope_deg, ...)

A job of several protocols (the main job: `bench/specs/main.toml`) lists them as
`[[protocols]]` tables, each a sweep's fields with its own `name`; a protocol's fields default
to the job's top-level ones, the timeouts are the job's. The job runs its protocols one after
the other (the progress bar names the one running); an episode two protocols share runs once::

    name = "main"
    controllers = ["all"]
    sims = ["all"]

    [[protocols]]
    name = "standing_pushes"
    push = { phases = ["standing"], dv = [0.3, 0.4], count = 20 }

    [[protocols]]
    name = "walks"
    scenarios = ["walk"]

Validation happens before anything runs: a wrong spec raises `SpecError`, one message naming
the field and what it accepts. The numeric ranges (seeds, scales, frictions, durations, push
levels and counts, the number of episodes) and the rule for `name` are in `bench.limits`.
"""

from __future__ import annotations

import functools
import hashlib
import itertools
import json
import tomllib
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

from bench.controllers import CONTROLLERS, ControllerSpec, controller_spec, refusal
from bench.limits import (
    CONTROL_PERIOD_S,
    FRICTION_MAX,
    MAX_EPISODE_SECONDS,
    MAX_EPISODES,
    MAX_WALK_SPEED,
    NAME_RULE,
    SCALE_RANGE,
    SEED_LIMIT,
    TIMEOUT_BASE_MAX_S,
    TIMEOUT_PER_SIM_MAX,
    valid_name,
)
from bench.push_protocol import (
    PHASES,
    PUSH_DURATION,
    PushProtocol,
    push_episodes,
    walking_push_direction_deg,
    walking_push_time,
)
from bench.robustness import parse_robustness, robustness_to_dict
from bench.runner import EpisodeSpec
from bench.scenarios import SCENARIOS, WALKS_WITH_SPEED
from estimators.base import DEFAULT_ESTIMATOR, ESTIMATORS
from robots.perturbation import LATER_PERTURBATION_FIELDS, NOMINAL, Perturbation
from robots.robot_registry import DEFAULT_ROBOT, ROBOTS
from sims.base import SIMULATORS
from wholebody.base import DEFAULT_WHOLE_BODY


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
    refused: str | None = None  # why the controller cannot run the scenario: an "n/a" row
    protocol: str | None = None  # the `[[protocols]]` entry it came from (not in its id)

    def labels(self) -> dict[str, Any]:
        push_time = self.run.push_time
        if push_time is None and self.run.push_step is not None:  # a walking push: its start
            push_time = walking_push_time(
                self.run.scale, self.run.push_step, self.run.robot, self.run.push_swing_fraction
            )
        return {
            "episode_id": self.episode_id,
            "controller": self.controller,
            "push_phase": self.push_phase,
            "push_dv_mps": self.push_dv_mps,
            "push_index": self.push_index,
            "push_time_s": push_time,
            "push_step": self.run.push_step,
            "push_impulse_Ns": self.run.push_impulse,
            "push_direction_deg": self.run.push_direction_deg
            if self.run.push_direction_name is None
            else walking_push_direction_deg(
                self.run.scale, self.run.push_step, self.run.robot, self.run.push_direction_name
            ),
            "push_swing_fraction": (
                None
                if self.run.push_step is None
                else 0.5
                if self.run.push_swing_fraction is None
                else self.run.push_swing_fraction
            ),
            "push_direction_name": self.run.push_direction_name,
        }


@dataclass(frozen=True)
class SweepSpec:
    controllers: tuple[str, ...]
    sims: tuple[str, ...]
    name: str = "sweep"
    scenarios: tuple[str, ...] = ()
    seeds: tuple[int, ...] = (0,)
    robots: tuple[str, ...] = (DEFAULT_ROBOT,)
    scales: tuple[float, ...] = (1.0,)
    frictions: tuple[float, ...] = (0.6,)
    estimator: str = DEFAULT_ESTIMATOR
    # True: `estimator` runs every controller, also one that comes with its own
    # (`ControllerSpec.estimator`); False: such a controller keeps its own while `estimator`
    # is the default. Only the default estimator needs it: any other is given to every one.
    estimator_for_every_controller: bool = False
    traces: tuple[str, ...] = ("walk",)
    push: PushProtocol | None = None
    duration: float | None = None  # [s] override for the plain scenarios
    speeds: tuple[float, ...] = ()  # [m/s] forward speeds of walk / walk_push; (): their own
    # wall-clock budget of an episode [s]: timeout_base_s + timeout_per_sim_s x simulated s.
    # How a sweep runs, not what it measures: left out of the digest (a resume may change it).
    timeout_base_s: float = 60.0
    timeout_per_sim_s: float = 10.0
    # robustness dimensions (`bench.robustness`): None is the nominal episode
    perturbations: tuple[Perturbation | None, ...] = (None,)
    # a job of several protocols (`[[protocols]]`): each a complete sweep of its own, the
    # fields above its defaults; the job's episodes are theirs, in order, each once
    protocols: tuple[SweepSpec, ...] = ()
    extra: dict = field(default_factory=dict, compare=False, repr=False)

    def to_dict(self) -> dict[str, Any]:
        data = asdict(self)
        data.pop("extra")
        data.pop("protocols")
        if self.protocols:  # each protocol's fields whole (they win over the job's on reading)
            data["protocols"] = [_protocol_table(protocol) for protocol in self.protocols]
        if self.push is not None:  # the protocol's later fields at their defaults: as before
            for name, default in (
                ("replicas", 1),
                ("swing_fractions", (0.5,)),
                ("directions", ("random",)),
            ):
                if getattr(self.push, name) == default:
                    data["push"].pop(name)
        perturbations = data.pop("perturbations")  # recorded as the spec field it came from
        if self.perturbations != (None,):  # (left out when nominal: as before robustness)
            data["robustness"] = robustness_to_dict(self.perturbations)
        del perturbations
        if self.push is None:
            data.pop("push")
        if not self.speeds:  # as before speeds existed: earlier digests stay valid
            data.pop("speeds")
        if self.robots == (DEFAULT_ROBOT,):  # as before robots existed
            data.pop("robots")
        if not self.estimator_for_every_controller:  # as before the field existed
            data.pop("estimator_for_every_controller")
        return data

    def identity(self) -> dict[str, Any]:
        """The fields that decide the episodes and their results (`to_dict` without the
        execution settings `EXECUTION_FIELDS`)."""
        data = self.to_dict()
        for name in EXECUTION_FIELDS:
            data.pop(name)
        return data

    def digest(self) -> str:
        return hashlib.sha1(json.dumps(self.identity(), sort_keys=True).encode()).hexdigest()[:12]

    def size(self) -> int:
        """The number of episodes of the grid, from its axes, without listing them (a job's:
        the sum of its protocols', counting an episode they share more than once)."""
        if self.protocols:
            return sum(protocol.size() for protocol in self.protocols)
        plain = sum(len(self.speeds_of(scenario)) for scenario in self.scenarios)
        per_point = plain + (self.push.episodes_per_grid_point() if self.push else 0)
        return (
            len(self.controllers)
            * len(self.sims)
            * len(self.perturbations)
            * len(self.robots)
            * len(self.scales)
            * len(self.frictions)
            * len(self.seeds)
            * per_point
        )

    def speeds_of(self, scenario: str) -> tuple[float | None, ...]:
        """The forward speeds [m/s] a plain scenario runs at (None: its own)."""
        return self.speeds if self.speeds and scenario in WALKS_WITH_SPEED else (None,)

    def wall_budget_s(self, simulated_s: float) -> float:
        """Wall-clock budget [s] of an episode of `simulated_s` simulated seconds."""
        return self.timeout_base_s + self.timeout_per_sim_s * simulated_s

    def estimator_of(self, controller: ControllerSpec) -> str:
        """The spec's estimator, unless it is the default, not given to every controller
        (`estimator_for_every_controller`), and the controller comes with its own
        (`ControllerSpec.estimator`)."""
        if (
            self.estimator == DEFAULT_ESTIMATOR
            and not self.estimator_for_every_controller
            and controller.estimator is not None
        ):
            return controller.estimator
        return self.estimator

    def episodes(self) -> list[Episode]:
        """Every episode of the grid, in a fixed order, each with a stable id; for a job of
        protocols, those of each protocol in order (labelled with its name), an episode that
        two protocols share once, under the first, with its trace kept if either keeps it."""
        if self.protocols:
            first: dict[str, Episode] = {}
            for protocol in self.protocols:
                for episode in protocol.episodes():
                    kept = first.get(episode.episode_id)
                    if kept is None:
                        first[episode.episode_id] = replace(episode, protocol=protocol.name)
                    elif episode.keep_trace and not kept.keep_trace:
                        first[episode.episode_id] = replace(kept, keep_trace=True)
            return list(first.values())
        result = []
        for controller in self.controllers:
            pair = controller_spec(controller)
            for sim in self.sims:
                for perturbation, robot, scale, friction, seed in itertools.product(
                    self.perturbations, self.robots, self.scales, self.frictions, self.seeds
                ):
                    common = dict(
                        planner=pair.planner,
                        stabilizer=pair.stabilizer,
                        whole_body=pair.whole_body,
                        sim=sim,
                        seed=seed,
                        estimator=self.estimator_of(pair),
                        scale=scale,
                        friction=friction,
                        robot=robot,
                        perturbation=perturbation,
                    )
                    for scenario in self.scenarios:
                        for speed in self.speeds_of(scenario):
                            run = EpisodeSpec(
                                scenario=scenario, duration=self.duration, speed=speed, **common
                            )
                            keep = scenario in self.traces
                            result.append(_episode(controller, run, keep_trace=keep))
                    if self.push is not None:
                        for labels, run in push_episodes(self.push, common):
                            keep = run.scenario in self.traces
                            result.append(_episode(controller, run, keep_trace=keep, **labels))
        return result


def _protocol_table(protocol: SweepSpec) -> dict[str, Any]:
    """A job's protocol as a table that reads back to it: every field it has, also those that
    `to_dict` leaves out at their defaults (robots, speeds, robustness), which the job's
    top-level fields would otherwise fill in; not the timeouts, which are the job's."""
    table = {k: v for k, v in protocol.to_dict().items() if k not in EXECUTION_FIELDS}
    table.setdefault("robots", list(protocol.robots))
    table.setdefault("speeds", list(protocol.speeds))
    table.setdefault("robustness", robustness_to_dict(protocol.perturbations))
    return table


# EpisodeSpec fields added after results were first published, with their defaults: left out
# of an episode's id while at the default, so that earlier result directories keep their ids
# (a resume of them runs nothing twice)
LATER_FIELDS = {
    "whole_body": DEFAULT_WHOLE_BODY,
    "speed": None,
    "steps": None,
    "robot": DEFAULT_ROBOT,
    "replica": 0,
    "perturbation": None,
    "push_swing_fraction": None,
    "push_direction_name": None,
}


def _episode(controller: str, run: EpisodeSpec, keep_trace: bool, **labels) -> Episode:
    fields = {k: v for k, v in asdict(run).items() if k not in LATER_FIELDS or v != LATER_FIELDS[k]}
    if run.perturbation is not None:  # its later fields too, while at their defaults
        fields["perturbation"] = {
            k: v
            for k, v in fields["perturbation"].items()
            if k not in LATER_PERTURBATION_FIELDS or v != getattr(NOMINAL, k)
        }
    key = json.dumps({"controller": controller, **fields, **labels}, sort_keys=True)
    episode_id = hashlib.sha1(key.encode()).hexdigest()[:16]
    refused = _refusal(controller, run.scenario, run.estimator)
    return Episode(episode_id, controller, run, keep_trace=keep_trace, refused=refused, **labels)


@functools.cache
def _refusal(controller: str, scenario: str, estimator: str) -> str | None:
    return refusal(controller_spec(controller), scenario, estimator)


# ---------------------------------------------------------------- parsing and validation

_TOP_FIELDS = {
    "name": f"a string of {NAME_RULE}",
    "controllers": "a list of controller names",
    "sims": "a list of simulator names",
    "scenarios": "a list of scenario names",
    "seeds": f"a list of integers in [0, {SEED_LIMIT - 1}]",
    "robots": "a list of robot names",
    "scales": f"a list of length scales in [{SCALE_RANGE[0]:g}, {SCALE_RANGE[1]:g}]",
    "frictions": f"a list of friction coefficients in (0, {FRICTION_MAX:g}]",
    "estimator": "an estimator name",
    "estimator_for_every_controller": "true or false (true: `estimator` also runs the "
    "controllers that come with their own)",
    "traces": "a list of scenario names",
    "duration": f"a number of seconds in [{CONTROL_PERIOD_S:g}, {MAX_EPISODE_SECONDS:g}]",
    "push": "a table (see bench.push_protocol)",
    "speeds": f"a list of forward speeds in [-{MAX_WALK_SPEED:g}, {MAX_WALK_SPEED:g}] m/s "
    f"(of {', '.join(WALKS_WITH_SPEED)})",
    "timeout_base_s": "a positive number of seconds (wall-clock budget of every episode)",
    "timeout_per_sim_s": "a positive number (wall-clock seconds per simulated second)",
    "robustness": "a table of robustness dimensions (see bench.robustness)",
    "protocols": "a list of tables ([[protocols]]), each a sweep's fields with a 'name'",
}
# fields that say how a sweep runs, not what it measures (not part of its digest)
EXECUTION_FIELDS = ("timeout_base_s", "timeout_per_sim_s")


def load_spec(path: str | Path) -> SweepSpec:
    """Read and validate a TOML sweep spec."""
    return spec_from_mapping(read_spec_file(path))


MAX_SPEC_BYTES = 1_000_000  # a spec is a few lines; a larger file is something else


def read_spec_file(path: str | Path) -> dict[str, Any]:
    """The fields of the TOML sweep spec file `path`, not yet validated. SpecError, one line
    naming the file, when it is missing, no regular file, too large, not UTF-8 or not TOML."""
    try:
        path = Path(path)
        if not path.exists():
            raise SpecError(f"sweep spec {path} does not exist")
        if path.is_dir():
            raise SpecError(f"sweep spec {path} is a directory; give a TOML file")
        if not path.is_file():
            raise SpecError(f"sweep spec {path} is not a regular file; give a TOML file")
        if path.stat().st_size > MAX_SPEC_BYTES:
            raise SpecError(
                f"sweep spec {path} has {path.stat().st_size} bytes, more than a spec's "
                f"{MAX_SPEC_BYTES}; give a TOML sweep spec"
            )
        raw = path.read_bytes()
    except SpecError:
        raise
    except OSError as exc:
        raise SpecError(f"sweep spec {path} cannot be read: {exc.strerror or exc}") from None
    except ValueError as exc:  # e.g. a NUL character in the path
        raise SpecError(f"sweep spec path {str(path)!r} is not valid: {exc}") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SpecError(
            f"sweep spec {path} is not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset "
            f"{exc.start}); give a TOML file"
        ) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        message = " ".join(str(exc).split())
        raise SpecError(f"sweep spec {path} is not valid TOML: {message}") from None


def spec_from_mapping(data: dict[str, Any]) -> SweepSpec:
    """Validate a spec given as a mapping (parsed TOML, or built from CLI flags): one sweep,
    or a job of several protocols (`[[protocols]]`: `_job_from_mapping`)."""
    if isinstance(data, dict) and "protocols" in data:
        return _job_from_mapping(data)
    return _sweep_from_mapping(data)


MAX_PROTOCOLS = 100


def _job_from_mapping(data: dict[str, Any]) -> SweepSpec:
    """A job of protocols: every `[[protocols]]` table is a sweep spec whose fields default to
    the job's top-level ones (a protocol's own win); each needs a distinct `name` (what the
    progress bar shows while it runs); the timeouts are set once, at the top. The job's
    top-level fields need not give episodes of their own."""
    protocols = data["protocols"]
    if (
        not isinstance(protocols, list)
        or not protocols
        or not all(isinstance(p, dict) for p in protocols)
    ):
        raise SpecError(f"sweep spec field 'protocols' must be {_TOP_FIELDS['protocols']}")
    if len(protocols) > MAX_PROTOCOLS:
        raise SpecError(
            f"sweep spec field 'protocols' has {len(protocols)} tables, more than "
            f"{MAX_PROTOCOLS}; split the job"
        )
    top = {k: v for k, v in data.items() if k != "protocols"}
    job = _sweep_from_mapping(top, episodes_required=False)
    parts: list[SweepSpec] = []
    for k, table in enumerate(protocols):
        here = f"protocols[{k}]"
        shared = sorted(set(table) & {"protocols", *EXECUTION_FIELDS})
        if shared:
            raise SpecError(
                f"sweep spec field '{here}.{shared[0]}': set it once, for the whole job, at the top"
            )
        if "name" not in table:
            raise SpecError(
                f"sweep spec field '{here}' needs a 'name' ({NAME_RULE}: shown while it runs)"
            )
        try:
            part = _sweep_from_mapping({**top, **table})
        except SpecError as exc:
            raise SpecError(f"protocol {table['name']!r} ({here}): {exc}") from None
        if part.name in [p.name for p in parts] or part.name == job.name:
            raise SpecError(
                f"sweep spec field '{here}.name': {part.name!r} names the job or another "
                "protocol; give each its own"
            )
        parts.append(part)
    total = sum(part.size() for part in parts)
    if total > MAX_EPISODES:
        raise SpecError(
            f"sweep spec: its protocols have {total} episodes, more than the {MAX_EPISODES} a "
            "sweep may have; split it into several sweeps"
        )
    return replace(job, protocols=tuple(parts))


def _sweep_from_mapping(data: dict[str, Any], episodes_required: bool = True) -> SweepSpec:
    """One sweep's spec (no protocols); with `episodes_required` False, a job's top-level
    fields, which may give no episodes."""
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
    seeds = tuple(
        _integer(f"seeds[{k}]", v, 0, SEED_LIMIT - 1)
        for k, v in enumerate(_list("seeds", data, [0]))
    )
    robots = _names("robots", data.get("robots", [DEFAULT_ROBOT]), sorted(ROBOTS))
    if not robots:
        raise SpecError("sweep spec field 'robots' must not be empty")
    scales = tuple(
        _in_range(f"scales[{k}]", v, *SCALE_RANGE)
        for k, v in enumerate(_list("scales", data, [1.0]))
    )
    for robot in robots:
        if not ROBOTS[robot].scalable and scales != (1.0,):
            raise SpecError(
                f"sweep spec field 'scales': robot {robot!r} has one size, so a sweep with it "
                f"takes scales = [1.0], got {list(scales)}"
            )
    frictions = tuple(
        _in_range(f"frictions[{k}]", v, 0.0, FRICTION_MAX, strict=True)
        for k, v in enumerate(_list("frictions", data, [0.6]))
    )
    for label, values in (("seeds", seeds), ("scales", scales), ("frictions", frictions)):
        if not values:
            raise SpecError(f"sweep spec field {label!r} must not be empty")
        if len(set(values)) != len(values):  # the same episodes twice, under one id
            raise SpecError(f"sweep spec field {label!r} names a value twice: {list(values)}")
    estimator = data.get("estimator", DEFAULT_ESTIMATOR)
    if not isinstance(estimator, str) or estimator not in ESTIMATORS.names():
        raise SpecError(
            f"sweep spec field 'estimator': unknown {estimator!r}; valid: "
            + ", ".join(ESTIMATORS.names())
        )
    for_every = data.get("estimator_for_every_controller", False)
    if not isinstance(for_every, bool):
        raise SpecError(
            "sweep spec field 'estimator_for_every_controller' must be "
            f"{_TOP_FIELDS['estimator_for_every_controller']}, got {for_every!r}"
        )
    name = data.get("name", "sweep")
    if not isinstance(name, str) or not valid_name(name):
        raise SpecError(f"sweep spec field 'name' must be {NAME_RULE}, got {name!r}")
    duration = data.get("duration")
    if duration is not None:
        duration = _in_range("duration", duration, CONTROL_PERIOD_S, MAX_EPISODE_SECONDS, unit="s")
    timeouts = {
        label: _in_range(label, data[label], 0.0, maximum, strict=True, unit=unit)
        for label, maximum, unit in (
            ("timeout_base_s", TIMEOUT_BASE_MAX_S, "s"),
            ("timeout_per_sim_s", TIMEOUT_PER_SIM_MAX, "s per simulated s"),
        )
        if label in data
    }
    push = None
    if "push" in data:
        if not isinstance(data["push"], dict):
            raise SpecError("sweep spec field 'push' must be a table")
        try:
            push = PushProtocol.from_mapping(data["push"])
        except ValueError as exc:
            raise SpecError(f"sweep spec field 'push.{exc}") from None
    perturbations: tuple[Perturbation | None, ...] = (None,)
    if "robustness" in data:
        if not isinstance(data["robustness"], dict):
            raise SpecError("sweep spec field 'robustness' must be a table (see bench.robustness)")
        try:
            perturbations = parse_robustness(data["robustness"])
        except ValueError as exc:
            raise SpecError(f"sweep spec field 'robustness.{exc}") from None
    if not scenarios and push is None and episodes_required:
        raise SpecError(
            "sweep spec: no episodes; give 'scenarios' (one of: "
            f"{', '.join(SCENARIOS)}) or a 'push' table (phases: {', '.join(PHASES)})"
        )
    speeds = tuple(
        _in_range(f"speeds[{k}]", v, -MAX_WALK_SPEED, MAX_WALK_SPEED, unit="m/s")
        for k, v in enumerate(_list("speeds", data, []))
    )
    if len(set(speeds)) != len(speeds):
        raise SpecError(f"sweep spec field 'speeds' names a speed twice: {list(speeds)}")
    if speeds and not set(scenarios) & set(WALKS_WITH_SPEED) and episodes_required:
        raise SpecError(
            "sweep spec field 'speeds' applies to the scenarios "
            f"{', '.join(WALKS_WITH_SPEED)}, and 'scenarios' has none of them"
        )
    if push is not None and "walking" in push.phases:
        _check_walking_push(push, scales, robots)
    spec = SweepSpec(
        controllers=controllers,
        sims=sims,
        name=name,
        scenarios=scenarios,
        seeds=seeds,
        robots=robots,
        scales=scales,
        frictions=frictions,
        estimator=estimator,
        estimator_for_every_controller=for_every,
        traces=traces,
        push=push,
        duration=duration,
        speeds=speeds,
        perturbations=perturbations,
        **timeouts,
    )
    total = spec.size()
    if total > MAX_EPISODES:
        raise SpecError(
            f"sweep spec: {total} episodes (controllers x sims x robustness x robots x scales x "
            "frictions x seeds x "
            f"(scenarios + push phases x dv x count x replicas)), more than the {MAX_EPISODES} "
            "a sweep may have; split it into several sweeps"
        )
    return spec


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
    if allow_all and "all" in value:  # "all" and more: the registered ones, then the others
        value = [name for entry in value for name in (valid if entry == "all" else [entry])]
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


def _integer(label: str, value: Any, minimum: int, maximum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not minimum <= value <= maximum:
        raise SpecError(
            f"sweep spec field {label!r} must be an integer in [{minimum}, {maximum}], "
            f"got {value!r}"
        )
    return value


def _in_range(
    label: str, value: Any, minimum: float, maximum: float, strict: bool = False, unit: str = ""
) -> float:
    """A finite number in [minimum, maximum] ((minimum, maximum] when `strict`); comparisons
    only, so that nan, inf and integers too large for a float are refused, not raised on."""
    number = isinstance(value, int | float) and not isinstance(value, bool)
    if not (
        number
        and (value > minimum if strict else value >= minimum)
        and value <= maximum  # False for nan
    ):
        raise SpecError(
            f"sweep spec field {label!r} must be a number in {'(' if strict else '['}"
            f"{minimum:g}, {maximum:g}]{' ' + unit if unit else ''}, got {value!r}"
        )
    return float(value)


def _check_walking_push(
    push: PushProtocol, scales: tuple[float, ...], robots: tuple[str, ...] = (DEFAULT_ROBOT,)
) -> None:
    """A walking push's episode (the walk up to mid single support `walking_push_step`, the
    push, `survival_time`) must fit MAX_EPISODE_SECONDS at every scale (the walk's steps
    last longer on a larger robot)."""
    for robot, scale, fraction in itertools.product(robots, scales, push.swing_fractions):
        start = walking_push_time(
            scale, push.walking_push_step, robot, None if fraction == 0.5 else fraction
        )
        end = start + PUSH_DURATION + push.survival_time
        if end > MAX_EPISODE_SECONDS:
            raise SpecError(
                f"sweep spec field 'push.survival_time': a walking push at scale {scale:g} "
                f"starts at {end - PUSH_DURATION - push.survival_time:.2f} s, so its episode "
                f"would last {end:.1f} s, more than {MAX_EPISODE_SECONDS:g} s; got "
                f"survival_time {push.survival_time:g}"
            )
