"""Imperfect sensors and delays (`sims.sensor_model`): the injected noise has the requested
standard deviation, the same seed gives the same noise in both simulators, and a delay of k
periods shifts commands and readings by exactly k periods."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from robots.perturbation import Perturbation
from robots.scene import Scene
from robots.types import JointCommand
from sims.base import make_simulator
from sims.sensor_model import DATASHEET, CommandDelay, SensorModel, datasheet

DT = 0.002


def _standing(sim_name, robot, model, periods, perturbation, seed=3):
    """(simulator readings, what the estimator would read) over `periods` standing periods."""
    sim = make_simulator(sim_name)
    initial = model.standing_state()
    raw = [sim.reset(robot, Scene(), initial)]
    sensors = SensorModel(perturbation, seed, robot.n_joints, len(robot.limbs), DT)
    read = [sensors.observe(raw[0])]
    hold = model.hold_command(initial)
    for _ in range(periods):
        raw.append(sim.step(hold))
        read.append(sensors.observe(raw[-1]))
    sim.close()
    return raw, read


def _offsets(raw, read) -> dict[str, np.ndarray]:
    """What the sensor model added, channel by channel, over all periods."""

    def stack(name):
        return np.array(
            [getattr(b, name) - getattr(a, name) for a, b in zip(raw, read, strict=True)]
        )

    rotation = np.array(
        [
            (
                Rotation.from_quat(np.roll(b.imu_orientation_world, -1))
                * Rotation.from_quat(np.roll(a.imu_orientation_world, -1)).inv()
            ).as_rotvec()
            for a, b in zip(raw, read, strict=True)
        ]
    )
    wrench = stack("contact_wrench_limb")
    return {
        "encoder_position_rad": stack("joint_position").ravel(),
        "encoder_velocity_rad_s": stack("joint_velocity").ravel(),
        "imu_tilt_rad": rotation[:, :2].ravel(),
        "imu_heading_rad": rotation[:, 2],
        "gyro_rad_s": stack("imu_angular_velocity_imu").ravel(),
        "accelerometer_m_s2": stack("imu_linear_acceleration_imu").ravel(),
        "force_N": wrench[:, :, :3].ravel(),
        "moment_xy_Nm": wrench[:, :, 3:5].ravel(),
        "moment_z_Nm": wrench[:, :, 5].ravel(),
    }


def test_datasheet_figures_follow_from_the_named_sensors():
    # 17-bit encoder: 2 pi / 131072 = 4.7937e-5 rad; / sqrt(12) = 1.3838e-5 rad
    assert DATASHEET.encoder_position_rad == pytest.approx(1.3838e-5, rel=1e-4)
    # finite difference over 2 ms: sqrt(2) x that / 0.002 = 9.785e-3 rad/s
    assert DATASHEET.encoder_velocity_rad_s == pytest.approx(9.785e-3, rel=1e-3)
    # 3DM-GX5-25: 0.005 deg/s/sqrt(Hz) x sqrt(500 Hz) = 0.1118 deg/s = 1.9514e-3 rad/s
    assert DATASHEET.gyro_rad_s == pytest.approx(1.9514e-3, rel=1e-4)
    # 25 micro-g/sqrt(Hz) x sqrt(500 Hz) = 5.4820e-3 m/s^2
    assert DATASHEET.accelerometer_m_s2 == pytest.approx(5.4820e-3, rel=1e-4)
    # a sample twice as long averages the white noise down by sqrt(2)
    assert datasheet(0.004).gyro_rad_s == pytest.approx(DATASHEET.gyro_rad_s / math.sqrt(2))


def test_injected_noise_has_the_requested_standard_deviation(robot, model):
    """Each channel's measured standard deviation over a 4 s standing episode within 5 % of
    the data sheet's times the requested multiple (2 000 periods: the estimate's own relative
    error is 1 / sqrt(2 x samples), at most 1.6 % for the heading's 2 000 samples)."""
    perturbation = Perturbation(noise_encoders=2.0, noise_imu=1.0, noise_ft=0.5)
    raw, read = _standing("mujoco", robot, model, 1999, perturbation)
    scale = {"encoder": 2.0, "imu": 1.0, "gyro": 1.0, "accelerometer": 1.0}
    for channel, offsets in _offsets(raw, read).items():
        multiple = next((v for k, v in scale.items() if channel.startswith(k)), 0.5)
        requested = multiple * getattr(DATASHEET, channel)
        assert abs(offsets.mean()) < 4 * requested / math.sqrt(offsets.size), channel
        assert offsets.std() == pytest.approx(requested, rel=0.05), channel


