"""The `centrobench` command line.

Bad input (an unknown name, a non-positive number, a missing optional package) exits with
status 2 and one line on stderr that says what is valid; never a traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from bench.limits import (
    CONTROL_PERIOD_S,
    FRICTION_MAX,
    MASS_RANGE_KG,
    MAX_EPISODE_SECONDS,
    MAX_HORIZON,
    MAX_PUSH_COUNT,
    MAX_PUSH_DV,
    MAX_PUSH_IMPULSE_NS,
    MAX_WALK_SPEED,
    MAX_WALK_STEPS,
    MAX_WORKERS,
    NAME_RULE,
    SCALE_RANGE,
    SEED_LIMIT,
    TIMEOUT_BASE_MAX_S,
    TIMEOUT_PER_SIM_MAX,
    valid_name,
)
from bench.push_protocol import MAX_REPLICAS
from bench.robustness import DIMENSIONS, EXAMPLES
from centroidal.gravity import GRAVITY
from estimators import DEFAULT_ESTIMATOR
from robots.perturbation import NOISE_CHANNELS
from sims.base import SIMULATORS, MissingDependencyError

T = TypeVar("T")


class UsageError(Exception):
    """Bad command-line input: reported as one line, exit status 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, no usage dump
        raise UsageError(message)


def _bounds(minimum: float | None, maximum: float | None, strict: bool, unit: str) -> str:
    """The valid range in words: "a positive number", ">= 0 N s", "in [0.1, 10]"..."""
    unit = f" {unit}" if unit else ""
    if minimum is not None and maximum is not None:
        return f"in {'(' if strict else '['}{minimum:g}, {maximum:g}]{unit}"
    if minimum is not None:
        if strict and minimum == 0:
            return "a positive number"
        return f"{'>' if strict else '>='} {minimum:g}{unit}"
    if maximum is not None:
        return f"<= {maximum:g}{unit}"
    return "a finite number"


