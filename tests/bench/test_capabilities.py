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


INERTIA_ROWS = ("direct_centroidal", "direct_centroidal/lagged_inertia")


def test_inertia_controlled_rows_read_the_tilt_that_only_the_five_mass_estimators_give():
    """Eqs. 12-15 feed back the inertia axes' tilt, which only the five-mass filters estimate
    (Ficht & Behnke's, Sec. 3.2's second filter, and ours, `five_mass_kalman_com`); the rows
    without inertia control read nothing more than any estimator gives."""
    from estimators.base import ESTIMATORS

    gives = {n: ESTIMATORS.get(n).gives for n in ESTIMATORS.names()}
    assert {n for n, g in gives.items() if "inertia_tilt" in g} == {
        "five_mass_kalman",
        "five_mass_kalman_com",
    }
    for name in (*INERTIA_ROWS, "direct_centroidal/bounded_inertia", "direct_centroidal/inertia"):
        assert controller_spec(name).needs_state == {"inertia_tilt"}, name
    for name in ("direct_centroidal/no_inertia", "direct_centroidal/leaky", "hold+posture"):
        assert not controller_spec(name).needs_state, name


def test_refusal_names_the_estimators_that_would_do():
    from bench.controllers import estimator_refusal

    full = controller_spec("direct_centroidal")
    assert estimator_refusal(full, "ground_truth") == (
        "direct_centroidal cannot run with the estimator ground_truth: it reads inertia_tilt "
        "(the tilt of the inertia's principal axes and its acceleration "
        "(RobotState.inertia_tilt, Ficht & Behnke eqs. 12-15)), which only five_mass_kalman, "
        "five_mass_kalman_com give"
    )
    assert estimator_refusal(full, "five_mass_kalman") is None
    assert (
        estimator_refusal(controller_spec("direct_centroidal/no_inertia"), "ground_truth") is None
    )
    # through `refusal` as well; without an estimator none is checked
    assert refusal(full, "stand", "kinematic_inertial").startswith(
        "direct_centroidal cannot run with the estimator kinematic_inertial"
    )
    assert refusal(full, "stand") is None


def test_sweep_with_an_estimator_without_the_tilt_records_n_a_rows(tmp_path: Path, monkeypatch):
    """`estimator = "ground_truth"` for every controller: the inertia-controlled rows are "n/a"
    with the reason before any episode starts; the row without inertia control runs."""
    log = tmp_path / "started.txt"
    monkeypatch.setenv(_ORDER_ENV, str(log))
    spec = spec_from_mapping(
        {
            "controllers": [*INERTIA_ROWS, "direct_centroidal/no_inertia"],
            "sims": ["mujoco"],
            "scenarios": ["stand"],
            "duration": 0.3,
            "estimator": "ground_truth",
            "estimator_for_every_controller": True,
        }
    )
    run_sweep(spec, tmp_path / "out", workers=1, progress=False, work=recording_work)
    rows = read_episodes(tmp_path / "out").set_index("controller")
    for name in INERTIA_ROWS:
        assert rows.loc[name, "status"] == "n/a"
        assert rows.loc[name, "error"].startswith(
            f"n/a: {name} cannot run with the estimator ground_truth: it reads inertia_tilt"
        )
    assert rows.loc["direct_centroidal/no_inertia", "error"].endswith("not run: order test")
    assert log.read_text().splitlines() == ["stand 0.3"]  # only the one without inertia control


def test_run_refuses_an_estimator_without_the_tilt_with_one_line(capsys):
    from bench.cli import main

    argv = ["run", "--controller", "direct_centroidal", "--sim", "mujoco", "--scenario", "stand"]
    assert main([*argv, "--estimator", "ground_truth"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert "direct_centroidal cannot run with the estimator ground_truth" in err[0]
