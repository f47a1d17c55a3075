"""Estimators on a standing robot: the proprioceptive estimate against ground truth, and the
measured ZMP against the CoM projection (at rest the ground reaction passes through the CoM)."""

import numpy as np
import pytest

from estimators.base import make_estimator
from estimators.ground_truth import GroundTruthEstimator
from estimators.proprioceptive import ProprioceptiveEstimator
from robots.humanoid import humanoid
from robots.model import RobotModel
from robots.scene import Scene
from sims.base import make_simulator


@pytest.fixture(scope="module")
def model():
    return RobotModel(humanoid())


@pytest.mark.parametrize("sim_name", ["mujoco", "pybullet"])
def test_proprioceptive_matches_ground_truth_while_standing(model, sim_name):
    initial = model.standing_state()
    command = model.hold_command(initial)
    truth, proprio = GroundTruthEstimator(model), ProprioceptiveEstimator(model)
    sim = make_simulator(sim_name)
    try:
        sensors = sim.reset(model.robot, Scene(), initial)
        truth.reset(initial, sensors)
        proprio.reset(initial, sensors)
        base_error, com_error, zmp_gap = [], [], []
        for _ in range(1000):  # 2 s
            sensors = sim.step(command)
            a, b = truth.estimate(sensors), proprio.estimate(sensors)
            base_error.append(np.linalg.norm(a.base_position_world - b.base_position_world))
            com_error.append(np.linalg.norm(a.com_position_world - b.com_position_world))
            zmp_gap.append(np.linalg.norm(a.zmp_world[:2] - a.com_position_world[:2]))
    finally:
        sim.close()
    assert max(base_error) < 0.005
    assert max(com_error) < 0.005
    assert max(zmp_gap[250:]) < 0.002  # after 0.5 s of settling
    np.testing.assert_allclose(b.base_orientation_world, a.base_orientation_world, atol=1e-9)
    np.testing.assert_allclose(
        b.base_angular_velocity_world, a.base_angular_velocity_world, atol=1e-6
    )
    assert b.contact_flag_limb.tolist() == [True, True, False, False]


def test_unknown_estimator_lists_the_known_ones(model):
    with pytest.raises(KeyError, match="ground_truth, proprioceptive"):
        make_estimator("kalman", model)
