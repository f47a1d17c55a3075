"""Imperfect sensors and a late loop (issue 21): what the estimator reads and what the servos
apply, between the simulator and the controller. The simulator's own `Sensors` stay exact
(the runner records the ground truth from them); the estimator gets `SensorModel.observe`'s.

Noise (white and Gaussian, one standard deviation per channel per control period of `dt`
seconds: `channel_sigmas`). Each channel's figure is given either in SI units
(`Perturbation.noise_<channel>`, for example `noise_gyro_rad_s`) or as a multiple of the data
sheet's (`Perturbation.noise_encoders`, `noise_imu`, `noise_ft`, per sensor group); the data
sheets (`DATASHEET`) are:

- joint encoders: a 17-bit absolute encoder (for example RLS AksIM-2, sold at 17 to 20 bits):
  quantisation q = 2 pi / 2^17 rad, position sigma = q / sqrt(12); velocity with the sigma
  of the finite difference of two readings one control period apart, sqrt(2) q / sqrt(12) /
  dt, drawn white and apart from the position noise (an adaptation: a true difference would
  be correlated with it and from one period to the next);
- IMU: MicroStrain 3DM-GX5-25 data sheet: gyro noise density 0.005 deg/s/sqrt(Hz),
  accelerometer 25 micro-g/sqrt(Hz), sampled at the control rate (sigma = density
  sqrt(1 / dt)); attitude accuracy 0.25 deg RMS roll and pitch, 0.8 deg heading, applied as a
  small rotation about the world axes;
- force/torque sensors: ATI Mini45 (SI-580-20 calibration) resolution, 1/4 N force, 1/188 N m
  (x, y) and 1/376 N m (z) torque, taken as the standard deviation.

A bias (`Perturbation.noise_bias` > 0) is a constant offset per episode per channel, drawn
once with the channel's figure (its SI value if given, else the data sheet's) times
`noise_bias`. The noise comes from
`numpy.random.default_rng([seed, NOISE_STREAM])` (the bias from `BIAS_STREAM`), drawn as one
vector per period in a fixed order whatever the simulator: the same seed gives the same noise
in MuJoCo and PyBullet and on every executor. A push's replicas (`bench.runner.
replica_changes`) are re-runs of one experiment on one robot: each replica after the first
reads its own noise (`[seed, NOISE_STREAM, replica]`), and all share the seed's bias (the
robot's sensors' offsets), as the push levels of a threshold do.

Delays: `CommandDelay` applies the command computed `k` periods earlier (the first command
until then: the servo holds its start-up target); `SensorModel` hands the estimator the reading
of `sensor_delay` periods ago (the first reading until then).
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, replace

import numpy as np

from robots.perturbation import NOISE_CHANNELS, NOISE_GROUP_OF_CHANNEL, Perturbation
from robots.types import JointCommand, Sensors
from sims.base import quaternion_product

NOISE_STREAM = 7_002
BIAS_STREAM = 7_003
ENCODER_BITS = 17


@dataclass(frozen=True)
class NoiseFigures:
    """One standard deviation per channel for a control period of `dt` [s]: encoder position
    [rad] and velocity [rad/s], IMU tilt (roll, pitch) and heading [rad], gyro [rad/s],
    accelerometer [m/s^2], force [N], moment about x, y and about z [N m]. The fields are
    `robots.perturbation.NOISE_CHANNELS`, in order."""

    encoder_position_rad: float
    encoder_velocity_rad_s: float
    imu_tilt_rad: float
    imu_heading_rad: float
    gyro_rad_s: float
    accelerometer_m_s2: float
    force_N: float
    moment_xy_Nm: float
    moment_z_Nm: float


def datasheet(dt: float) -> NoiseFigures:
    """The named sensors' figures (module docstring) for a control period `dt` [s]."""
    quantum = 2.0 * math.pi / 2**ENCODER_BITS
    position = quantum / math.sqrt(12.0)
    rate = 1.0 / dt  # [Hz] samples per second
    return NoiseFigures(
        encoder_position_rad=position,
        encoder_velocity_rad_s=math.sqrt(2.0) * position / dt,
        imu_tilt_rad=math.radians(0.25),
        imu_heading_rad=math.radians(0.8),
        gyro_rad_s=math.radians(0.005) * math.sqrt(rate),
        accelerometer_m_s2=25e-6 * 9.80665 * math.sqrt(rate),
        force_N=0.25,
        moment_xy_Nm=1.0 / 188.0,
        moment_z_Nm=1.0 / 376.0,
    )


DATASHEET = datasheet(0.002)
"""The figures at the default control period, 2 ms."""


def channel_sigmas(perturbation: Perturbation, dt: float) -> NoiseFigures:
    """Each channel's standard deviation for a control period `dt` [s]: its SI value
    (`Perturbation.noise_<channel>`) where that is positive, else its group's multiple
    (`noise_encoders`, `noise_imu`, `noise_ft`) of the data sheet's figure."""
    sheet = datasheet(dt)
    values = {}
    for channel in NOISE_CHANNELS:
        si = float(getattr(perturbation, f"noise_{channel}"))
        multiple = float(getattr(perturbation, f"noise_{NOISE_GROUP_OF_CHANNEL[channel]}"))
        values[channel] = si if si > 0.0 else multiple * getattr(sheet, channel)
    return NoiseFigures(**values)


