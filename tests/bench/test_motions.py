"""Murooka et al.'s multi-contact motions (Fig. 4) as contact sequences (`bench.motions`),
and episodes of `preview_control` + `centroidal_feedback` on them in both simulators."""

import math

import numpy as np
import pytest

from bench.controllers import CONTROLLERS, refusal
from bench.scenarios import make_scenario
from robots.humanoid import humanoid
from robots.model import RobotModel
from robots.multi_contact_scenes import MOTION_PERIOD_S, WALL_INNER_FACE_Y
from robots.scene import contact_normal
from tests.bench.episodes import run_controller

DT = 0.002
GRAVITY = 9.81


def _check_phases_cover(scenario):
    assert scenario.phases[0].start == 0.0
    for a, b in zip(scenario.phases, scenario.phases[1:], strict=False):
        assert a.end == pytest.approx(b.start, abs=1e-12)
    assert scenario.phases[-1].end == pytest.approx(scenario.duration, abs=1e-12)


@pytest.mark.parametrize("scale", [1.0, 1.2])
def test_moving_contacts_puts_each_palm_on_its_wall_facing_it(scale):
    """(E): the palms' contacts lie on the walls' faces (y = +-0.45 m x scale) with their
    normals (z axes) out of the wall, towards the robot; each hand leaves from its standing
    pose (a waypoint); the walls and floors move only once both hands are on."""
    model = RobotModel(humanoid(scale))
    scenario = make_scenario("moving_contacts", model)
    _check_phases_cover(scenario)
    last = scenario.phases[-1]
    assert sorted(last.limbs) == ["left_foot", "left_hand", "right_foot", "right_hand"]
    for contact in last.contacts:
        if contact.limb.endswith("hand"):
            side = 1.0 if contact.limb == "left_hand" else -1.0
            assert contact.position_world[1] == pytest.approx(side * WALL_INNER_FACE_Y * scale)
            np.testing.assert_allclose(
                contact_normal(contact.orientation_world), (0, -side, 0), atol=1e-12
            )
    standing = model.standing_state()
    for waypoint in scenario.limb_waypoints:
        frame = model.robot.limb(waypoint.limb).contact_frame
        np.testing.assert_allclose(
            waypoint.position_world, model.frame_pose(standing, frame)[0], atol=1e-12
        )
    on_walls = min(p.start for p in scenario.phases if len(p.contacts) == 4)
    for box in scenario.scene.moving_boxes:
        assert box.start_time == pytest.approx(on_walls + 0.8 * math.sqrt(scale))
        assert box.period == pytest.approx(MOTION_PERIOD_S * math.sqrt(scale))
    assert scenario.duration - on_walls >= 2 * MOTION_PERIOD_S * math.sqrt(scale)


def test_flat_ground_controllers_are_refused_the_motions():
    reason = refusal(CONTROLLERS["preview_zmp+dcm"], "moving_contacts")
    assert reason is not None
    assert "multi_contact" in reason
    assert refusal(CONTROLLERS["preview_control+centroidal_feedback"], "moving_contacts") is None


@pytest.fixture(scope="module", params=["mujoco", "pybullet"])
def moving_contacts_episode(request):
    return request.param, run_controller(
        "preview_control+centroidal_feedback", request.param, "moving_contacts"
    )


def test_moving_contacts_balances_without_a_fall(moving_contacts_episode):
    _, result = moving_contacts_episode
    assert result.summary["status"] == "ok", result.summary["error"]
    assert not result.summary["fell"]


def test_moving_contacts_feet_and_walls_carry_the_weight(moving_contacts_episode):
    """While floors and walls move (after both hands are on), the measured contact forces'
    vertical components (the feet's normal forces, about level to 2 deg, and the palms'
    friction along their frames' y axes, which are world z for the left palm and -z for the
    right) average to m g: the robot neither sinks nor rises over the motion."""
    _, result = moving_contacts_episode
    trace = result.trace
    model = RobotModel(humanoid())
    start = max(
        box.start_time for box in make_scenario("moving_contacts", model).scene.moving_boxes
    )
    moving = trace[trace["time"] >= start]
    vertical = (
        moving["wrench_measured_left_foot_fz"]
        + moving["wrench_measured_right_foot_fz"]
        + moving["wrench_measured_left_hand_fy"]
        - moving["wrench_measured_right_hand_fy"]
    )
    weight = model.robot.total_mass * GRAVITY
    assert vertical.mean() == pytest.approx(weight, rel=0.01)


def test_moving_contacts_hands_stay_mostly_on_the_moving_walls(moving_contacts_episode):
    """The damping control (eq. 15) keeps each palm on its wall for most of the motion: a
    wall receding faster than F_d / K_d (the desired force over Table II's 10000 N s/m) leaves
    the palm for a while (the left one for about 2.5 s of each 8 s period), but it is back in
    every period of the motion."""
    _, result = moving_contacts_episode
    trace = result.trace
    scenario = make_scenario("moving_contacts", RobotModel(humanoid()))
    boxes = scenario.scene.moving_boxes
    start, period = max(b.start_time for b in boxes), boxes[0].period
    moving = trace[trace["time"] >= start]
    for hand in ("left_hand", "right_hand"):
        assert moving[f"contact_{hand}"].mean() > 0.5
        for k in range(2):
            window = moving[(moving["time"] >= start + k * period)]
            window = window[window["time"] < start + (k + 1) * period]
            assert window[f"contact_{hand}"].mean() > 0.25, (hand, k)


def test_table_iv_rows_are_reported_per_number_of_contacts(moving_contacts_episode):
    """`latency_by_contacts_us`: Table IV's rows for each number of planned contacts (2 feet,
    + one hand, + both hands), over as many periods as the phases with that many last."""
    _, result = moving_contacts_episode
    by_contacts = result.summary["latency_by_contacts_us"]
    scenario = make_scenario("moving_contacts", RobotModel(humanoid()))
    expected: dict[str, float] = {}
    for phase in scenario.phases:
        key = str(len(phase.contacts))
        expected[key] = expected.get(key, 0.0) + (phase.end - phase.start) / DT
    assert sorted(by_contacts) == ["2", "3", "4"]
    for key, periods in expected.items():
        rows = by_contacts[key]
        assert set(rows) == {
            "centroidal_control",
            "reference",
            "preview",
            "projection",
            "distribution",
        }
        assert rows["projection"]["periods"] == pytest.approx(periods, abs=2)
        for values in rows.values():
            assert values["median"] <= values["p99"]
