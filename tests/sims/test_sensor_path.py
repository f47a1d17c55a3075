"""The compiled sensor path (issue 16) against the straightforward one it replaced.

Each period of a short episode (the robot rocked by its joint servos and pushed on the torso and
then on a foot, so that contacts come and go and one push lands on a limb's own body) the
`Sensors` of each backend are compared with the same quantities computed the old way: MuJoCo's
contacts one by one with `mj_contactForce`, PyBullet's contact points, base pose, link frames
and IMU converted with numpy (`sims.base.limb_wrenches`, `ground_truth`). The bounds are
rounding: the engine sums the contacts of a body in another order (MuJoCo's `cfrc_ext`), and the
kernels multiply 3x3 rotations row by row where numpy calls BLAS.
"""

import dataclasses

import numpy as np
import pytest

from robots.scene import Scene
from robots.types import JointCommand
from sims.base import limb_wrenches, make_simulator, quaternion_to_matrix, tilt_angle
from sims.kernels import servo_torque_kernel
from sims.sensor_buffer import SensorLayout

WRENCH_ATOL = 1e-9  # [N], [N m]: rounding of sums of forces of up to ~600 N
STATE_ATOL = 1e-12  # [m], [m/s], [rad/s]


def rocking(model, initial, t: float) -> JointCommand:
    """The standing posture with the hips and ankles swayed at 1.5 Hz (contacts shift)."""
    command = model.hold_command(initial)
    names = model.robot.joint_names
    position = command.position.copy()
    for k, name in enumerate(names):
        if "hip_roll" in name or "ankle_roll" in name:
            position[k] += 0.06 * np.sin(2 * np.pi * 1.5 * t)
    return JointCommand(
        position, command.velocity, command.torque_feedforward, command.kp, command.kd
    )


def episodes(robot, model, sim_name, reference):
    """Run 1.2 s; after each period call reference(sim, sensors)."""
    initial = model.standing_state()
    foot = robot.limbs[0].link
    sim = make_simulator(sim_name)
    try:
        sim.reset(robot, Scene(), initial)
        for k in range(600):
            if k == 100:
                sim.push("torso", np.array([12.0, 6.0, 0.0]), 0.1)
            if k == 300:
                sim.push(foot, np.array([0.0, 3.0, 0.0]), 0.05)  # on a limb's own body
            sensors = sim.step(rocking(model, initial, sim.time))
            reference(sim, sensors)
    finally:
        sim.close()


def test_mujoco_limb_wrenches_equal_the_sum_of_its_contacts(robot, model):
    seen = {"periods": 0, "limb_pushed": 0}

    def reference(sim, sensors):
        d = sim.data
        bodies, points, forces = sim._contacts()
        wrench, flags = limb_wrenches(
            bodies,
            points,
            forces,
            sim._limb_body,
            d.site_xpos[sim._limb_site],
            d.site_xmat[sim._limb_site].reshape(-1, 3, 3),
        )
        np.testing.assert_allclose(sensors.contact_wrench_limb, wrench, rtol=0, atol=WRENCH_ATOL)
        np.testing.assert_array_equal(sensors.contact_flag_limb, flags)
        truth = sim.ground_truth()
        for name in (
            "base_position_world",
            "base_orientation_world",
            "base_linear_velocity_world",
            "joint_position",
            "joint_velocity",
        ):
            np.testing.assert_array_equal(getattr(sensors, name), getattr(truth, name))
        np.testing.assert_allclose(
            sensors.base_angular_velocity_world,
            truth.base_angular_velocity_world,
            rtol=0,
            atol=STATE_ATOL,
        )
        np.testing.assert_array_equal(sensors.imu_orientation_world, d.sensordata[sim._imu_quat])
        np.testing.assert_array_equal(sensors.imu_angular_velocity_imu, d.sensordata[sim._imu_gyro])
        np.testing.assert_array_equal(
            sensors.imu_linear_acceleration_imu, d.sensordata[sim._imu_accel]
        )
        assert sim._tilt(sensors) == pytest.approx(
            tilt_angle(sensors.base_orientation_world), abs=1e-12
        )
        seen["periods"] += 1
        seen["limb_pushed"] += sim._limb_pushed

    episodes(robot, model, "mujoco", reference)
    assert seen["periods"] == 600
    assert seen["limb_pushed"] == 25  # the foot push: 50 physics steps = 25 periods, per contact


