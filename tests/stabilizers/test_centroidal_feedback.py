"""The gains of centroidal_feedback (Murooka's Appendix relation, eq. 19, and Table III), its
damping control and distribution, and the DCM baseline's feedback (Appendix eqs. 17-18)."""

from dataclasses import replace

import numpy as np
import pytest

from stabilizers.centroidal_feedback import TABLE_III, appendix_gains, scaled_table_iii


def test_appendix_relation_reproduces_the_papers_numbers():
    # Appendix: m = 105, omega^2 = 10.3, K_xi = 2 -> K_PL about 2163, K_DL about 674
    kp, kd = appendix_gains(105.0, 10.3, 2.0)
    assert kp == pytest.approx(2163, abs=1)
    assert kd == pytest.approx(674, abs=1)


def _poles(mass: float, kp: float, kd: float) -> np.ndarray:
    """[1/s] the roots of m s^2 + K_D s + K_P: the closed loop of a point mass m [kg] under the
    feedback f = -K_P e - K_D e' (the LIPM's CoM error, or a body of inertia m turning)."""
    return np.sort_complex(np.roots([mass, kd, kp]))


@pytest.mark.parametrize("ladder", [False, True])
def test_the_scaled_gains_give_our_robot_table_iii_s_closed_loop(standing, ladder):
    """The gains the stabilizer takes on our standing robot (Table III's, or its ladder row,
    rescaled): the CoM error's closed loop, m e'' = -K_P e - K_D e', has HRP-5P's poles under
    Table III in units of each robot's omega (eq. 19 keeps the DCM gain K_xi), and the angular
    loop, of an inertia m h^2, HRP-5P's poles in 1/s (the same natural frequency and damping
    ratio; `angular_gain_ratio`). The poles are the roots of each loop's characteristic
    polynomial, computed apart from the scaling."""
    from stabilizers.centroidal_feedback import TABLE_III_LADDER, CentroidalFeedbackStabilizer

    model, scenario, state = standing
    stabilizer = CentroidalFeedbackStabilizer(DT)
    stabilizer.reset(model, replace(scenario, ladder_gains=ladder), state)
    mass, height = model.robot.total_mass, float(state.com_position_world[2])
    table = TABLE_III_LADDER if ladder else TABLE_III
    hrp_mass, hrp_height = 105.0, 0.95  # HRP-5P (Murooka's Appendix: omega^2 = 9.8 / 0.95)
    omega, hrp_omega = np.sqrt(9.81 / height), np.sqrt(9.8 / hrp_height)
    for axis in range(3):
        ours = _poles(mass, stabilizer.kp[axis], stabilizer.kd[axis])
        hrp = _poles(hrp_mass, table["kp"][axis], table["kd"][axis])
        np.testing.assert_allclose(ours / omega, hrp / hrp_omega, rtol=1e-9)
    angular = (stabilizer.kp[3:], stabilizer.kd[3:])
    if not ladder:  # Table III: no angular feedback
        assert not np.any(angular)
        return
    for axis in range(3, 6):
        ours = _poles(mass * height**2, stabilizer.kp[axis], stabilizer.kd[axis])
        hrp = _poles(hrp_mass * hrp_height**2, table["kp"][axis], table["kd"][axis])
        np.testing.assert_allclose(ours, hrp, rtol=1e-9)
    assert abs(omega / hrp_omega - 1) > 0.05  # the robots differ: the linear poles moved


# --- Damping control of the limb ends (eqs. 15-16, Table II) -------------------------------

DT = 0.002


@pytest.fixture(scope="module")
def standing():
    from dataclasses import replace

    from bench.scenarios import make_scenario
    from robots.humanoid import humanoid
    from robots.model import RobotModel

    model = RobotModel(humanoid())
    scenario = make_scenario("stand", model)
    state = model.standing_state()
    n_limbs = len(model.robot.limbs)
    state = replace(
        state,
        com_position_world=model.com_position_world(state),
        com_velocity_world=np.zeros(3),
        contact_wrench_limb=np.zeros((n_limbs, 6)),
        contact_flag_limb=np.zeros(n_limbs, dtype=bool),
    )
    return model, scenario, state