def test_attitude_noise_is_about_the_world_axes_of_a_tilted_and_turned_imu():
    """The attitude figures are roll and pitch (0.25 deg) and heading (0.8 deg) of the world:
    on an IMU pitched 30 deg and yawed 40 deg (synthetic readings, 20 000 periods) the noise's
    rotation vector, in world axes, has those standard deviations. Standing upright and
    unturned, noise about the body's axes looks the same; here it mixes heading into tilt."""
    from robots.types import Sensors

    n, k = 5, 2
    turned = Rotation.from_euler("ZY", [40.0, 30.0], degrees=True)
    quaternion = np.roll(turned.as_quat(), 1)  # (w, x, y, z)
    raw = Sensors(
        0.0, np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(3), np.array([1.0, 0, 0, 0]),
        np.zeros(3), np.zeros(3), quaternion, np.zeros(3), np.zeros(3), np.zeros((k, 6)),
        np.zeros(k, dtype=bool),
    )  # fmt: skip
    model = SensorModel(Perturbation(noise_imu=1.0), 11, n, k, DT)
    noise = np.array(
        [
            (
                Rotation.from_quat(np.roll(model.observe(raw).imu_orientation_world, -1))
                * turned.inv()
            ).as_rotvec()
            for _ in range(20_000)
        ]
    )
    expected = [DATASHEET.imu_tilt_rad] * 2 + [DATASHEET.imu_heading_rad]
    np.testing.assert_allclose(noise.std(axis=0), expected, rtol=0.03)  # 1 / sqrt(2 N) = 0.5 %


def test_noise_given_in_si_units_replaces_the_data_sheets_for_that_channel(robot, model):
    """The gyro's noise at 0.01 rad/s and the F/T force's at 1 N (SI units) beside the IMU
    group at twice the data sheet: each channel's measured standard deviation within 5 % of
    what was asked, the channels of no group or SI value exact."""
    perturbation = Perturbation(noise_imu=2.0, noise_gyro_rad_s=0.01, noise_force_N=1.0)
    requested = {
        "gyro_rad_s": 0.01,
        "force_N": 1.0,
        "imu_tilt_rad": 2.0 * DATASHEET.imu_tilt_rad,
        "imu_heading_rad": 2.0 * DATASHEET.imu_heading_rad,
        "accelerometer_m_s2": 2.0 * DATASHEET.accelerometer_m_s2,
    }
    raw, read = _standing("mujoco", robot, model, 1999, perturbation)
    for channel, offsets in _offsets(raw, read).items():
        if channel in requested:
            assert offsets.std() == pytest.approx(requested[channel], rel=0.05), channel
        else:  # encoders and F/T moments: untouched
            assert np.all(offsets == 0.0), channel


def test_a_bias_scales_with_a_channels_si_figure(robot):
    """The bias is drawn with each channel's figure: the gyro's with 0.01 rad/s is the data
    sheet's bias (the same draws) times 0.01 / 1.95e-3; every other channel's is unchanged."""
    n, k = robot.n_joints, len(robot.limbs)
    sheet = SensorModel(Perturbation(noise_bias=1.0), 3, n, k, DT).bias
    si = SensorModel(Perturbation(noise_bias=1.0, noise_gyro_rad_s=0.01), 3, n, k, DT).bias
    gyro = slice(2 * n + 3, 2 * n + 6)  # after the encoders and the IMU's rotation
    np.testing.assert_allclose(si[gyro], sheet[gyro] * 0.01 / DATASHEET.gyro_rad_s, rtol=1e-12)
    assert np.abs(si[gyro]).max() > 1e-3  # a bias of the size asked for, not zero
    others = np.ones(si.size, dtype=bool)
    others[gyro] = False
    np.testing.assert_array_equal(si[others], sheet[others])


