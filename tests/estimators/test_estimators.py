"""Estimators on a standing robot: the proprioceptive estimate against ground truth, and the
measured ZMP against the CoM projection (at rest the ground reaction passes through the CoM)."""

from types import SimpleNamespace

import numpy as np
import pytest

from estimators.base import make_estimator
from estimators.ground_truth import GroundTruthEstimator
from estimators.kinematic_inertial import KinematicInertialEstimator
from estimators.proprioceptive import ProprioceptiveEstimator
from robots.humanoid import humanoid
from robots.model import RobotModel
from robots.scene import Scene
from sims.base import make_simulator


@pytest.fixture(scope="module")
def model():
    return RobotModel(humanoid())


def _held(model, sim_name, estimator, periods, scene=None, push_period=None, impulse=None):
    """The robot standing with its joints held for `periods` control periods of `scene`: the
    (ground truth, `estimator`) state pairs of every period after reset, and the fall reason
    (None: it stood). `impulse` [N s] (world) pushes the torso over 0.1 s from the start of
    period `push_period`."""
    initial = model.standing_state()
    command = model.hold_command(initial)
    truth = GroundTruthEstimator(model)
    sim = make_simulator(sim_name)
    try:
        sensors = sim.reset(model.robot, scene or Scene(), initial)
        truth.reset(initial, sensors)
        estimator.reset(initial, sensors)
        pairs = [(truth.estimate(sensors), None)]
        for k in range(periods):
            if k == push_period:
                sim.push("torso", np.asarray(impulse, dtype=float), 0.1)
            sensors = sim.step(command)
            pairs.append((truth.estimate(sensors), estimator.estimate(sensors)))
        return pairs[1:], sim.fall_reason()
    finally:
        sim.close()


@pytest.mark.parametrize("sim_name", ["mujoco", "pybullet"])
@pytest.mark.parametrize("kind", [ProprioceptiveEstimator, KinematicInertialEstimator])
def test_proprioceptive_matches_ground_truth_while_standing(model, sim_name, kind):
    """Without a plan, `kinematic_inertial` anchors the feet where they stand, as
    `proprioceptive` does."""
    pairs, _ = _held(model, sim_name, kind(model), 1000)  # 2 s
    base_error = [np.linalg.norm(a.base_position_world - b.base_position_world) for a, b in pairs]
    com_error = [np.linalg.norm(a.com_position_world - b.com_position_world) for a, b in pairs]
    zmp_gap = [np.linalg.norm(a.zmp_world[:2] - a.com_position_world[:2]) for a, b in pairs]
    a, b = pairs[-1]
    assert max(base_error) < 0.005
    assert max(com_error) < 0.005
    assert max(zmp_gap[250:]) < 0.002  # after 0.5 s of settling
    np.testing.assert_allclose(b.base_orientation_world, a.base_orientation_world, atol=1e-9)
    np.testing.assert_allclose(
        b.base_angular_velocity_world, a.base_angular_velocity_world, atol=1e-6
    )
    assert b.contact_flag_limb.tolist() == [True, True, False, False]


@pytest.mark.parametrize("sim_name", ["mujoco", "pybullet"])
def test_kinematic_inertial_puts_the_stance_feet_where_the_plan_holds_them(model, sim_name):
    """A plan that holds both feet 50 mm forward and 30 mm right of where they stand: the
    estimated base and CoM are the true ones moved by that offset, the orientation the IMU's,
    and a foot the plan does not hold (lifted in the plan) carries no weight in the estimate."""
    initial = model.standing_state()
    command = model.hold_command(initial)
    offset = np.array([0.05, -0.03, 0.0])
    feet = [k for k, limb in enumerate(model.robot.limbs) if limb.name.endswith("foot")]
    targets = np.zeros((len(model.robot.limbs), 3))
    for k in feet:
        position, _ = model.frame_pose(initial, model.robot.limbs[k].contact_frame)
        targets[k] = position + offset
    both = SimpleNamespace(
        contact_limbs=tuple(model.robot.limbs[k].name for k in feet),
        limb_target_position_world=targets,
    )
    elsewhere = targets.copy()
    elsewhere[feet[1]] += [0.2, 0.0, 0.0]  # a lifted foot's target: must not move the estimate
    one = SimpleNamespace(
        contact_limbs=both.contact_limbs[:1], limb_target_position_world=elsewhere
    )
    truth, anchored = GroundTruthEstimator(model), KinematicInertialEstimator(model)
    sim = make_simulator(sim_name)
    try:
        sensors = sim.reset(model.robot, Scene(), initial)
        truth.reset(initial, sensors)
        anchored.reset(initial, sensors)
        gaps = []
        for k in range(500):  # 1 s: both feet held, then only the first
            anchored.follow(both if k < 250 else one)
            sensors = sim.step(command)
            a, b = truth.estimate(sensors), anchored.estimate(sensors)
            gaps.append(np.linalg.norm(b.com_position_world - a.com_position_world - offset))
    finally:
        sim.close()
    assert max(gaps) < 0.002  # against a 58 mm offset
    np.testing.assert_allclose(b.base_orientation_world, a.base_orientation_world, atol=1e-9)
    assert anchored.planned_contact[feet].tolist() == [True, False]