def test_pybullet_sensors_equal_the_numpy_conversion(robot, model):
    def reference(sim, sensors):
        links, points, forces = sim._contacts()
        frames = [sim._index["link:" + limb.contact_frame] for limb in robot.limbs]
        import pybullet as pb

        states = pb.getLinkStates(
            sim.body, frames, computeForwardKinematics=1, physicsClientId=sim.client
        )
        wrench, flags = limb_wrenches(
            np.array(links),
            points,
            forces,
            sim._limb_link,
            np.array([s[4] for s in states]),
            np.array([quaternion_to_matrix([s[5][3], *s[5][:3]]) for s in states]),
        )
        np.testing.assert_allclose(sensors.contact_wrench_limb, wrench, rtol=0, atol=WRENCH_ATOL)
        np.testing.assert_array_equal(sensors.contact_flag_limb, flags)
        truth = sim.ground_truth()
        for name in (
            "base_position_world",
            "base_orientation_world",
            "base_linear_velocity_world",
            "base_angular_velocity_world",
        ):
            np.testing.assert_allclose(
                getattr(sensors, name), getattr(truth, name), rtol=0, atol=STATE_ATOL
            )
        np.testing.assert_array_equal(sensors.joint_position, truth.joint_position)
        np.testing.assert_array_equal(sensors.joint_velocity, truth.joint_velocity)
        _, imu_quat, imu_velocity, imu_omega = sim._imu_state()
        rotation = quaternion_to_matrix(imu_quat)
        specific = (imu_velocity - np.array(sim._imu_velocity_before)) / sim.scene.physics_dt
        specific[2] += sim.scene.gravity
        np.testing.assert_array_equal(sensors.imu_orientation_world, imu_quat)
        np.testing.assert_allclose(
            sensors.imu_angular_velocity_imu, rotation.T @ imu_omega, rtol=0, atol=STATE_ATOL
        )
        np.testing.assert_allclose(
            sensors.imu_linear_acceleration_imu, rotation.T @ specific, rtol=0, atol=1e-9
        )

    episodes(robot, model, "pybullet", reference)


@pytest.mark.parametrize("sim_name", ["mujoco", "pybullet"])
def test_a_link_other_than_a_limb_on_the_ground_is_a_fall(robot, model, sim_name):
    """The robot placed lying on its back (with no height or tilt limit): the kernels' count of
    the contacts on links that are not limbs ends it."""
    lying_robot = dataclasses.replace(robot, fall_height=0.0)
    initial = model.standing_state()
    lying = type(initial)(
        np.array([0.0, 0.0, 0.12]),
        np.array([np.cos(np.pi / 4), 0.0, -np.sin(np.pi / 4), 0.0]),  # pitched back 90 deg
        np.zeros(3),
        np.zeros(3),
        initial.joint_position,
        initial.joint_velocity,
    )
    sim = make_simulator(sim_name)
    try:
        sim.reset(lying_robot, Scene(max_tilt=np.pi), lying)
        for _ in range(50):
            sim.step(model.hold_command(initial))
            if sim.fall_reason():
                break
        reason = sim.fall_reason()
    finally:
        sim.close()
    assert reason is not None
    assert "touching the scene" in reason, reason


def test_servo_kernel_is_the_numpy_servo_law_bit_for_bit():
    rng = np.random.default_rng(7)
    n = 23
    position, velocity, feedforward, q, dq = rng.normal(size=(5, n))
    kp, kd, limit = rng.uniform(1, 500, n), rng.uniform(0.1, 20, n), rng.uniform(0.5, 50, n)
    tau = kp * (position - q) + kd * (velocity - dq) + feedforward
    expected = np.minimum(np.maximum(tau, -limit), limit)
    got = servo_torque_kernel(position, velocity, feedforward, kp, kd, q, dq, limit)
    np.testing.assert_array_equal(got, expected)
    assert (np.abs(got) == limit).any()  # both branches of the clip are exercised
    assert (np.abs(got) < limit).any()


