"""The `centrobench` command line.

Bad input (an unknown name, a non-positive number, a missing optional package) exits with
status 2 and one line on stderr that says what is valid; never a traceback.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Sequence

import numpy as np

from sims.base import SIMULATORS, MissingDependencyError


class UsageError(Exception):
    """Bad command-line input: reported as one line, exit status 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, no usage dump
        raise UsageError(message)


def _number(kind: str, minimum: float | None = None, strict: bool = False):
    """An argparse type: a finite float, above `minimum` (strict) or at least it."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{kind} must be a number, got {text!r}") from None
        if not np.isfinite(value):
            raise argparse.ArgumentTypeError(f"{kind} must be finite, got {text}")
        if minimum is not None and (value <= minimum if strict else value < minimum):
            bound = "a positive number" if strict and minimum == 0 else f">= {minimum:g}"
            raise argparse.ArgumentTypeError(f"{kind} must be {bound}, got {text}")
        return value

    return parse


def _positive(kind: str):
    return _number(kind, 0.0, strict=True)


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
        type=_positive("--scale"),
        default=1.0,
        help="length scale (1 = 1.60 m); mass scales with its cube",
    )
    robot.add_argument(
        "--mass",
        type=_positive("--mass"),
        default=None,
        help="total mass [kg] instead of the scaled one",
    )
    robot.add_argument("--json", action="store_true", help="one JSON object on stdout")

    run = commands.add_parser("run", help="run one episode and summarise it")
    run.add_argument("--planner", required=True, help="a planner name (see `centrobench list`)")
    run.add_argument("--stabilizer", required=True, help="a stabilizer name")
    run.add_argument("--sim", required=True, type=_one_simulator, help="mujoco or pybullet")
    run.add_argument("--scenario", required=True, help="a scenario name")
    run.add_argument(
        "--duration",
        type=_positive("--duration"),
        default=None,
        help="simulated seconds (default: the scenario's)",
    )
    run.add_argument(
        "--push-impulse",
        type=_number("--push-impulse", 0.0),
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
        "--estimator", default="ground_truth", help="ground_truth (default) or proprioceptive"
    )
    run.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    run.add_argument("--out", default=None, help="write the per-period trace to FILE.parquet")
    run.add_argument("--json", action="store_true", help="the summary as one JSON object")

    commands.add_parser("list", help="the registered planners, stabilizers, scenarios, sims")

    compare = commands.add_parser(
        "compare",
        help="Murooka Sec. V-G: planners side by side (projection errors, feedback, timing)",
    )
    compare.add_argument(
        "--planners",
        required=True,
        type=lambda text: [n.strip() for n in text.split(",") if n.strip()],
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
    compare.add_argument(
        "--horizons",
        type=lambda text: [int(n) for n in text.split(",")],
        default=None,
        help="also time linear_mpc's update for these horizon lengths, e.g. 10,20,40,80",
    )
    compare.add_argument(
        "--formulations",
        type=lambda text: [n.strip() for n in text.split(",")],
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
        type=_positive("--duration"),
        default=3.0,
        help="simulated seconds (default 3)",
    )
    demo.add_argument("--scale", type=_positive("--scale"), default=1.0, help="length scale")

    sweep = commands.add_parser(
        "sweep",
        help="run a grid of episodes (TOML spec or flags) on local processes or Ray",
    )
    sweep.add_argument("--spec", default=None, help="a TOML sweep spec (see bench/sweep_spec.py)")
    _names_arg = lambda text: [n.strip() for n in text.split(",") if n.strip()]  # noqa: E731
    _numbers_arg = lambda text: [float(n) for n in text.split(",") if n.strip()]  # noqa: E731
    sweep.add_argument("--controllers", type=_names_arg, help="planner+stabilizer names, or all")
    sweep.add_argument("--sims", type=_names_arg, help="mujoco, pybullet or all")
    sweep.add_argument("--scenarios", type=_names_arg, help="scenarios without a push")
    sweep.add_argument("--push-dv", type=_numbers_arg, help="push levels dv = J / m [m/s]")
    sweep.add_argument("--push-count", type=int, help="pushes per level (default 20)")
    sweep.add_argument("--push-phases", type=_names_arg, help="standing, walking")
    sweep.add_argument("--push-seed", type=int, help="seed of the push directions (default 0)")
    sweep.add_argument("--seeds", type=lambda t: [int(n) for n in t.split(",")], help="seeds")
    sweep.add_argument("--scales", type=_numbers_arg, help="robot length scales")
    sweep.add_argument("--frictions", type=_numbers_arg, help="friction coefficients")
    sweep.add_argument("--duration", type=float, help="seconds of the plain scenarios")
    sweep.add_argument("--name", default=None, help="the sweep's name")
    sweep.add_argument("--out", default=None, help="result directory (default results/NAME)")
    sweep.add_argument("--executor", default="local", choices=("local", "ray"))
    sweep.add_argument("--address", default=None, help="Ray cluster address (with --executor ray)")
    sweep.add_argument("--workers", type=int, default=None, help="processes (default: cores)")
    sweep.add_argument("--resume", action="store_true", help="run only the missing episodes")
    sweep.add_argument("--overwrite", action="store_true", help="delete earlier results in OUT")
    sweep.add_argument("--no-progress", action="store_true", help="no progress bar")

    report = commands.add_parser("report", help="build report.md and report.html from results")
    report.add_argument("results", help="a sweep's result directory")
    report.add_argument("--out", default=None, help="output directory (default: RESULTS)")
    report.add_argument(
        "--benchmark-json", default=None, help="a pytest-benchmark JSON file to add as a table"
    )
    return parser


def _robot(args: argparse.Namespace) -> int:
    from bench.robot_check import robot_report
    from robots.humanoid import humanoid

    report = robot_report(humanoid(args.scale, total_mass=args.mass))
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


def _validate_names(args: argparse.Namespace) -> None:
    """Unknown planner / stabilizer / scenario / estimator: one line with the known names."""
    from bench.scenarios import SCENARIOS
    from planners.base import planner_spec
    from robots.estimators import ESTIMATORS
    from stabilizers.base import stabilizer_spec

    planner_spec(args.planner)
    stabilizer_spec(args.stabilizer)
    if args.scenario not in SCENARIOS:
        raise UsageError(
            f"unknown scenario {args.scenario!r}; choose one of: {', '.join(SCENARIOS)}"
        )
    if args.estimator not in ESTIMATORS:
        raise UsageError(
            f"unknown estimator {args.estimator!r}; choose one of: {', '.join(ESTIMATORS)}"
        )


def _compare(args: argparse.Namespace) -> int:
    from bench.compare import compare, horizon_timing
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
    formulations = args.formulations or list(FORMULATIONS)
    for name in formulations:
        if name not in FORMULATIONS:
            raise UsageError(
                f"unknown formulation {name!r}; choose one of: {', '.join(FORMULATIONS)}"
            )
    if args.horizons is not None and any(h < 1 for h in args.horizons):
        raise UsageError(f"--horizons must be positive sample counts, got {args.horizons}")
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

    table = compare(args.planners, args.scenario, args.sims, args.stabilizer, progress=progress)
    with _pd_options():
        print(table.drop(columns=["error"]).to_string(index=False, float_format="%.4g"))
    failed = table[table["status"] != "ok"]
    for _, row in failed.iterrows():
        print(f"{row['planner']} on {row['sim']}: {row['status']}: {row['error']}")
    if args.out:
        table.to_csv(args.out, index=False)
    if args.horizons:
        timing = horizon_timing(formulations, args.horizons)
        print()
        with _pd_options():
            print(
                timing.pivot(
                    index="formulation", columns="horizon_samples", values="median_ms"
                ).to_string(float_format="%.2f")
            )
        if args.out:
            timing.to_csv(args.out.replace(".csv", "") + "_horizons.csv", index=False)
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
    )
    result = run_episode(spec)
    summary = summary_json_ready(result.summary)
    if args.out:
        from bench.results import write_trace

        write_trace(result.trace, summary, args.out)
    if args.json:
        print(json.dumps(summary))
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
        print(
            f"simulated {summary['duration']:.2f} s, real-time factor "
            f"{summary['real_time_factor'] or 0:.2f}, CoM error RMS "
            f"{(summary['com_error_rms_m'] or 0) * 1e3:.2f} mm"
        )
        print(f"{'stage':<16} {'median us':>10} {'p99 us':>10} {'max us':>10}")
        for stage, stats in summary["latency_us"].items():
            print(
                f"{stage:<16} {stats['median']:>10.1f} {stats['p99']:>10.1f} {stats['max']:>10.1f}"
            )
    return 0 if summary["status"] != "error" else 1


def _list(args: argparse.Namespace) -> int:
    from bench.scenarios import SCENARIOS
    from planners.base import PLANNERS
    from robots.estimators import ESTIMATORS
    from stabilizers.base import STABILIZERS

    sections = {
        "planners": {n: PLANNERS.get(n).description for n in PLANNERS.names()},
        "stabilizers": {n: STABILIZERS.get(n).description for n in STABILIZERS.names()},
        "scenarios": {n: s.description for n, s in SCENARIOS.items()},
        "simulators": {n: "" for n in SIMULATORS},
        "estimators": {n: "" for n in ESTIMATORS},
    }
    for title, entries in sections.items():
        print(f"{title}:")
        for name, description in entries.items():
            print(f"  {name:<16} {description}".rstrip())
    return 0


def _demo(args: argparse.Namespace) -> int:
    from robots.humanoid import humanoid
    from robots.model import RobotModel
    from robots.scene import Scene
    from sims.base import make_simulator

    robot = humanoid(args.scale)
    model = RobotModel(robot)
    initial = model.standing_state()
    command = model.hold_command(initial)
    weight = robot.total_mass * 9.81
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
    """The spec's fields: from --spec (TOML), overridden by the flags given."""
    import tomllib

    data: dict = {}
    if args.spec is not None:
        from pathlib import Path

        try:
            data = tomllib.loads(Path(args.spec).read_text())
        except FileNotFoundError:
            raise UsageError(f"sweep spec {args.spec} does not exist") from None
        except tomllib.TOMLDecodeError as exc:
            raise UsageError(f"sweep spec {args.spec} is not valid TOML: {exc}") from None
    for flag in ("controllers", "sims", "scenarios", "seeds", "scales", "frictions", "duration"):
        value = getattr(args, flag)
        if value is not None:
            data[flag] = value
    if args.name is not None:
        data["name"] = args.name
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
    if push is not None:
        data["push"] = push
    return data


