"""Stabilizer `passthrough`: hands a whole-body planner's decision to the whole-body layer
unchanged, for methods with no separate stabilization (Sherikov et al. 2014 decide the
accelerations and contact wrenches in one hierarchy, `planners.capturability_hierarchy`; the
`inverse_dynamics` layer turns them into torques)."""

from __future__ import annotations

import time

import numpy as np

from robots.model import RobotModel
from robots.scene import Scenario
from robots.types import CentroidalPlan, RobotState, WholeBodyTargets
from stabilizers.base import StabilizerSpec, register


class PassthroughStabilizer:
    name = "passthrough"

    def __init__(self, dt: float) -> None:
        self.dt = dt

    def reset(self, robot: RobotModel, scenario: Scenario, state: RobotState) -> None:
        self.limb_names = robot.robot.limb_names

    def stabilize(self, t: float, plan: CentroidalPlan, state: RobotState) -> WholeBodyTargets:
        start = time.perf_counter_ns()
        if plan.generalized_acceleration is None or plan.contact_wrench_limb is None:
            raise ValueError(
                "passthrough needs a planner that decides the whole body's accelerations and "
                "contact wrenches (capturability_hierarchy)"
            )
        in_contact = np.array([name in plan.contact_limbs for name in self.limb_names])
        return WholeBodyTargets(
            com_position_world=plan.com_planned_world,
            base_orientation_world=plan.base_orientation_planned_world,
            limb_position_world=plan.limb_target_position_world,
            limb_orientation_world=plan.limb_target_orientation_world,
            limb_in_contact=in_contact,
            com_desired_world=plan.com_planned_world,
            zmp_desired_world=plan.zmp_planned_world,
            contact_wrench_desired_limb=plan.contact_wrench_limb,
            generalized_acceleration=plan.generalized_acceleration,
            timings_ns={"passthrough": time.perf_counter_ns() - start},
            limb_tracked=plan.limb_tracked,
        )


register(
    StabilizerSpec(
        "passthrough", PassthroughStabilizer, "none: the planner's accelerations and wrenches"
    )
)
