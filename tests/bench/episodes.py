"""Running a registered controller's episode in tests: its parts, its own estimator and
whole-body layer, as `centrobench run --controller NAME` does."""

from bench.controllers import controller_spec
from bench.runner import EpisodeResult, EpisodeSpec, run_episode


def run_controller(
    controller: str, sim: str, scenario: str, estimator: str | None = None, **kwargs
) -> EpisodeResult:
    """`estimator` None: the controller's own."""
    spec = controller_spec(controller)
    return run_episode(
        EpisodeSpec(
            spec.planner,
            spec.stabilizer,
            sim,
            scenario,
            estimator=estimator or spec.episode_estimator,
            whole_body=spec.whole_body,
            **kwargs,
        )
    )
