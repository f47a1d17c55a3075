"""`make bench-full` (bench/specs/main_full.toml, about 7 hours) shrunk to minutes: every one
of its protocols as written, but with two controllers in MuJoCo, the first push level, two
pushes and two replicas, and the first magnitude of each robustness dimension; then the
report. What it guards: that the publication job runs through and reports every protocol,
not what the full job finds (first run by hand on 2026-11-29: 171 episodes, no error, in
5 min 13 s on 2 workers)."""

from __future__ import annotations

import copy
from pathlib import Path

import pytest

from bench.dataset import read_episodes
from bench.sweep import run_sweep
from bench.sweep_spec import read_spec_file, spec_from_mapping
from reports.build import build_report

FULL = Path(__file__).parents[2] / "bench" / "specs" / "main_full.toml"
CONTROLLERS = ["preview_control+centroidal_feedback", "hold+posture"]


def _shrunk(data: dict) -> dict:
    """main_full.toml's fields with every protocol kept, each made small."""
    small = copy.deepcopy(data)
    small.update(name="full_smoke", controllers=CONTROLLERS, sims=["mujoco"])
    for protocol in small["protocols"]:
        if "controllers" in protocol and protocol["controllers"] == ["all"]:
            protocol["controllers"] = CONTROLLERS
        push = protocol.get("push")
        if push:
            push["dv"] = push["dv"][:1]
            push["count"] = 2
            push["replicas"] = min(push.get("replicas", 1), 2)
            if "swing_fractions" in push:
                push["swing_fractions"] = push["swing_fractions"][:2]
            if "directions" in push:
                push["directions"] = push["directions"][:2]
        for dimension, magnitudes in protocol.get("robustness", {}).items():
            protocol["robustness"][dimension] = magnitudes[:1]
    return small


@pytest.mark.slow
def test_every_protocol_of_the_full_job_runs_and_is_reported(tmp_path):
    data = read_spec_file(FULL)
    spec = spec_from_mapping(_shrunk(data))
    assert [p.name for p in spec.protocols] == [p["name"] for p in data["protocols"]]
    run_sweep(spec, tmp_path / "out", workers=2, progress=False)
    rows = read_episodes(tmp_path / "out")
    assert len(rows) == len(spec.episodes())
    assert not rows["status"].isin(["error", "timeout"]).any()
    # every kind of episode the full job has: the walks, both push phases with their levels
    # and replicas, the motions, the hierarchy, JVRC-1, every robustness dimension
    assert {"walk", "stand_push", "walk_push", "hand_wall", "reach", "reach_push"} <= set(
        rows["scenario"]
    )
    assert set(rows["replica"].dropna()) == {0, 1}
    assert set(rows["robot"]) == {"centrobench_humanoid", "jvrc1"}
    (robustness,) = [p["robustness"] for p in data["protocols"] if "robustness" in p]
    perturbed = set(rows["perturbation"].dropna()) - {"nominal"}
    assert perturbed == {f"{name}={values[0]}" for name, values in robustness.items()}
    report = tmp_path / "out" / "report.md"
    build_report(tmp_path / "out", tmp_path / "out")
    text = report.read_text()
    for section in (
        "## 1. Which pushes each controller survives",
        "## 3. The papers' own benchmarks",
        "## 4. What each controller costs per control period",
        "## Robust push thresholds",
        "## Walking pushes by timing and direction",
        "## Degradation along the robustness dimensions",
        "## Reaching tests (Sherikov et al. Tests 1-2)",
    ):
        assert section in text, section
