"""Where the inertia controller's loop closes (issue 17; docs/ficht-behnke.md, "Where the
inertia controller's loop closes", 2026-12-03). An experiment, not part of the package.

One episode of a Ficht & Behnke row with a state mixed from two sources, the five-mass filter
(`five_mass_kalman`) running beside the simulator's state on the same sensors:

    python docs/experiments/tilt_source.py SOURCE[-noacc][-filter] [ROW] [SIM] [SCENARIO] [S]

SOURCE is where the joint angles of the fed-back inertia tilt (eqs. 13-14's theta_f) come
from: `measured` (the encoders, as the paper), `joints` (the previous period's joint targets,
so that the servos' tracking is not in the tilt's path), `ikpose` (the pose generator's own
configuration, base included, so that neither the servos nor the floor are). `-noacc` drops
the tilt acceleration (`flywheel_zmp` then takes the ZMP as given: right for the simulator's
force-sensor ZMP, which already holds the flywheel's reaction); `-filter` feeds the filter's
whole state (CoM, ZMP) instead of the simulator's. ROW defaults to `direct_centroidal`, SIM to
`mujoco`, SCENARIO to `stand`, S (duration) to 3.
"""

import copy
import dataclasses
import sys

import numpy as np
import pinocchio as pin

import wholebody.five_mass_pose as five_mass_pose
from bench.controllers import controller_spec
from bench.runner import EpisodeSpec, run_episode
from centroidal.tilt import flywheel_angles
from estimators.base import ESTIMATORS, ComponentSpec
from estimators.five_mass_kalman import FiveMassKalmanEstimator
from estimators.ground_truth import GroundTruthEstimator
from robots.five_mass import FiveMassModel

LAST: dict = {}  # the pose generator's last command and configuration
_command = five_mass_pose.FiveMassPoseLayer.command


def _recording_command(self, targets, state):
    command = _command(self, targets, state)
    LAST["command"] = command
    LAST["q"] = self.ik.q.copy()
    return command


five_mass_pose.FiveMassPoseLayer.command = _recording_command
ARG = sys.argv[1]
SOURCE = ARG.split("-")[0]
NO_ACCELERATION = "-noacc" in ARG
FILTER_STATE = "-filter" in ARG
assert SOURCE in ("measured", "joints", "ikpose"), SOURCE


class Mixed(GroundTruthEstimator):
    name = "mixed"

    def __init__(self, model, dt):
        super().__init__(model)
        self.kalman = FiveMassKalmanEstimator(model, dt)
        self.five = FiveMassModel(model)
        self.pose_data = self.model.createData()

    def reset(self, initial, sensors):
        super().reset(initial, sensors)
        self.kalman.reset(initial, sensors)
        self.pose_tilt_filter = copy.deepcopy(self.kalman.tilt_filter)
        LAST.clear()

    def follow(self, plan):
        self.kalman.follow(plan)

    def _flywheel(self, q):
        """theta_f [rad] (2,) of configuration q, as the filter measures it."""
        pin.framesForwardKinematics(self.model, self.pose_data, q)
        feet = sum(self.pose_data.oMf[f].translation for f in self.kalman.foot_frames) / 2
        com = pin.centerOfMass(self.model, self.pose_data, q)
        axes = self.five.evaluate(q).axes_world
        return flywheel_angles(axes[:, 2], com - feet)

    def estimate(self, sensors):
        truth = super().estimate(sensors)
        seen = sensors
        if SOURCE == "joints" and "command" in LAST:
            seen = dataclasses.replace(
                sensors,
                joint_position=LAST["command"].position,
                joint_velocity=LAST["command"].velocity,
            )
        kalman = self.kalman.estimate(seen)
        tilt = (
            kalman.inertia_tilt,
            kalman.inertia_tilt_rate,
            kalman.inertia_tilt_acceleration,
        )
        if SOURCE == "ikpose":
            q = LAST.get("q", self.robot_model.configuration(truth))
            tilt = self.pose_tilt_filter.update(self._flywheel(q)[None])
        return dataclasses.replace(
            kalman if FILTER_STATE else truth,
            inertia_tilt=np.array(tilt[0]),
            inertia_tilt_rate=np.array(tilt[1]),
            inertia_tilt_acceleration=None if NO_ACCELERATION else np.array(tilt[2]),
        )


ESTIMATORS.names()  # the built-in estimators first
ESTIMATORS.register(ComponentSpec("mixed", Mixed, "experiment", gives=frozenset({"inertia_tilt"})))
row, sim, scenario, duration = (
    sys.argv[2:] + ["direct_centroidal", "mujoco", "stand", "3"][len(sys.argv) - 2 :]
)[:4]
spec = controller_spec(row)
summary = run_episode(
    EpisodeSpec(
        planner=spec.planner,
        stabilizer=spec.stabilizer,
        whole_body=spec.whole_body,
        sim=sim,
        scenario=scenario,
        duration=float(duration),
        estimator="mixed",
    )
).summary
print(ARG, row, sim, scenario, summary["status"], summary.get("fall_time"))