def _number(
    kind: str,
    minimum: float | None = None,
    strict: bool = False,
    maximum: float | None = None,
    unit: str = "",
) -> Callable[[str], float]:
    """An argparse type: a finite float, above `minimum` (strict) or at least it, and at most
    `maximum`; the error names `kind` (the flag), the valid range and what was given."""

    def parse(text: str) -> float:
        bounds = _bounds(minimum, maximum, strict, unit)
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{kind} must be a number ({bounds}), got {text!r}"
            ) from None
        if not np.isfinite(value):
            raise argparse.ArgumentTypeError(f"{kind} must be finite ({bounds}), got {text!r}")
        too_low = minimum is not None and (value <= minimum if strict else value < minimum)
        if too_low or (maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(f"{kind} must be {bounds}, got {text!r}")
        return value

    parse.__name__ = f"number for {kind}"
    return parse


def _positive(kind: str) -> Callable[[str], float]:
    return _number(kind, 0.0, strict=True)


def _integer(kind: str, minimum: int, maximum: int) -> Callable[[str], int]:
    """An argparse type: an integer in [minimum, maximum]; the error names `kind` (the flag),
    the range and what was given."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or not minimum <= value <= maximum:
            raise argparse.ArgumentTypeError(
                f"{kind} must be an integer in [{minimum}, {maximum}], got {text!r}"
            )
        return value

    parse.__name__ = f"integer for {kind}"
    return parse


def _listed(kind: str, item: Callable[[str], T], what: str) -> Callable[[str], list[T]]:
    """An argparse type: a comma-separated list of at least one `item` (`what` says which;
    empty entries, as after a trailing comma, are skipped)."""

    def parse(text: str) -> list[T]:
        parts = [part.strip() for part in text.split(",") if part.strip()]
        if not parts:
            raise argparse.ArgumentTypeError(
                f"{kind} must be a comma-separated list of {what}, got {text!r}"
            )
        return [item(part) for part in parts]

    parse.__name__ = f"list for {kind}"
    return parse


def _names(kind: str, what: str) -> Callable[[str], list[str]]:
    """An argparse type: a comma-separated list of at least one name (checked later against
    the registry, which lists the valid ones)."""
    return _listed(kind, str, what)


def _robustness_values(
    kind: str, integer: bool, allow_groups: bool = False
) -> Callable[[str], list[tuple[str | None, float]]]:
    """An argparse type: a comma-separated list of magnitudes (integers if `integer`), and
    with `allow_groups` entries GROUP=X too (a noise group: encoders, imu, ft); each as
    (group or None, value). The ranges are checked with the spec (`bench.robustness`)."""

    def item(text: str) -> tuple[str | None, float]:
        group, _, value = text.rpartition("=")
        if group and not allow_groups:
            raise argparse.ArgumentTypeError(f"{kind} takes numbers, got {text!r}")
        if group and group not in NOISE_GROUPS:
            raise argparse.ArgumentTypeError(
                f"{kind}: unknown sensor group {group!r}; groups: {', '.join(NOISE_GROUPS)}"
            )
        what = "integers" if integer else "numbers"
        try:
            number = int(value) if integer else float(value)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{kind} must list {what}, got {text!r}") from None
        if not np.isfinite(number):
            raise argparse.ArgumentTypeError(f"{kind} must list finite {what}, got {text!r}")
        return (group or None, number)

    return _listed(kind, item, "magnitudes")


NOISE_GROUPS = ("encoders", "imu", "ft", *NOISE_CHANNELS)
"""What `--noise` entries GROUP=X name: a sensor group (X a multiple of its data sheet's
figures) or one channel (X its standard deviation in SI units, `robots.perturbation`)."""


def _seed(kind: str) -> Callable[[str], int]:
    return _integer(kind, 0, SEED_LIMIT - 1)


def _episode_seconds(kind: str) -> Callable[[str], float]:
    """Simulated seconds: one control period at least (else no period runs), at most
    MAX_EPISODE_SECONDS (the trace is preallocated)."""
    return _number(kind, CONTROL_PERIOD_S, maximum=MAX_EPISODE_SECONDS, unit="s")


def _scale(kind: str) -> Callable[[str], float]:
    return _number(kind, SCALE_RANGE[0], maximum=SCALE_RANGE[1])


def _robot_name(text: str) -> str:
    """An argparse type: a registered robot's name (`robots.robot_registry`)."""
    from robots.robot_registry import robot_entry

    try:
        robot_entry(text)
    except KeyError as exc:
        raise argparse.ArgumentTypeError(exc.args[0]) from None
    return text


def _add_robot(parser: argparse.ArgumentParser) -> None:
    from robots.robot_registry import DEFAULT_ROBOT, ROBOTS

    parser.add_argument(
        "--robot",
        type=_robot_name,
        default=DEFAULT_ROBOT,
        help=f"{', '.join(ROBOTS)} (default {DEFAULT_ROBOT})",
    )


def _robot_of(args: argparse.Namespace, scale: float = 1.0, mass: float | None = None):
    """The description of --robot at `scale` (and `mass`); UsageError, one line, for a robot
    that has one size."""
    from robots.robot_registry import make_robot

    try:
        return make_robot(args.robot, scale, mass)
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def _sweep_name(text: str) -> str:
    """An argparse type: a sweep name, one plain path component (results/NAME)."""
    if not valid_name(text):
        raise argparse.ArgumentTypeError(f"--name must be {NAME_RULE}, got {text!r}")
    return text


def _output_file(flag: str, text: str, make_parents: bool, suffix: str | None = None) -> Path:
    """Refuse an output file that cannot be written, before anything runs: an existing
    directory, a path below a file, a missing folder (unless `make_parents`: the writer
    creates it) or a folder without write permission; with `suffix` (".parquet", ".csv"),
    also a name with another ending, since the writer's format is fixed (`run --out t.csv`
    wrote Parquet into t.csv). Touches nothing."""
    path = Path(text)
    if "\0" in text:
        raise UsageError(f"{flag} {text!r} is no valid path (it holds a NUL character)")
    if path.is_dir():
        raise UsageError(f"{flag} {text} is a directory; give a file name")
    if suffix is not None and path.suffix.lower() != suffix:
        kind = suffix.removeprefix(".").capitalize() if suffix != ".csv" else "CSV"
        raise UsageError(f"{flag} {text}: the file is written as {kind}; name it FILE{suffix}")
    folder = path.parent
    if not make_parents and not folder.exists():
        raise UsageError(f"{flag} {text}: folder {folder} does not exist")
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    if not folder.is_dir():
        raise UsageError(f"{flag} {text}: {folder} is not a folder")
    if not os.access(folder, os.W_OK):
        raise UsageError(f"{flag} {text}: folder {folder} is not writable")
    return path


GIF_MIN_FPS = 0.002
"""[1/s] the lowest frame rate of a GIF replay: a GIF frame's delay is 16 bits of 10 ms."""


def _write_failed(flag: str, path: str | Path, exc: OSError) -> UsageError:
    """One line for an output file that could not be written after all."""
    reason = exc.strerror or str(exc) or type(exc).__name__
    return UsageError(f"{flag} {path}: cannot write it: {reason}")


def _one_simulator(text: str) -> str:
    if text not in SIMULATORS:
        raise argparse.ArgumentTypeError(
            f"unknown simulator {text!r}; choose from: {', '.join(SIMULATORS)}"
        )
    return text


def _simulator_names(text: str) -> list[str]:
    names = list(SIMULATORS) if text == "all" else [n.strip() for n in text.split(",")]
    for name in names:
        if name not in SIMULATORS:
            raise argparse.ArgumentTypeError(
                f"unknown simulator {name!r}; choose from: {', '.join(SIMULATORS)}, all"
            )
    return names


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="centrobench",
        description="Humanoid centroidal planners and stabilizers from the literature, run on "
        "MuJoCo and PyBullet with the same robot and measured the way the papers measure them.",
    )
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    robot = commands.add_parser(
        "robot",
        help="the robot as pinocchio, MuJoCo and PyBullet load it, and their largest differences",
    )
    robot.add_argument(
        "--scale",
        type=_scale("--scale"),
        default=1.0,
        help=f"length scale (1 = 1.60 m), {SCALE_RANGE[0]:g} to {SCALE_RANGE[1]:g}; mass "
        "scales with its cube",
    )
    robot.add_argument(
        "--mass",
        type=_number("--mass", MASS_RANGE_KG[0], maximum=MASS_RANGE_KG[1], unit="kg"),
        default=None,
        help="total mass [kg] instead of the scaled one",
    )
    _add_robot(robot)
    robot.add_argument("--json", action="store_true", help="one JSON object on stdout")

    run = commands.add_parser("run", help="run one episode and summarise it")
    run.add_argument(
        "--controller",
        default=None,
        help="a controller name (see `centrobench list`), or give its parts:",
    )
    run.add_argument("--planner", default=None, help="a planner name")
    run.add_argument("--stabilizer", default=None, help="a stabilizer name")
    run.add_argument("--whole-body", default=None, help="a whole-body layer name (default ik)")
    run.add_argument("--sim", required=True, type=_one_simulator, help="mujoco or pybullet")
    run.add_argument("--scenario", required=True, help="a scenario name")
    _add_robot(run)
    run.add_argument(
        "--duration",
        type=_episode_seconds("--duration"),
        default=None,
        help=f"simulated seconds, {CONTROL_PERIOD_S:g} to {MAX_EPISODE_SECONDS:g} "
        "(default: the scenario's)",
    )
    run.add_argument(
        "--push-impulse",
        type=_number("--push-impulse", 0.0, maximum=MAX_PUSH_IMPULSE_NS, unit="N s"),
        default=None,
        help="push impulse [N s] (scenarios with a push)",
    )
    run.add_argument(
        "--push-direction",
        type=_number("--push-direction"),
        default=None,
        help="push direction [deg], 0 = forward (+x), 90 = left (+y)",
    )
    run.add_argument(
        "--speed",
        type=_number("--speed", -MAX_WALK_SPEED, maximum=MAX_WALK_SPEED, unit="m/s"),
        default=None,
        help="forward speed [m/s] of walk and walk_push (default: their 0.139 m/s)",
    )
    run.add_argument(
        "--estimator",
        default=None,
        help=f"an estimator name (default: the controller's own, else {DEFAULT_ESTIMATOR}; "
        "see `centrobench list`)",
    )
    run.add_argument(
        "--seed", type=_seed("--seed"), default=0, help="random seed, 0 to 2**32 - 1 (default 0)"
    )
    run.add_argument("--out", default=None, help="write the per-period trace to FILE.parquet")
    run.add_argument("--json", action="store_true", help="the summary as one JSON object")

    check = commands.add_parser(
        "check",
        help="can the robot's joints follow a scenario at all: the IK alone on its targets, "
        "links touching the scene, task errors, joints at limits (no dynamics)",
    )
    check.add_argument("--scenario", required=True, help="a scenario name")
    check.add_argument(
        "--scale",
        type=_scale("--scale"),
        default=1.0,
        help=f"robot length scale, {SCALE_RANGE[0]:g} to {SCALE_RANGE[1]:g} (default 1)",
    )
    _add_robot(check)
    check.add_argument("--json", action="store_true", help="one JSON object on stdout")

    commands.add_parser(
        "list",
        help="the registered controllers, planners, stabilizers, whole-body layers, "
        "estimators, scenarios, simulators and robots",
    )

    compare = commands.add_parser(
        "compare",
        help="Murooka Sec. V-G: planners side by side (projection errors, feedback, timing)",
    )
    compare.add_argument(
        "--planners",
        required=True,
        type=_names("--planners", "planner names (see `centrobench list`)"),
        help="comma-separated planner names, e.g. preview_control,linear_mpc",
    )
    compare.add_argument("--scenario", default="walk", help="a scenario name (default walk)")
    compare.add_argument(
        "--sims",
        type=_simulator_names,
        default=list(SIMULATORS),
        help="mujoco, pybullet, a comma-separated list or all (default: all)",
    )
    compare.add_argument(
        "--stabilizer", default="centroidal_feedback", help="default centroidal_feedback"
    )
    _add_robot(compare)
    compare.add_argument(
        "--horizons",
        type=_listed(
            "--horizons",
            _integer("every --horizons value", 1, MAX_HORIZON),
            f"horizon sample counts in [1, {MAX_HORIZON}]",
        ),
        default=None,
        help="also time linear_mpc's update for these horizon lengths, e.g. 10,20,40,80 "
        f"(at most {MAX_HORIZON})",
    )
    compare.add_argument(
        "--formulations",
        type=_names("--formulations", "formulation names"),
        default=None,
        help="formulations for --horizons (default: all)",
    )
    compare.add_argument("--out", default=None, help="also write the table(s) to FILE.csv")

    demo = commands.add_parser(
        "demo", help="load the robot in each simulator, hold the standing posture, summarise"
    )
    demo.add_argument(
        "--sim",
        type=_simulator_names,
        default=list(SIMULATORS),
        help="mujoco, pybullet, a comma-separated list or all (default: all)",
    )
    demo.add_argument(
        "--duration",
        type=_episode_seconds("--duration"),
        default=3.0,
        help=f"simulated seconds, {CONTROL_PERIOD_S:g} to {MAX_EPISODE_SECONDS:g} (default 3)",
    )
    demo.add_argument("--scale", type=_scale("--scale"), default=1.0, help="length scale")
    _add_robot(demo)

    sweep = commands.add_parser(
        "sweep",
        help="run a grid of episodes (TOML spec or flags) on local processes or Ray",
    )
    sweep.add_argument("--spec", default=None, help="a TOML sweep spec (see bench/sweep_spec.py)")
    sweep.add_argument(
        "--controllers",
        type=_names("--controllers", "controller names (planner+stabilizer) or all"),
        help="planner+stabilizer names, or all",
    )
    sweep.add_argument(
        "--sims", type=_names("--sims", "simulator names or all"), help="mujoco, pybullet or all"
    )
    sweep.add_argument(
        "--scenarios",
        type=_names("--scenarios", "scenario names"),
        help="scenarios without a push",
    )
    sweep.add_argument(
        "--estimator",
        default=None,
        help="an estimator name for every controller, also those that come with their own "
        f"(default: each controller's own, else {DEFAULT_ESTIMATOR}; see `centrobench list`)",
    )
    dv = f"velocity changes in (0, {MAX_PUSH_DV:g}] m/s"
    sweep.add_argument(
        "--push-dv",
        type=_listed(
            "--push-dv",
            _number("every --push-dv value", 0.0, True, MAX_PUSH_DV, unit="m/s"),
            dv,
        ),
        help=f"push levels dv = J / m [m/s], at most {MAX_PUSH_DV:g}",
    )
    sweep.add_argument(
        "--push-count",
        type=_integer("--push-count", 1, MAX_PUSH_COUNT),
        help=f"pushes per level, 1 to {MAX_PUSH_COUNT} (default 20)",
    )
    sweep.add_argument(
        "--push-phases", type=_names("--push-phases", "push phases"), help="standing, walking"
    )
    sweep.add_argument(
        "--push-seed",
        type=_seed("--push-seed"),
        help="seed of the push directions, 0 to 2**32 - 1 (default 0)",
    )
    sweep.add_argument(
        "--seeds",
        type=_listed("--seeds", _seed("every --seeds value"), f"integers in [0, {SEED_LIMIT - 1}]"),
        help="seeds, 0 to 2**32 - 1",
    )
    sweep.add_argument(
        "--scales",
        type=_listed(
            "--scales",
            _scale("every --scales value"),
            f"length scales in [{SCALE_RANGE[0]:g}, {SCALE_RANGE[1]:g}]",
        ),
        help=f"robot length scales, {SCALE_RANGE[0]:g} to {SCALE_RANGE[1]:g}",
    )
    sweep.add_argument(
        "--frictions",
        type=_listed(
            "--frictions",
            _number("every --frictions value", 0.0, True, FRICTION_MAX),
            f"friction coefficients in (0, {FRICTION_MAX:g}]",
        ),
        help=f"friction coefficients, at most {FRICTION_MAX:g}",
    )
    sweep.add_argument(
        "--speeds",
        type=_listed(
            "--speeds",
            _number("every --speeds value", -MAX_WALK_SPEED, maximum=MAX_WALK_SPEED, unit="m/s"),
            f"forward speeds in [-{MAX_WALK_SPEED:g}, {MAX_WALK_SPEED:g}] m/s",
        ),
        help="forward speeds [m/s] of walk and walk_push",
    )
    sweep.add_argument(
        "--duration",
        type=_episode_seconds("--duration"),
        help=f"seconds of the plain scenarios, {CONTROL_PERIOD_S:g} to {MAX_EPISODE_SECONDS:g}",
    )
    sweep.add_argument(
        "--name", type=_sweep_name, default=None, help=f"the sweep's name: {NAME_RULE}"
    )
    sweep.add_argument("--out", default=None, help="result directory (default results/NAME)")
    sweep.add_argument("--executor", default="local", choices=("local", "ray"))
    sweep.add_argument("--address", default=None, help="Ray cluster address (with --executor ray)")
    sweep.add_argument(
        "--workers",
        type=_integer("--workers", 1, MAX_WORKERS),
        default=None,
        help=f"processes, 1 to {MAX_WORKERS} (default: cores)",
    )
    sweep.add_argument("--resume", action="store_true", help="run only the missing episodes")
    sweep.add_argument(
        "--retry-errors",
        action="store_true",
        help="with --resume: also run again the episodes that ended in an error or a timeout",
    )
    sweep.add_argument(
        "--no-branching",
        action="store_true",
        help="run every pushed episode from the start, instead of branching the episodes that "
        "differ only in their push from one run at the push time (same results, slower)",
    )
    sweep.add_argument(
        "--overwrite",
        action="store_true",
        help="start again: earlier results in OUT are moved aside, and deleted once the new "
        "sweep has written its first episode",
    )
    sweep.add_argument(
        "--timeout-base-s",
        type=_number("--timeout-base-s", 0.0, strict=True, maximum=TIMEOUT_BASE_MAX_S),
        default=None,
        help="wall-clock budget of every episode [s] (default 60) ...",
    )
    sweep.add_argument(
        "--timeout-per-sim-s",
        type=_number("--timeout-per-sim-s", 0.0, strict=True, maximum=TIMEOUT_PER_SIM_MAX),
        default=None,
        help="... plus this many seconds per simulated second (default 10); past it an "
        "episode ends as 'timeout'",
    )
    sweep.add_argument("--no-progress", action="store_true", help="no progress bar")
    sweep.add_argument(
        "--push-replicas",
        type=_integer("--push-replicas", 1, MAX_REPLICAS),
        help=f"trials of every push, 1 to {MAX_REPLICAS} (default 1); replicas after the first "
        "start with a small seeded change (the robust threshold takes 4 of 5)",
    )
    sweep.add_argument(
        "--push-swing-fractions",
        type=_listed(
            "--push-swing-fractions",
            _number("every --push-swing-fractions value", 0.0, maximum=1.0),
            "fractions in [0, 1]",
        ),
        help="walking pushes centred at these fractions of the single support (default 0.5)",
    )
    sweep.add_argument(
        "--push-directions",
        type=_names("--push-directions", "push directions"),
        help="walking pushes: random (the --push-count uniform directions) and/or inward, "
        "outward, forward, backward relative to the support foot (default random)",
    )
    robustness = sweep.add_argument_group(
        "robustness dimensions (bench/robustness.py): each a comma-separated list of "
        "magnitudes, varied one dimension at a time around the nominal episode"
    )
    for dimension, (_fields, integer, *_rest, accepts) in DIMENSIONS.items():
        flag = "--" + dimension.replace("_", "-").lower()
        example = EXAMPLES[dimension] + (",imu=4" if dimension == "noise" else "")
        extra = (
            "; an entry GROUP=X sets one group (encoders, imu, ft: multiples) or one channel "
            "(X in SI units, e.g. gyro_rad_s=0.01; channels: " + ", ".join(NOISE_CHANNELS) + ")"
            if dimension == "noise"
            else ""
        )
        robustness.add_argument(
            flag,
            type=_robustness_values(flag, integer, allow_groups=dimension == "noise"),
            dest=f"robustness_{dimension}",
            metavar="LIST",
            help=f"{accepts}, e.g. {flag} {example}{extra}",
        )

    speed = commands.add_parser(
        "speed",
        help="Ficht & Behnke Table 1: the highest forward speed each controller walks at",
    )
    speed.add_argument(
        "--controllers",
        required=True,
        type=_names("--controllers", "controller names or all"),
        help="controller names (ablations included), or all",
    )
    speed.add_argument(
        "--sims",
        type=_simulator_names,
        default=list(SIMULATORS),
        help="mujoco, pybullet or all (default all)",
    )
    speed.add_argument("--out", required=True, help="directory for speed.parquet and speed.md")
    speed.add_argument(
        "--workers", type=_integer("--workers", 1, MAX_WORKERS), default=None, help="processes"
    )
    speed.add_argument(
        "--steps",
        type=_integer("--steps", 2, MAX_WALK_STEPS),
        default=12,
        help="steps of the gait command (default 12: 21 of direct_centroidal's own)",
    )
    speed.add_argument(
        "--maximum",
        type=_number("--maximum", 0.0, strict=True, maximum=MAX_WALK_SPEED, unit="m/s"),
        default=0.8,
        help="the ladder's top speed [m/s] (default 0.8)",
    )
    speed.add_argument(
        "--increment",
        type=_number("--increment", 0.0, strict=True, maximum=MAX_WALK_SPEED, unit="m/s"),
        default=0.05,
        help="the ladder's step, also its first speed [m/s] (default 0.05)",
    )
    speed.add_argument(
        "--resolution",
        type=_number("--resolution", 0.0, strict=True, maximum=MAX_WALK_SPEED, unit="m/s"),
        default=0.01,
        help="the bisection's grid [m/s], at most the increment (default 0.01)",
    )
    speed.add_argument(
        "--replicas",
        type=_integer("--replicas", 1, MAX_REPLICAS),
        default=1,
        help="walks per speed, replica 0 nominal, the others with a small seeded initial "
        "velocity; a speed is walked when R - R // 5 of them walk (4 of 5) (default 1)",
    )

    report = commands.add_parser("report", help="build report.md and report.html from results")
    report.add_argument(
        "results",
        nargs="+",
        help="a sweep's result directory, or several to report together (for example the "
        "main job's and a sweep of a controller that is not in it)",
    )
    report.add_argument("--out", default=None, help="output directory (default: the first RESULTS)")
    report.add_argument(
        "--benchmark-json", default=None, help="a pytest-benchmark JSON file to add as a table"
    )
    report.add_argument(
        "--replays",
        action="store_true",
        help="first make the replays the report offers (one walk and the first fall per "
        "controller: each episode runs again) into OUT/replays/",
    )

    replay = commands.add_parser(
        "replay",
        help="run a recorded episode again and draw it: the robot and the scene in 3-D with "
        "time, CoM, ZMP and contact forces, as an HTML page with a player (or a GIF)",
    )
    replay.add_argument("results", help="the sweep's result directory")
    replay.add_argument("episode_id", help="the episode's id (the report and the rows name it)")
    replay.add_argument("--out", required=True, help="the file to write: .html or .gif")
    replay.add_argument(
        "--fps",
        type=_number("--fps", 0.0, strict=True, maximum=500.0),
        default=10.0,
        help="frames per simulated second (default 10; at most 500, one per control period)",
    )
    return parser


