"""The paper's two controller pairs on the walk, preview_control + centroidal_feedback and the
classic baseline preview_zmp + dcm: each walks 10 steps in both simulators, the planned ZMP
stays in the support polygon (Murooka Fig. 3B), the measured foot forces carry m g, the summary
carries the Table IV latency rows and the Sec. V-G projection errors; and the reference follows
the paper's rules."""

import numpy as np
import pytest

from bench.runner import EpisodeSpec, run_episode
from bench.scenarios import make_scenario
from planners.reference import com_reference, support_centre
from robots.humanoid import humanoid
from robots.model import RobotModel

SIMS = ["mujoco", "pybullet"]
PAIRS = [("preview_control", "centroidal_feedback"), ("preview_zmp", "dcm")]
RUNS = [(planner, stabilizer, sim) for planner, stabilizer in PAIRS for sim in SIMS]
RUN_IDS = [f"{p}+{s}-{sim}" for p, s, sim in RUNS]


@pytest.fixture(scope="module")
def walks():
    return {run: run_episode(EpisodeSpec(*run, "walk")) for run in RUNS}


@pytest.mark.parametrize("run", RUNS, ids=RUN_IDS)
def test_walks_ten_steps_without_falling(walks, run):
    result = walks[run]
    summary = result.summary
    assert summary["status"] == "ok", summary["error"] or summary["fall_reason"]
    assert summary["fell"] is False
    scenario = make_scenario("walk", RobotModel(humanoid()))
    assert summary["duration"] == pytest.approx(scenario.duration, abs=0.003)
    # every planned footstep was taken, the feet alternating from the right, and the robot
    # ends where the plan ends (a step short would leave its CoM about 6 cm behind)
    assert summary["steps_taken"] == 10
    limbs = list(result.footsteps["limb"])
    assert limbs == ["right_foot", "left_foot"] * 5
    final = result.trace.iloc[-1]
    last = scenario.phases[-1].contacts
    end_x = np.mean([c.position_world[0] for c in last])
    assert final["com_actual_x"] == pytest.approx(end_x, abs=0.01)
    assert abs(final["com_actual_y"]) < 0.01


@pytest.mark.parametrize("run", RUNS, ids=RUN_IDS)
def test_planned_zmp_stays_in_the_support_polygon(walks, run):
    """The plan's ZMP stays CONTACT_MARGIN (10 mm) inside the soles, the margin of the cones
    it is projected onto (Murooka Fig. 3: polygons "with inner margins"; measured: on the
    margin at its closest in every run)."""
    from robots.limbs import CONTACT_MARGIN

    margin = CONTACT_MARGIN * humanoid().scale
    assert walks[run].summary["zmp_margin_min_m"] >= margin - 1e-9
    assert (walks[run].trace["zmp_margin_m"] >= margin - 1e-9).all()


@pytest.mark.parametrize("run", RUNS, ids=RUN_IDS)
def test_feet_carry_the_weight_in_every_single_support(walks, run):
    """Momentum balance: over each single-support phase the CoM's vertical velocity returns
    close to where it started, so the measured vertical foot force averages m g. (A servo
    oscillating at the physics step once made the stance foot read 1.2 m g here.)"""
    trace = walks[run].trace
    scenario = make_scenario("walk", RobotModel(humanoid()))
    weight = humanoid().total_mass * 9.81
    vertical = sum(trace[f"wrench_measured_{foot}_fz"] for foot in ("left_foot", "right_foot"))
    singles = [p for p in scenario.phases if len(p.contacts) == 1]
    assert len(singles) == 10
    for phase in singles:
        inside = (trace["time"] >= phase.start + 0.05) & (trace["time"] < phase.end - 0.05)
        assert vertical[inside].mean() == pytest.approx(weight, rel=0.03), phase.start


@pytest.mark.parametrize("run", [r for r in RUNS if r[1] == "centroidal_feedback"])
def test_summary_has_table_iv_rows_and_projection_errors(walks, run):
    summary = walks[run].summary
    for row in ("reference", "preview", "projection", "distribution", "centroidal_total"):
        assert row in summary["latency_us"]
    errors = summary["projection_error"]
    assert set(errors) == {
        "planned_force_N",
        "planned_moment_Nm",
        "desired_force_N",
        "desired_moment_Nm",
    }
    # on flat ground the walk's plan stays inside its cones: little is left to project (the
    # paper's single digits are on (B) and (C), Sec. V-G); measured 0.005-0.08 N, 0.14-0.41 N m
    for value in errors.values():
        assert 0.0 < value < 1.0  # N or N m
    trace = walks[run].trace
    # every Table IV row was timed in every period
    for row in ("reference", "preview", "projection", "distribution"):
        assert (trace[f"t_{row}_us"] > 0.0).all(), row
    # Table IV's "Total control" is the planner and the stabilizer, which contain those rows
    assert (trace["t_centroidal_control_us"] >= trace["t_centroidal_total_us"]).all()
    assert "centroidal_control" in summary["latency_us"]


