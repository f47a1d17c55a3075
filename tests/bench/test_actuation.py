"""The torque use an episode reports (`bench.actuation`): the largest share of a limit, its
joint, and the periods in which the clipping decided a torque."""

from __future__ import annotations

import numpy as np
import pytest

from bench.actuation import TorqueUse
from bench.runner import EpisodeSpec, run_episode
from robots.perturbation import Perturbation


def test_torque_use_counts_shares_and_clipped_periods():
    use = TorqueUse(("knee", "ankle"), np.array([10.0, 20.0]))
    assert use.summary()["torque_share_max"] is None  # nothing observed yet
    use.observe(np.array([5.0, -10.0]))  # half of each limit
    use.observe(np.array([-2.0, 20.0]))  # the ankle at its limit
    use.observe(np.array([0.0, 1.0]))
    assert use.summary() == {
        "torque_share_max": 1.0,
        "torque_share_joint": "ankle",
        "torque_saturated_fraction": pytest.approx(1 / 3),
    }


def test_a_joint_without_torque_is_at_its_limit():
    use = TorqueUse(("knee", "ankle"), np.array([10.0, 0.0]))  # torque_scale 0 on the ankle
    use.observe(np.array([5.0, 0.0]))
    assert use.summary() == {
        "torque_share_max": 1.0,
        "torque_share_joint": "ankle",
        "torque_saturated_fraction": 1.0,
    }


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
def test_standing_uses_part_of_the_limits_and_weak_joints_clip(sim):
    """Standing, the humanoid needs well under its joints' limits (no period clipped: the
    knees, the most loaded, hold the bent stance with about 30 N m of their 300 N m); with every
    limit cut to 3 % (`torque_scale`, 9 N m at the knee) some joint is at its limit in most
    periods, the share is 1, and it falls."""
    nominal = run_episode(EpisodeSpec("hold", "posture", sim, "stand", duration=1.0)).summary
    assert nominal["status"] == "ok"
    assert 0.01 < nominal["torque_share_max"] < 0.5
    assert nominal["torque_saturated_fraction"] == 0.0
    weak = run_episode(
        EpisodeSpec(
            "hold",
            "posture",
            sim,
            "stand",
            duration=1.0,
            perturbation=Perturbation(torque_scale=0.03),
        )
    ).summary
    assert weak["torque_share_max"] == pytest.approx(1.0)
    assert weak["torque_saturated_fraction"] > 0.5
    assert weak["fell"]
