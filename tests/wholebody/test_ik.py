"""Whole-body IK: reachable targets are reached, limits always hold, the Jacobians it uses
are the derivatives of its own errors."""

from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest

from centroidal.rotations import from_matrix, log
from robots.humanoid import humanoid
from robots.model import RobotModel
from robots.types import RobotState, WholeBodyTargets
from wholebody.ik import IKWeights, WholeBodyIK

DT = 0.002


@pytest.fixture(scope="module")
def model():
    return RobotModel(humanoid())


def _targets_of(model, state, in_contact=(True, True, False, False)):
    robot = model.robot
    poses = [model.frame_pose(state, limb.contact_frame) for limb in robot.limbs]
    com = model.com_position_world(state)
    return WholeBodyTargets(
        com_position_world=com,
        base_orientation_world=state.base_orientation_world,
        limb_position_world=np.array([p for p, _ in poses]),
        limb_orientation_world=np.array([from_matrix(r) for _, r in poses]),
        limb_in_contact=np.array(in_contact),
        com_desired_world=com,
        zmp_desired_world=np.zeros(3),
    )


def _out_of_reach(targets, com_shift, limb_shifts):
    """`targets` with the CoM target moved by `com_shift` [m] and limb k's position target by
    `limb_shifts[k]` [m]."""
    far = targets.limb_position_world.copy()
    for k, shift in limb_shifts.items():
        far[k] += shift
    return replace(
        targets,
        com_position_world=targets.com_position_world + np.asarray(com_shift),
        limb_position_world=far,
    )


def _ik_state(ik):
    q = ik.q
    return RobotState.at_rest(q[:3], np.r_[q[6], q[3:6]], q[7:])


@pytest.mark.parametrize("seed", range(4))
def test_reachable_targets_are_reached(model, seed):
    """Targets taken from a random configuration (base moved and turned, every joint moved
    within its limits) are reached from the standing posture to < 1 mm and < 0.01 rad."""
    robot = model.robot
    rng = np.random.default_rng(seed)
    lower, upper = robot.array("lower"), robot.array("upper")
    joints = np.clip(
        np.array(robot.nominal_posture) + rng.uniform(-0.3, 0.3, robot.n_joints),
        lower + 0.05,
        upper - 0.05,
    )
    yaw = rng.uniform(-0.2, 0.2)
    start = model.standing_state()
    goal = RobotState.at_rest(
        start.base_position_world + rng.uniform(-0.05, 0.05, 3),
        [np.cos(yaw / 2), 0, 0, np.sin(yaw / 2)],
        joints,
    )
    targets = _targets_of(model, goal)
    ik = WholeBodyIK(model, DT)
    ik.reset(start)
    for _ in range(1500):
        ik.solve(targets)
    reached = _ik_state(ik)
    assert np.linalg.norm(model.com_position_world(reached) - targets.com_position_world) < 1e-3
    for limb in robot.limbs:
        p, r = model.frame_pose(reached, limb.contact_frame)
        p_goal, r_goal = model.frame_pose(goal, limb.contact_frame)
        assert np.linalg.norm(p - p_goal) < 1e-3
        assert np.linalg.norm(log(r @ r_goal.T)) < 0.01


def test_unreachable_targets_keep_joints_within_limits(model):
    robot = model.robot
    start = model.standing_state()
    targets = _out_of_reach(  # left hand 2 m away
        _targets_of(model, start), [0.5, 0.3, -0.6], {2: [1.5, 1.0, 1.0], 3: [-1.0, -1.5, -1.0]}
    )
    ik = WholeBodyIK(model, DT)
    ik.reset(start)
    speed_limit = robot.array("velocity_limit")
    for _ in range(600):
        joints, velocity = ik.solve(targets)
        assert np.all(joints >= robot.array("lower"))
        assert np.all(joints <= robot.array("upper"))
        assert np.all(np.abs(velocity) <= speed_limit * (1 + 1e-6))
    at_limit = np.isclose(joints, robot.array("lower")) | np.isclose(joints, robot.array("upper"))
    assert at_limit.any()  # the targets really pushed some joint to its limit