def test_reference_follows_the_contact_sequence():
    """Sec. V-B: horizontal CoM at the supporting foot in single support, the middle of both in
    double support; height a constant offset above the mean support height."""
    model = RobotModel(humanoid())
    scenario = make_scenario("walk", model)
    reference = com_reference(scenario, 0.005, 2000, height_offset=0.8)
    for phase in scenario.phases[:6]:
        t = (phase.start + phase.end) / 2
        feet = np.array([c.position_world for c in phase.contacts])
        np.testing.assert_allclose(reference[int(t / 0.005), :2], feet[:, :2].mean(axis=0))
        assert reference[int(t / 0.005), 2] == pytest.approx(feet[:, 2].mean() + 0.8)
        centre, _ = support_centre(scenario, t)
        np.testing.assert_allclose(centre, feet[:, :2].mean(axis=0))


@pytest.mark.parametrize("name", ["walk", "walk_turn"])
def test_the_zmp_previews_reference_is_2_cm_inward_of_the_support_soles(name):
    """`zmp_reference` (the BaselineWalkingController's `zmpOffset`): in every single support
    the reference is the supporting sole's centre moved 2 cm toward the midline along the
    sole's own y axis (on `walk_turn` the soles are yawed); in double support on parallel feet
    (`walk`) it is the feet's midpoint, as `com_reference`; the height column is
    `com_reference`'s."""
    from centroidal.rotations import to_matrix
    from planners.preview_zmp import zmp_reference

    model = RobotModel(humanoid())
    scenario = make_scenario(name, model)
    n_samples = int(scenario.duration / 0.005) + 10
    shifted = zmp_reference(scenario, 0.005, n_samples, 0.8)
    plain = com_reference(scenario, 0.005, n_samples, 0.8)
    np.testing.assert_array_equal(shifted[:, 2], plain[:, 2])
    singles = doubles = 0
    for phase in scenario.phases:
        i = round((phase.start + phase.end) / 2 / 0.005)
        feet = [c for c in phase.contacts if c.limb.endswith("foot")]
        if len(feet) == 1:
            singles += 1
            inward = -1.0 if feet[0].limb == "left_foot" else 1.0
            sole_y = to_matrix(feet[0].orientation_world)[:2, 1]
            expected = np.asarray(feet[0].position_world[:2]) + inward * 0.02 * sole_y
            np.testing.assert_allclose(shifted[i, :2], expected, atol=1e-12)
        else:
            doubles += 1
            if name == "walk":
                np.testing.assert_allclose(shifted[i, :2], plain[i, :2], atol=1e-12)
    yaws = [abs(to_matrix(c.orientation_world)[0, 1]) for p in scenario.phases for c in p.contacts]
    assert (max(yaws) > 0.1) == (name == "walk_turn")  # the turn's soles are yawed
    assert singles >= 8
    assert doubles >= 8


@pytest.mark.slow
@pytest.mark.parametrize("run", RUNS, ids=RUN_IDS)
@pytest.mark.parametrize("direction", [90.0, 270.0])
def test_walks_through_a_lateral_push_mid_single_support(run, direction):
    """`walk_push` at its default 10 N s (0.17 m/s for 58.4 kg), to either side."""
    summary = run_episode(
        EpisodeSpec(*run, "walk_push", push_impulse=10.0, push_direction_deg=direction)
    ).summary
    assert summary["status"] == "ok", summary["error"] or summary["fall_reason"]


def test_the_cart_tables_height_follows_a_stepping_reference_smoothly():
    """`preview_zmp`'s height: JVRC-1's reference steps by 0.048 mm between its soles' supports;
    the planned vertical acceleration stays below 1e-3 m/s^2 (the planned vertical force
    within 0.01 % of m g; twice differentiating the step planned 12 m/s^2, a negative vertical
    force), reaches the new height within 1 um in 2 s, and a reference equal to the height
    plans exactly zero."""
    from planners.preview_zmp import follow_height

    omega, dt, step = float(np.sqrt(9.81 / 0.86)), 0.002, 4.8e-5
    state, accelerations = np.array([0.86, 0.0]), []
    for _ in range(1000):
        z, velocity, acceleration = follow_height(state, 0.86 + step, omega, dt)
        state = np.array([z, velocity])
        accelerations.append(acceleration)
    assert max(abs(a) for a in accelerations) < 1e-3
    assert abs(state[0] - (0.86 + step)) < 1e-6
    assert follow_height(np.array([0.86, 0.0]), 0.86, omega, dt) == (0.86, 0.0, 0.0)


def test_the_cart_table_wrench_has_the_cart_tables_zmp():
    """`preview_zmp`'s planned wrench (no moment about the CoM), with gravity and taken about
    the world origin, has its ZMP where the cart-table model puts it: p = c - (c_z / g) c''
    (Kajita et al. 2003) on the floor z = 0, for a constant height (c_z'' = 0)."""
    from centroidal.projection import GRAVITY  # the vector (0, 0, g)
    from centroidal.wrench import zmp_on_plane
    from planners.preview_zmp import cart_table_wrench

    mass, com = 58.4, np.array([0.12, -0.04, 0.8])
    acceleration = np.array([0.7, -0.3, 0.0])
    wrench = cart_table_wrench(mass, acceleration)
    assert np.array_equal(wrench[3:], np.zeros(3))
    force = wrench[:3] + mass * GRAVITY
    about_origin = np.concatenate([force, np.cross(com, force) + wrench[3:]])
    expected = com[:2] - com[2] / GRAVITY[2] * acceleration[:2]
    np.testing.assert_allclose(zmp_on_plane(about_origin)[:2], expected, atol=1e-12)
