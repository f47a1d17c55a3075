"""Robustness dimensions in the loop (issue 21): model errors change the simulated robot only,
as physics predicts; delays shift what the runner applies and hands over by exactly k periods;
replicas differ by a small seeded change; the sweep spec expands one dimension at a time."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import bench.runner as runner_module
from bench.robustness import dimension_of, parse_robustness, perturbation_for
from bench.runner import (
    REPLICA_PUSH_JITTER_S,
    EpisodeSpec,
    replica_changes,
    run_episode,
)
from bench.sweep_spec import SpecError, spec_from_mapping
from robots.humanoid import humanoid
from robots.model import RobotModel
from robots.perturbation import (
    PAYLOAD_OFFSET_FROM_TORSO_COM,
    Perturbation,
    predicted_com_shift,
    simulated_robot,
    simulated_scene,
)
from robots.robot_registry import make_robot

G = 9.81
SPECS = Path(__file__).parents[2] / "bench" / "specs"


def test_torso_is_where_the_arms_branch():
    assert humanoid().torso_link == "torso"  # the humanoid's base
    jvrc = make_robot("jvrc1")
    assert jvrc.torso_link != jvrc.base_link  # JVRC-1's chest, above its waist joints
    assert jvrc.link(jvrc.torso_link).inertial.mass > 5.0


def test_payload_moves_the_centre_of_mass_by_the_lever_rule():
    robot = humanoid()
    heavy = simulated_robot(robot, Perturbation(payload_kg=5.0), seed=0)
    assert heavy.total_mass == pytest.approx(robot.total_mass + 5.0, abs=1e-12)
    nominal, truth = RobotModel(robot), RobotModel(heavy)
    state = nominal.standing_state()
    torso_com = robot.link("torso").inertial.com_in_link
    position, rotation = nominal.frame_pose(state, "torso")
    payload_world = position + rotation @ np.add(torso_com, PAYLOAD_OFFSET_FROM_TORSO_COM)
    com = nominal.com_position_world(state)
    expected = predicted_com_shift(robot, com, payload_world, 5.0)
    # 5 kg 0.1 m behind the torso's centre of mass: about 8 mm back
    assert expected[0] < -0.005
    np.testing.assert_allclose(truth.com_position_world(state) - com, expected, rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", ["centrobench_humanoid", "jvrc1"])
def test_com_offset_moves_the_simulated_robots_centre_of_mass_forward(name):
    robot = make_robot(name)  # JVRC-1's torso (its chest) is pitched when it stands
    moved = simulated_robot(robot, Perturbation(com_offset_m=0.02), seed=0)
    assert moved.total_mass == pytest.approx(robot.total_mass, abs=1e-12)
    state = RobotModel(robot).standing_state()
    shift = RobotModel(moved).com_position_world(state) - RobotModel(robot).com_position_world(
        state
    )
    np.testing.assert_allclose(shift, [0.02, 0.0, 0.0], rtol=0, atol=1e-12)


def test_mass_errors_are_bounded_seeded_and_keep_each_links_centre_of_mass():
    robot = humanoid()
    changed = simulated_robot(robot, Perturbation(mass_error=0.1), seed=5)
    again = simulated_robot(robot, Perturbation(mass_error=0.1), seed=5)
    other = simulated_robot(robot, Perturbation(mass_error=0.1), seed=6)
    assert changed == again
    assert changed != other
    factors = np.array(
        [b.inertial.mass / a.inertial.mass for a, b in zip(robot.links, changed.links, strict=True)]
    )
    assert np.all(np.abs(factors - 1.0) <= 0.1)
    assert np.ptp(factors) > 0.05
    # uniform on [0.9, 1.1]: lighter and heavier links alike, over a few seeds mean 1
    pooled = np.concatenate(
        [
            [
                b.inertial.mass / a.inertial.mass
                for a, b in zip(
                    robot.links,
                    simulated_robot(robot, Perturbation(mass_error=0.1), seed=s).links,
                    strict=True,
                )
            ]
            for s in range(10)
        ]
    )
    assert pooled.min() < 0.92
    assert pooled.max() > 1.08
    assert abs(pooled.mean() - 1.0) < 0.02  # sigma of the mean 0.058 / sqrt(250) = 0.004
    for a, b, f in zip(robot.links, changed.links, factors, strict=True):
        assert b.inertial.com_in_link == a.inertial.com_in_link
        np.testing.assert_allclose(b.inertial.inertia_matrix, f * a.inertial.inertia_matrix)
    changed.validate()


def test_torque_scale_scales_the_simulated_limits_only():
    robot = humanoid()
    weak = simulated_robot(robot, Perturbation(torque_scale=0.5), seed=0)
    np.testing.assert_allclose(weak.array("torque_limit"), 0.5 * robot.array("torque_limit"))
    assert weak.array("kp").tolist() == robot.array("kp").tolist()
    assert simulated_robot(robot, Perturbation(gain_scale=0.5), seed=0) is robot


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
def test_a_payload_unknown_to_the_controller_weighs_on_the_feet_under_the_true_com(sim):
    """Standing 2 s with 5 kg on the torso that the controller does not know: the feet carry
    (M + m_p) g, and at rest the measured centre of pressure lies under the true centre of
    mass, not under the one the controller's model gives."""
    payload = 5.0
    result = run_episode(
        EpisodeSpec(
            planner="preview_control",
            stabilizer="centroidal_feedback",
            sim=sim,
            scenario="stand",
            duration=2.0,
            perturbation=Perturbation(payload_kg=payload),
        )
    )
    assert result.summary["status"] == "ok"
    assert result.summary["payload_kg"] == payload
    last = result.trace.iloc[-100:]  # the last 0.2 s
    force = sum(last[f"wrench_measured_{f}_fz"].mean() for f in ("left_foot", "right_foot"))
    mass = humanoid().total_mass + payload
    assert force == pytest.approx(mass * G, rel=0.005)
    true_com = last[["com_true_x", "com_true_y"]].mean().to_numpy()
    believed = last[["com_actual_x", "com_actual_y"]].mean().to_numpy()
    cop = last[["zmp_actual_x", "zmp_actual_y"]].mean().to_numpy()
    assert np.abs(cop - true_com).max() < 1e-3
    assert np.abs(true_com - believed).max() > 5e-3  # the controller is wrong by mm, not 0