def _stabilizer_and_plan(standing, contact_limbs):
    from dataclasses import replace

    from planners.hold import HoldPlanner
    from stabilizers.centroidal_feedback import CentroidalFeedbackStabilizer

    model, scenario, state = standing
    planner = HoldPlanner(DT)
    planner.reset(model, scenario, state)
    plan = replace(planner.plan(0.0, state), contact_limbs=contact_limbs)
    stabilizer = CentroidalFeedbackStabilizer(DT)
    stabilizer.reset(model, scenario, state)
    return stabilizer, plan


def _with_wrenches(state, wrenches):
    from dataclasses import replace

    return replace(state, contact_wrench_limb=np.asarray(wrenches, dtype=float))


def test_contact_damping_integrates_the_force_error(standing):
    """Two feet in contact: K_d dr/dt = K_f (f^a - f^d) (eq. 15, Table II contact row: K_d 1e4,
    K_s 0, K_f 1 for the linear part), so 100 N more than desired under the left foot moves its
    target up by 100 / 1e4 * dt per period; the free hands keep zero compliance."""
    stabilizer, plan = _stabilizer_and_plan(standing, ("left_foot", "right_foot"))
    model, _, state = standing
    left = model.robot.limb_names.index("left_foot")
    targets = stabilizer.stabilize(0.0, plan, state)
    measured = targets.contact_wrench_desired_limb.copy()  # exactly as desired: no motion
    measured[left, 2] += 100.0
    before = stabilizer.compliance_linear.copy()
    targets = stabilizer.stabilize(DT, plan, _with_wrenches(state, measured))
    moved = stabilizer.compliance_linear - before
    assert moved[left, 2] == pytest.approx(100.0 / 1e4 * DT, rel=1e-6)
    others = np.delete(np.arange(len(moved)), left)
    np.testing.assert_allclose(moved[others], 0.0, atol=1e-9)
    np.testing.assert_allclose(
        targets.limb_position_world[left] - plan.limb_target_position_world[left],
        stabilizer.compliance_linear[left],
        atol=1e-12,
    )


def test_contact_damping_tilts_the_foot_with_the_moment_error(standing):
    """Roll/pitch: K_d 100, K_s 0, K_f 1; yaw has K_f 0 (Table II)."""
    stabilizer, plan = _stabilizer_and_plan(standing, ("left_foot", "right_foot"))
    model, _, state = standing
    left = model.robot.limb_names.index("left_foot")
    desired = stabilizer.stabilize(0.0, plan, state).contact_wrench_desired_limb
    measured = desired.copy()
    measured[left, 3:] += [2.0, -3.0, 5.0]  # N m, sole frame (aligned with world here)
    before = stabilizer.compliance_angular[left].copy()
    stabilizer.stabilize(DT, plan, _with_wrenches(state, measured))
    np.testing.assert_allclose(
        stabilizer.compliance_angular[left] - before,
        [2.0 / 100 * DT, -3.0 / 100 * DT, 0.0],
        atol=1e-9,
    )


def test_free_limb_returns_with_the_spring(standing):
    """Free phase: K_f 0, so Delta r decays as K_d dr/dt = -K_s Delta r: per period a factor
    1 - dt K_s / K_d (linear 2250 / 300, angular 400 / 40)."""
    stabilizer, plan = _stabilizer_and_plan(standing, ("left_foot",))
    model, _, state = standing
    right = model.robot.limb_names.index("right_foot")
    stabilizer.compliance_linear[right] = [0.01, -0.02, 0.03]
    stabilizer.compliance_angular[right] = [0.02, 0.0, -0.01]
    stabilizer.stabilize(0.0, plan, state)
    np.testing.assert_allclose(
        stabilizer.compliance_linear[right], np.array([0.01, -0.02, 0.03]) * (1 - DT * 7.5)
    )
    np.testing.assert_allclose(
        stabilizer.compliance_angular[right], np.array([0.02, 0.0, -0.01]) * (1 - DT * 10.0)
    )


def test_single_contact_uses_the_free_linear_parameters(standing):
    """Table II's note: with one limb in contact its linear components take the non-contact
    values (K_d 300, K_s 2250, K_f 0), so a force error does not move it."""
    stabilizer, plan = _stabilizer_and_plan(standing, ("left_foot",))
    model, _, state = standing
    left = model.robot.limb_names.index("left_foot")
    desired = stabilizer.stabilize(0.0, plan, state).contact_wrench_desired_limb
    measured = desired.copy()
    measured[left, 2] += 100.0
    measured[left, 3] += 2.0
    stabilizer.stabilize(DT, plan, _with_wrenches(state, measured))
    np.testing.assert_allclose(stabilizer.compliance_linear[left], 0.0, atol=1e-12)
    assert stabilizer.compliance_angular[left][0] > 0.0  # the moment still acts