def test_contact_limbs_are_held_when_the_com_target_conflicts(model):
    """The CoM is asked to move 7 cm while the hands are also held where they are, which the
    arms cannot fully satisfy: the compromise moves the CoM most of the way and leaves the
    contact feet where they are (they carry the largest weight)."""
    start = model.standing_state()
    targets = _targets_of(model, start)
    shift = np.array([0.03, 0.04, -0.05])
    moved = WholeBodyTargets(
        targets.com_position_world + shift,
        *[
            getattr(targets, f)
            for f in (
                "base_orientation_world",
                "limb_position_world",
                "limb_orientation_world",
                "limb_in_contact",
                "com_desired_world",
                "zmp_desired_world",
            )
        ],
    )
    ik = WholeBodyIK(model, DT)
    ik.reset(start)
    for _ in range(300):
        ik.solve(moved)
    state = _ik_state(ik)
    for k in (0, 1):
        p, r = model.frame_pose(state, model.robot.limbs[k].contact_frame)
        assert np.linalg.norm(p - targets.limb_position_world[k]) < 5e-5
        assert np.linalg.norm(log(r)) < 1e-4  # still flat
    remaining = np.linalg.norm(model.com_position_world(state) - moved.com_position_world)
    assert remaining < 0.5 * np.linalg.norm(shift)


def test_angular_momentum_task_reduces_momentum_of_the_step(model):
    """Murooka V-F: with the centroidal angular momentum task, the IK step carries less
    angular momentum I_all dq than without it, for the same targets."""
    start = model.standing_state()
    targets = _targets_of(model, start, in_contact=(True, True, False, False))
    hands = targets.limb_position_world.copy()
    hands[2] += [0.2, 0.0, 0.2]
    hands[3] += [0.2, 0.0, 0.2]
    targets = WholeBodyTargets(
        targets.com_position_world,
        targets.base_orientation_world,
        hands,
        targets.limb_orientation_world,
        targets.limb_in_contact,
        targets.com_desired_world,
        targets.zmp_desired_world,
    )
    momentum = {}
    for weight in (0.0, 100.0):
        ik = WholeBodyIK(model, DT, IKWeights(angular_momentum=weight))
        ik.reset(start)
        q0 = ik.q.copy()
        ik.solve(targets)
        step = pin.difference(model.model, q0, ik.q) / DT
        momentum[weight] = np.linalg.norm(
            pin.computeCentroidalMap(model.model, model.model.createData(), q0)[3:] @ step
        )
    assert momentum[100.0] < 0.5 * momentum[0.0]


def test_the_ik_s_task_rows_are_the_derivatives_of_its_own_errors(model):
    """The rows the IK assembles (`solve` writes them into its buffers): at a random
    configuration whose own poses are the targets (every error zero), each task's Jacobian row
    J is minus the derivative of its error e = target - current along the tangent space
    (finite differences of the IK's own errors, re-assembled at q + eps e_i), for the CoM, the
    tracked limbs (one limb untracked, so the rows skip it) and the base orientation, and each
    row carries its task's weight. A row taken in another frame (LOCAL for LOCAL_WORLD_ALIGNED),
    the base's linear rows for its angular ones, or a limb's rows matched to another limb's
    targets differs from the derivative by O(1)."""
    m = model.model
    rng = np.random.default_rng(5)
    robot = model.robot
    joints = np.clip(
        np.array(robot.nominal_posture) + rng.uniform(-0.4, 0.4, robot.n_joints),
        robot.array("lower") + 0.05,
        robot.array("upper") - 0.05,
    )
    turn = rng.normal(0.0, 0.3, 3)
    state = RobotState.at_rest(
        np.array([0.0, 0.0, 0.8]) + rng.uniform(-0.2, 0.2, 3), from_matrix(pin.exp3(turn)), joints
    )
    tracked = np.array([True, True, False, True])
    targets = replace(_targets_of(model, state), limb_tracked=tracked)
    ik = WholeBodyIK(model, DT)
    weights = ik.weights
    n = 6 * int(tracked.sum()) + 3 + 3  # the tracked limbs, the CoM, the base orientation

    def rows(q):
        ik.q = q.copy()
        ik.solve(targets)
        return ik._jacobian[:n].copy(), ik._error[:n].copy(), ik._weight[:n].copy()

    q = model.configuration(state)
    jacobian, error, weight = rows(q)
    np.testing.assert_allclose(error, 0.0, atol=1e-9)  # the targets are q's own poses
    eps = 1e-6
    numeric = np.array(
        [(rows(pin.integrate(m, q, eps * np.eye(m.nv)[i]))[1] - error) / eps for i in range(m.nv)]
    ).T
    np.testing.assert_allclose(jacobian, -numeric, atol=1e-4)
    contact = targets.limb_in_contact[tracked]  # the tracked limbs: the feet, the right hand
    expected = np.r_[
        np.repeat(np.where(contact, weights.contact, weights.limb), 6),
        np.full(3, weights.com),
        np.full(3, weights.base_orientation),
    ]
    np.testing.assert_array_equal(weight, expected)