class _Recording:
    """Wraps an object and records the first argument of `method` and its return value."""

    def __init__(self, inner, method: str, calls: list, results: list | None = None) -> None:
        self._inner, self._method, self._calls, self._results = inner, method, calls, results

    def __getattr__(self, name):
        attribute = getattr(self._inner, name)
        if name != self._method:
            return attribute

        def recorded(*args, **kwargs):
            self._calls.append(args[0])
            value = attribute(*args, **kwargs)
            if self._results is not None:
                self._results.append(value)
            return value

        return recorded


@pytest.mark.parametrize(("command_delay", "sensor_delay"), [(2, 0), (0, 3), (1, 1)])
def test_delays_shift_commands_and_readings_by_exactly_k_periods(
    monkeypatch, command_delay, sensor_delay
):
    computed, applied, readings, handed = [], [], [], []
    make_simulator, make_whole_body = runner_module.make_simulator, runner_module.make_whole_body
    make_estimator = runner_module.make_estimator
    monkeypatch.setattr(
        runner_module,
        "make_simulator",
        lambda name: _Recording(make_simulator(name), "step", applied, readings),
    )
    monkeypatch.setattr(
        runner_module,
        "make_whole_body",
        lambda *a: _Recording(make_whole_body(*a), "command", [], computed),
    )
    monkeypatch.setattr(
        runner_module,
        "make_estimator",
        lambda *a: _Recording(make_estimator(*a), "estimate", handed),
    )
    result = run_episode(
        EpisodeSpec(
            planner="preview_control",
            stabilizer="centroidal_feedback",
            sim="mujoco",
            scenario="stand",
            duration=0.1,
            perturbation=Perturbation(command_delay=command_delay, sensor_delay=sensor_delay),
        )
    )
    assert result.summary["status"] == "ok"
    n = len(computed)
    assert n == len(applied) == 50
    k = command_delay
    assert all(applied[j] is computed[0] for j in range(k + 1))
    assert all(applied[j] is computed[j - k] for j in range(k, n))
    # the estimator reads once after the reset, then once per period: in period j >= 1 it
    # gets the simulator's reading of period j - 1 (its step's result) from `k` periods before
    k = sensor_delay
    assert len(handed) == n + 1
    assert all(handed[j + 1].time == 0.0 for j in range(k + 1))  # the reset's until then
    for j in range(1 + k, n):
        assert handed[j + 1].time == readings[j - 1 - k].time
        assert np.array_equal(handed[j + 1].joint_position, readings[j - 1 - k].joint_position)