def test_unknown_estimator_lists_the_known_ones(model):
    with pytest.raises(KeyError, match="ground_truth, kinematic_inertial, proprioceptive"):
        make_estimator("kalman", model, 0.002)


def test_kinematic_inertial_holds_the_base_when_no_limb_carries_weight(model):
    """Sensors that show no contact force (a bounce): the base stays where the last stance
    put it, whatever velocity was estimated as the feet unloaded."""
    from dataclasses import replace

    initial = model.standing_state()
    sim = make_simulator("mujoco")
    try:
        sensors = sim.reset(model.robot, Scene(), initial)
        estimator = KinematicInertialEstimator(model)
        estimator.reset(initial, sensors)
        sensors = sim.step(model.hold_command(initial))
        before = estimator.estimate(sensors).base_position_world
        estimator.base_velocity = np.array([0.5, 0.0, 1.0])  # an outlier, as in the fall
        for k in range(10):
            airborne = replace(
                sensors,
                time=sensors.time + 0.002 * (k + 1),
                contact_wrench_limb=np.zeros_like(sensors.contact_wrench_limb),
            )
            after = estimator.estimate(airborne).base_position_world
    finally:
        sim.close()
    np.testing.assert_array_equal(after, before)


@pytest.mark.parametrize("sim_name", ["mujoco", "pybullet"])
def test_five_mass_kalman_zmp_agrees_with_the_force_sensors_on_a_standing_robot(model, sim_name):
    """Ficht & Behnke eq. 7 from the IMU and encoders only, against the ZMP of the feet's
    force sensors (`ground_truth` estimator): within 0.5 mm after 0.5 s of settling (measured
    0.010 / 0.043 mm, MuJoCo / PyBullet; standing, eq. 7's acceleration term is near zero, so
    this checks its CoM and frames; eq. 6's rotation is checked on a leaning robot below), and
    the CoM within 1 mm of the ground truth's; the tilt filter's flywheel angle within 1e-8 rad
    of eq. 13's at the true configuration."""
    import pinocchio as pin

    from centroidal.tilt import flywheel_angles
    from estimators.five_mass_kalman import FiveMassKalmanEstimator
    from robots.five_mass import FiveMassModel

    initial = model.standing_state()
    command = model.hold_command(initial)
    truth, kalman = GroundTruthEstimator(model), FiveMassKalmanEstimator(model)
    sim = make_simulator(sim_name)
    try:
        sensors = sim.reset(model.robot, Scene(), initial)
        truth.reset(initial, sensors)
        kalman.reset(initial, sensors)
        zmp_gap, com_error = [], []
        for _ in range(1000):
            sensors = sim.step(command)
            a, b = truth.estimate(sensors), kalman.estimate(sensors)
            zmp_gap.append(np.linalg.norm(a.zmp_world[:2] - b.zmp_world[:2]))
            com_error.append(np.linalg.norm(a.com_position_world - b.com_position_world))
    finally:
        sim.close()
    assert max(zmp_gap[250:]) < 0.0005
    assert max(com_error) < 0.001  # measured 2.2e-4 m
    q = model.configuration(a)
    five = FiveMassModel(model).evaluate(q)
    data = model.model.createData()
    pin.framesForwardKinematics(model.model, data, q)
    feet = sum(data.oMf[f].translation for f in kalman.foot_frames) / 2
    true_tilt = flywheel_angles(five.axes_world[:, 2], five.com_world - feet)
    assert np.abs(b.inertia_tilt - true_tilt).max() < 1e-8  # measured 2.5e-9 / 7.4e-10 rad
    # standing still, the flywheel neither turns nor accelerates (the tilt filter's states;
    # measured 5.0e-5 rad/s and 1.6e-4 rad/s^2 at most)
    assert np.abs(b.inertia_tilt_rate).max() < 2e-4
    assert np.abs(b.inertia_tilt_acceleration).max() < 6e-4


