"""Replays (`centrobench replay`): an episode of a sweep runs again, ends as recorded, and its
page holds every recorded period, drawn at one frame per period when asked."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from bench.cli import main
from bench.replay import ReplayError, check_same_ending, frame_rows, replay
from bench.sweep import run_sweep
from bench.sweep_spec import spec_from_mapping

DURATION = 0.1  # [s]: 50 control periods


@pytest.fixture(scope="module")
def sweep(tmp_path_factory) -> tuple[Path, str]:
    root = tmp_path_factory.mktemp("replay") / "results"
    spec = spec_from_mapping(
        {
            "controllers": ["hold+posture"],
            "sims": ["mujoco"],
            "scenarios": ["stand", "walk"],
            "duration": DURATION,
        }
    )
    rows = run_sweep(spec, root, workers=1, progress=False)
    return root, str(rows["episode_id"].iloc[0])


def test_a_replay_draws_every_recorded_period(sweep, tmp_path):
    root, episode = sweep
    out = replay(root, episode, tmp_path / "stand.html", fps=500.0)  # a frame per period
    page = out.read_text()
    data = json.loads(
        re.search(r"<script type='application/json' id='episode-trace'>(.*?)</script>", page)[1]
    )
    periods = round(DURATION / 0.002)
    assert len(data["rows"]) == periods
    times = [row[data["columns"].index("time")] for row in data["rows"]]
    assert times == pytest.approx([0.002 * k for k in range(periods)])
    assert len(set(re.findall(r"frames\[(\d+)\]", page))) == periods
    # joint positions of every period are in it (the configuration the frames show)
    assert sum(c.startswith("q_true_") for c in data["columns"]) == 24


def test_frames_are_taken_at_the_requested_rate_and_include_the_last_period():
    import pandas as pd

    trace = pd.DataFrame({"time": [0.002 * k for k in range(500)]})
    rows = frame_rows(trace, 20.0)
    assert rows[0] == 0
    assert rows[-1] == 499
    assert list(rows[:3]) == [0, 25, 50]  # every 0.05 s


def test_a_replay_that_ends_otherwise_than_recorded_is_refused():
    with pytest.raises(ReplayError, match="ended 'ok', recorded 'fell'"):
        check_same_ending({"status": "ok", "fall_time": None}, {"status": "fell"})
    with pytest.raises(ReplayError, match=r"fell at 1\.2 s, recorded 1\.3 s"):
        check_same_ending(
            {"status": "fell", "fall_time": 1.2}, {"status": "fell", "fall_time": 1.3}
        )
    check_same_ending({"status": "ok", "fall_time": None}, {"status": "ok", "fall_time": None})


def test_replay_command_refuses_unknown_episodes_and_files_in_one_line(sweep, capsys, tmp_path):
    root, episode = sweep
    assert main(["replay", str(root), "nope", "--out", str(tmp_path / "x.html")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"centrobench: error: episode 'nope' is not in the sweep recorded in {root}"]
    assert main(["replay", str(root), episode, "--out", str(tmp_path / "x.mp4")]) == 2
    assert "give a .html or .gif file" in capsys.readouterr().err
    assert main(["replay", str(tmp_path), episode, "--out", str(tmp_path / "x.html")]) == 2
    assert "has no sweep.json" in capsys.readouterr().err


@pytest.mark.parametrize("record", ["[1, 2]", '{"name": "x"}', '"spec"'])
def test_replay_of_a_record_without_a_spec_table_says_so(record, tmp_path, capsys):
    (tmp_path / "sweep.json").write_text(record)  # valid JSON of another shape
    assert main(["replay", str(tmp_path), "e1", "--out", str(tmp_path / "x.html")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        f"centrobench: error: {tmp_path}/sweep.json is not a readable sweep record: "
        "it has no 'spec' table"
    ]  # a list's was "list indices must be integers or slices, not str"


def test_report_with_replays_draws_the_walk_once_and_lists_it(sweep, tmp_path, capsys):
    root, _ = sweep
    out = tmp_path / "report"
    assert main(["report", str(root), "--out", str(out), "--replays"]) == 0
    made = sorted((out / "replays").glob("*.html"))
    assert len(made) == 1  # the walk (no episode fell)
    markdown = (out / "report.md").read_text()
    assert f"replays/{made[0].name}" in markdown