def _gyro_offsets(monkeypatch, perturbation: Perturbation, replica: int) -> np.ndarray:
    """What the sensor model added to the gyro readings the estimator got [rad/s] (periods, 3)
    over 0.05 s of `stand` (seed 0, replica `replica`)."""
    readings, handed = [], []
    make_simulator, make_estimator = runner_module.make_simulator, runner_module.make_estimator
    monkeypatch.setattr(
        runner_module,
        "make_simulator",
        lambda name: _Recording(make_simulator(name), "step", [], readings),
    )
    monkeypatch.setattr(
        runner_module,
        "make_estimator",
        lambda *a: _Recording(make_estimator(*a), "estimate", handed),
    )
    spec = EpisodeSpec(
        planner="preview_control",
        stabilizer="centroidal_feedback",
        sim="mujoco",
        scenario="stand",
        duration=0.05,
        perturbation=perturbation,
        replica=replica,
    )
    assert run_episode(spec).summary["status"] == "ok"
    # period j >= 1 reads the simulator's reading of period j - 1 (the delay test above)
    return np.array(
        [
            handed[j + 1].imu_angular_velocity_imu - readings[j - 1].imu_angular_velocity_imu
            for j in range(1, len(readings))
        ]
    )


def test_a_push_s_replicas_read_their_own_noise_and_share_the_robot_s_bias(monkeypatch):
    """Replicas are re-runs on one robot: with white IMU noise, replica 1's gyro noise is not
    replica 0's (it was, draw for draw, before 2026-12-03: the replicas of a noisy threshold
    sampled one noise sequence); with a bias alone both read the same constant offset."""
    noisy = Perturbation(noise_imu=1.0)
    first, second = (_gyro_offsets(monkeypatch, noisy, r) for r in (0, 1))
    assert first.std() > 1e-3  # [rad/s] the data sheet's 1.95e-3 at 2 ms
    assert np.abs(first - second).max() > 1e-3
    biased = Perturbation(noise_bias=1.0)
    first, second = (_gyro_offsets(monkeypatch, biased, r) for r in (0, 1))
    assert np.abs(first[0]).max() > 1e-4  # a bias, not zero
    np.testing.assert_allclose(second, first, rtol=0, atol=1e-12)
    assert np.ptp(first, axis=0).max() < 1e-12  # constant


def test_replicas_differ_by_a_small_seeded_change_and_replica_0_is_the_episode():
    initial = RobotModel(humanoid()).standing_state()
    same, shift = replica_changes(initial, seed=0, replica=0)
    assert same is initial
    assert shift == 0.0
    first = replica_changes(initial, seed=0, replica=1)
    assert first[1] == replica_changes(initial, seed=0, replica=1)[1]  # seeded
    shifts = [replica_changes(initial, 0, r)[1] for r in range(1, 30)]
    assert max(abs(s) for s in shifts) <= REPLICA_PUSH_JITTER_S
    assert len(set(shifts)) == len(shifts)
    velocity = first[0].base_linear_velocity_world
    assert velocity[2] == 0.0
    assert 0.0 < np.linalg.norm(velocity) < 0.05
    np.testing.assert_array_equal(first[0].joint_position, initial.joint_position)