def test_the_imu_acceleration_transported_to_the_com_is_the_com_acceleration(model):
    """`transport_to_com` (ours): c'' = t'' + d/dt (c' - t') for the IMU's origin t, the
    relative velocity from the kinematics and differenced over one step. Moved with constant
    generalised accelerations (base turning and translating, every joint) from the standing
    pose, the transported IMU acceleration equals pinocchio's CoM acceleration within the
    backward difference's O(dt) error, where the IMU's own differs from it by much more."""
    import pinocchio as pin

    from estimators.five_mass_kalman import transport_to_com

    pm, data = model.model, model.model.createData()
    imu = model.frame_id[model.robot.imu_frame]
    rng = np.random.default_rng(3)
    q = model.configuration(model.standing_state())
    v = rng.normal(0.0, 0.3, pm.nv)
    a = rng.normal(0.0, 5.0, pm.nv)
    dt = 1e-4
    previous, gaps, errors = None, [], []
    for _ in range(200):
        pin.forwardKinematics(pm, data, q, v, a)
        pin.updateFramePlacements(pm, data)
        pin.centerOfMass(pm, data, q, v, a, False)
        imu_acceleration = pin.getFrameClassicalAcceleration(
            pm, data, imu, pin.LOCAL_WORLD_ALIGNED
        ).linear
        relative = (
            data.vcom[0] - pin.getFrameVelocity(pm, data, imu, pin.LOCAL_WORLD_ALIGNED).linear
        )
        transported = transport_to_com(imu_acceleration, relative, previous, dt)
        if previous is not None:
            errors.append(np.linalg.norm(transported - data.acom[0]))
            gaps.append(np.linalg.norm(imu_acceleration - data.acom[0]))
        previous = relative.copy()
        q = pin.integrate(pm, q, v * dt + a * dt * dt / 2)
        v = v + a * dt
    assert min(gaps) > 1.0  # [m/s^2] the trunk's acceleration is not the CoM's here
    assert max(errors) < 1e-3


def _held_still(model, time: float, orientation, specific_force):
    """Synthetic sensors at `time` [s] of the robot held in its standing posture with the base
    (and IMU) at `orientation` (w, x, y, z), every rate zero, the accelerometer reading
    `specific_force` [m/s^2] (IMU axes), every limb touching and unloaded."""
    from robots.types import Sensors

    initial = model.standing_state()
    n_joints, n_limbs = len(initial.joint_position), len(model.robot.limbs)
    orientation = np.asarray(orientation, dtype=float)
    zero3 = np.zeros(3)
    return Sensors(
        time, initial.joint_position.copy(), np.zeros(n_joints), np.zeros(n_joints),
        initial.base_position_world.copy(), orientation, zero3, zero3, orientation, zero3,
        np.asarray(specific_force, dtype=float), np.zeros((n_limbs, 6)),
        np.ones(n_limbs, dtype=bool),
    )  # fmt: skip


def test_eq_6_unrotates_the_trunk_acceleration_of_a_leaning_robot(model):
    """Ficht & Behnke eq. 6 measures "the unrotated and unbiased for gravity trunk
    acceleration" R a - g. A robot held still at a 0.15 rad lean (synthetic sensors: the IMU
    turned with the base, its specific force R^T [0, 0, g], every rate zero) accelerates
    nowhere, so the filter's CoM acceleration stays near zero and eq. 7's ZMP under the CoM.
    On a standing robot the rotation hardly matters (its tilt is 1e-4 rad): the test there
    passes with R^T a or with a unrotated; here either gives ~g sin(0.3) or ~g sin(0.15)
    (1.5-2.9 m/s^2), a ZMP metres off."""
    from scipy.spatial.transform import Rotation

    from estimators.five_mass_kalman import GRAVITY, FiveMassKalmanEstimator

    initial = model.standing_state()
    lean = Rotation.from_euler("x", 0.15)
    base = lean * Rotation.from_quat(initial.base_orientation_world, scalar_first=True)
    quaternion = base.as_quat(scalar_first=True)
    specific_force = base.as_matrix().T @ np.array([0.0, 0.0, GRAVITY])
    kalman = FiveMassKalmanEstimator(model)
    kalman.reset(initial, _held_still(model, 0.0, quaternion, specific_force))
    for k in range(1, 501):
        state = kalman.estimate(_held_still(model, k * kalman.dt, quaternion, specific_force))
    assert np.abs(state.com_acceleration_world[:2]).max() < 1e-6  # [m/s^2]
    np.testing.assert_allclose(state.zmp_world[:2], state.com_position_world[:2], atol=1e-6)


