"""Per-worker set-up caches (issue 16): robots, pinocchio models and compiled MuJoCo models are
built once per process, PyBullet clients are reused. An episode set up from the caches must be
the episode set up from scratch, bit for bit, also after an episode that fell."""

import pytest

from bench.runner import EpisodeSpec, clear_setup_caches, run_episode
from robots.model import cached_model
from sims import mujoco_sim, pybullet_sim


def trace_of(spec: EpisodeSpec):
    result = run_episode(spec)
    timing = [c for c in result.trace.columns if c.startswith("t_")]
    return result.summary, result.trace.drop(columns=timing)


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
def test_cached_setup_gives_the_fresh_episode_even_after_a_fall(sim):
    walk = EpisodeSpec("preview_control", "centroidal_feedback", sim, "walk", duration=1.0)
    fall = EpisodeSpec(
        "hold",
        "posture",
        sim,
        "stand_push",
        push_impulse=150.0,
        push_direction_deg=0.0,
        duration=4.0,
    )
    clear_setup_caches()
    fresh_summary, fresh = trace_of(walk)
    fall_summary, _ = trace_of(fall)
    assert fall_summary["status"] == "fell"
    model_hits_before = cached_model.cache_info().hits
    assert model_hits_before >= 1  # the fall reused the walk's model
    if sim == "mujoco":
        assert mujoco_sim.build_model.cache_info().hits >= 1
    else:
        assert len(pybullet_sim._idle_clients) == 1  # the walk's client served the fall
    again_summary, again = trace_of(walk)
    assert cached_model.cache_info().hits > model_hits_before
    assert fresh_summary["status"] == again_summary["status"] == "ok"
    assert fresh.equals(again)
    assert len(fresh) == 500