def _robot(args: argparse.Namespace) -> int:
    from bench.robot_check import robot_report

    report = robot_report(_robot_of(args, args.scale, args.mass))
    if args.json:
        print(json.dumps(report, indent=2))
        return 0
    print(f"{report['robot']}: scale {report['scale']:g}, height {report['height_m']:.3f} m")
    print(
        f"{'model':<10} {'mass [kg]':>14} {'DoF':>4} {'bodies':>6}  largest difference from "
        "pinocchio: mass (rel)  CoM [m]  inertia (rel)  joints"
    )
    for source, info in report["models"].items():
        line = f"{source:<10} {info['total_mass_kg']:>14.9f} {info['dof']:>4} {info['bodies']:>6}"
        gap = report["max_discrepancy_vs_pinocchio"].get(source)
        if gap is None:
            line += "  (reference)"
        else:
            joints = "same order and limits" if gap["same_joint_order"] else "DIFFERENT ORDER"
            line += (
                f"  {gap['mass_rel']:.1e}  {gap['com_m']:.1e}  {gap['inertia_rel']:.1e}  {joints}"
            )
        print(line)
    return 0


def _check(args: argparse.Namespace) -> int:
    from dataclasses import asdict

    from bench.kinematic_check import check_scenario, format_check
    from bench.scenarios import make_scenario
    from robots.model import RobotModel

    model = RobotModel(_robot_of(args, args.scale))
    check = check_scenario(model, make_scenario(args.scenario, model))
    if args.json:
        print(json.dumps({**asdict(check), "feasible": check.feasible}, indent=2))
    else:
        print(format_check(check))
    return 0


