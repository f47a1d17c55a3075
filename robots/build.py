"""Generated robot files: URDF and MJCF written once per description into the build cache.

The cache folder is `$CENTROBENCH_BUILD_DIR` if set, else `build/` in a source checkout, else
`~/.cache/centrobench`. File names carry a hash of the content, so a changed spec never reads a
stale file, and files are written atomically (parallel workers may generate the same robot).
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

from robots.mjcf import to_mjcf
from robots.spec import RobotDescription
from robots.urdf import to_urdf


def build_dir() -> Path:
    """The folder generated files go to (created if missing)."""
    env = os.environ.get("CENTROBENCH_BUILD_DIR")
    if env:
        path = Path(env)
    else:
        checkout = Path(__file__).resolve().parents[1]
        if (checkout / "pyproject.toml").exists():
            path = checkout / "build"
        else:
            path = Path.home() / ".cache" / "centrobench"
    path.mkdir(parents=True, exist_ok=True)
    return path


def _write_once(path: Path, text: str) -> Path:
    if path.exists():
        return path
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.replace(tmp, path)
    return path


@dataclass(frozen=True)
class RobotFiles:
    urdf: Path
    mjcf: Path


def generate(robot: RobotDescription) -> RobotFiles:
    """Write (if needed) and return the URDF and MJCF of `robot`."""
    urdf, mjcf = to_urdf(robot), to_mjcf(robot)
    digest = hashlib.sha256((urdf + mjcf).encode()).hexdigest()[:12]
    folder = build_dir() / "robots"
    folder.mkdir(parents=True, exist_ok=True)
    stem = f"{robot.name}_s{robot.scale:g}_{digest}"
    return RobotFiles(
        urdf=_write_once(folder / f"{stem}.urdf", urdf),
        mjcf=_write_once(folder / f"{stem}.xml", mjcf),
    )