def noise_sigmas(perturbation: Perturbation, n_joints: int, n_limbs: int, dt: float) -> np.ndarray:
    """The standard deviation of every noisy entry (`channel_sigmas`), in the order
    `SensorModel` draws them: joint positions (n), joint velocities (n), IMU rotation vector
    (3, world), gyro (3), accelerometer (3), limb wrenches (6 per limb)."""
    f = channel_sigmas(perturbation, dt)
    wrench = [f.force_N] * 3 + [f.moment_xy_Nm, f.moment_xy_Nm, f.moment_z_Nm]
    return np.concatenate(
        [
            np.full(n_joints, f.encoder_position_rad),
            np.full(n_joints, f.encoder_velocity_rad_s),
            np.array([f.imu_tilt_rad, f.imu_tilt_rad, f.imu_heading_rad]),
            np.full(3, f.gyro_rad_s),
            np.full(3, f.accelerometer_m_s2),
            np.tile(wrench, n_limbs),
        ]
    )


def _rotation_quaternion(rotation_vector: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation vector [rad]."""
    angle = float(np.linalg.norm(rotation_vector))
    if angle == 0.0:
        return np.array([1.0, 0.0, 0.0, 0.0])
    axis = rotation_vector / angle
    return np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * axis])


class SensorModel:
    """What the estimator reads: the simulator's `Sensors` with noise, bias and delay."""

    def __init__(
        self,
        perturbation: Perturbation,
        seed: int,
        n_joints: int,
        n_limbs: int,
        dt: float,
        replica: int = 0,
    ) -> None:
        """replica: the push replica (module docstring); replica 0 reads the seed's noise."""
        self.n, self.k = n_joints, n_limbs
        self.delay = int(perturbation.sensor_delay)
        sigma = noise_sigmas(perturbation, n_joints, n_limbs, dt)
        unit = noise_sigmas(  # the bias's figures: SI values where given, else the data sheet's
            replace(perturbation, noise_encoders=1.0, noise_imu=1.0, noise_ft=1.0),
            n_joints,
            n_limbs,
            dt,
        )
        self.sigma = sigma if np.any(sigma) else None
        stream = [seed, NOISE_STREAM] if replica == 0 else [seed, NOISE_STREAM, replica]
        self.rng = np.random.default_rng(stream)
        self.bias = None
        if perturbation.noise_bias:
            bias_rng = np.random.default_rng([seed, BIAS_STREAM])
            self.bias = perturbation.noise_bias * unit * bias_rng.standard_normal(unit.size)
        self.readings: deque[Sensors] = deque(maxlen=self.delay + 1)

    def observe(self, sensors: Sensors) -> Sensors:
        """The reading the estimator gets now, for the simulator's `sensors` of this period."""
        reading = self._corrupt(sensors)
        if not self.readings:  # the first reading: it stands for the `delay` before it
            self.readings.extend([reading] * self.delay)
        self.readings.append(reading)
        return self.readings[0]

    def _corrupt(self, sensors: Sensors) -> Sensors:
        if self.sigma is None and self.bias is None:
            return sensors
        offset = np.zeros(2 * self.n + 9 + 6 * self.k)
        if self.sigma is not None:
            offset += self.sigma * self.rng.standard_normal(offset.size)
        if self.bias is not None:
            offset += self.bias
        n, imu = self.n, 2 * self.n
        return replace(
            sensors,
            joint_position=sensors.joint_position + offset[:n],
            joint_velocity=sensors.joint_velocity + offset[n:imu],
            imu_orientation_world=quaternion_product(
                _rotation_quaternion(offset[imu : imu + 3]), sensors.imu_orientation_world
            ),
            imu_angular_velocity_imu=sensors.imu_angular_velocity_imu + offset[imu + 3 : imu + 6],
            imu_linear_acceleration_imu=sensors.imu_linear_acceleration_imu
            + offset[imu + 6 : imu + 9],
            contact_wrench_limb=sensors.contact_wrench_limb + offset[imu + 9 :].reshape(self.k, 6),
        )


class CommandDelay:
    """Applies each joint command `k` control periods after it was computed (the first
    command during the first `k` periods), with the servo gains times `gain_scale`."""

    def __init__(self, k: int, gain_scale: float = 1.0) -> None:
        self.queue: deque[JointCommand] = deque(maxlen=k + 1)
        self.k = k
        self.gain_scale = gain_scale

    def apply(self, command: JointCommand) -> JointCommand:
        if self.gain_scale != 1.0:
            command = replace(
                command, kp=command.kp * self.gain_scale, kd=command.kd * self.gain_scale
            )
        if not self.queue:
            self.queue.extend([command] * self.k)
        self.queue.append(command)
        return self.queue[0]
