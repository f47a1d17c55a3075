"""The whole control loop, per stage and per period, for every registered controller in both
simulators (`make benchmark`; issue 16's benchmark that stays). Nothing here asserts a time.

Each case runs the first 3 s of `walk` (standing, then the first step) once and reports, in the
benchmark's `extra_info`, the median per period of every stage [us] and the ratios that do not
depend on the machine's speed: the simulator stage against the engine's own work in it
(`sim_engine`: its physics steps and, for MuJoCo, the sensor forward pass), and the control
stages against that engine work. A later change that slows the loop shows up as a ratio.
"""

import pytest

from bench.controllers import CONTROLLERS
from bench.runner import EpisodeSpec, run_episode

pytestmark = pytest.mark.benchmark(group="loop")
STAGES = ("estimator", "planner", "stabilizer", "whole_body", "sim", "sim_engine")


@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
@pytest.mark.parametrize("controller", sorted(CONTROLLERS))
def test_loop(benchmark, controller, sim):
    spec = CONTROLLERS[controller]
    episode = EpisodeSpec(
        spec.planner, spec.stabilizer, sim, "walk", duration=3.0, whole_body=spec.whole_body
    )
    result = benchmark.pedantic(run_episode, args=(episode,), rounds=1, iterations=1)
    latency = result.summary["latency_us"]
    # `hold` + `posture` does not walk: its periods up to the fall are timed all the same
    assert result.summary["status"] in ("ok", "fell"), result.summary["error"]
    benchmark.extra_info["status"] = result.summary["status"]
    medians = {stage: latency[stage]["median"] for stage in STAGES}
    medians["control_total"] = latency["control_total"]["median"]
    benchmark.extra_info.update({f"{k}_median_us": round(v, 1) for k, v in medians.items()})
    benchmark.extra_info["sim_over_engine"] = round(medians["sim"] / medians["sim_engine"], 2)
    benchmark.extra_info["control_over_engine"] = round(
        medians["control_total"] / medians["sim_engine"], 2
    )
