"""The push-survival protocol after Ficht & Behnke, Table 2: for each impulse level, `count`
pushes (20) from directions drawn uniformly on the horizontal circle with a fixed seed,
applied at the torso's centre of mass (`RobotDescription.torso_link`, the link the arms branch
from: the humanoid's base, JVRC-1's chest) for 0.1 s, (a) while standing and (b) in the middle of a
single-support phase while walking; an episode survives when the robot has not fallen 3 s
after the push ends.

Levels are velocity changes dv = J / m [m/s], so that robots of different mass compare (the
paper's 1.2 ... 2.8 N s on its robot of about 6.6 kg are 0.18 ... 0.42 m/s); each episode
records the impulse J = m dv [N s] for the robot at hand (its nominal mass at the episode's
scale: under a payload or a mass error, the simulated robot of mass m_sim changes its velocity
by m / m_sim of dv). Every controller, simulator and level gets the same directions.

Standing pushes start at 1.5 s: every registered controller but Ficht & Behnke's, and our
`hold` + `posture` baseline in MuJoCo (about 1 mm/s), has settled by then in both simulators
(its ground-truth CoM speed below 1 mm/s over the last 0.1 s before the push;
`tests/bench/test_sweep_spec.py` asserts it, and names the measured exceptions). Walking
pushes come at a time of the `walk` scenario's fixed schedule (the middle of its
`walking_push_step`-th single support): a controller that chooses its own step times
(`direct_centroidal`) is pushed at the same time, in whatever phase of its own gait that is.
With IK joint targets only (the `ik` layer, the default since the paper's configuration became
the main job's entry) the servos sag under the load and the robot sways at 2-4 mm/s until about
1 s (measured, `preview_control` + `centroidal_feedback` in MuJoCo: 3.7 mm/s at 0.2 s, 0.55 at
1.0 s, 0.16 at 1.5 s); with feed-forward torques it had settled by 0.1 s, and pushes started at
0.2 s.
"""

from __future__ import annotations

import functools
from collections.abc import Iterator
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from bench.limits import MAX_EPISODE_SECONDS, MAX_PUSH_COUNT, MAX_PUSH_DV, SEED_LIMIT
from bench.scenarios import SUPPORT_DIRECTIONS, WALK_STEPS
from robots.robot_registry import DEFAULT_ROBOT, make_robot

PHASES = ("standing", "walking")
MAX_REPLICAS = 100
PUSH_DURATION = 0.1  # [s] Ficht & Behnke's pushes; our scenarios' default
_EPISODE = (
    f"standing_push_time + {PUSH_DURATION:g} s + survival_time at most {MAX_EPISODE_SECONDS:g} s"
)
_FIELDS = {
    "phases": "a list of: standing, walking",
    "dv": f"a list of positive velocity changes [m/s], at most {MAX_PUSH_DV:g}",
    "count": f"a positive integer (pushes per level), at most {MAX_PUSH_COUNT}",
    "seed": f"an integer in [0, {SEED_LIMIT - 1}] (seed of the push directions)",
    "survival_time": f"a positive number of seconds after the push ({_EPISODE})",
    "standing_push_time": f"a non-negative number of seconds, the push start ({_EPISODE})",
    "walking_push_step": f"an integer in [1, {WALK_STEPS}] (the walk's single-support phase "
    "pushed mid-way)",
    "replicas": f"a positive integer, at most {MAX_REPLICAS} (trials of every push, each but "
    "the first with a small seeded change of the initial state and the push time)",
    "swing_fractions": "a list of fractions in [0, 1] of the pushed single support at which "
    "walking pushes are centred (default [0.5], the middle)",
    "directions": "a list of: random (the `count` uniform directions), "
    + ", ".join(SUPPORT_DIRECTIONS)
    + " (walking pushes relative to the support foot, one push each)",
}