@pytest.mark.parametrize("name", ["five_mass_kalman", "proprioceptive", "ground_truth"])
def test_an_estimator_made_for_a_control_period_runs_at_it(model, name):
    """`make_estimator(name, model, dt)` builds the estimator for the scene's control period:
    on a robot standing in a 250 Hz scene (0.004 s periods) each one's ZMP stays within 2 mm of
    the CoM's projection once settled. `five_mass_kalman` is a filter of fixed period; built
    without the scene's dt (0.002 s) it refused every period of this scene as an error."""
    dt = 0.004
    estimator = make_estimator(name, model, dt)
    pairs, _ = _held(model, "mujoco", estimator, round(1.0 / dt), Scene(control_dt=dt))
    gaps = [np.linalg.norm(b.zmp_world[:2] - a.com_position_world[:2]) for a, b in pairs]
    assert pairs[-1][1].time == pytest.approx(1.0)  # the scene's periods, each 0.004 s
    assert max(gaps[round(0.5 / dt) :]) < 0.002


@pytest.mark.parametrize("sim_name", ["mujoco", "pybullet"])
@pytest.mark.parametrize("kind", [ProprioceptiveEstimator, KinematicInertialEstimator])
def test_proprioceptive_follows_a_pushed_robot(model, sim_name, kind):
    """A standing robot pushed forward (10 N s at the torso over 0.1 s, its joints held)
    sways 40 mm and back without falling: the stance-foot kinematics follow it, so the
    estimate's CoM stays within 1 mm of the true one and its velocity within 0.015 m/s
    (measured 0.60 / 0.67 mm and 9.3e-3 / 9.5e-3 m/s, MuJoCo / PyBullet), and the base rate is the
    gyro's. (Standing still the base moves 8e-5 m in 2 s, which an estimator that kept the
    initial base would match too.)"""
    pairs, fell = _held(model, sim_name, kind(model), 1000, push_period=100, impulse=[10, 0, 0])
    start, pairs = pairs[99][0].com_position_world, pairs[100:]  # from the push on
    moved = [np.linalg.norm(a.com_position_world - start) for a, _ in pairs]
    speed = [np.linalg.norm(a.com_velocity_world) for a, _ in pairs]
    com_error = [np.linalg.norm(a.com_position_world - b.com_position_world) for a, b in pairs]
    velocity_error = [np.linalg.norm(a.com_velocity_world - b.com_velocity_world) for a, b in pairs]
    rate_error = [
        np.abs(a.base_angular_velocity_world - b.base_angular_velocity_world).max()
        for a, b in pairs
    ]
    assert fell is None
    assert max(moved) > 0.03  # [m] the push moved it
    assert max(speed) > 0.15  # [m/s]
    assert max(com_error) < 0.001
    assert max(velocity_error) < 0.015
    assert max(rate_error) < 1e-6


def test_the_five_mass_filter_takes_one_step_per_sensor_time(model):
    """The runner hands the reset's reading to the estimator twice (before its loop and in its
    first period). Read twice, it is one measurement: the second call returns the first's
    estimate, and the filter then runs as if it had been read once (before 2026-12-03 the
    second call predicted dt ahead: with a trunk accelerating at 2 m/s^2 the next ZMP was
    9.7 mm off and the states differed for about 1 s; at rest, as the runner starts, by
    nothing measurable)."""
    from estimators.five_mass_kalman import GRAVITY, FiveMassKalmanEstimator

    initial = model.standing_state()
    upright = initial.base_orientation_world
    accelerating = np.array([2.0, 0.0, GRAVITY])  # [m/s^2] IMU axes (the base is upright)

    def run(reads_of_the_first: int) -> list:
        kalman = FiveMassKalmanEstimator(model)
        kalman.reset(initial, _held_still(model, 0.0, upright, accelerating))
        states = [
            kalman.estimate(_held_still(model, 0.0, upright, accelerating))
            for _ in range(reads_of_the_first)
        ]
        for k in range(1, 51):
            states.append(kalman.estimate(_held_still(model, k * 0.002, upright, accelerating)))
        return states

    once, twice = run(1), run(2)
    np.testing.assert_array_equal(twice[1].com_position_world, twice[0].com_position_world)
    np.testing.assert_array_equal(twice[1].com_velocity_world, twice[0].com_velocity_world)
    for a, b in zip(once, twice[1:], strict=True):
        np.testing.assert_allclose(b.com_position_world, a.com_position_world, atol=1e-12)
        np.testing.assert_allclose(b.com_acceleration_world, a.com_acceleration_world, atol=1e-12)
        np.testing.assert_allclose(b.zmp_world, a.zmp_world, atol=1e-12)
    assert once[-1].com_acceleration_world[0] > 1.0  # the filter follows the acceleration