def test_sensor_layout_views_cover_the_buffer_once():
    layout = SensorLayout(n_joints=5, n_limbs=3)
    buffer = np.arange(layout.size, dtype=float)
    sensors = layout.sensors(0.5, buffer, np.zeros(3, dtype=bool))
    parts = [
        sensors.joint_position,
        sensors.joint_velocity,
        sensors.joint_torque,
        sensors.base_position_world,
        sensors.base_orientation_world,
        sensors.base_linear_velocity_world,
        sensors.base_angular_velocity_world,
        sensors.imu_orientation_world,
        sensors.imu_angular_velocity_imu,
        sensors.imu_linear_acceleration_imu,
        sensors.contact_wrench_limb.ravel(),
    ]
    assert [len(p) for p in parts] == [5, 5, 5, 3, 4, 3, 3, 4, 3, 3, 18]
    np.testing.assert_array_equal(np.concatenate(parts), buffer)  # in order, each entry once
    assert sensors.contact_wrench_limb.shape == (3, 6)
    assert all(np.shares_memory(p, buffer) for p in parts)


@pytest.mark.parametrize("sim_name", ["mujoco", "pybullet"])
def test_an_arm_against_a_rail_is_not_a_fall_but_the_torso_is(robot, model, sim_name):
    """A hand's arm links (`Limb.touch_links`: upper arm, forearm, wrist) may touch the scene
    (a forearm beside the rail the hand holds) without the robot counting as fallen; the
    torso may not. A box is placed 5 mm into the standing robot's left forearm, then into its
    torso."""
    import pinocchio as pin

    from robots.scene import Box

    initial = model.standing_state()
    data = model.model.createData()
    pin.forwardKinematics(model.model, data, model.configuration(initial))
    joints = [
        data.oMi[model.model.getJointId(f"left_{j}")].translation for j in ("elbow", "wrist_pitch")
    ]
    forearm_middle = (joints[0] + joints[1]) / 2
    outside = forearm_middle[1] + 0.04 + 0.05 - 0.005  # capsule radius 0.04, box half 0.05
    results = {}
    for name, centre in (
        ("forearm", (forearm_middle[0], outside, forearm_middle[2])),
        ("torso", (0.0, 0.0, 1.05)),
    ):
        box = Box(f"against_{name}", tuple(float(v) for v in centre), (0.05, 0.05, 0.05))
        sim = make_simulator(sim_name)
        try:
            sim.reset(robot, Scene(boxes=(box,)), initial)
            touched = False
            for _ in range(25):
                sim.step(model.hold_command(initial))
                touched |= bool(sim._links_touching_scene() - {"left_foot", "right_foot"})
            results[name] = (touched, sim.fall_reason())
        finally:
            sim.close()
    assert results["forearm"][0], "the box should touch the forearm"
    assert results["forearm"][1] is None, results["forearm"][1]
    assert results["torso"][1] is not None
    assert "torso touching the scene" in results["torso"][1]


@pytest.mark.parametrize("sim_name", ["mujoco", "pybullet"])
def test_a_scenes_fall_height_replaces_the_robots(robot, model, sim_name):
    """A robot standing with its base below its own fall height has fallen in a scene without
    one of its own, and has not in a scene whose lower `Scene.fall_height` allows the crouch
    (Fig. 4 D's supports)."""
    standing = model.standing_state()
    base_height = float(standing.base_position_world[2])
    high = dataclasses.replace(robot, fall_height=base_height + 0.1)
    reasons = []
    for scene in (Scene(), Scene(fall_height=base_height - 0.1)):
        sim = make_simulator(sim_name)
        try:
            sim.reset(high, scene, standing)
            for _ in range(10):
                sim.step(model.hold_command(standing))
            reasons.append(sim.fall_reason())
        finally:
            sim.close()
    assert reasons[0] is not None
    assert reasons[0].startswith("base height")
    assert f"{base_height + 0.1:.3f} m" in reasons[0]
    assert reasons[1] is None
