"""`kinematic_inertial`: the state Murooka et al.'s controller is given (RA-L 2022, Sec. V-A2:
"the joint angles from the joint encoders, the contact wrench from the 6-axis force sensors
... and the link orientation from the IMU"): no measured base position. As in the authors'
mc_rtc set-up (the KinematicInertial observer with its anchor frame on the control robot's
target contact poses), the base is placed by kinematics so that the limbs in contact are where
the plan puts them.

- Base orientation and angular velocity: the IMU's (as `proprioceptive`).
- Base position: the limbs that the last plan holds in contact and whose force sensor carries
  more than `contact_threshold` of the weight are the stance; each is anchored at the plan's
  target position for it (`CentroidalPlan.limb_target_position_world`, taken every period),
  and the base is placed so that the stance limbs, weighted by their vertical forces, are at
  their anchors.
- Base linear velocity: the stance limbs do not move (as `proprioceptive`).
- No limb carrying weight: the base stays where the last stance put it (`_flight`).

The CoM a controller then feeds back is measured relative to its own planned contacts: a foot
that lands 5 mm short of its target moves the measured CoM, not the plan. With the simulator's
ground-truth position instead (`ground_truth`), every touchdown error is fed back as a CoM error
that the controller corrects by leaning (measured: with Murooka's pair, short steps pitch the
robot forward by about 0.6 deg per step until it falls, at 0.02 m/s in both simulators; with
this estimator it walks).

Before the first plan (and for limbs the plan does not hold) a limb is anchored where the
kinematics put it, as in `proprioceptive`.
"""

from __future__ import annotations

import numpy as np

from estimators.base import ComponentSpec, register
from estimators.proprioceptive import ProprioceptiveEstimator
from robots.model import RobotModel
from robots.types import CentroidalPlan, RobotState, Sensors


class KinematicInertialEstimator(ProprioceptiveEstimator):
    name = "kinematic_inertial"

    def __init__(self, model: RobotModel, contact_threshold: float = 0.05) -> None:
        super().__init__(model, contact_threshold)
        self.limb_names = model.robot.limb_names
        self.planned_contact = np.zeros(len(self.limb_frames), dtype=bool)
        self.planned_position = np.zeros((len(self.limb_frames), 3))
        self._contacts_seen: tuple[str, ...] | None = None

    def reset(self, initial: RobotState, sensors: Sensors) -> None:
        super().reset(initial, sensors)
        self.planned_contact[:] = False
        self._contacts_seen = None

    def follow(self, plan: CentroidalPlan) -> None:
        """Take the plan's contacts and their target positions as the anchors to come."""
        if plan.contact_limbs != self._contacts_seen:
            self._contacts_seen = plan.contact_limbs
            self.planned_contact = np.array([n in plan.contact_limbs for n in self.limb_names])
        self.planned_position = plan.limb_target_position_world

    def _flight(self, dt: float) -> None:
        """No limb carries weight (a bounce, a foot chattering as it lands): the base stays
        where the last stance put it, as mc_rtc's observer keeps its last anchor; integrating a
        velocity measured as the feet unload carried the estimate 0.45 m off in 0.2 s."""

    def _stance(self, vertical_force: np.ndarray) -> np.ndarray:
        stance = vertical_force > self.contact_force
        if self._contacts_seen is not None:
            stance &= self.planned_contact
        return stance

    def _anchor(self, stance: np.ndarray, landed: np.ndarray) -> None:
        held = stance & self.planned_contact if self._contacts_seen is not None else None
        if held is not None and held.any():  # every period, as mc_rtc's anchor frame
            self.anchors[held] = self.planned_position[held]
        super()._anchor(stance, landed if held is None else landed & ~held)


register(
    ComponentSpec(
        "kinematic_inertial",
        lambda model, dt: KinematicInertialEstimator(model),  # dt unused: it uses the sensors' time
        "IMU orientation, base placed by kinematics on the plan's contacts (Murooka's set-up)",
    )
)