def test_a_bias_is_noise_bias_times_the_figures(robot):
    """`noise_bias` is the multiple of each channel's figure: 5 gives five times the bias of 1
    (the same draws), in every channel."""
    n, k = robot.n_joints, len(robot.limbs)
    one = SensorModel(Perturbation(noise_bias=1.0), 3, n, k, DT).bias
    five = SensorModel(Perturbation(noise_bias=5.0), 3, n, k, DT).bias
    np.testing.assert_allclose(five, 5.0 * one, rtol=1e-12)
    assert np.all(one != 0.0)


def test_the_same_seed_gives_the_same_noise_in_both_simulators(robot, model):
    perturbation = Perturbation(noise_encoders=1.0, noise_imu=1.0, noise_ft=1.0, noise_bias=1.0)
    mujoco = _offsets(*_standing("mujoco", robot, model, 50, perturbation))
    pybullet = _offsets(*_standing("pybullet", robot, model, 50, perturbation))
    for channel in mujoco:
        # equal but for the rounding of adding to different readings (1e-9 of the reading)
        np.testing.assert_allclose(mujoco[channel], pybullet[channel], rtol=0, atol=1e-9)
    other = _offsets(*_standing("mujoco", robot, model, 50, perturbation, seed=4))
    assert not np.allclose(other["gyro_rad_s"], mujoco["gyro_rad_s"])


def test_bias_is_constant_over_an_episode(robot, model):
    raw, read = _standing("mujoco", robot, model, 30, Perturbation(noise_bias=5.0))
    offsets = _offsets(raw, read)
    gyro = offsets["gyro_rad_s"].reshape(-1, 3)
    assert np.ptp(gyro, axis=0).max() < 1e-12  # the same offset every period
    assert np.abs(gyro[0]).max() > 0.1 * 5.0 * DATASHEET.gyro_rad_s  # and not zero


def test_nominal_sensor_model_passes_readings_through(robot, model):
    raw, read = _standing("mujoco", robot, model, 3, Perturbation())
    assert all(a is b for a, b in zip(raw, read, strict=True))


@pytest.mark.parametrize("k", [0, 1, 3])
def test_sensor_delay_hands_over_the_reading_k_periods_old(robot, model, k):
    raw, read = _standing("mujoco", robot, model, 10, Perturbation(sensor_delay=k))
    assert all(read[j] is raw[0] for j in range(k + 1))  # the first reading until then
    assert all(read[j] is raw[j - k] for j in range(k, len(raw)))


def _command(k: int, n: int = 4) -> JointCommand:
    return JointCommand(
        np.full(n, float(k)), np.zeros(n), np.full(n, -float(k)), np.full(n, 100.0), np.ones(n)
    )


@pytest.mark.parametrize("k", [0, 1, 2, 5])
def test_command_delay_applies_the_command_k_periods_later(k):
    delay = CommandDelay(k)
    computed = [_command(j) for j in range(20)]
    applied = [delay.apply(c) for c in computed]
    assert all(applied[j] is computed[0] for j in range(k + 1))
    assert all(applied[j] is computed[j - k] for j in range(k, 20))


def test_gain_scale_scales_the_applied_gains_only():
    applied = CommandDelay(0, gain_scale=0.5).apply(_command(2))
    assert np.array_equal(applied.kp, np.full(4, 50.0))
    assert np.array_equal(applied.kd, np.full(4, 0.5))
    assert np.array_equal(applied.position, np.full(4, 2.0))
    assert np.array_equal(applied.torque_feedforward, np.full(4, -2.0))