def _resolve_controller(args: argparse.Namespace) -> None:
    """Fill args.planner, args.stabilizer and args.whole_body from --controller, or check that
    the parts were given; one line naming what is missing or unknown."""
    from bench.controllers import CONTROLLERS, controller_spec
    from wholebody.base import DEFAULT_WHOLE_BODY

    if args.controller is not None:
        given = [f for f in ("planner", "stabilizer", "whole_body") if getattr(args, f)]
        if given:
            flags = ", ".join("--" + f.replace("_", "-") for f in given)
            raise UsageError(f"--controller names all three parts; drop {flags}")
        spec = controller_spec(args.controller)
        args.planner, args.stabilizer, args.whole_body = (
            spec.planner,
            spec.stabilizer,
            spec.whole_body,
        )
        args.estimator = args.estimator or spec.estimator or DEFAULT_ESTIMATOR
        return
    if args.planner is None or args.stabilizer is None:
        raise UsageError(
            "give --controller NAME (one of: "
            f"{', '.join(CONTROLLERS)}) or --planner and --stabilizer"
        )
    args.whole_body = args.whole_body or DEFAULT_WHOLE_BODY
    args.estimator = args.estimator or DEFAULT_ESTIMATOR


def _validate_names(args: argparse.Namespace) -> None:
    """Unknown controller / planner / stabilizer / whole-body layer / scenario / estimator:
    one line with the known names."""
    from bench.scenarios import SCENARIOS
    from estimators.base import ESTIMATORS
    from planners.base import planner_spec
    from stabilizers.base import stabilizer_spec
    from wholebody.base import WHOLE_BODY_LAYERS

    _resolve_controller(args)
    planner_spec(args.planner)
    stabilizer_spec(args.stabilizer)
    WHOLE_BODY_LAYERS.get(args.whole_body)
    if args.scenario not in SCENARIOS:
        raise UsageError(
            f"unknown scenario {args.scenario!r}; choose one of: {', '.join(SCENARIOS)}"
        )
    if args.estimator not in ESTIMATORS.names():
        raise UsageError(
            f"unknown estimator {args.estimator!r}; choose one of: {', '.join(ESTIMATORS.names())}"
        )


