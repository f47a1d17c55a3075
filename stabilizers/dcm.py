"""Stabilizer `dcm`: DCM proportional feedback to a command ZMP (Murooka et al. 2022,
Appendix eqs. 17-18; Englsberger et al., Morisawa et al.), then the same wrench distribution
and damping control as `centroidal_feedback` (eqs. 13-16).

With omega = sqrt(g / h) (h: desired CoM height above the support), the DCM
xi = c + c' / omega (horizontal), and the desired ZMP z^d (the plan's):
    z^c = z^d + K_xi (xi^a - xi^d)                                     (eq. 17)
    c''^c = omega^2 (c^d - z^c)                                         (eq. 18a)
    f^c = m c''^c                                                       (eq. 18c)
and vertically the planned force with the Table III PD on the height (scaled as in
`centroidal_feedback`); the command resultant moment about the CoM is zero (the LIPM's force
passes through the CoM). K_xi = 2, the Appendix's value for HRP-5P, which by eq. 19 "roughly
matches" Table III's linear gains (they imply K_xi = 1.85 from K_P and 1.97 from K_D). So on
our humanoid `dcm` acts with m omega^2 K_xi = 1387 N/m and m omega K_xi = 403 N s/m where
`centroidal_feedback`'s rescaled Table III has 1280 / 397 (8 % stiffer). omega is taken each
period from the desired CoM's height above the plan's ZMP (ours; the Appendix's LIPM has a
constant height).
"""

from __future__ import annotations

import numpy as np

from robots.types import CentroidalPlan, RobotState
from stabilizers.base import StabilizerSpec, register
from stabilizers.centroidal_feedback import GRAVITY, CentroidalFeedbackStabilizer

K_XI = 2.0


class DcmStabilizer(CentroidalFeedbackStabilizer):
    name = "dcm"

    def desired_wrench(self, plan: CentroidalPlan, state: RobotState) -> np.ndarray:
        com_d, velocity_d, _, _ = plan.desired_state()
        com_a, velocity_a = state.com_position_world, state.com_velocity_world
        height = com_d[2] - plan.zmp_planned_world[2]
        omega = np.sqrt(GRAVITY / height)
        dcm_d = com_d[:2] + velocity_d[:2] / omega
        dcm_a = com_a[:2] + velocity_a[:2] / omega
        zmp_c = plan.zmp_planned_world[:2] + K_XI * (dcm_a - dcm_d)  # eq. 17
        horizontal = self.mass * omega**2 * (com_d[:2] - zmp_c)  # eq. 18a, 18c
        vertical = (
            plan.wrench_projected_world[2]
            + self.kp[2] * (com_d[2] - com_a[2])
            + self.kd[2] * (velocity_d[2] - velocity_a[2])
        )
        return np.array([horizontal[0], horizontal[1], vertical, 0.0, 0.0, 0.0])


register(
    StabilizerSpec(
        "dcm",
        DcmStabilizer,
        "DCM feedback to a command ZMP (Murooka Appendix), distribution, damping",
        needs=frozenset({"force_torque_sensors"}),
    )
)