def _sweep(args: argparse.Namespace) -> int:
    from bench.sweep import run_sweep
    from bench.sweep_spec import SpecError, spec_from_mapping

    try:
        spec = spec_from_mapping(_sweep_mapping(args))
    except SpecError as exc:
        raise UsageError(str(exc)) from None
    if args.workers is not None and args.workers < 1:
        raise UsageError(f"--workers must be >= 1, got {args.workers}")
    if args.resume and args.overwrite:
        raise UsageError("--resume and --overwrite exclude each other")
    out = args.out or f"results/{spec.name}"
    total = len(spec.episodes())
    print(f"sweep {spec.name!r}: {total} episodes -> {out} ({args.executor})", file=sys.stderr)
    try:
        frame = run_sweep(
            spec,
            out,
            executor=args.executor,
            workers=args.workers,
            address=args.address,
            resume=args.resume,
            overwrite=args.overwrite,
            progress=not args.no_progress,
        )
    except FileExistsError as exc:
        raise UsageError(str(exc)) from None
    except ImportError as exc:
        raise UsageError(str(exc)) from None
    except KeyboardInterrupt:
        print(
            f"\ninterrupted: the finished episodes are in {out}; "
            "run the same command with --resume to complete the sweep",
            file=sys.stderr,
        )
        return 130
    counts = frame["status"].value_counts().to_dict()
    print(
        f"{len(frame)} episodes in {out}: "
        + ", ".join(f"{n} {status}" for status, n in sorted(counts.items())),
        file=sys.stderr,
    )
    return 0


def _report(args: argparse.Namespace) -> int:
    from reports.build import build_report

    out = args.out or args.results
    try:
        paths = build_report(args.results, out, benchmark_json=args.benchmark_json)
    except FileNotFoundError as exc:
        raise UsageError(str(exc)) from None
    for path in paths:
        print(path)
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return 0
        commands = {
            "robot": _robot,
            "demo": _demo,
            "run": _run,
            "list": _list,
            "compare": _compare,
            "sweep": _sweep,
            "report": _report,
        }
        return commands[args.command](args)
    except (UsageError, MissingDependencyError, ValueError, KeyError) as exc:
        message = exc.args[0] if exc.args else str(exc)
        print(f"centrobench: error: {message}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
