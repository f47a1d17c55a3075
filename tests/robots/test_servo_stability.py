"""The joint servo law tau = kp (q_d - q) - kd qdot, applied by both simulators at every physics
step and integrated by semi-implicit Euler, must be numerically stable for the robot's own
inertia. For a swinging limb the ankle sees only the foot's inertia (4e-3 kg m^2 in roll):
an ankle kd of 8 N m s/rad once gave kd dt / I = 2.06, a closed loop that grew by 1.2 per step,
and a 500 Hz oscillation that the 2 ms control period aliased into a stance foot reading 1.2 m g.
"""

import numpy as np
import pinocchio as pin
import pytest

from bench.scenarios import make_scenario
from robots.humanoid import humanoid
from robots.model import RobotModel


def _closed_loop_spectral_radius(scale: float) -> float:
    """Largest |eigenvalue| of one semi-implicit Euler step of the servoed joints, torso held:
    v+ = v - dt M^-1 (Kp q + Kd v), q+ = q + dt v+ (linearised at the standing posture)."""
    robot = humanoid(scale)
    model = RobotModel(robot)
    dt = make_scenario("stand", model).scene.physics_dt
    q = model.configuration(model.standing_state())
    mass = pin.crba(model.model, model.model.createData(), q)
    mass = np.triu(mass) + np.triu(mass, 1).T
    inverse = np.linalg.inv(mass[6:, 6:])
    kp, kd = np.diag(robot.array("kp")), np.diag(robot.array("kd"))
    n = len(kp)
    eye = np.eye(n)
    step = np.block(
        [
            [eye - dt * dt * inverse @ kp, dt * (eye - dt * inverse @ kd)],
            [-dt * inverse @ kp, eye - dt * inverse @ kd],
        ]
    )
    return float(np.abs(np.linalg.eigvals(step)).max())


@pytest.mark.parametrize("scale", [0.6, 1.0, 1.5])
def test_servo_is_stable_at_the_physics_step(scale):
    assert _closed_loop_spectral_radius(scale) < 1.0


def test_the_old_ankle_gains_were_unstable():
    """The check itself can fail: with the old ankle kd (15 and 8 N m s/rad) it does."""
    import robots.humanoid as module

    saved = dict(module._LEG_JOINTS)
    try:
        for kind, kd in (("ankle_pitch", 15.0), ("ankle_roll", 8.0)):
            limits, speed, torque, kp, _ = saved[kind]
            module._LEG_JOINTS[kind] = (limits, speed, torque, kp, kd)
        module.humanoid.cache_clear()  # descriptions are cached per process
        assert _closed_loop_spectral_radius(1.0) > 1.0
    finally:
        module._LEG_JOINTS.clear()
        module._LEG_JOINTS.update(saved)
        module.humanoid.cache_clear()
