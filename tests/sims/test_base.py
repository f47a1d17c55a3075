"""The shared simulator pieces: servo law, scene validation, registry, push arguments."""

import numpy as np
import pytest

from robots.humanoid import humanoid
from robots.model import RobotModel
from robots.scene import Scene
from robots.types import JointCommand
from sims.base import cross, limb_wrenches, make_simulator, tilt_angle
from sims.servo import servo_torque


def test_servo_law_and_clipping():
    command = JointCommand(
        position=np.array([1.0, 0.0, 0.0]),
        velocity=np.array([0.0, 2.0, 0.0]),
        torque_feedforward=np.array([0.5, 0.0, -3.0]),
        kp=np.array([10.0, 10.0, 10.0]),
        kd=np.array([1.0, 1.0, 1.0]),
    )
    q = np.array([0.9, 0.0, 0.0])
    dq = np.array([0.0, 1.0, 0.0])
    tau = servo_torque(command, q, dq, torque_limit=np.array([100.0, 100.0, 2.0]))
    np.testing.assert_allclose(tau, [10 * 0.1 + 0.5, 1.0 * 1.0, -2.0])


def test_scene_needs_whole_physics_steps_per_control_period():
    assert Scene(physics_dt=0.001, control_dt=0.002).substeps == 2
    with pytest.raises(ValueError, match="whole number"):
        Scene(physics_dt=0.0015, control_dt=0.002).validate()
    with pytest.raises(ValueError, match="friction"):
        Scene(friction=0.0).validate()


def test_unknown_simulator_lists_the_known_ones():
    with pytest.raises(KeyError, match="mujoco, pybullet"):
        make_simulator("gazebo")


def test_cross_of_vectors_and_of_stacks_is_the_cross_product():
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(5, 3)), rng.normal(size=(5, 3))
    np.testing.assert_allclose(cross(a, b), np.cross(a, b), atol=1e-15)
    np.testing.assert_allclose(cross(a[0], b[0]), np.cross(a[0], b[0]), atol=1e-15)
    np.testing.assert_allclose(cross(np.eye(3)[0], np.eye(3)[1]), [0.0, 0.0, 1.0])


def test_limb_wrenches_sum_each_limbs_contacts_about_its_frame():
    """Two 100 N vertical contacts 0.1 m either side of limb 7's frame origin (x), one lateral
    10 N contact on an unknown body: limb 7 carries 200 N and no moment; limb 9 nothing. The
    frame is turned 90 deg about z, so a world x force reads as -y in it."""
    owner = np.array([7, 7, 3])
    points = np.array([[1.1, 0.0, 0.0], [0.9, 0.0, 0.0], [0.0, 0.0, 0.0]])
    forces = np.array([[0.0, 0.0, 100.0], [0.0, 0.0, 100.0], [10.0, 0.0, 0.0]])
    quarter = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    origins = np.array([[1.0, 0.0, 0.0], [5.0, 5.0, 0.0]])
    wrench, flags = limb_wrenches(
        owner, points, forces, np.array([7, 9]), origins, np.array([quarter, np.eye(3)])
    )
    np.testing.assert_allclose(wrench[0], [0, 0, 200, 0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(wrench[1], np.zeros(6))
    assert flags.tolist() == [True, False]
    # one off-centre contact: moment (p - o) x f = (0.1, 0, 0) x (0, 0, 100) = (0, -10, 0)
    # in world, which is (-10, 0, 0) in the turned frame (R^T (0, -10, 0))
    wrench, _ = limb_wrenches(
        owner[:1], points[:1], forces[:1], np.array([7]), origins[:1], quarter[None]
    )
    np.testing.assert_allclose(wrench[0], [0, 0, 100, -10, 0, 0], atol=1e-12)
    empty, none = limb_wrenches(
        np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3)), np.array([7]), origins[:1], quarter[None]
    )
    assert not none.any()
    assert not empty.any()


def test_tilt_angle():
    assert tilt_angle(np.array([1.0, 0, 0, 0])) == pytest.approx(0.0)
    half = np.deg2rad(40) / 2
    assert tilt_angle(np.array([np.cos(half), np.sin(half), 0, 0])) == pytest.approx(np.deg2rad(40))


@pytest.mark.parametrize("sim_name", ["mujoco", "pybullet"])
def test_push_arguments_are_checked(sim_name):
    robot = humanoid()
    sim = make_simulator(sim_name)
    try:
        sim.reset(robot, Scene(), RobotModel(robot).standing_state())
        with pytest.raises(KeyError, match="no link"):
            sim.push("tail", np.array([1.0, 0, 0]), 0.1)
        with pytest.raises(ValueError, match="duration"):
            sim.push("torso", np.array([1.0, 0, 0]), 0.0)
        with pytest.raises(ValueError, match="finite"):
            sim.push("torso", np.array([np.nan, 0, 0]), 0.1)
    finally:
        sim.close()


@pytest.mark.parametrize("sim_name", ["mujoco", "pybullet"])
def test_physics_step_and_control_period_follow_the_scene(sim_name):
    robot = humanoid()
    model = RobotModel(robot)
    initial = model.standing_state()
    scene = Scene(physics_dt=0.0005, control_dt=0.002)
    sim = make_simulator(sim_name)
    try:
        sim.reset(robot, scene, initial)
        sensors = sim.step(model.hold_command(initial))
        assert sensors.time == pytest.approx(0.002)
        if sim_name == "mujoco":
            assert sim.model.opt.timestep == 0.0005
        else:
            from sims.pybullet_sim import pb as pybullet

            parameters = pybullet.getPhysicsEngineParameters(physicsClientId=sim.client)
            assert parameters["fixedTimeStep"] == 0.0005
    finally:
        sim.close()
