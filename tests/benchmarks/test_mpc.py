"""linear_mpc's update (one planner call: contacts, QP build and solve, projection check) per
formulation and solver at the default horizon (20 samples of 0.1 s), and preview_control's in
the same run, on the walk at the first contact switch (t = 0.9 s: the horizon holds double and
single support)."""

from dataclasses import replace

import numpy as np
import pytest

from bench.scenarios import make_scenario
from centroidal.mpc_formulations import FORMULATIONS
from planners.linear_mpc import LinearMpcPlanner
from planners.preview_control import PreviewControlPlanner
from robots.humanoid import humanoid
from robots.model import RobotModel

T = 0.9
SLOW = {"cvxpy:OSQP", "casadi:qpoases"}  # hundreds of ms per update: fewer rounds


@pytest.fixture(scope="module")
def setup():
    model = RobotModel(humanoid())
    scenario = make_scenario("walk", model)
    state = model.standing_state()
    state = replace(
        state, com_position_world=model.com_position_world(state), com_velocity_world=np.zeros(3)
    )
    return model, scenario, state


def _ready(planner, setup):
    model, scenario, state = setup
    planner.reset(model, scenario, state)
    planner.plan(T - 0.002, state)  # builds the caches (and cvxpy's / CasADi's problem)
    return planner


@pytest.mark.benchmark(group="mpc-update")
@pytest.mark.parametrize("formulation", FORMULATIONS)
def test_linear_mpc_update(benchmark, setup, formulation):
    planner = _ready(LinearMpcPlanner(0.002, formulation=formulation), setup)
    state = setup[2]
    rounds = 5 if formulation in SLOW else 30
    plan = benchmark.pedantic(planner.plan, args=(T, state), rounds=rounds, iterations=1)
    assert planner.solver_failures == 0
    assert np.all(np.isfinite(plan.wrench_planned_world))


@pytest.mark.benchmark(group="mpc-update")
def test_preview_control_update(benchmark, setup):
    planner = _ready(PreviewControlPlanner(0.002), setup)
    plan = benchmark(planner.plan, T, setup[2])
    assert np.all(np.isfinite(plan.wrench_planned_world))
