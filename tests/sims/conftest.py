"""Fixtures shared by the simulator tests: the humanoid at scale 1 and its pinocchio model
(one per test module)."""

import pytest

from robots.humanoid import humanoid
from robots.model import RobotModel


@pytest.fixture(scope="module")
def robot():
    return humanoid()


@pytest.fixture(scope="module")
def model(robot):
    return RobotModel(robot)