def test_robustness_table_varies_one_dimension_at_a_time():
    spec = spec_from_mapping(
        {
            "controllers": ["hold+posture"],
            "sims": ["mujoco"],
            "scenarios": ["stand"],
            "robustness": {"noise": [0, 1, 2], "delay": [1], "payload_kg": [5.0]},
        }
    )
    labels = [(e.run.perturbation or Perturbation()).label() for e in spec.episodes()]
    assert labels == ["nominal", "noise=1", "noise=2", "delay=1", "payload_kg=5"]
    assert len({e.episode_id for e in spec.episodes()}) == 5
    # read back from the spec's record: the same perturbations
    record = spec.to_dict()["robustness"]
    assert parse_robustness(record) == spec.perturbations
    # the whole record is a spec again (a replay reads it): the same episodes
    import json

    again = spec_from_mapping(json.loads(json.dumps(spec.to_dict())))
    assert [e.episode_id for e in again.episodes()] == [e.episode_id for e in spec.episodes()]
    assert dimension_of(perturbation_for("delay", 2)) == ("delay", 2.0)
    gyro = parse_robustness({"nominal": False, "noise_gyro_rad_s": [0.01]})
    assert gyro == (Perturbation(noise_gyro_rad_s=0.01),)
    assert gyro[0].label() == "noise_gyro_rad_s=0.01"
    assert dimension_of(gyro[0]) == ("noise_gyro_rad_s", 0.01)
    assert dimension_of(Perturbation(noise_imu=1.0, payload_kg=1.0)) is None


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ({"noise": [-1]}, "'robustness.noise' must be a list of numbers in [0, 1000]"),
        ({"delay": [1.5]}, "'robustness.delay' must be a list of integers in [0, 100]"),
        (
            {"noise_force_N": [-0.1]},
            "'robustness.noise_force_N' must be a list of numbers in [0, 250] (N, one standard "
            "deviation of white noise on the F/T forces only (data sheet: 0.25 at 2 ms)), got -0.1",
        ),
        ({"torque_scale": [0]}, "'robustness.torque_scale' must be a list of numbers in (0, 10]"),
        ({"wind": [1]}, "'robustness.wind' is unknown"),
        ({"nominal": False}, "'robustness.nominal' is false and no dimension is given"),
        ([1], "'robustness' must be a table"),
    ],
)
def test_bad_robustness_tables_are_refused_with_one_line(table, message):
    base = {"controllers": ["hold+posture"], "sims": ["mujoco"], "scenarios": ["stand"]}
    with pytest.raises(SpecError) as error:
        spec_from_mapping({**base, "robustness": table})
    assert message in str(error.value)
    assert "\n" not in str(error.value)


def test_push_replicas_multiply_the_pushes_and_keep_the_ids_of_replica_0():
    base = {
        "controllers": ["hold+posture"],
        "sims": ["mujoco"],
        "push": {"dv": [0.2], "count": 3},
    }
    one = spec_from_mapping(base).episodes()
    five = spec_from_mapping({**base, "push": {**base["push"], "replicas": 5}}).episodes()
    assert len(five) == 5 * len(one) == 15
    assert [e.episode_id for e in five if e.run.replica == 0] == [e.episode_id for e in one]
    assert sorted(e.run.replica for e in five) == sorted(list(range(5)) * 3)
    assert "replicas" not in spec_from_mapping(base).to_dict()["push"]  # digest as before
    # a replica's push may come up to the jitter late: its episode is that much longer, so
    # that every replica is judged over the whole survival time after its push
    from bench.runner import REPLICA_PUSH_JITTER_S

    nominal = {e.push_index: e.run.duration for e in one}
    for e in five:
        longer = REPLICA_PUSH_JITTER_S if e.run.replica > 0 else 0.0
        assert e.run.duration == pytest.approx(nominal[e.push_index] + longer, abs=1e-12)


MAIN_JOB_2026_11_24 = {
    "name": "main",
    "controllers": ["all"],
    "sims": ["all"],
    "scenarios": ["walk"],
    "traces": ["walk"],
    "seeds": [0],
    "push": {"phases": ["standing"], "dv": [0.2, 0.25, 0.3, 0.35, 0.4], "count": 20, "seed": 0},
}
"""The main job's spec until issue 22 (bench/specs/main.toml at bff0d1a)."""


def test_the_main_jobs_digest_and_ids_are_those_before_robustness():
    """Recorded at e332790, before the robustness dimensions: a resume of an earlier main job
    runs nothing twice."""
    spec = spec_from_mapping(MAIN_JOB_2026_11_24)
    episodes = spec.episodes()
    assert spec.digest() == "ffa92370b0e9"
    assert (len(episodes), episodes[5].episode_id) == (1414, "c1877594b2453ab7")