def test_distribution_reproduces_the_desired_wrench_when_feasible(standing):
    """Eqs. 13-14: the limbs' desired wrenches sum to w^d (feasible here: standing), and each
    foot carries half the weight when the CoM is centred."""
    stabilizer, plan = _stabilizer_and_plan(standing, ("left_foot", "right_foot"))
    model, _, state = standing
    targets = stabilizer.stabilize(0.0, plan, state)
    np.testing.assert_allclose(
        targets.wrench_distributed_world, targets.wrench_desired_world, atol=1e-3
    )
    names = model.robot.limb_names
    weight = model.robot.total_mass * 9.81
    for foot in ("left_foot", "right_foot"):
        fz = targets.contact_wrench_desired_limb[names.index(foot), 2]
        assert fz == pytest.approx(weight / 2, rel=0.02)


def test_ladder_gains_are_table_iiis_note_for_hrp5p():
    """Table III's note for the ladder: K_P = diag(3000 x 3, 1000 x 3), K_D = diag(1000 x 3,
    333 x 3): for HRP-5P (105 kg, CoM 0.95 m) the angular gains as printed, and for any robot
    the linear ones 1.5 times the default row's, as the table's."""
    kp, kd = scaled_table_iii(105.0, 0.95, ladder=True)
    np.testing.assert_allclose(kp[3:], [1000] * 3, rtol=1e-12)
    np.testing.assert_allclose(kd[3:], [333] * 3, rtol=1e-12)
    for mass, height in ((105.0, 0.95), (58.4, 0.826)):
        kp, kd = scaled_table_iii(mass, height, ladder=True)
        kp0, kd0 = scaled_table_iii(mass, height)
        np.testing.assert_allclose(kp[:3], 1.5 * kp0[:3], rtol=1e-12)
        np.testing.assert_allclose(kd[:3], 1000 / 666 * kd0[:3], rtol=1e-12)


def test_angular_gains_scale_with_the_inertia_scale():
    """`angular_gain_ratio`: m h^2; twice the mass doubles the angular gains, twice the
    height quadruples them; HRP-5P's own numbers give 1."""
    from stabilizers.centroidal_feedback import angular_gain_ratio

    assert angular_gain_ratio(105.0, 0.95) == pytest.approx(1.0, rel=1e-12)
    assert angular_gain_ratio(120.0, 0.8) == pytest.approx(2 * angular_gain_ratio(60.0, 0.8))
    assert angular_gain_ratio(60.0, 1.6) == pytest.approx(4 * angular_gain_ratio(60.0, 0.8))


def test_a_motions_hand_damping_replaces_table_iis_hand_kd(standing):
    """Table II's note: a motion's hand K_d (1000 on the wall) for hands in contact with
    others; the feet keep 10000, and a free hand the non-contact values."""
    from dataclasses import replace

    from stabilizers.centroidal_feedback import CentroidalFeedbackStabilizer

    model, scenario, state = standing
    names = model.robot.limb_names
    stabilizer, plan = _stabilizer_and_plan(standing, ("left_foot", "right_foot", "left_hand"))
    default = stabilizer._configuration(plan).kd
    stabilizer = CentroidalFeedbackStabilizer(DT)
    stabilizer.reset(model, replace(scenario, hand_contact_kd_linear=1000.0), state)
    kd = stabilizer._configuration(plan).kd
    left_hand, right_hand = names.index("left_hand"), names.index("right_hand")
    assert default[left_hand, :3].tolist() == [1e4] * 3
    assert kd[left_hand, :3].tolist() == [1000.0] * 3
    assert kd[left_hand, 3:].tolist() == default[left_hand, 3:].tolist()
    assert kd[right_hand].tolist() == default[right_hand].tolist() == [300.0] * 3 + [40.0] * 3
    for foot in ("left_foot", "right_foot"):
        assert kd[names.index(foot)].tolist() == default[names.index(foot)].tolist()


