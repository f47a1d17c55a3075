"""The joint servo law tau = kp (q_d - q) - kd qdot, applied by both simulators at every physics
step and integrated by semi-implicit Euler, must be numerically stable for the robot's own
inertia, with the torso held and with the base free (a mode of the waist and hips that only
shows with the base free). For a swinging limb the ankle sees only the foot's inertia (4e-3
kg m^2 in roll): an ankle kd of 8 N m s/rad once gave kd dt / I = 2.06, a closed loop that grew
by 1.2 per step, and a 500 Hz oscillation that the 2 ms control period aliased into a stance
foot reading 1.2 m g.
"""

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

from bench.scenarios import make_scenario
from robots.model import RobotModel
from robots.robot_registry import make_robot
from robots.spec import RobotDescription

# With the base free its six rigid-body modes are neutral (eigenvalue 1, no gravity in the
# linearisation): stable means no eigenvalue above 1 by more than rounding.
NEUTRAL = 1e-9


def closed_loop_spectral_radius(robot: RobotDescription, base_free: bool) -> float:
    """Largest |eigenvalue| of one semi-implicit Euler step of the servoed joints,
    v+ = v - dt M^-1 (Kp q + Kd v), q+ = q + dt v+, linearised at the standing posture; with
    the torso held (the joints' block of M) or the base free (all of M, no gains on the base)."""
    model = RobotModel(robot)
    dt = make_scenario("stand", model).scene.physics_dt
    q = model.configuration(model.standing_state())
    mass = pin.crba(model.model, model.model.createData(), q)
    mass = np.triu(mass) + np.triu(mass, 1).T
    n_joints = robot.n_joints
    n = mass.shape[0] if base_free else n_joints
    kp, kd = np.zeros((n, n)), np.zeros((n, n))
    kp[-n_joints:, -n_joints:] = np.diag(robot.array("kp"))
    kd[-n_joints:, -n_joints:] = np.diag(robot.array("kd"))
    inverse = np.linalg.inv(mass if base_free else mass[6:, 6:])
    eye = np.eye(n)
    step = np.block(
        [
            [eye - dt * dt * inverse @ kp, dt * (eye - dt * inverse @ kd)],
            [-dt * inverse @ kp, eye - dt * inverse @ kd],
        ]
    )
    return float(np.abs(np.linalg.eigvals(step)).max())


ROBOTS = [("centrobench_humanoid", 0.6), ("centrobench_humanoid", 1.0),
          ("centrobench_humanoid", 1.5), ("jvrc1", 1.0)]  # fmt: skip


@pytest.mark.parametrize("base_free", [False, True], ids=["torso_held", "base_free"])
@pytest.mark.parametrize(("name", "scale"), ROBOTS)
def test_servo_is_stable_at_the_physics_step(name, scale, base_free):
    radius = closed_loop_spectral_radius(make_robot(name, scale), base_free)
    if base_free:
        assert radius <= 1.0 + NEUTRAL
    else:
        assert radius < 1.0


def test_the_old_ankle_gains_were_unstable():
    """The check itself can fail: with the old ankle kd (15 and 8 N m s/rad) it does."""
    import robots.humanoid as module

    saved = dict(module._LEG_JOINTS)
    try:
        for kind, kd in (("ankle_pitch", 15.0), ("ankle_roll", 8.0)):
            limits, speed, torque, kp, _ = saved[kind]
            module._LEG_JOINTS[kind] = (limits, speed, torque, kp, kd)
        module.humanoid.cache_clear()  # descriptions are cached per process
        robot = module.humanoid(1.0)
        assert closed_loop_spectral_radius(robot, base_free=False) > 1.0
        assert closed_loop_spectral_radius(robot, base_free=True) > 1.0 + NEUTRAL
    finally:
        module._LEG_JOINTS.clear()
        module._LEG_JOINTS.update(saved)
        module.humanoid.cache_clear()


def test_jvrc1s_source_gains_are_unstable_without_rotor_inertia():
    """mc_mujoco's JVRC-1 gains (kp 500-6000 N m/rad, kd 20-80 N m s/rad), stable there with
    the rotor inertias its model adds, diverge on our model without them, held or free: what
    `robots.jvrc1.servo_gains_without_rotor_inertia` adapts."""
    from robots.jvrc1 import _SOURCE_SERVO, _kind, jvrc1

    robot = jvrc1()
    joints = []
    for joint in robot.joints:
        kp, kd, _, _ = _SOURCE_SERVO[_kind(joint.name)]
        joints.append(dataclasses.replace(joint, kp=kp, kd=kd))
    source = dataclasses.replace(robot, joints=tuple(joints))
    assert closed_loop_spectral_radius(source, base_free=False) > 2.0
    assert closed_loop_spectral_radius(source, base_free=True) > 2.0
