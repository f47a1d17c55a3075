"""`ground_truth`: the base pose and twist from the simulator's ground truth (the rest as every
estimator: `estimators.base.EstimatorBase`)."""

from __future__ import annotations

from estimators.base import ComponentSpec, EstimatorBase, register
from robots.types import RobotState, Sensors


class GroundTruthEstimator(EstimatorBase):
    name = "ground_truth"

    def estimate(self, sensors: Sensors) -> RobotState:
        return self._complete(sensors.ground_truth(), sensors)


register(
    ComponentSpec(
        "ground_truth",
        lambda model, dt: GroundTruthEstimator(model),  # dt: unused, a state of one period
        "base pose and twist from the simulator",
    )
)