def _ground_height(sim, x: float, y: float) -> float:
    """The highest surface [m] under (x, y), by a ray cast down from 1 m in the simulator's own
    collision world (MuJoCo `mj_ray`, PyBullet `rayTest`); nan if none."""
    if sim.name == "mujoco":
        import mujoco

        geom = np.zeros(1, dtype=np.int32)
        # every geom group, static geoms included, no body excluded: cast where no robot is
        distance = mujoco.mj_ray(
            sim.model,
            sim.data,
            np.array([x, y, 1.0]),
            np.array([0.0, 0.0, -1.0]),
            None,
            1,
            -1,
            geom,
        )
        return np.nan if distance < 0 else 1.0 - distance
    import pybullet as pb

    hit = pb.rayTest([x, y, 1.0], [x, y, -1.0], physicsClientId=sim.client)[0]
    return np.nan if hit[0] < 0 else hit[3][2]


@pytest.mark.parametrize("sim_name", ["mujoco", "pybullet"])
@pytest.mark.parametrize(
    "perturbation",
    [Perturbation(ground_height_m=0.02), Perturbation(slope_deg=5.0), Perturbation(slope_deg=-5.0)],
    ids=lambda p: p.label(),
)
def test_the_simulated_ground_is_where_the_perturbation_puts_it(sim_name, perturbation):
    """Rays cast down in each simulator's own world hit the tiles' tops and the ramp's plane
    (z = (x - x0) tan(slope) from x0 = GROUND_START_M), and flat ground where the robot stands;
    the controller's scene stays flat."""
    from robots.perturbation import GROUND_START_M
    from robots.scene import Scene
    from sims.base import make_simulator

    robot = humanoid()
    flat = Scene()
    scene = simulated_scene(flat, perturbation, seed=4)
    assert simulated_scene(flat, Perturbation(), seed=4) is flat
    sim = make_simulator(sim_name)
    sim.reset(robot, scene, RobotModel(robot).standing_state())
    try:
        assert _ground_height(sim, 0.0, 0.6) == pytest.approx(0.0, abs=1e-6)  # beside the robot
        if perturbation.ground_height_m:
            tiles = [b for b in scene.boxes if b.name.startswith("ground_tile")]
            heights = [2 * b.half_extents[2] for b in tiles]
            assert len(tiles) == 20 * 7
            assert min(heights) > 0.0
            assert max(heights) <= 0.02
            assert np.std(heights) > 0.004  # uniform on (0, 2 cm]: 5.8 mm
            for box in tiles[::17]:
                x, y, _ = box.center_world
                assert _ground_height(sim, x, y) == pytest.approx(2 * box.half_extents[2], abs=1e-6)
            # the field starts GROUND_START_M ahead: under the standing robot, flat ground
            edge = min(b.center_world[0] - b.half_extents[0] for b in tiles)
            assert edge == pytest.approx(GROUND_START_M, abs=1e-12)
            assert _ground_height(sim, 0.5 * GROUND_START_M, 0.0) == pytest.approx(0.0, abs=1e-6)
            again = simulated_scene(flat, perturbation, seed=4)
            other = simulated_scene(flat, perturbation, seed=5)
            assert again == scene
            assert other != scene
        else:
            slope = np.radians(perturbation.slope_deg)
            for x in (0.5, 1.0, 2.0):
                expected = (x - GROUND_START_M) * np.tan(slope)
                assert _ground_height(sim, x, 0.1) == pytest.approx(expected, abs=1e-6)
    finally:
        sim.close()


