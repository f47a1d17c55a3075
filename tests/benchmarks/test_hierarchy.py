"""Sherikov et al.'s hierarchy (three levels, 78 variables) solved at a contact switch: the
first period of single support after standing (the paper: "the number of iterations increases
during transition between the left and right supports"), by the controller's DAQP backend and
by the reference cascade of QPs in the same run; compare with the paper's 0.92 ms mean solve
(i5-3360M) as a ratio to the cascade here, not as an absolute figure."""

from dataclasses import replace

import numpy as np
import pytest

import planners.capturability_hierarchy as module
from bench.scenarios import make_scenario
from centroidal.hierarchy import solve_hierarchy
from robots.humanoid import humanoid
from robots.model import RobotModel

SWITCH = 1.0  # [s] the first step's lift-off


@pytest.fixture(scope="module")
def switch():
    """The hierarchy of the period at the switch and the active set of the period before."""
    model = RobotModel(humanoid())
    state = model.standing_state()
    state = replace(
        state, com_position_world=model.com_position_world(state), com_velocity_world=np.zeros(3)
    )
    planner = module.CapturabilityHierarchyPlanner(0.002)
    planner.reset(model, make_scenario("stand", model), state)
    planner.schedule.start(SWITCH, "right_foot")
    captured = []
    original = module.solve_hierarchy

    def capture(levels, n, **kwargs):
        captured.append((levels, n))
        return original(levels, n, **kwargs)

    module.solve_hierarchy = capture
    try:
        planner.plan(SWITCH - 0.002, state)
        before = planner.warm[1]
        planner.plan(SWITCH, state)
    finally:
        module.solve_hierarchy = original
    levels, n = captured[-1]
    return levels, n, before


@pytest.mark.benchmark(group="hierarchy-solve")
@pytest.mark.parametrize("solver", ["daqp", "cascade"])
def test_hierarchy_solve_at_a_contact_switch(benchmark, switch, solver):
    levels, n, _ = switch
    reference = solve_hierarchy(levels, n, solver="cascade")
    rounds = 30 if solver == "daqp" else 10
    solution = benchmark.pedantic(
        solve_hierarchy, args=(levels, n), kwargs={"solver": solver}, rounds=rounds, iterations=1
    )
    np.testing.assert_allclose(solution.violation_norm, reference.violation_norm, rtol=0, atol=1e-6)