def _compare(args: argparse.Namespace) -> int:
    from bench.compare import compare, horizon_timing, paper_rows
    from bench.scenarios import SCENARIOS
    from centroidal.mpc_formulations import FORMULATIONS
    from planners.base import planner_spec
    from stabilizers.base import stabilizer_spec

    for name in args.planners:
        planner_spec(name)
    stabilizer_spec(args.stabilizer)
    if args.scenario not in SCENARIOS:
        raise UsageError(
            f"unknown scenario {args.scenario!r}; choose one of: {', '.join(SCENARIOS)}"
        )
    from bench.controllers import ControllerSpec, refusal
    from estimators import DEFAULT_ESTIMATOR

    for name in args.planners:  # as `run` refuses them, and a sweep makes them n/a
        reason = refusal(ControllerSpec(name, args.stabilizer), args.scenario, DEFAULT_ESTIMATOR)
        if reason is not None:
            raise UsageError(reason)
    if len(set(args.planners)) != len(args.planners) or len(set(args.sims)) != len(args.sims):
        raise UsageError(
            f"--planners {','.join(args.planners)} --sims {','.join(args.sims)}: a name twice "
            "runs the same episodes twice"
        )
    if args.formulations and not args.horizons:
        raise UsageError("--formulations times the MPC's formulations: it goes with --horizons")
    formulations = args.formulations or list(FORMULATIONS)
    for name in formulations:
        if name not in FORMULATIONS:
            raise UsageError(
                f"unknown formulation {name!r}; choose one of: {', '.join(FORMULATIONS)}"
            )
    horizons_out = None
    if args.out:
        _output_file("--out", args.out, make_parents=False, suffix=".csv")
        if args.horizons:
            horizons_out = str(Path(args.out).with_suffix("")) + "_horizons.csv"
            _output_file("--out", horizons_out, make_parents=False)
    n = len(args.planners) * len(args.sims)
    print(f"running {n} episodes ({args.scenario}) ...", file=sys.stderr, flush=True)
    done = []

    def progress(row: dict) -> None:
        done.append(row)
        print(
            f"  [{len(done)}/{n}] {row['planner']} on {row['sim']}: {row['status']}",
            file=sys.stderr,
            flush=True,
        )

    table = compare(
        args.planners,
        args.scenario,
        args.sims,
        args.stabilizer,
        progress=progress,
        robot=args.robot,
    )
    with _pd_options():
        print(table.drop(columns=["error"]).to_string(index=False, float_format="%.4g"))
        paper = paper_rows(args.scenario, args.planners)
        if paper is not None:
            print("\nMurooka et al. 2022, Sec. V-G (HRP-5P, Choreonoid): mean projection errors")
            print(paper.to_string(index=False, float_format="%.4g"))
    failed = table[table["status"] != "ok"]
    for _, row in failed.iterrows():
        print(f"{row['planner']} on {row['sim']}: {row['status']}: {row['error']}")
    if args.out:
        try:
            table.to_csv(args.out, index=False)
        except OSError as exc:
            raise _write_failed("--out", args.out, exc) from None
    if args.horizons:
        timing = horizon_timing(formulations, args.horizons, robot=args.robot)
        print()
        with _pd_options():
            print(
                timing.pivot(
                    index="formulation", columns="horizon_samples", values="median_ms"
                ).to_string(float_format="%.2f")
            )
        if horizons_out:
            try:
                timing.to_csv(horizons_out, index=False)
            except OSError as exc:
                raise _write_failed("--out", horizons_out, exc) from None
    return 0


def _pd_options():
    import pandas as pd

    return pd.option_context("display.width", 200, "display.max_columns", 30)