def test_distribution_uses_the_plans_contact_polygons(standing):
    """`CentroidalPlan.contact_surfaces` reaches eqs. 13-14: standing on two feet whose
    polygons are only their toes (x from 0.03 to 0.10 m in the sole frame), the desired
    centre of pressure of each foot (in its contact frame: -my / fz) lies on that polygon,
    while with the whole soles (no contact_surfaces) it lies under the CoM, at the centre."""
    from dataclasses import replace

    from robots.limbs import limb_surfaces

    model, scenario, state = standing
    names = model.robot.limb_names
    feet = ("left_foot", "right_foot")
    surfaces = limb_surfaces(model.robot, scenario.scene.friction)
    toes = np.array([[0.10, 0.05], [0.03, 0.05], [0.03, -0.05], [0.10, -0.05]])
    stabilizer, plan = _stabilizer_and_plan(standing, feet)
    cop = {}
    for contact_surfaces in (
        None,
        tuple(replace(surfaces[f], vertices_in_frame=toes) for f in feet),
    ):
        targets = stabilizer.stabilize(0.0, replace(plan, contact_surfaces=contact_surfaces), state)
        wrenches = targets.contact_wrench_desired_limb
        cop[contact_surfaces is None] = [
            -wrenches[names.index(f), 4] / wrenches[names.index(f), 2] for f in feet
        ]
    com_x = state.com_position_world[0]
    for foot, x in zip(feet, cop[True], strict=True):
        sole = model.frame_pose(state, model.robot.limb(foot).contact_frame)[0]
        assert x == pytest.approx(com_x - sole[0], abs=0.005)
    for x in cop[False]:
        assert 0.03 - 1e-6 <= x <= 0.10 + 1e-6


def test_damping_acts_along_a_contact_surfaces_own_axes(standing):
    """A contact whose surface has its own frame (`ContactSurface.rotation_in_frame` R_s,
    origin o: a hand resting on a rail in its grasping pose) is damped per axis of that frame,
    as eq. 15 is written for the contact's normal and tangents (Table II's contact row), and
    the surface frame turns about o: a moment error about the surface's normal moves nothing
    (K_f 0 for it); one about its y tangent turns the limb about that tangent at K_f e / K_d
    (100), and the limb's origin by (R_c - R_limb) o; a force error along the normal through o
    moves the limb along the normal at e / K_d (1e4). A general R_s and a turned target: damped
    in the limb frame's axes, or with R_s on the wrong side, these fail."""
    from dataclasses import replace

    from scipy.spatial.transform import Rotation

    from centroidal.rotations import exp, from_matrix, log, to_matrix
    from robots.limbs import limb_surfaces

    model, scenario, state = standing
    names = model.robot.limb_names
    feet = ("left_foot", "right_foot")
    left = names.index("left_foot")
    surfaces = limb_surfaces(model.robot, scenario.scene.friction)
    turn = Rotation.from_rotvec([0.3, -0.5, 0.8]).as_matrix()
    origin = np.array([0.02, -0.03, 0.05])
    own = replace(surfaces["left_foot"], rotation_in_frame=turn, origin_in_frame=origin)
    stabilizer, plan = _stabilizer_and_plan(standing, feet)
    orientations = plan.limb_target_orientation_world.copy()
    frame = Rotation.from_rotvec([0.1, 0.2, -0.4]).as_matrix()
    orientations[left] = from_matrix(frame)
    plan = replace(
        plan,
        contact_surfaces=(own, surfaces["right_foot"]),
        limb_target_orientation_world=orientations,
    )
    desired = stabilizer.stabilize(0.0, plan, state).contact_wrench_desired_limb
    target = plan.limb_target_position_world[left]

    def step(force_surface, moment_surface):
        stabilizer.compliance_linear[:] = 0.0
        stabilizer.compliance_angular[:] = 0.0
        measured = desired.copy()
        force = turn @ np.asarray(force_surface, dtype=float)  # in the limb's frame
        measured[left, :3] += force
        measured[left, 3:] += turn @ np.asarray(moment_surface, dtype=float) + np.cross(
            origin, force
        )
        out = stabilizer.stabilize(DT, plan, _with_wrenches(state, measured))
        limb = to_matrix(out.limb_orientation_world[left])
        return out.limb_position_world[left] - target, log(frame.T @ limb)  # limb frame

    moved, turned = step([0, 0, 0], [0, 0, 5.0])  # about the normal
    np.testing.assert_allclose(turned, 0.0, atol=1e-12)
    np.testing.assert_allclose(moved, 0.0, atol=1e-12)
    moved, turned = step([0, 0, 0], [0, 2.0, 0])  # about the y tangent
    np.testing.assert_allclose(turned, turn @ [0, 2.0 / 100 * DT, 0], atol=1e-12)
    pivot = frame @ (np.eye(3) - exp(turned)) @ origin  # the surface turns about o
    np.testing.assert_allclose(moved, pivot, atol=1e-12)
    assert np.linalg.norm(pivot) > 1e-6
    moved, turned = step([0, 0, 100.0], [0, 0, 0])  # along the normal, through o
    np.testing.assert_allclose(moved, frame @ turn @ [0, 0, 100.0 / 1e4 * DT], atol=1e-12)
    np.testing.assert_allclose(turned, 0.0, atol=1e-12)


