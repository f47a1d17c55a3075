"""The per-period data objects keep the dataclass contract with their fast `__init__`."""

import dataclasses

import numpy as np
import pytest

from robots.types import JointCommand, RobotState, per_period


def test_fast_init_keeps_fields_defaults_equality_and_immutability():
    a = np.zeros(3)
    state = RobotState(a, np.array([1.0, 0, 0, 0]), a, a, a, a, time=0.5)
    assert state.time == 0.5
    assert state.com_position_world is None  # a default
    assert set(vars(state)) == {f.name for f in dataclasses.fields(RobotState)}
    with pytest.raises(dataclasses.FrozenInstanceError):
        state.time = 1.0
    moved = dataclasses.replace(state, time=2.0)
    assert moved.time == 2.0
    assert moved.base_position_world is state.base_position_world
    kp = np.ones(3)
    command = JointCommand(a, a, a, kp, a)
    assert command.kp is kp
    assert command.position is a
    with pytest.raises(TypeError):
        JointCommand(a, a, a, a)  # a missing field is still an error
    with pytest.raises(TypeError):
        JointCommand(a, a, a, a, a, extra=a)  # as is an unknown one


def test_per_period_refuses_default_factories():
    @dataclasses.dataclass(frozen=True)
    class WithFactory:
        values: list = dataclasses.field(default_factory=list)

    with pytest.raises(TypeError, match="default factories"):
        per_period(WithFactory)