def _run(args: argparse.Namespace) -> int:
    from bench.runner import EpisodeSpec, run_episode, summary_json_ready
    from bench.scenarios import SCENARIOS

    _validate_names(args)
    if (args.push_impulse is not None or args.push_direction is not None) and not SCENARIOS[
        args.scenario
    ].takes_push:
        pushing = ", ".join(s.name for s in SCENARIOS.values() if s.takes_push)
        raise UsageError(f"scenario {args.scenario!r} takes no push; scenarios with one: {pushing}")
    from bench.controllers import ControllerSpec, controller_spec, refusal
    from bench.scenarios import WALKS_WITH_SPEED

    controller = (
        controller_spec(args.controller)
        if args.controller
        else ControllerSpec(args.planner, args.stabilizer, whole_body=args.whole_body)
    )
    reason = refusal(controller, args.scenario, args.estimator)
    if reason is not None:
        raise UsageError(reason)
    if args.speed is not None and args.scenario not in WALKS_WITH_SPEED:
        raise UsageError(
            f"--speed is for the scenarios {', '.join(WALKS_WITH_SPEED)}, not {args.scenario!r}"
        )
    if args.out:
        # write_trace makes the folders
        _output_file("--out", args.out, make_parents=True, suffix=".parquet")
    spec = EpisodeSpec(
        planner=args.planner,
        stabilizer=args.stabilizer,
        sim=args.sim,
        scenario=args.scenario,
        seed=args.seed,
        duration=args.duration,
        push_impulse=args.push_impulse,
        push_direction_deg=args.push_direction,
        estimator=args.estimator,
        whole_body=args.whole_body,
        speed=args.speed,
        robot=args.robot,
    )
    if args.duration is not None and SCENARIOS[args.scenario].takes_push:
        from bench.runner import _pushed
        from robots.model import cached_model
        from robots.robot_registry import make_robot

        pushes = _pushed(spec, cached_model(make_robot(args.robot))).pushes
        if pushes and pushes[0].time >= args.duration:
            raise UsageError(
                f"--duration {args.duration:g} s ends before the push at {pushes[0].time:g} s "
                f"of {args.scenario!r}"
            )
    result = run_episode(spec)
    summary = summary_json_ready(result.summary)
    _print_summary(summary, args.json)  # first: a trace that cannot be written loses nothing
    if args.out:
        from bench.results import write_trace

        footsteps_path = footsteps_file(args.out)
        try:
            write_trace(result.trace, summary, args.out)
            if result.footsteps is not None:
                result.footsteps.to_parquet(footsteps_path, index=False)
        except OSError as exc:
            raise _write_failed("--out", args.out, exc) from None
    return 0 if summary["status"] != "error" else 1


def footsteps_file(trace_path: str) -> str:
    """Where `run --out FILE.parquet` writes the steps taken: FILE.footsteps.parquet."""
    return f"{Path(trace_path).with_suffix('')}.footsteps.parquet"