def test_walking_pushes_at_swing_fractions_and_support_relative_directions():
    push = {
        "phases": ["walking"],
        "dv": [0.3],
        "count": 2,
        "swing_fractions": [0.2, 0.5, 0.7],
        "directions": ["random", "inward", "outward", "forward", "backward"],
    }
    base = {"controllers": ["preview_control+centroidal_feedback"], "sims": ["mujoco"]}
    episodes = spec_from_mapping({**base, "push": push}).episodes()
    assert len(episodes) == 3 * (2 + 4)  # fractions x (random directions + named ones)
    labels = [e.labels() for e in episodes]
    assert sorted({label["push_swing_fraction"] for label in labels}) == [0.2, 0.5, 0.7]
    named = {label["push_direction_name"]: label for label in labels[2:6]}
    # step 3 is a left-foot support (the walk starts on the right foot): inward is -y
    assert named["inward"]["push_direction_deg"] == pytest.approx(270.0)
    assert named["outward"]["push_direction_deg"] == pytest.approx(90.0)
    assert named["forward"]["push_direction_deg"] == pytest.approx(0.0)
    assert named["backward"]["push_direction_deg"] == pytest.approx(180.0)
    # the default protocol: as before (middle of the swing, random directions only)
    plain = spec_from_mapping({**base, "push": {"phases": ["walking"], "dv": [0.3]}})
    assert "swing_fractions" not in plain.to_dict()["push"]
    assert {e.run.push_swing_fraction for e in plain.episodes()} == {None}


@pytest.mark.parametrize("step", range(1, 11))
def test_support_relative_pushes_point_where_their_names_say(step):
    """In every single support of the walk: the inward push points to the side of the other
    foot (its last and next footholds), the forward push along the support sole's x axis,
    and a push at fraction f of the single support is centred at start + f (end - start)."""
    from bench.scenarios import make_scenario
    from robots.scene import ContactPhase

    model = RobotModel(humanoid())
    scenario = make_scenario("walk_push", model, push_step=step, push_direction_name="inward")
    single = [p for p in scenario.phases if len(p.contacts) == 1]
    phase: ContactPhase = single[step - 1]
    support = phase.contacts[0]
    others = [
        c.position_world
        for p in scenario.phases
        for c in p.contacts
        if c.limb != support.limb and abs(p.start - phase.start) < 2.0
    ]
    impulse = np.array(scenario.pushes[0].impulse_world)
    lateral = np.mean(others, axis=0)[1] - support.position_world[1]
    assert np.sign(impulse[1]) == np.sign(lateral)
    assert abs(impulse[0]) < 1e-9 * np.linalg.norm(impulse)
    forward = make_scenario("walk_push", model, push_step=step, push_direction_name="forward")
    assert forward.pushes[0].impulse_world[0] > 0
    late = make_scenario("walk_push", model, push_step=step, push_swing_fraction=0.7)
    push = late.pushes[0]
    centre = phase.start + 0.7 * (phase.end - phase.start)
    assert push.time + push.duration / 2 == pytest.approx(centre, abs=1e-12)


def test_robustness_spec_file_varies_each_dimension_alone():
    from bench.sweep_spec import load_spec

    spec = load_spec(SPECS / "robustness.toml")
    labels = [p.label() if p else "nominal" for p in spec.perturbations]
    assert labels == [
        "nominal",
        "noise=1",
        "noise=4",
        "delay=1",
        "delay=3",
        "payload_kg=10",
        "torque_scale=0.5",
        "ground_height_m=0.02",
        "slope_deg=4",
    ]
    assert len(spec.episodes()) == 3 * 2 * len(labels) * (1 + 10)


def test_perturbed_episodes_keep_the_ids_they_had_before_the_si_noise_channels():
    """Recorded at 2ae8308, before the per-channel noise fields: a resume or a replay of an
    earlier robustness sweep finds its perturbed episodes (the digest alone cannot tell)."""
    from bench.sweep_spec import load_spec

    spec = load_spec(SPECS / "robustness.toml")
    episodes = spec.episodes()
    assert spec.digest() == "e0a00b445f29"
    assert (episodes[11].run.perturbation.label(), episodes[11].episode_id) == (
        "noise=1",
        "ba053a0d276fec5f",
    )
    # a channel in SI units is part of the id
    gyro = spec_from_mapping(
        {
            "controllers": ["hold+posture"],
            "sims": ["mujoco"],
            "scenarios": ["stand"],
            "robustness": {"nominal": False, "noise_gyro_rad_s": [0.01, 0.02]},
        }
    ).episodes()
    assert len({e.episode_id for e in gyro}) == 2