def test_a_limbs_compliance_keeps_its_pose_when_its_damping_axes_change(standing):
    """`_change_damping_axes`: a limb's compliance leaving a surface's own axes R_s (and
    coming back) is re-expressed, R_s p, so that the compliant pose R exp(R_s p_s) and the
    displacement R R_s p_s are the same in either axes."""
    from scipy.spatial.transform import Rotation

    from centroidal.rotations import exp

    model, _, _ = standing
    stabilizer, _ = _stabilizer_and_plan(standing, ("left_foot", "right_foot"))
    k = model.robot.limb_names.index("left_hand")
    axes = np.tile(np.eye(3), (len(model.robot.limbs), 1, 1))
    axes[k] = Rotation.from_rotvec([0.3, -0.5, 0.8]).as_matrix()
    stabilizer._change_damping_axes(axes)
    linear, angular = np.array([0.01, -0.02, 0.03]), np.array([0.05, 0.02, -0.04])
    stabilizer.compliance_linear[k], stabilizer.compliance_angular[k] = linear, angular
    stabilizer._change_damping_axes(None)  # back to the contact frame's axes
    np.testing.assert_allclose(stabilizer.compliance_linear[k], axes[k] @ linear, atol=1e-15)
    np.testing.assert_allclose(
        exp(stabilizer.compliance_angular[k]), axes[k] @ exp(angular) @ axes[k].T, atol=1e-14
    )
    stabilizer._change_damping_axes(axes)
    np.testing.assert_allclose(stabilizer.compliance_linear[k], linear, atol=1e-15)
    np.testing.assert_allclose(stabilizer.compliance_angular[k], angular, atol=1e-15)


def test_dcm_feedback_is_eq_18_and_eq_19s_pd_on_the_com():
    """Appendix eqs. 17-18: z^c = z^d + K_xi (xi^a - xi^d), f^c = m omega^2 (c^d - z^c); with
    xi = c + c' / omega this is the feed-forward m omega^2 (c^d - z^d) plus a PD on the CoM
    with K_P = m omega^2 K_xi and K_D = m omega K_xi (eq. 19); vertically the planned force
    plus the height PD; no moment about the CoM."""
    from types import SimpleNamespace

    from stabilizers.dcm import K_XI, DcmStabilizer

    mass, height = 58.4, 0.8
    omega = np.sqrt(9.81 / height)
    com_d, velocity_d = np.array([0.10, -0.02, height]), np.array([0.2, 0.05, 0.0])
    zmp_d = np.array([0.07, 0.01, 0.0])
    com_a = com_d + np.array([-0.01, 0.004, 0.002])
    velocity_a = velocity_d + np.array([0.03, -0.02, 0.01])
    plan = SimpleNamespace(
        desired_state=lambda: (com_d, velocity_d, None, None),
        zmp_planned_world=zmp_d,
        wrench_projected_world=np.array([0.0, 0.0, mass * 9.81, 0.0, 0.0, 0.0]),
    )
    state = SimpleNamespace(com_position_world=com_a, com_velocity_world=velocity_a)
    gains = SimpleNamespace(mass=mass, kp=np.full(6, 1280.0), kd=np.full(6, 397.0))
    wrench = DcmStabilizer.desired_wrench(gains, plan, state)
    feedforward = mass * omega**2 * (com_d[:2] - zmp_d[:2])
    pd = mass * omega**2 * K_XI * (com_d[:2] - com_a[:2]) + mass * omega * K_XI * (
        velocity_d[:2] - velocity_a[:2]
    )
    np.testing.assert_allclose(wrench[:2], feedforward + pd, rtol=1e-12)
    vertical = (
        mass * 9.81 + 1280.0 * (com_d[2] - com_a[2]) + 397.0 * (velocity_d[2] - velocity_a[2])
    )
    assert wrench[2] == pytest.approx(vertical, rel=1e-12)
    np.testing.assert_array_equal(wrench[3:], np.zeros(3))
