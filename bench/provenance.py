"""What every result records about where it came from: package versions, git commit, CPU."""

from __future__ import annotations

import functools
import os
import platform
import socket
import subprocess
import sys
from importlib import metadata
from pathlib import Path

PACKAGES = (
    "centrobench",
    "mujoco",
    "pybullet",
    "pin",
    "qpsolvers",
    "daqp",
    "piqp",
    "osqp",
    "clarabel",
    "proxsuite",
    "quadprog",
    "numpy",
    "scipy",
)


@functools.cache
def versions() -> dict[str, str | None]:
    result: dict[str, str | None] = {}
    for package in PACKAGES:
        try:
            result[package] = metadata.version(package)
        except metadata.PackageNotFoundError:
            result[package] = None
    return result


@functools.cache
def git_commit() -> str | None:
    """The checkout's commit (with "-dirty" if it has uncommitted changes), or None."""

    def git(*args: str) -> str:
        root = Path(__file__).resolve().parents[1]
        return subprocess.run(
            ["git", *args], cwd=root, capture_output=True, text=True, timeout=10, check=True
        ).stdout.strip()

    try:
        commit = git("rev-parse", "HEAD")
        dirty = git("status", "--porcelain", "--untracked-files=no")
    except (OSError, subprocess.SubprocessError):
        return None
    return commit + ("-dirty" if dirty else "")


@functools.cache
def cpu() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def worker() -> str:
    """Where this episode runs: "ray:<node id>:<pid>" inside a Ray worker, else
    "<host name>:<pid>" (so that a sweep's rows say which node and process ran them)."""
    ray = sys.modules.get("ray")
    if ray is not None and ray.is_initialized():
        return f"ray:{ray.get_runtime_context().get_node_id()}:{os.getpid()}"
    return f"{socket.gethostname()}:{os.getpid()}"


def provenance() -> dict:
    return {
        "versions": versions(),
        "git_commit": git_commit(),
        "cpu": cpu(),
        "worker": worker(),
    }
