"""The robots a run can choose by name: `--robot NAME` on the command line, `robots = [...]` in a
sweep spec, `EpisodeSpec.robot`. Unknown names are answered with the known ones.

- `centrobench_humanoid`: the generated humanoid (`robots.humanoid`), any `--scale`.
- `jvrc1`: JVRC-1 from the `jvrc-description` package (`robots.jvrc1`), one size only.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from robots.spec import RobotDescription

DEFAULT_ROBOT = "centrobench_humanoid"


@dataclass(frozen=True)
class RobotEntry:
    """A registered robot: `build(scale, total_mass)` gives its description; `scalable` False
    means only scale 1 (and its own mass) exist."""

    name: str
    description: str
    build: Callable[[float, float | None], RobotDescription]
    scalable: bool


def _humanoid(scale: float, total_mass: float | None) -> RobotDescription:
    from robots.humanoid import humanoid

    return humanoid(scale, total_mass)


def _jvrc1(scale: float, total_mass: float | None) -> RobotDescription:
    from robots.jvrc1 import jvrc1

    return jvrc1()


ROBOTS: dict[str, RobotEntry] = {
    entry.name: entry
    for entry in (
        RobotEntry(
            "centrobench_humanoid",
            "the generated humanoid: 1.60 m, 58.4 kg, 24 joints at scale 1 (any --scale)",
            _humanoid,
            True,
        ),
        RobotEntry(
            "jvrc1",
            "JVRC-1 (jvrc-description 1.1.1): 62.4 kg, 29 joints (neck and fingers locked)",
            _jvrc1,
            False,
        ),
    )
}


def robot_entry(name: str) -> RobotEntry:
    """The entry `name`; KeyError naming the known robots otherwise."""
    if name not in ROBOTS:
        raise KeyError(f"unknown robot {name!r}; choose one of: {', '.join(sorted(ROBOTS))}")
    return ROBOTS[name]


def make_robot(
    name: str = DEFAULT_ROBOT, scale: float = 1.0, total_mass: float | None = None
) -> RobotDescription:
    """The description of robot `name` at `scale` (with `total_mass` [kg] if given). A robot
    that cannot be scaled refuses any scale but 1 and any mass with one ValueError line."""
    entry = robot_entry(name)
    if not entry.scalable and (scale != 1.0 or total_mass is not None):
        raise ValueError(
            f"robot {name!r} has one size and mass: scale must be 1 and no mass given "
            f"(got scale {scale:g}, mass {total_mass})"
        )
    return entry.build(scale, total_mass)