def test_unknown_solver_is_rejected(model):
    with pytest.raises(ValueError, match="available"):
        WholeBodyIK(model, DT, solver="no_such_solver")


def test_direct_daqp_solves_the_same_qp_as_quadprog_through_qpsolvers(model):
    """The default solver is DAQP called directly; quadprog through qpsolvers is an
    independent solver of the same QP: the same steps, with speed bounds active (targets out
    of reach)."""
    start = model.standing_state()
    targets = _out_of_reach(_targets_of(model, start), [0.3, 0.2, -0.3], {2: [1.5, 1.0, 1.0]})
    direct, reference = WholeBodyIK(model, DT), WholeBodyIK(model, DT, solver="quadprog")
    direct.reset(start)
    reference.reset(start)
    speed_limit = model.robot.array("velocity_limit")
    at_bound = 0
    for _ in range(100):
        joints, velocity = direct.solve(targets)
        joints_ref, velocity_ref = reference.solve(targets)
        np.testing.assert_allclose(velocity, velocity_ref, atol=1e-6)
        np.testing.assert_allclose(joints, joints_ref, atol=1e-8)
        at_bound += int(np.any(np.isclose(np.abs(velocity), speed_limit, rtol=1e-9)))
        reference.q = direct.q.copy()  # the same linearisation point every call
    assert at_bound > 0  # some speed bound was active


def test_the_angular_momentum_task_follows_the_plan_s_momentum(model):
    """Murooka Sec. V-F's task, I_all dq -> L^p dt (the authors' momentum task targets the
    planned momentum): the base planned to pitch at 0.5 rad/s for 0.2 s, feet held, with the
    plan's angular momentum L^p = I omega^p (eq. 6, 4.40 kg m^2/s). The whole body's momentum
    I_all q' is nearer L^p with the task toward L^p (measured 2.36 kg m^2/s off on average)
    than without the task (2.96) or toward zero (3.24, ours until 2026-12-03, which also held
    the base back: 0.0915 of the planned 0.1 rad). With the feet held a base turn carries less
    momentum than I omega (1.44 kg m^2/s without the task), so the task turns the base further
    than planned (0.117 rad): eq. 6's approximation, which Sec. V-F measures."""
    start = model.standing_state()
    base = _targets_of(model, start)
    planned = model.constant_inertia() @ [0.0, 0.5, 0.0]  # L^p [kg m^2/s]
    gap, turned = {}, {}
    for label, weight, target in (
        ("no task", 0.0, planned),
        ("toward L^p", 100.0, planned),
        ("toward 0", 100.0, None),
    ):
        ik = WholeBodyIK(model, DT, IKWeights(angular_momentum=weight))
        ik.reset(start)
        data = model.model.createData()
        gaps = []
        for i in range(1, 101):
            angle = 0.5 * DT * i
            before = ik.q.copy()
            ik.solve(
                replace(
                    base,
                    base_orientation_world=np.array([np.cos(angle / 2), 0, np.sin(angle / 2), 0]),
                    angular_momentum_world=target,
                )
            )
            rate = pin.difference(model.model, before, ik.q) / DT  # q' of the step
            momentum = pin.computeCentroidalMap(model.model, data, before)[3:] @ rate
            gaps.append(np.linalg.norm(momentum - planned))
        gap[label] = np.mean(gaps[5:])
        turned[label] = log(pin.Quaternion(ik.q[6], *ik.q[3:6]).matrix())[1]
    assert gap["toward L^p"] < 0.9 * gap["no task"]
    assert gap["toward L^p"] < 0.9 * gap["toward 0"]
    assert turned["no task"] == pytest.approx(0.1, rel=0.01)
    assert turned["toward 0"] < 0.095  # held back