def test_eq_7_puts_the_zmp_behind_a_forward_accelerating_com(model):
    """Eq. 7 from the LIPM, x'' = g / z (x - p): a CoM accelerating forward has its ZMP behind
    it by z x'' / g, z the CoM height above the support sole. Synthetic sensors: the robot
    held upright with its accelerometer reading 2 m/s^2 forward; once the filter's
    acceleration has risen (above 1 m/s^2), its ZMP lies behind its CoM by the filter's
    acceleration times z / g, z from pinocchio's CoM and sole of the standing posture (not
    from the estimator), and sideways under it."""
    import pinocchio as pin

    from estimators.five_mass_kalman import GRAVITY, FiveMassKalmanEstimator

    initial = model.standing_state()
    upright = initial.base_orientation_world
    accelerating = np.array([2.0, 0.0, GRAVITY])
    kalman = FiveMassKalmanEstimator(model)
    kalman.reset(initial, _held_still(model, 0.0, upright, accelerating))
    for k in range(1, 101):
        state = kalman.estimate(_held_still(model, k * kalman.dt, upright, accelerating))
    q = model.configuration(initial)
    data = model.model.createData()
    com = pin.centerOfMass(model.model, data, q)
    pin.framesForwardKinematics(model.model, data, q)
    sole = data.oMf[model.frame_id[model.robot.limbs[kalman.foot_index[0]].contact_frame]]
    height = com[2] - sole.translation[2]
    acceleration = state.com_acceleration_world[0]
    assert acceleration > 1.0
    behind = state.com_position_world[0] - state.zmp_world[0]
    assert behind == pytest.approx(height / GRAVITY * acceleration, rel=1e-3)
    assert abs(state.zmp_world[1] - state.com_position_world[1]) < 1e-3


def test_a_hand_in_contact_does_not_make_the_lower_foot_the_support(model):
    """The five-mass filter anchors its support sole on the plan's foothold while the plan has
    that foot as its support. A plan in contact with one foot and one hand (right foot, left
    hand) supports on that foot: the left sole, found lower (both are level here, the first
    one wins), is not snapped onto the plan's left target 5 cm away, and the estimate equals
    the one of a plan on the right foot alone (before 2026-12-04 any two contacts counted as
    double support, and the CoM estimate moved by the 5 cm)."""
    from estimators.five_mass_kalman import GRAVITY, FiveMassKalmanEstimator

    initial = model.standing_state()
    upright = initial.base_orientation_world
    still = np.array([0.0, 0.0, GRAVITY])
    names = list(model.robot.limb_names)

    def estimate(contacts):
        kalman = FiveMassKalmanEstimator(model)
        kalman.reset(initial, _held_still(model, 0.0, upright, still))
        assert names[kalman.foot_index[kalman.support]] == "left_foot"
        targets = np.zeros((len(names), 3))
        targets[names.index("left_foot")] = kalman.anchor + np.array([0.05, 0.0, 0.0])
        targets[names.index("right_foot")] = kalman.data.oMf[kalman.foot_frames[1]].translation
        kalman.follow(SimpleNamespace(contact_limbs=contacts, limb_target_position_world=targets))
        return kalman.estimate(_held_still(model, kalman.dt, upright, still))

    alone = estimate(("right_foot",))
    with_hand = estimate(("right_foot", "left_hand"))
    both_feet = estimate(("left_foot", "right_foot"))
    np.testing.assert_allclose(with_hand.com_position_world, alone.com_position_world, atol=1e-12)
    # double support does snap the lower (left) sole: the estimate moves with it
    assert both_feet.com_position_world[0] - alone.com_position_world[0] > 0.04
