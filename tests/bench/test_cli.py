"""The command line: help, the robot report, the demo, and one-line errors for bad input."""

import json
import subprocess
import sys

import pytest

from bench.cli import footsteps_file, main
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
        assert info["dof"] == 30
    for gap in report["max_discrepancy_vs_pinocchio"].values():
        assert gap["mass_rel"] <= 1e-9
        assert gap["com_m"] <= 1e-9
        assert gap["inertia_rel"] <= 1e-9
        assert gap["same_joint_order"]
    assert report["height_m"] == pytest.approx(1.60 * scale)


def test_robot_json_shows_jvrc1s_three_models_identical():
    result = run_cli("robot", "--robot", "jvrc1", "--json")
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["robot"] == "jvrc1"
    for info in report["models"].values():
        assert info["total_mass_kg"] == pytest.approx(62.4, rel=1e-9)
        assert info["actuated_joints"] == 29
    for gap in report["max_discrepancy_vs_pinocchio"].values():
        assert max(gap["mass_rel"], gap["com_m"], gap["inertia_rel"]) <= 1e-9
        assert gap["same_bodies"]
        assert gap["same_joint_order"]
        assert gap["joint_limit_rad"] <= 1e-9


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (["robot", "--robot", "atlas"], "unknown robot 'atlas'; choose one of: centrobench"),
        (["robot", "--robot", "jvrc1", "--scale", "2"], "robot 'jvrc1' has one size and mass"),
        (["robot", "--scale", "-1"], "--scale must be in [0.1, 10], got '-1'"),
        (["robot", "--scale", "abc"], "must be a number"),
        (["robot", "--mass", "0"], "--mass must be in [0.001, 1e+06] kg, got '0'"),
        (["demo", "--sim", "gazebo"], "choose from: mujoco, pybullet"),
        (["nonsense"], "choose from 'robot', 'run', 'check', 'list', 'compare', 'demo'"),
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


