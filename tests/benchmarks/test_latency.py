"""Per-stage timing runs (pytest-benchmark; `make benchmark`). Nothing here asserts a time:
the figures go into the benchmark report.

Stages on the `stand` contact set, in a state recorded from a MuJoCo run: the whole-body IK
with each QP backend, the whole-body layer (IK + feed-forward), the estimators, the `hold`
planner and the `posture` stabilizer.
"""

import numpy as np
import pytest

from bench.scenarios import make_scenario
from estimators.ground_truth import GroundTruthEstimator
from estimators.proprioceptive import ProprioceptiveEstimator
from planners.hold import HoldPlanner
from robots.humanoid import humanoid
from robots.model import RobotModel
from sims.base import make_simulator
from stabilizers.posture import PostureStabilizer
from wholebody.ik import WholeBodyIK
from wholebody.ik_feedforward import IkFeedforwardLayer

pytestmark = pytest.mark.benchmark(group="stages", min_rounds=200, warmup=True)
DT = 0.002


@pytest.fixture(scope="module")
def setup():
    model = RobotModel(humanoid())
    scenario = make_scenario("stand", model)
    initial = model.standing_state()
    sim = make_simulator("mujoco")
    sensors = sim.reset(model.robot, scenario.scene, initial)
    for _ in range(100):
        sensors = sim.step(model.hold_command(initial))
    sim.close()
    estimator = GroundTruthEstimator(model)
    estimator.reset(initial, sensors)
    state = estimator.estimate(sensors)
    planner = HoldPlanner(DT)
    planner.reset(model, scenario, state)
    plan = planner.plan(0.2, state)
    stabilizer = PostureStabilizer(DT)
    stabilizer.reset(model, scenario, state)
    targets = stabilizer.stabilize(0.2, plan, state)
    return {
        "model": model,
        "initial": initial,
        "sensors": sensors,
        "state": state,
        "planner": planner,
        "plan": plan,
        "stabilizer": stabilizer,
        "targets": targets,
    }


@pytest.mark.parametrize("solver", ["daqp", "quadprog", "proxqp", "osqp", "clarabel"])
def test_ik(benchmark, setup, solver):
    ik = WholeBodyIK(setup["model"], DT, solver=solver)
    ik.reset(setup["initial"])
    targets = setup["targets"]
    joints, _ = benchmark(ik.solve, targets)
    assert np.all(np.isfinite(joints))


def test_whole_body_layer(benchmark, setup):
    layer = IkFeedforwardLayer(setup["model"], DT)
    layer.reset(setup["model"], setup["initial"])
    command = benchmark(layer.command, setup["targets"], setup["initial"])
    assert np.all(np.isfinite(command.torque_feedforward))


@pytest.mark.parametrize("cls", [GroundTruthEstimator, ProprioceptiveEstimator])
def test_estimator(benchmark, setup, cls):
    estimator = cls(setup["model"])
    estimator.reset(setup["initial"], setup["sensors"])
    state = benchmark(estimator.estimate, setup["sensors"])
    assert np.all(np.isfinite(state.com_position_world))


def test_hold_planner(benchmark, setup):
    plan = benchmark(setup["planner"].plan, 0.2, setup["state"])
    assert plan.contact_limbs == ("left_foot", "right_foot")


def test_posture_stabilizer(benchmark, setup):
    targets = benchmark(setup["stabilizer"].stabilize, 0.2, setup["plan"], setup["state"])
    assert targets.limb_in_contact.tolist() == [True, True, False, False]