def strict_json(value: Any) -> Any:
    """`value` with every NaN or infinite float as None, so that the JSON printed is strict
    (RFC 8259 has no NaN: jq and most parsers refuse Python's `NaN` token); a p99 that is not
    stated, for one, is null."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {key: strict_json(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [strict_json(item) for item in value]
    return value


def _print_summary(summary: dict, as_json: bool) -> None:
    """An episode's summary: one JSON object (strict: `strict_json`), or three lines and the
    latency table."""
    if as_json:
        print(json.dumps(strict_json(summary), allow_nan=False))
    else:
        print(
            f"{summary['planner']} + {summary['stabilizer']} on {summary['sim']}, "
            f"{summary['scenario']}: {summary['status']}"
            + (
                f" at {summary['fall_time']:.3f} s ({summary['fall_reason']})"
                if summary["fell"]
                else ""
            )
            + (f": {summary['error']}" if summary["error"] else "")
        )
        com_error = summary["com_error_rms_m"]
        print(
            f"simulated {summary['duration']:.2f} s, real-time factor "
            f"{summary['real_time_factor'] or 0:.2f}, CoM error RMS "
            + ("–" if com_error is None else f"{com_error * 1e3:.2f} mm")
        )
        print(f"{'stage':<16} {'median us':>10} {'p99 us':>10} {'max us':>10}")
        for stage, stats in summary["latency_us"].items():
            print(
                f"{stage:<16} {stats['median']:>10.1f} {stats['p99']:>10.1f} {stats['max']:>10.1f}"
            )


def _list(args: argparse.Namespace) -> int:
    from bench.controllers import ABLATIONS, CONTROLLERS
    from bench.scenarios import SCENARIOS
    from estimators.base import ESTIMATORS
    from planners.base import PLANNERS
    from robots.robot_registry import ROBOTS
    from stabilizers.base import STABILIZERS
    from wholebody.base import DEFAULT_WHOLE_BODY, WHOLE_BODY_LAYERS

    def described(registry, default: str | None = None) -> dict[str, str]:
        return {
            n: registry.get(n).description
            + (" (default)" if n == default else "")
            + (f" (gives: {', '.join(sorted(g))})" if (g := registry.get(n).gives) else "")
            for n in registry.names()
        }

    def show(specs) -> None:
        for name, spec in specs.items():
            print(
                f"  {name}\n      ({spec.planner}, {spec.stabilizer}, {spec.whole_body}) "
                f"{spec.description}\n      can: {', '.join(sorted(spec.can))}"
                + (f"; needs: {', '.join(sorted(spec.needs))}" if spec.needs else "")
                + (f"; reads: {', '.join(sorted(spec.needs_state))}" if spec.needs_state else "")
                + (f"; estimator: {spec.estimator}" if spec.estimator else "")
            )

    print("controllers (planner, stabilizer, whole-body layer):")
    show(CONTROLLERS)
    print("ablations and methods not yet in the main job (not in a sweep of all controllers):")
    show({n: s for n, s in ABLATIONS.items() if n not in CONTROLLERS})
    sections = {
        "planners": described(PLANNERS),
        "stabilizers": described(STABILIZERS),
        "whole-body layers": described(WHOLE_BODY_LAYERS, DEFAULT_WHOLE_BODY),
        "estimators": described(ESTIMATORS, DEFAULT_ESTIMATOR),
        "scenarios": {n: s.description for n, s in SCENARIOS.items()},
        "simulators": {n: "" for n in SIMULATORS},
        "robots": {n: r.description for n, r in ROBOTS.items()},
    }
    for title, entries in sections.items():
        print(f"{title}:")
        for name, description in entries.items():
            print(f"  {name:<16} {description}".rstrip())
    return 0


def _demo(args: argparse.Namespace) -> int:
    from robots.model import RobotModel
    from robots.scene import Scene
    from sims.base import make_simulator

    robot = _robot_of(args, args.scale)
    model = RobotModel(robot)
    initial = model.standing_state()
    command = model.hold_command(initial)
    weight = robot.total_mass * GRAVITY
    print(
        f"{robot.name}: {robot.total_mass:.2f} kg, {robot.n_joints} joints, "
        f"standing CoM height {model.com_position_world(initial)[2]:.3f} m; "
        f"holding the standing posture for {args.duration:g} s"
    )
    print(
        f"{'simulator':<10} {'fell':>5} {'feet Fz / m g':>14} {'CoM moved [mm]':>15} "
        f"{'real-time factor':>17}"
    )
    for name in args.sim:
        sim = make_simulator(name)
        try:
            sim.reset(robot, Scene(), initial)
            com0 = model.com_position_world(initial)
            steps = round(args.duration / Scene().control_dt)
            start = time.perf_counter()
            for _ in range(steps):
                sensors = sim.step(command)
            elapsed = time.perf_counter() - start
            moved = np.linalg.norm(model.com_position_world(sensors.ground_truth())[:2] - com0[:2])
            fz = sensors.contact_wrench_limb[:2, 2].sum() / weight
            fell = sim.fall_reason() or "no"
            print(
                f"{name:<10} {fell:>5} {fz:>14.4f} {moved * 1e3:>15.3f} "
                f"{args.duration / elapsed:>17.1f}"
            )
        finally:
            sim.close()
    return 0


def _sweep_mapping(args: argparse.Namespace) -> dict:
    """The spec's fields: from --spec (TOML), overridden by the flags given. SpecError for a
    --spec that cannot be read as TOML."""
    from bench.sweep_spec import SpecError, read_spec_file

    data: dict = {} if args.spec is None else read_spec_file(args.spec)
    if isinstance(data.get("protocols"), list):
        return _job_mapping(args, data, SpecError)
    for flag in (
        "controllers",
        "sims",
        "scenarios",
        "seeds",
        "scales",
        "frictions",
        "duration",
        "speeds",
    ):
        value = getattr(args, flag)
        if value is not None:
            data[flag] = value
    if args.name is not None:
        data["name"] = args.name
    data.update(_estimator_fields(args))
    for flag in ("timeout_base_s", "timeout_per_sim_s"):
        if getattr(args, flag) is not None:
            data[flag] = getattr(args, flag)
    push = dict(data.get("push", {})) if isinstance(data.get("push"), dict) else data.get("push")
    for flag, key in (
        ("push_dv", "dv"),
        ("push_count", "count"),
        ("push_phases", "phases"),
        ("push_seed", "seed"),
    ):
        value = getattr(args, flag)
        if value is not None:
            push = push if isinstance(push, dict) else {}
            push[key] = value
    for flag, key in (
        ("push_replicas", "replicas"),
        ("push_swing_fractions", "swing_fractions"),
        ("push_directions", "directions"),
    ):
        if getattr(args, flag) is not None:
            push = push if isinstance(push, dict) else {}
            push[key] = getattr(args, flag)
    if push is not None:
        data["push"] = push
    overrides: dict[str, list[float]] = {}  # a flag replaces the spec's list of its dimension
    for dimension in DIMENSIONS:
        for group, value in getattr(args, f"robustness_{dimension}", None) or []:
            overrides.setdefault(dimension if group is None else f"noise_{group}", []).append(value)
    if overrides:
        table = dict(data["robustness"]) if isinstance(data.get("robustness"), dict) else {}
        data["robustness"] = {**table, **overrides}
    return data


JOB_FLAGS = ("controllers", "sims", "seeds")
"""The grid flags that apply to a job of protocols: to each of its protocols."""


def _estimator_fields(args: argparse.Namespace) -> dict:
    """The spec fields of `sweep --estimator NAME`: NAME for every controller, also those
    that come with their own estimator (as `run --estimator` does)."""
    if args.estimator is None:
        return {}
    return {"estimator": args.estimator, "estimator_for_every_controller": True}


def _job_mapping(args: argparse.Namespace, data: dict, error: type[Exception]) -> dict:
    """A job of protocols (`[[protocols]]`) from --spec: --controllers, --sims and --seeds
    replace those of every protocol, --name and the timeouts the job's; every other grid flag
    is refused (it would mean something different in each protocol)."""
    grid = ("scenarios", "scales", "frictions", "duration", "speeds", "push_dv", "push_count")
    grid += ("push_phases", "push_seed", "push_replicas", "push_swing_fractions")
    grid += ("push_directions", *(f"robustness_{d}" for d in DIMENSIONS))
    for flag in grid:
        if getattr(args, flag, None) is not None:
            option = "--" + flag.removeprefix("robustness_").replace("_", "-").lower()
            raise error(
                f"{option}: the spec {args.spec} is a job of protocols; set it in its "
                "[[protocols]] tables (only --controllers, --sims, --seeds, --name and the "
                "timeouts apply to a whole job)"
            )
    data = dict(data)
    protocols = [dict(p) if isinstance(p, dict) else p for p in data["protocols"]]
    for flag in JOB_FLAGS:
        value = getattr(args, flag)
        if value is not None:
            data[flag] = value
            for protocol in protocols:
                if isinstance(protocol, dict):
                    protocol[flag] = value
    for protocol in protocols:  # the job's estimator for each protocol, as the grid flags
        if isinstance(protocol, dict):
            protocol.update(_estimator_fields(args))
    data.update(_estimator_fields(args))
    data["protocols"] = protocols
    if args.name is not None:
        data["name"] = args.name
    for flag in ("timeout_base_s", "timeout_per_sim_s"):
        if getattr(args, flag) is not None:
            data[flag] = getattr(args, flag)
    return data


def _sweep(args: argparse.Namespace) -> int:
    from bench.sweep import run_sweep
    from bench.sweep_spec import SpecError, spec_from_mapping

    try:
        spec = spec_from_mapping(_sweep_mapping(args))
    except SpecError as exc:
        raise UsageError(str(exc)) from None
    out = args.out or f"results/{spec.name}"

    def announce(total: int, todo: int, notes: list[str]) -> None:
        refused = sum(episode.refused is not None for episode in spec.episodes())
        done = total - todo - refused  # the n/a rows are written, never run
        parts = ([f"{refused} n/a"] if refused else []) + ([f"{done} done"] if done else [])
        left = f" ({', '.join([*parts, f'{todo} to run'])})" if parts else ""
        print(
            f"sweep {spec.name!r}: {total} episodes{left} -> {out} ({args.executor})",
            file=sys.stderr,
        )
        if spec.protocols:  # a job: what it runs, in order
            counts: dict[str, int] = {}
            for episode in spec.episodes():
                counts[episode.protocol] = counts.get(episode.protocol, 0) + 1
            for k, (name, count) in enumerate(counts.items()):
                print(f"  {k + 1}/{len(counts)} {name}: {count} episodes", file=sys.stderr)
        for note in notes:
            print(f"  {note}", file=sys.stderr)

    from bench.dataset import ResultStoreError

    try:
        frame = run_sweep(
            spec,
            out,
            executor=args.executor,
            workers=args.workers,
            address=args.address,
            resume=args.resume,
            overwrite=args.overwrite,
            retry_errors=args.retry_errors,
            progress=not args.no_progress,
            on_start=announce,
            branching=not args.no_branching,
        )
    except (ResultStoreError, ImportError) as exc:
        raise UsageError(str(exc)) from None
    except RuntimeError as exc:  # the executor could not run (workers die at start-up)
        print(f"centrobench: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 1
    except KeyboardInterrupt as exc:
        from bench.sweep import SweepTerminated

        terminated = isinstance(exc, SweepTerminated)
        print(
            f"\n{'terminated (SIGTERM)' if terminated else 'interrupted'}: the finished "
            f"episodes are in {out}; run the same command with --resume (not --overwrite) to "
            "complete the sweep"
            + (
                " (an --overwrite stopped before its first episode put the earlier results back)"
                if args.overwrite
                else ""
            ),
            file=sys.stderr,
        )
        return 143 if terminated else 130
    counts = frame["status"].value_counts().to_dict()
    print(
        f"{len(frame)} episodes in {out}: "
        + ", ".join(f"{n} {status}" for status, n in sorted(counts.items())),
        file=sys.stderr,
    )
    return 0


def _speed(args: argparse.Namespace) -> int:
    from bench.controllers import CONTROLLERS, controller_spec
    from bench.speed_protocol import SpeedInterrupted, SpeedProtocol, run_speed_protocol
    from reports.tables import speed_table

    controllers = []  # "all" stands for the registered controllers, ablations may follow
    for name in args.controllers:
        for controller in CONTROLLERS if name == "all" else [name]:
            if controller not in controllers:
                controllers.append(controller)
    for name in controllers:
        controller_spec(name)  # KeyError naming the known ones
    sims = args.sims
    try:
        protocol = SpeedProtocol(
            start=args.increment,
            increment=args.increment,
            maximum=args.maximum,
            resolution=args.resolution,
            steps=args.steps,
            replicas=args.replicas,
        )
    except ValueError as exc:
        if not 0 < args.increment <= args.maximum:  # the protocol's start is --increment here
            raise UsageError(
                f"speed: --increment {args.increment:g} (the first speed tried) must be "
                f"positive and at most --maximum {args.maximum:g}"
            ) from None
        raise UsageError(f"speed: {exc}") from None
    out = Path(args.out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _write_failed("--out", out, exc) from None
    for name in ("speed.parquet", "speed.md"):  # before the search, not after its hours
        _output_file("--out", str(out / name), make_parents=False)
    try:
        trials = run_speed_protocol(controllers, sims, protocol, workers=args.workers)
    except SpeedInterrupted as exc:  # the finished walks kept, apart from a complete table
        partial = out / "speed.partial.parquet"
        try:
            exc.trials.to_parquet(partial)
        except OSError as error:
            raise _write_failed("--out", out, error) from None
        print(
            f"centrobench speed: {'terminated (SIGTERM)' if exc.terminated else 'interrupted'}; "
            f"the {len(exc.trials)} walks that had ended are in {partial} (the searches are "
            "incomplete: no table is written)",
            file=sys.stderr,
        )
        return 143 if exc.terminated else 130
    table = speed_table(trials)
    with _pd_options():
        print(table.to_string(index=False))
    try:
        trials.to_parquet(out / "speed.parquet")
        (out / "speed.md").write_text(table.to_markdown(index=False, floatfmt=".4g") + "\n")
        (out / "speed.partial.parquet").unlink(missing_ok=True)  # an interrupted run's
    except OSError as exc:
        raise _write_failed("--out", out, exc) from None
    return 0


def _replay(args: argparse.Namespace) -> int:
    from bench.replay import ReplayError, replay

    _output_file("--out", args.out, make_parents=True)  # before the episode runs again
    if str(args.out).lower().endswith(".gif") and args.fps < GIF_MIN_FPS:
        raise UsageError(
            f"--fps {args.fps:g}: a GIF's frame lasts at most 655 s, so a .gif needs --fps of "
            f"at least {GIF_MIN_FPS:g}"
        )
    try:
        path = replay(args.results, args.episode_id, args.out, fps=args.fps)
    except ReplayError as exc:
        raise UsageError(str(exc)) from None
    except OSError as exc:
        raise _write_failed("--out", args.out, exc) from None
    print(path)
    return 0


def _make_replays(results: list[str], out: str) -> None:
    """The replays the report offers (`reports.robustness.replay_choices`), into
    OUT/replays/: each episode runs again; one that cannot be replayed is reported on stderr
    and left out."""
    from bench.replay import replay
    from reports.build import read_all_results
    from reports.robustness import REPLAY_FOLDER, replay_choices

    episodes, _, _ = read_all_results([Path(r) for r in results])
    made = set()
    for choice in replay_choices(episodes).itertuples():
        if choice.episode_id in made:  # a walk that is also the first fall: drawn once
            continue
        made.add(choice.episode_id)
        target = Path(out) / REPLAY_FOLDER / f"{choice.episode_id}.html"
        print(f"replay of {choice.controller} ({choice.what}) -> {target}", file=sys.stderr)
        try:
            replay(choice.results_dir or results[0], choice.episode_id, target)
        except Exception as exc:  # a replay that fails (ReplayError or else) leaves out itself
            print(f"centrobench: replay of {choice.episode_id} left out: {exc}", file=sys.stderr)


def _report(args: argparse.Namespace) -> int:
    from reports.build import build_report

    out = args.out or args.results[0]
    if Path(out).is_file():
        raise UsageError(f"--out {out} is a file; give a folder for the report")
    try:
        if args.replays:
            _make_replays(args.results, out)
        paths = build_report(args.results, out, benchmark_json=args.benchmark_json)
    except FileNotFoundError as exc:
        if exc.filename is None:  # no results: build_report's own one-line message
            raise UsageError(str(exc)) from None
        raise _write_failed("--out", out, exc) from None
    except OSError as exc:
        raise _write_failed("--out", out, exc) from None
    for path in paths:
        print(path)
    return 0


NAMED_OPTIONS = ("out", "estimator", "controller", "planner", "stabilizer", "whole_body", "spec")
"""Options whose empty value would silently mean their default (`_refuse_empty`)."""


def _refuse_empty(args: argparse.Namespace) -> None:
    """An option given as "" is refused: `--estimator ""` ran with the default estimator and
    `--out ""` wrote to the default folder (or the working directory) without a word."""
    for name in NAMED_OPTIONS:
        value = getattr(args, name, None)
        if isinstance(value, str) and not value.strip():
            flag = "--" + name.replace("_", "-")
            raise UsageError(f"{flag} is empty; give a value or leave the option out")


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return 0
        _refuse_empty(args)
        commands = {
            "robot": _robot,
            "check": _check,
            "demo": _demo,
            "run": _run,
            "list": _list,
            "compare": _compare,
            "sweep": _sweep,
            "report": _report,
            "replay": _replay,
            "speed": _speed,
        }
        status = commands[args.command](args)
        sys.stdout.flush()  # a closed pipe (`| head -1`) shows here, not at interpreter exit
        return status
    except BrokenPipeError:
        # the reader of stdout went away (`centrobench robot --json | head -1`): stop quietly,
        # as the Python docs advise (signal module, "Note on SIGPIPE"): point stdout at
        # devnull so that the flush at exit does not fail again, and exit 1 like Python does
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except (OSError, ValueError):  # stdout is no file (captured in-process)
            pass
        return 1
    except (UsageError, MissingDependencyError, ValueError, KeyError) as exc:
        # a KeyError's str() quotes its message; a UnicodeDecodeError's args[0] is the codec
        message = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        text = _one_line(str(message)) or type(exc).__name__
        print(f"centrobench: error: {text}", file=sys.stderr)
        return 2


def _one_line(message: str) -> str:
    """`message` on one line: its lines joined with a space (a simulator's error can span
    several)."""
    return " ".join(line.strip() for line in message.splitlines() if line.strip())


if __name__ == "__main__":
    sys.exit(main())
