"""The command line: help, the robot report, the demo, and one-line errors for bad input."""

import json
import subprocess
import sys

import pytest

from bench.cli import main
from robots.humanoid import NOMINAL_MASS_KG
from sims import base


def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "bench.cli", *args],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )


def test_help_lists_the_commands():
    result = run_cli("--help")
    assert result.returncode == 0
    for command in ("robot", "demo"):
        assert command in result.stdout


@pytest.mark.parametrize("scale", [1.0, 1.2])
def test_robot_json_shows_identical_models(scale):
    result = run_cli("robot", "--scale", str(scale), "--json")
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert set(report["models"]) == {"pinocchio", "mujoco", "pybullet"}
    for info in report["models"].values():
        assert info["total_mass_kg"] == pytest.approx(NOMINAL_MASS_KG * scale**3, rel=1e-9)
        assert info["dof"] == 26
    for gap in report["max_discrepancy_vs_pinocchio"].values():
        assert gap["mass_rel"] <= 1e-9
        assert gap["com_m"] <= 1e-9
        assert gap["inertia_rel"] <= 1e-9
        assert gap["same_joint_order"]
    assert report["height_m"] == pytest.approx(1.60 * scale)


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (["robot", "--scale", "-1"], "positive"),
        (["robot", "--scale", "abc"], "must be a number"),
        (["robot", "--mass", "0"], "positive"),
        (["demo", "--sim", "gazebo"], "choose from: mujoco, pybullet"),
        (["nonsense"], "choose from 'robot', 'run', 'list', 'compare', 'demo'"),
    ],
)
def test_bad_input_is_one_clear_line(args, expected):
    result = run_cli(*args)
    assert result.returncode == 2
    lines = [line for line in result.stderr.splitlines() if "build time" not in line]
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("centrobench: error:")
    assert expected in lines[0]
    assert "Traceback" not in result.stderr


def test_missing_simulator_package_names_the_extra(monkeypatch, capsys):
    spec = base.SIMULATORS["mujoco"]
    broken = base.SimulatorSpec(spec.name, spec.module, spec.cls, "no_such_package_xyz", "mujoco")
    monkeypatch.setitem(base.SIMULATORS, "mujoco", broken)
    assert main(["demo", "--sim", "mujoco", "--duration", "0.1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert "pip install 'centrobench[mujoco]'" in err[0]


def test_demo_stands_in_both_simulators(capsys):
    assert main(["demo", "--duration", "0.5"]) == 0
    out = capsys.readouterr().out.splitlines()
    rows = {line.split()[0]: line.split() for line in out[2:]}
    assert set(rows) == {"mujoco", "pybullet"}
    for row in rows.values():
        assert row[1] == "no"  # did not fall
        assert float(row[2]) == pytest.approx(1.0, abs=0.02)  # feet carry m g