@dataclass(frozen=True)
class PushProtocol:
    dv: tuple[float, ...]
    phases: tuple[str, ...] = ("standing",)
    count: int = 20
    seed: int = 0
    survival_time: float = 3.0
    standing_push_time: float = 1.5
    walking_push_step: int = 3
    replicas: int = 1  # trials per push (`bench.runner.replica_changes`)
    swing_fractions: tuple[float, ...] = (0.5,)  # walking pushes: where in the single support
    directions: tuple[str, ...] = ("random",)  # walking pushes: random and/or support-relative

    @classmethod
    def from_mapping(cls, data: dict[str, Any]) -> PushProtocol:
        """Validated protocol; ValueError messages start with the field name (so that the
        caller can prefix "push.")."""
        unknown = sorted(set(data) - set(_FIELDS))
        if unknown:
            raise ValueError(f"{unknown[0]}' is unknown; valid fields: {', '.join(_FIELDS)}")
        if "dv" not in data:
            raise ValueError(f"dv' is missing ({_FIELDS['dv']})")
        dv = data["dv"]
        if not isinstance(dv, list) or not dv:
            raise ValueError(f"dv' must be {_FIELDS['dv']}, got {dv!r}")
        for value in dv:
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ValueError(f"dv' must be {_FIELDS['dv']}, got {value!r}")
            if not 0 < value <= MAX_PUSH_DV:  # False for nan, inf and huge integers too
                raise ValueError(f"dv' must be {_FIELDS['dv']}, got {value!r}")
        if len({float(value) for value in dv}) != len(dv):  # the same pushes twice, one id
            raise ValueError(f"dv' names a level twice: {dv!r}")
        phases = data.get("phases", ["standing"])
        if isinstance(phases, str):
            phases = [phases]
        if (
            not isinstance(phases, list)
            or not phases
            or not all(isinstance(phase, str) and phase in PHASES for phase in phases)
        ):
            raise ValueError(f"phases' must be {_FIELDS['phases']}, got {phases!r}")
        count = _integer("count", data.get("count", 20), 1, MAX_PUSH_COUNT)
        seed = _integer("seed", data.get("seed", 0), 0, SEED_LIMIT - 1)
        step = _integer("walking_push_step", data.get("walking_push_step", 3), 1, WALK_STEPS)
        replicas = _integer("replicas", data.get("replicas", 1), 1, MAX_REPLICAS)
        fractions = data.get("swing_fractions", [0.5])
        if (
            not isinstance(fractions, list)
            or not fractions
            or not all(
                isinstance(f, int | float) and not isinstance(f, bool) and 0.0 <= f <= 1.0
                for f in fractions
            )
        ):
            raise ValueError(
                f"swing_fractions' must be {_FIELDS['swing_fractions']}, got {fractions!r}"
            )
        directions = data.get("directions", ["random"])
        if (
            not isinstance(directions, list)
            or not directions
            or not all(d in ("random", *SUPPORT_DIRECTIONS) for d in directions)
        ):
            raise ValueError(f"directions' must be {_FIELDS['directions']}, got {directions!r}")
        for label, values in (
            ("phases", phases),
            ("swing_fractions", [float(f) for f in fractions]),
            ("directions", directions),
        ):
            if len(set(values)) != len(values):  # as for dv: the same pushes twice, one id
                raise ValueError(f"{label}' names a value twice: {values!r}")
        for label, value, default in (
            ("swing_fractions", fractions, [0.5]),
            ("directions", directions, ["random"]),
        ):
            if value != default and "walking" not in phases:
                raise ValueError(
                    f"{label}' applies to walking pushes and phases has none (got {phases!r})"
                )
        survival = _number("survival_time", data.get("survival_time", 3.0), strict=True)
        push_time = _number("standing_push_time", data.get("standing_push_time", 1.5))
        if push_time + PUSH_DURATION + survival > MAX_EPISODE_SECONDS:
            label = "survival_time" if "survival_time" in data else "standing_push_time"
            raise ValueError(
                f"{label}' makes the standing push episode {push_time + PUSH_DURATION + survival:g}"
                f" s long; the longest is {MAX_EPISODE_SECONDS:g} s ({_EPISODE}), got "
                f"standing_push_time {push_time:g}, survival_time {survival:g}"
            )
        return cls(
            dv=tuple(float(v) for v in dv),
            phases=tuple(phases),
            count=count,
            seed=seed,
            survival_time=survival,
            standing_push_time=push_time,
            walking_push_step=step,
            replicas=replicas,
            swing_fractions=tuple(float(f) for f in fractions),
            directions=tuple(directions),
        )

    def episodes_per_grid_point(self) -> int:
        """How many episodes `push_episodes` makes for one grid point."""
        standing = self.count if "standing" in self.phases else 0
        named = len([d for d in self.directions if d != "random"])
        random = self.count if "random" in self.directions else 0
        walking = len(self.swing_fractions) * (random + named) if "walking" in self.phases else 0
        return len(self.dv) * self.replicas * (standing + walking)

    def directions_deg(self) -> np.ndarray:
        """The `count` push directions [deg], uniform on [0, 360) from `seed`."""
        return np.random.default_rng(self.seed).uniform(0.0, 360.0, self.count)


