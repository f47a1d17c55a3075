"""Capabilities: a controller declares what it can do, a scenario what it needs; a sweep
records an "n/a" row with the reason for a pair that does not fit (and runs the rest), and
`run` refuses it with one line."""

import os
from pathlib import Path

import pytest

from bench import scenarios
from bench.controllers import CONTROLLERS, controller_spec, refusal
from bench.dataset import read_episodes
from bench.sweep import run_sweep
from bench.sweep_spec import spec_from_mapping
from robots.registry import MULTI_CONTACT
from tests.bench.test_sweep import _ORDER_ENV, recording_work


@pytest.fixture
def multi_contact_scenario(monkeypatch):
    """A scenario that asks for multi-contact (standing, as a stand-in for the walls,
    rails and ladders to come)."""
    spec = scenarios.ScenarioSpec(
        "hands_on_wall",
        scenarios.stand,
        "stand-in for a multi-contact scenario",
        False,
        MULTI_CONTACT,
    )
    monkeypatch.setitem(scenarios.SCENARIOS, spec.name, spec)
    return spec.name


def test_registered_controllers_declare_their_capabilities():
    assert CONTROLLERS["preview_control+centroidal_feedback"].can == MULTI_CONTACT
    assert CONTROLLERS["linear_mpc+centroidal_feedback"].can == MULTI_CONTACT
    assert CONTROLLERS["preview_zmp+dcm"].can == {"flat_ground", "turning"}
    assert CONTROLLERS["hold+posture"].can == {"flat_ground", "turning"}
    assert controller_spec("capturability_hierarchy").can == {"flat_ground"}  # world-axis boxes
    assert "force_torque_sensors" in CONTROLLERS["preview_zmp+dcm"].needs  # damping control
    assert not CONTROLLERS["hold+posture"].needs
    # a combination can only what both of its parts can
    assert controller_spec("preview_control+dcm").can == {"flat_ground", "turning"}
    for controller in CONTROLLERS.values():
        for name in ("stand", "stand_push", "walk", "walk_push", "walk_side"):
            assert refusal(controller, name) is None
        turns = controller.name != "capturability_hierarchy"
        assert (refusal(controller, "walk_turn") is None) == turns


def test_the_hierarchy_refuses_a_turning_walk_with_the_reason():
    """Its footstep rectangles, CoP boxes (eqs. 11-12) and swing sole are in world axes:
    `walk_turn` is refused before the episode (an "n/a" row in a sweep)."""
    assert refusal(controller_spec("capturability_hierarchy"), "walk_turn") == (
        "capturability_hierarchy cannot do turning (walking paths that turn (footholds and "
        "soles yawed along the path)), which walk_turn needs"
    )


def test_sweep_records_n_a_rows_and_runs_the_rest(
    tmp_path: Path, monkeypatch, multi_contact_scenario
):
    log = tmp_path / "started.txt"
    monkeypatch.setenv(_ORDER_ENV, str(log))
    spec = spec_from_mapping(
        {
            "controllers": ["preview_zmp+dcm", "preview_control+centroidal_feedback"],
            "sims": ["mujoco"],
            "scenarios": [multi_contact_scenario],
            "duration": 0.3,
        }
    )
    run_sweep(spec, tmp_path / "out", workers=1, progress=False, work=recording_work)
    rows = read_episodes(tmp_path / "out").set_index("controller")
    refused = rows.loc["preview_zmp+dcm"]
    assert refused["status"] == "n/a"
    assert refused["error"] == (
        "n/a: preview_zmp+dcm cannot do multi_contact (contacts of any limb on any surface "
        "(hands on walls, rails, rungs)), which hands_on_wall needs"
    )
    assert rows.loc["preview_control+centroidal_feedback", "error"].endswith("not run: order test")
    assert log.read_text().splitlines() == [f"{multi_contact_scenario} 0.3"]  # only one started
    assert os.path.exists(tmp_path / "out" / "sweep.json")


def test_run_refuses_a_scenario_the_controller_cannot_do(capsys, multi_contact_scenario):
    from bench.cli import main

    argv = ["run", "--controller", "hold+posture", "--sim", "mujoco"]
    assert main([*argv, "--scenario", multi_contact_scenario]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert "hold+posture cannot do multi_contact" in err[0]