@pytest.mark.parametrize("robot", ["centrobench_humanoid", "jvrc1"])
def test_demo_stands_in_both_simulators(capsys, robot):
    assert main(["demo", "--duration", "0.5", "--robot", robot]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(robot)
    rows = {line.split()[0]: line.split() for line in out[2:]}
    assert set(rows) == {"mujoco", "pybullet"}
    for row in rows.values():
        assert row[1] == "no"  # did not fall
        assert float(row[2]) == pytest.approx(1.0, abs=0.02)  # feet carry m g


# ------------------------------------------------- bad input refused before anything runs

RUN = ["run", "--planner", "hold", "--stabilizer", "posture", "--sim", "mujoco"]
RUN += ["--scenario", "stand"]
SWEEP = ["sweep", "--controllers", "hold+posture", "--sims", "mujoco", "--scenarios", "stand"]
SEEDS_0_TO_100 = ",".join(str(seed) for seed in range(101))


class Ran(Exception):
    """Raised by the stand-ins of everything that runs: bad input must not get that far."""


def stub_runners(patch: pytest.MonkeyPatch, message: str, error: type[Exception]) -> None:
    """Replace every runner (episode, sweep, comparison, robot report, simulator) by one that
    raises `error(message)`: bad input must not get that far."""
    import bench.compare
    import bench.robot_check
    import bench.runner
    import bench.sweep

    def ran(*args, **kwargs):
        raise error(message)

    for module, name in (
        (bench.runner, "run_episode"),
        (bench.sweep, "run_sweep"),
        (bench.compare, "compare"),
        (bench.compare, "horizon_timing"),
        (bench.robot_check, "robot_report"),
        (base, "make_simulator"),
    ):
        patch.setattr(module, name, ran)


@pytest.fixture
def nothing_runs(monkeypatch, tmp_path):
    """The working directory is an empty tmp folder, and every runner is replaced by one
    that raises `Ran` (`stub_runners`)."""
    stub_runners(monkeypatch, "bad input got as far as running something", Ran)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def refused(argv: list[str], capsys) -> str:
    """Run `main(argv)`, assert exit status 2 and one stderr line; returns that line."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("centrobench: error: ")
    assert "Traceback" not in err
    return lines[0]


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        # item 7/9: durations shorter than a control period or longer than the trace can hold
        ([*RUN, "--duration", "0.001"], "--duration must be in [0.002, 600] s, got '0.001'"),
        ([*RUN, "--duration", "1e12"], "--duration must be in [0.002, 600] s, got '1e12'"),
        (["demo", "--duration", "0.0001"], "--duration must be in [0.002, 600] s, got '0.0001'"),
        ([*SWEEP, "--duration", "0.001"], "--duration must be in [0.002, 600] s"),
        ([*SWEEP, "--duration", "nan"], "--duration must be finite (in [0.002, 600] s)"),
        # seeds outside numpy's [0, 2**32)
        ([*RUN, "--seed", "-1"], "--seed must be an integer in [0, 4294967295], got '-1'"),
        ([*RUN, "--seed", "4294967296"], "--seed must be an integer in [0, 4294967295]"),
        ([*SWEEP, "--seeds", "abc"], "every --seeds value must be an integer in [0, 4294967295]"),
        ([*SWEEP, "--seeds", "0,-1"], "got '-1'"),
        ([*SWEEP, "--push-dv", "0.2", "--push-seed", "-1"], "--push-seed must be an integer in"),
        # robot size and mass
        (["robot", "--scale", "1e-9"], "--scale must be in [0.1, 10], got '1e-9'"),
        (["robot", "--mass", "1e-12"], "--mass must be in [0.001, 1e+06] kg, got '1e-12'"),
        ([*SWEEP, "--scales", "1,1e-9"], "every --scales value must be in [0.1, 10], got '1e-9'"),
        (["demo", "--scale", "inf"], "--scale must be finite"),
        # compare
        (["compare", "--planners", ""], "--planners must be a comma-separated list of planner"),
        (["compare", "--planners", " , "], "--planners must be a comma-separated list"),
        (
            ["compare", "--planners", "hold", "--horizons", "100000"],
            "every --horizons value must be an integer in [1, 100], got '100000'",
        ),
        (
            ["compare", "--planners", "hold", "--horizons", "a"],
            "every --horizons value must be an integer in [1, 100], got 'a'",
        ),
        (["compare", "--planners", "hold", "--horizons", "10,0"], "got '0'"),
        # the other sweep flags
        ([*SWEEP, "--push-dv", "1e307"], "every --push-dv value must be in (0, 100] m/s"),
        ([*SWEEP, "--push-dv", "0.2,abc"], "every --push-dv value must be a number"),
        ([*SWEEP, "--push-dv", ""], "--push-dv must be a comma-separated list of velocity"),
        ([*SWEEP, "--push-dv", "0.2", "--push-count", "0"], "--push-count must be an integer"),
        ([*SWEEP, "--push-dv", "0.2", "--push-count", "2.5"], "in [1, 10000], got '2.5'"),
        ([*SWEEP, "--push-dv", "0.2", "--push-count", "10001"], "in [1, 10000], got '10001'"),
        ([*SWEEP, "--workers", "0"], "--workers must be an integer in [1, 256], got '0'"),
        ([*SWEEP, "--workers", "many"], "--workers must be an integer in [1, 256]"),
        ([*SWEEP, "--frictions", "-1"], "every --frictions value must be in (0, 5], got '-1'"),
        ([*SWEEP, "--frictions", "inf"], "every --frictions value must be finite"),
        ([*SWEEP, "--controllers", ""], "--controllers must be a comma-separated list"),
        # a sweep's name is one plain path component
        ([*SWEEP, "--name", "../../x"], "--name must be 1 to 100 letters, digits"),
        ([*SWEEP, "--name", ""], "got ''"),
        ([*SWEEP, "--name", ".hidden"], "not starting with '.'"),
        ([*SWEEP, "--name", "a/b"], "got 'a/b'"),
        ([*SWEEP, "--name", "x..y"], "without '..'"),
        # robustness dimensions
        ([*SWEEP, "--noise", "foo=1"], "--noise: unknown sensor group 'foo'; groups: encoders"),
        ([*SWEEP, "--noise", "-1"], "'robustness.noise' must be a list of numbers in [0, 1000]"),
        ([*SWEEP, "--delay", "1.5"], "--delay must list integers, got '1.5'"),
        ([*SWEEP, "--payload-kg", "imu=1"], "--payload-kg takes numbers, got 'imu=1'"),
        ([*SWEEP, "--gain-scale", "nan"], "--gain-scale must list finite numbers, got 'nan'"),
        ([*SWEEP, "--mass-error", "1"], "'robustness.mass_error' must be a list of numbers in"),
        ([*SWEEP, "--push-dv", "0.2", "--push-replicas", "0"], "--push-replicas must be an"),
        (
            [*SWEEP, "--push-dv", "0.2", "--push-directions", "sideways"],
            "'push.directions' must be a list of: random",
        ),
        (
            [*SWEEP, "--push-dv", "0.2", "--push-swing-fractions", "1.5"],
            "every --push-swing-fractions value must be in [0, 1], got '1.5'",
        ),
        # the sweep's size, from its axes
        (
            [*SWEEP, "--push-dv", "1", "--push-count", "10000", "--seeds", SEEDS_0_TO_100],
            "1010101 episodes",
        ),
    ],
)
def test_bad_flag_is_refused_before_anything_runs(argv, expected, nothing_runs, capsys):
    line = refused(argv, capsys)
    assert expected in line
    assert list(nothing_runs.iterdir()) == []  # no results/ folder, no file


def test_unwritable_run_out_is_refused_before_the_episode(nothing_runs, capsys):
    (nothing_runs / "file").write_text("")
    line = refused([*RUN, "--duration", "0.01", "--out", "file/trace.parquet"], capsys)
    assert "--out file/trace.parquet: file is not a folder" in line
    line = refused([*RUN, "--duration", "0.01", "--out", str(nothing_runs)], capsys)
    assert f"--out {nothing_runs} is a directory" in line


def test_unwritable_compare_out_is_refused_before_the_episodes(nothing_runs, capsys):
    argv = ["compare", "--planners", "hold", "--sims", "mujoco"]
    line = refused([*argv, "--out", "missing/table.csv"], capsys)
    assert "--out missing/table.csv: folder missing does not exist" in line
    (nothing_runs / "table.csv").mkdir()
    line = refused([*argv, "--out", "table.csv"], capsys)
    assert "--out table.csv is a directory" in line


def test_run_prints_the_summary_before_a_trace_that_cannot_be_written(
    monkeypatch, tmp_path, capsys
):
    import bench.results

    def fail(*args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(bench.results, "write_trace", fail)
    out = tmp_path / "trace.parquet"
    assert main([*RUN, "--duration", "0.01", "--out", str(out)]) == 2
    captured = capsys.readouterr()
    assert captured.out.startswith("hold + posture on mujoco, stand: ok")  # not lost
    assert captured.err.splitlines() == [
        f"centrobench: error: --out {out}: cannot write it: Permission denied"
    ]


def test_spec_that_is_no_toml_file_is_named(nothing_runs, capsys):
    line = refused(["sweep", "--spec", str(nothing_runs)], capsys)
    assert line.endswith(f"sweep spec {nothing_runs} is a directory; give a TOML file")
    (nothing_runs / "binary.toml").write_bytes(b"\xff\xfe\x00name = 1")
    line = refused(["sweep", "--spec", "binary.toml"], capsys)
    assert "sweep spec binary.toml is not UTF-8 text (byte 0xff at offset 0)" in line
    line = refused(["sweep", "--spec", "missing.toml"], capsys)
    assert "sweep spec missing.toml does not exist" in line
    assert sorted(p.name for p in nothing_runs.iterdir()) == ["binary.toml"]


@pytest.mark.parametrize(
    ("content", "expected"),
    [
        ("[1, 2]", "is not pytest-benchmark JSON: an object with a 'benchmarks' list"),
        ("[1, 2]", "got a JSON list"),
        ("{'benchmarks': ", "is not readable JSON: Expecting property name"),
        ('{"benchmarks": [{"name": "x"}]}', "got an object without that"),
        (None, "is not readable JSON: Is a directory"),
    ],
)
def test_bad_benchmark_json_is_named(content, expected, nothing_runs, capsys):
    path = nothing_runs / "bench.json"
    if content is None:
        path.mkdir()
    else:
        path.write_text(content)
    line = refused(["report", "results", "--benchmark-json", str(path)], capsys)
    assert f"benchmark file {path} " in line
    assert expected in line
    assert sorted(p.name for p in nothing_runs.iterdir()) == ["bench.json"]


def test_error_messages_are_collapsed_to_one_line(monkeypatch, capsys):
    import bench.robot_check

    def fail(*args, **kwargs):
        raise ValueError("Error: 'inertia must have positive eigenvalues'\nElement 'torso'")

    monkeypatch.setattr(bench.robot_check, "robot_report", fail)
    line = refused(["robot"], capsys)
    assert line == (
        "centrobench: error: Error: 'inertia must have positive eigenvalues' Element 'torso'"
    )


def test_closed_stdout_pipe_ends_quietly():
    """`centrobench robot --json | head -0`: the reader is gone before the output is
    written; no traceback, exit status 1 (as Python's own on EPIPE)."""
    process = subprocess.Popen(
        [sys.executable, "-m", "bench.cli", "robot", "--json"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    process.stdout.close()  # before the report (about a second) is printed
    _, err = process.communicate(timeout=300)
    assert process.returncode == 1
    assert "Traceback" not in err.decode()
    assert "BrokenPipeError" not in err.decode()


def test_runs_help_names_the_whole_body_layer_it_defaults_to():
    """`--whole-body`'s help says "(default ik_feedforward)" until 2026-12-03; the default
    filled in when only a planner and a stabilizer are given is DEFAULT_WHOLE_BODY."""
    from wholebody.base import DEFAULT_WHOLE_BODY

    result = run_cli("run", "--help")
    assert result.returncode == 0, result.stderr
    assert f"(default {DEFAULT_WHOLE_BODY})" in " ".join(result.stdout.split())


def test_list_shows_every_registry_and_marks_the_defaults():
    from bench.controllers import CONTROLLERS
    from estimators import DEFAULT_ESTIMATOR
    from estimators.base import ESTIMATORS
    from wholebody.base import DEFAULT_WHOLE_BODY, WHOLE_BODY_LAYERS

    result = run_cli("list")
    assert result.returncode == 0, result.stderr
    sections: dict[str, list[str]] = {}
    for line in result.stdout.splitlines():
        if not line.startswith(" "):
            current = sections.setdefault(line.rstrip(":"), [])
        else:
            current.append(line.strip())
    assert set(sections) >= {
        "controllers (planner, stabilizer, whole-body layer)",
        "planners",
        "stabilizers",
        "whole-body layers",
        "estimators",
        "scenarios",
        "simulators",
    }
    for name in CONTROLLERS:
        assert name in sections["controllers (planner, stabilizer, whole-body layer)"]
    for title, registry, default in (
        ("whole-body layers", WHOLE_BODY_LAYERS, DEFAULT_WHOLE_BODY),
        ("estimators", ESTIMATORS, DEFAULT_ESTIMATOR),
    ):
        lines = sections[title]
        assert [line.split()[0] for line in lines] == list(registry.names())
        assert [line.split()[0] for line in lines if line.endswith("(default)")] == [default]
    # what the estimators give beyond the common state, and who reads it
    assert [
        line.split()[0] for line in sections["estimators"] if "(gives: inertia_tilt)" in line
    ] == [
        "five_mass_kalman",
        "five_mass_kalman_com",
    ]


@pytest.fixture
def recorded_sweeps(monkeypatch, tmp_path) -> list:
    """The specs `centrobench sweep` would run (run_sweep records its spec and raises
    `Ran`), in an empty working directory."""
    import bench.sweep

    seen = []

    def record(spec, *args, **kwargs):
        seen.append(spec)
        raise Ran("recorded")

    monkeypatch.setattr(bench.sweep, "run_sweep", record)
    monkeypatch.chdir(tmp_path)
    return seen


def test_robustness_flags_make_the_specs_table(recorded_sweeps):
    seen = recorded_sweeps
    argv = [*SWEEP, "--noise", "1,imu=4,gyro_rad_s=0.01", "--noise-force-n", "0.5"]
    argv += ["--delay", "2", "--payload-kg", "5"]
    argv += ["--push-dv", "0.2", "--push-count", "2", "--push-replicas", "5"]
    argv += ["--push-phases", "walking"]
    argv += ["--push-swing-fractions", "0.2,0.7", "--push-directions", "random,inward"]
    with pytest.raises(Ran):
        main(argv)
    (spec,) = seen
    labels = [(p.label() if p else "nominal") for p in spec.perturbations]
    assert labels == [
        "nominal",
        "noise=1",
        "noise_imu=4",
        "noise_gyro_rad_s=0.01",  # one channel in SI units, [rad/s]
        "noise_force_N=0.5",
        "delay=2",
        "payload_kg=5",
    ]
    assert spec.perturbations[3].noise_gyro_rad_s == 0.01
    assert spec.perturbations[3].noise_imu == 0.0
    assert spec.push.replicas == 5
    assert spec.push.swing_fractions == (0.2, 0.7)
    assert spec.push.directions == ("random", "inward")
    # 7 perturbations x (1 stand + 2 fractions x (2 random + 1 inward) pushes x 5 replicas)
    assert len(spec.episodes()) == 7 * (1 + 2 * 3 * 5)
    assert spec.push.episodes_per_grid_point() == 2 * 3 * 5


JOB_TOML = """
name = "job"
controllers = ["all"]
sims = ["mujoco"]

[[protocols]]
name = "pushes"
push = { dv = [0.3], count = 2 }

[[protocols]]
name = "walks"
controllers = ["preview_control+centroidal_feedback"]
scenarios = ["walk"]
"""


def test_a_jobs_flags_apply_to_every_protocol_or_are_refused(recorded_sweeps, tmp_path, capsys):
    """--controllers, --sims and --seeds replace those of every protocol of a job; a flag
    that would mean something different in each protocol (--push-dv) is refused."""
    seen = recorded_sweeps
    (tmp_path / "job.toml").write_text(JOB_TOML)
    with pytest.raises(Ran):
        main(["sweep", "--spec", "job.toml", "--controllers", "hold+posture", "--seeds", "3"])
    (spec,) = seen
    assert [p.name for p in spec.protocols] == ["pushes", "walks"]
    assert [p.controllers for p in spec.protocols] == [("hold+posture",)] * 2
    assert [p.seeds for p in spec.protocols] == [(3,)] * 2
    line = refused(["sweep", "--spec", "job.toml", "--push-dv", "0.2"], capsys)
    assert "--push-dv: the spec job.toml is a job of protocols; set it in its [[protocols]]" in line
    assert not seen[1:]


def test_the_sweeps_first_line_counts_n_a_rows_apart_from_episodes_done(tmp_path, capsys):
    """One episode to run and one the controller cannot run (n/a: written, never run); on a
    resume the episode is done."""
    argv = ["sweep", "--controllers", "hold+posture", "--sims", "mujoco", "--no-progress"]
    argv += ["--scenarios", "stand,ladder", "--duration", "0.1", "--out", str(tmp_path / "r")]
    assert main(argv) == 0
    first = capsys.readouterr().err.splitlines()[0]
    assert first.startswith("sweep 'sweep': 2 episodes (1 n/a, 1 to run) -> ")
    assert main([*argv, "--resume"]) == 0
    first = capsys.readouterr().err.splitlines()[0]
    assert first.startswith("sweep 'sweep': 2 episodes (1 n/a, 1 done, 0 to run) -> ")


def _one_line_refusal(result: subprocess.CompletedProcess) -> str:
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr
    lines = [line for line in result.stderr.splitlines() if line.startswith("centrobench")]
    assert len(lines) == 1, result.stderr
    return lines[0]


def test_run_refuses_a_duration_that_ends_before_the_push():
    """`stand_push` pushes at 2 s: a 1.9 s episode would report "ok" for a push never given."""
    line = _one_line_refusal(
        run_cli(
            "run", "--controller", "hold+posture", "--sim", "mujoco", "--scenario",
            "stand_push", "--push-impulse", "40", "--duration", "1.9",
        )
    )  # fmt: skip
    assert "--duration 1.9 s ends before the push at 2 s" in line


def test_report_with_replays_of_a_folder_without_results_is_one_line(tmp_path):
    line = _one_line_refusal(run_cli("report", str(tmp_path), "--replays"))
    assert "no readable episode results" in line


def test_replay_checks_its_output_before_it_runs_the_episode_again(tmp_path):
    """A GIF's frame delay is 16 bits of 10 ms (at most 655 s: --fps 0.001 overflowed inside
    PIL), and an --out below a file is refused before the episode is run again (it said "File
    exists" after running it)."""
    line = _one_line_refusal(
        run_cli("replay", str(tmp_path), "e1", "--out", str(tmp_path / "x.gif"), "--fps", "0.001")
    )
    assert "a .gif needs --fps of at least 0.002" in line
    (tmp_path / "afile").write_text("")
    line = _one_line_refusal(
        run_cli("replay", str(tmp_path), "e1", "--out", str(tmp_path / "afile" / "x.html"))
    )
    assert "is not a folder" in line


def test_speed_checks_its_output_files_before_the_search(tmp_path):
    """A directory where speed.parquet goes: refused at once, not after the whole search."""
    (tmp_path / "speed.parquet").mkdir()
    line = _one_line_refusal(
        run_cli(
            "speed", "--controllers", "hold+posture", "--sims", "mujoco", "--out", str(tmp_path)
        )
    )
    assert "speed.parquet is a directory" in line


def test_compare_refuses_what_run_refuses_and_flags_that_would_do_nothing():
    """`compare` ran `hold` + `direct_centroidal` (no five-mass estimator to give the tilt) and
    reported "ok"; it repeated a planner named twice; --formulations without --horizons was
    ignored. Each is now one line before anything runs."""
    line = _one_line_refusal(
        run_cli(
            "compare", "--planners", "hold", "--stabilizer", "direct_centroidal", "--sims",
            "mujoco", "--scenario", "stand",
        )
    )  # fmt: skip
    assert "reads inertia_tilt" in line
    line = _one_line_refusal(run_cli("compare", "--planners", "hold,hold", "--sims", "mujoco"))
    assert "a name twice" in line
    line = _one_line_refusal(
        run_cli("compare", "--planners", "linear_mpc", "--formulations", "dense:daqp")
    )
    assert "goes with --horizons" in line


@pytest.mark.parametrize(
    "argv",
    [
        ["run", "--controller", "hold+posture", "--sim", "mujoco", "--scenario", "stand",
         "--estimator", ""],
        ["sweep", "--controllers", "hold+posture", "--sims", "mujoco", "--scenarios", "stand",
         "--out", ""],
        ["report", "results/x", "--out", ""],
    ],
)  # fmt: skip
def test_an_empty_option_is_refused_not_taken_for_its_default(argv):
    line = _one_line_refusal(run_cli(*argv))
    assert "is empty; give a value or leave the option out" in line


def test_speed_and_report_name_the_flag_that_is_wrong(tmp_path):
    line = _one_line_refusal(
        run_cli(
            "speed", "--controllers", "hold+posture", "--out", str(tmp_path), "--increment",
            "0.5", "--maximum", "0.1",
        )
    )  # fmt: skip
    assert "--increment 0.5 (the first speed tried) must be positive and at most --maximum" in line
    (tmp_path / "report.md").write_text("")
    line = _one_line_refusal(run_cli("report", str(tmp_path), "--out", str(tmp_path / "report.md")))
    assert "is a file; give a folder for the report" in line


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        # `run --out t.csv` wrote Parquet into t.csv, and `compare --out t.parquet` wrote CSV
        (
            [*RUN, "--out", "t.csv"],
            "--out t.csv: the file is written as Parquet; name it FILE.parquet",
        ),
        (
            ["compare", "--planners", "hold", "--sims", "mujoco", "--out", "t.parquet"],
            "--out t.parquet: the file is written as CSV; name it FILE.csv",
        ),
        ([*RUN, "--out", "trace"], "name it FILE.parquet"),
    ],
)
def test_an_output_named_for_another_format_is_refused(argv, expected, nothing_runs, capsys):
    assert expected in refused(argv, capsys)
    assert list(nothing_runs.iterdir()) == []


def test_the_steps_taken_are_written_beside_the_trace():
    assert footsteps_file("out/walk.parquet") == "out/walk.footsteps.parquet"
    assert footsteps_file("out/walk.PARQUET") == "out/walk.footsteps.parquet"