def _integer(label: str, value: Any, minimum: int, maximum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not minimum <= value <= maximum:
        raise ValueError(f"{label}' must be {_FIELDS[label]}, got {value!r}")
    return value


def _number(label: str, value: Any, strict: bool = False) -> float:
    """A number of seconds in [0, MAX_EPISODE_SECONDS] ((0, ...] when `strict`); comparisons
    only, so that nan, inf and integers too large for a float are refused, not raised on."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ValueError(f"{label}' must be {_FIELDS[label]}, got {value!r}")
    if not ((value > 0 if strict else value >= 0) and value <= MAX_EPISODE_SECONDS):
        raise ValueError(f"{label}' must be {_FIELDS[label]}, got {value!r}")
    return float(value)


@functools.cache
def robot_mass(scale: float, robot: str = DEFAULT_ROBOT) -> float:
    """Total mass [kg] of `robot` (`robots.robot_registry`) at `scale`."""
    return float(make_robot(robot, scale).total_mass)


@functools.cache
def walking_push_time(
    scale: float, step: int, robot: str = DEFAULT_ROBOT, fraction: float | None = None
) -> float:
    """Start [s] of the push centred at `fraction` (None: 0.5, the middle) of the walk's
    single-support phase `step`."""
    from bench.scenarios import make_scenario
    from robots.model import RobotModel

    scenario = make_scenario(
        "walk_push",
        RobotModel(make_robot(robot, scale)),
        push_step=step,
        push_swing_fraction=fraction,
    )
    return float(scenario.pushes[0].time)


@functools.cache
def walking_push_direction_deg(
    scale: float, step: int, robot: str = DEFAULT_ROBOT, name: str = "inward"
) -> float:
    """World direction [deg] of the walking push `name` relative to the support foot of the
    walk's single-support phase `step` (`bench.scenarios.support_direction_deg`)."""
    from bench.scenarios import make_scenario
    from robots.model import RobotModel

    scenario = make_scenario(
        "walk_push", RobotModel(make_robot(robot, scale)), push_step=step, push_direction_name=name
    )
    x, y, _ = scenario.pushes[0].impulse_world
    return float(np.rad2deg(np.arctan2(y, x)) % 360.0)


def push_episodes(protocol: PushProtocol, common: dict[str, Any]) -> Iterator[tuple[dict, Any]]:
    """(labels, EpisodeSpec) for every phase x level x direction; `common` holds the
    EpisodeSpec fields shared by the grid point (planner, stabilizer, sim, seed, scale...)."""
    from bench.runner import EpisodeSpec

    robot = common.get("robot", DEFAULT_ROBOT)
    mass = robot_mass(common["scale"], robot)
    directions = protocol.directions_deg()
    for phase in protocol.phases:
        if phase == "standing":
            base = EpisodeSpec(
                scenario="stand_push",
                push_time=protocol.standing_push_time,
                duration=protocol.standing_push_time + PUSH_DURATION + protocol.survival_time,
                **common,
            )
            yield from _pushes(protocol, phase, base, mass, directions, ("random",))
            continue
        for fraction in protocol.swing_fractions:
            start = walking_push_time(
                common["scale"],
                protocol.walking_push_step,
                robot,
                None if fraction == 0.5 else fraction,
            )
            base = EpisodeSpec(
                scenario="walk_push",
                push_step=protocol.walking_push_step,
                duration=start + PUSH_DURATION + protocol.survival_time,
                push_swing_fraction=None if fraction == 0.5 else fraction,
                **common,
            )
            yield from _pushes(protocol, phase, base, mass, directions, protocol.directions)


def _pushes(
    protocol: PushProtocol,
    phase: str,
    base: Any,
    mass: float,
    random_directions: np.ndarray,
    directions: tuple[str, ...],
) -> Iterator[tuple[dict, Any]]:
    """Every level x direction x replica of one phase (and swing fraction) from `base`. A
    replica's push starts up to `bench.runner.REPLICA_PUSH_JITTER_S` earlier or later than
    the protocol's (its row's `push_time_s` is its own): its episode gets that much more
    time, so that every replica is judged over the whole survival time."""
    from bench.runner import REPLICA_PUSH_JITTER_S

    for dv in protocol.dv:
        for name in directions:
            if name == "random":
                pushes = [
                    (index, {"push_direction_deg": round(float(direction), 9)})
                    for index, direction in enumerate(random_directions)
                ]
            else:  # one push, relative to the support foot (`bench.scenarios.walk_push`)
                pushes = [(None, {"push_direction_name": name})]
            for index, fields in pushes:
                labels = {"push_phase": phase, "push_dv_mps": dv, "push_index": index}
                for replica in range(protocol.replicas):
                    longer = {}
                    if replica > 0:  # its push may start up to the jitter later
                        longer["duration"] = base.duration + REPLICA_PUSH_JITTER_S
                    yield (
                        labels,
                        replace(
                            base,
                            push_impulse=round(mass * dv, 9),
                            replica=replica,
                            **fields,
                            **longer,
                        ),
                    )
