"""The `hold` planner's standing reference, and the resultant-wrench convention every planner
shares (w-bar = m c'' with gravity apart: `CentroidalPlan`, Murooka eqs. 9-10)."""

from dataclasses import replace

import numpy as np
import pytest

from bench.scenarios import make_scenario
from centroidal.rotations import to_matrix
from centroidal.support import margin_inside, support_halfplanes, surface_vertices_world
from planners.base import PLANNERS, planner_spec
from planners.hold import HoldPlanner
from robots.model import RobotModel
from robots.robot_registry import make_robot

DT = 0.002
GRAVITY = 9.81


def _at_rest(model: RobotModel):
    state = model.standing_state()
    return replace(
        state, com_position_world=model.com_position_world(state), com_velocity_world=np.zeros(3)
    )


@pytest.fixture(scope="module", params=["centrobench_humanoid", "jvrc1"])
def model(request):
    return RobotModel(make_robot(request.param))


def test_holds_reference_starts_at_the_robots_com_and_settles_over_the_feet(model):
    """The first plan's CoM is the robot's own, at rest; after 3 s the reference is within
    0.1 mm of the feet's midpoint at the start height, and at every period in between the
    planned ZMP is inside the two soles' support polygon and the planned force is m c''."""
    scenario = make_scenario("stand", model)
    state = _at_rest(model)
    planner = HoldPlanner(DT)
    planner.reset(model, scenario, state)
    start = model.com_position_world(state)
    feet = [c for c in scenario.phases[0].contacts if c.limb.endswith("foot")]
    middle = np.mean([c.position_world for c in feet], axis=0)
    limbs = {limb.name: limb for limb in model.robot.limbs}
    corners = [
        surface_vertices_world(
            limbs[c.limb].half_extents, np.asarray(c.position_world), to_matrix(c.orientation_world)
        )
        for c in feet
    ]
    halfplanes = support_halfplanes(np.vstack(corners)[:, :2])
    first = planner.plan(0.0, state)
    np.testing.assert_allclose(first.com_planned_world, start, atol=1e-12)
    np.testing.assert_allclose(first.com_velocity_planned_world, 0.0, atol=1e-12)
    for k in range(int(3.0 / DT) + 1):
        plan = planner.plan(k * DT, state)
        assert margin_inside(halfplanes, plan.zmp_planned_world[:2]) > 0.0
        np.testing.assert_allclose(
            plan.wrench_planned_world[:3],
            model.total_mass * plan.com_acceleration_planned_world,
            atol=1e-9,
        )
    np.testing.assert_allclose(plan.com_planned_world[:2], middle[:2], atol=1e-4)
    assert plan.com_planned_world[2] == pytest.approx(start[2], abs=1e-12)


@pytest.mark.parametrize("name", PLANNERS.names())
def test_every_planners_resultant_leaves_gravity_out(name, model):
    """At rest on both feet, every planner's planned and projected vertical resultant force is
    under 1 % of the weight (the contact forces carry m g; the resultant w-bar is m c'', and a
    stabilizer adds the weight back, eqs. 9-10; the horizontal force may start non-zero where
    the CoM starts off the planner's nominal point, 14 N on JVRC-1). Five-mass and the
    hierarchy planned m (c'' + g) and the contact forces' sum before 2026-11-27: a stabilizer
    composed with them would have doubled the weight."""
    planner = planner_spec(name).factory(DT)
    state = _at_rest(model)
    planner.reset(model, make_scenario("stand", model), state)
    plan = planner.plan(0.0, state)
    weight = model.total_mass * GRAVITY
    assert abs(plan.wrench_planned_world[2]) < 0.01 * weight
    assert abs(plan.wrench_projected_world[2]) < 0.01 * weight
