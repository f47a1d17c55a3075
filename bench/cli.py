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


def _positive(kind: str):
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{kind} must be a number, got {text!r}") from None
        if not np.isfinite(value) or value <= 0:
            raise argparse.ArgumentTypeError(f"{kind} must be a positive number, got {text}")
        return value

    return parse


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


def _demo(args: argparse.Namespace) -> int:
    from robots.humanoid import humanoid
    from robots.model import RobotModel
    from sims.base import make_simulator
    from sims.scene import Scene

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


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return 0
        return {"robot": _robot, "demo": _demo}[args.command](args)
    except (UsageError, MissingDependencyError, ValueError, KeyError) as exc:
        message = exc.args[0] if exc.args else str(exc)
        print(f"centrobench: error: {message}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
