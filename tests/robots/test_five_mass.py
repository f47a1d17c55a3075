"""The five-mass description (Ficht & Behnke Sec. 2) against pinocchio over random postures."""

import numpy as np
import pinocchio as pin
import pytest

from robots.five_mass import GROUPS, FiveMassModel, inertia_error
from robots.humanoid import humanoid
from robots.model import RobotModel
from wholebody.five_mass_pose import inertia_axis_jacobian


@pytest.fixture(scope="module")
def model():
    return RobotModel(humanoid())


def _random_postures(model, count, seed=0):
    rng = np.random.default_rng(seed)
    q = model.configuration(model.standing_state())
    robot = model.robot
    for _ in range(count):
        sample = q.copy()
        sample[:3] = rng.normal(0.0, 0.5, 3)
        sample[3:7] = pin.Quaternion(pin.exp3(rng.normal(0.0, 0.3, 3))).coeffs()
        sample[7:] = rng.uniform(robot.array("lower"), robot.array("upper"))
        yield sample


def test_five_masses_sum_to_the_robot_and_their_mean_is_pinocchios_com(model):
    five_model = FiveMassModel(model)
    data = model.model.createData()
    for q in _random_postures(model, 20):
        five = five_model.evaluate(q)
        assert five.mass.sum() == pytest.approx(model.robot.total_mass, abs=1e-12)
        mean = five.mass @ five.position_world / five.mass.sum()
        np.testing.assert_allclose(five.com_world, mean, atol=1e-12)
        np.testing.assert_allclose(
            five.com_world, pin.centerOfMass(model.model, data, q), atol=1e-12
        )


def test_each_limb_mass_is_the_sum_of_its_links(model):
    five = FiveMassModel(model).evaluate(model.configuration(model.standing_state()))
    links = {link.name: link.inertial.mass for link in model.robot.links}
    expected = {
        "left_leg": sum(m for n, m in links.items() if n.startswith("left_") and "hip" in n)
        + links["left_thigh"]
        + links["left_shank"]
        + links["left_ankle_link"]
        + links["left_foot"],
        "left_arm": sum(
            m
            for n, m in links.items()
            if n.startswith("left_")
            and any(part in n for part in ("shoulder", "arm", "wrist", "hand"))
        ),
    }
    for group, mass in expected.items():
        assert five.mass[GROUPS.index(group)] == pytest.approx(mass, abs=1e-12)
    assert five.mass[0] == pytest.approx(links["torso"], abs=1e-12)


def test_the_point_mass_inertia_misses_the_links_own_rotational_inertia(model):
    """Stated bound, measured: the relative Frobenius error of I_R against pinocchio's
    composite rigid-body inertia is 0.29 on average and at most 0.33 over these postures;
    point masses lose each group's own inertia about its CoM, most of it the torso's."""
    errors = np.array([inertia_error(model, q) for q in _random_postures(model, 20, seed=1)])
    assert errors[:, 0].max() < 1e-12  # the CoM is exact
    assert 0.15 < errors[:, 1].mean() < 0.4
    assert errors[:, 1].max() < 0.4


def test_what_the_point_masses_miss_is_exactly_each_groups_own_inertia(model):
    """Huygens-Steiner: the robot's rotational inertia about its CoM (pinocchio's composite
    rigid-body inertia) is I_R, the five point masses' about the CoM, plus each group's own
    rotational inertia about the group's CoM; so the error of the test above is those alone."""
    five_model = FiveMassModel(model)
    pin_model = model.model
    data = pin_model.createData()
    limb_joints = {j for root in five_model.root_ids for j in pin_model.subtrees[root]}
    groups = [list(pin_model.subtrees[root]) for root in five_model.root_ids]
    groups.insert(0, [j for j in range(1, pin_model.njoints) if j not in limb_joints])
    for q in _random_postures(model, 10, seed=5):
        five = five_model.evaluate(q)
        pin.ccrba(pin_model, data, q, np.zeros(pin_model.nv))
        own = np.zeros((3, 3))
        for joints in groups:
            group = pin.Inertia.Zero()
            for j in joints:
                group += data.oMi[j].act(pin_model.inertias[j])
            own += group.inertia  # about the group's CoM, world axes
        total = np.array(data.Ig.inertia)
        np.testing.assert_allclose(five.inertia_world + own, total, atol=1e-9 * np.abs(total).max())


def test_principal_axes_are_a_right_handed_eigenbasis(model):
    five_model = FiveMassModel(model)
    for q in _random_postures(model, 10, seed=2):
        five = five_model.evaluate(q)
        axes = five.axes_world
        np.testing.assert_allclose(axes.T @ axes, np.eye(3), atol=1e-12)
        assert np.linalg.det(axes) == pytest.approx(1.0)
        np.testing.assert_allclose(five.inertia_world @ axes, axes * five.moments, atol=1e-9)
        assert five.moments[2] < min(five.moments[:2])  # z: the smallest moment


def test_jacobians_of_the_masses_and_of_the_inertia_axis_match_finite_differences(model):
    five_model = FiveMassModel(model)
    rng = np.random.default_rng(3)
    for q in _random_postures(model, 5, seed=4):
        five, jacobians = five_model.jacobians(q)
        axis_jacobian = inertia_axis_jacobian(
            five.mass, five.position_world, jacobians, five.axes_world, five.moments
        )
        dv = rng.standard_normal(model.model.nv) * 1e-7
        moved = five_model.evaluate(pin.integrate(model.model, q, dv))
        change = moved.position_world - five.position_world
        np.testing.assert_allclose(change, jacobians @ dv, atol=1e-11 + 1e-4 * np.abs(change).max())
        axis_change = moved.axes_world[:, 2] - five.axes_world[:, 2]
        np.testing.assert_allclose(
            axis_change, axis_jacobian @ dv, atol=1e-3 * np.abs(axis_change).max() + 1e-12
        )


def test_on_a_robot_with_a_waist_the_arms_begin_at_the_shoulders():
    """JVRC-1's arms leave the pelvis through its 3-DoF waist: each arm group is the links from
    its shoulder down (not the waist's subtree, which holds both arms and the head), and the
    waist's links and the head are the torso's; the five masses still sum to the robot."""
    from robots.jvrc1 import jvrc1

    model = RobotModel(jvrc1())
    five_model = FiveMassModel(model)
    roots = {group: model.model.names[joint] for group, joint in five_model.roots.items()}
    assert roots == {
        "left_leg": "L_HIP_P",
        "right_leg": "R_HIP_P",
        "left_arm": "L_SHOULDER_P",
        "right_arm": "R_SHOULDER_P",
    }
    five = five_model.evaluate(model.configuration(model.standing_state()))
    links = {link.name: link.inertial.mass for link in model.robot.links}
    arm = sum(m for n, m in links.items() if n.startswith("L_") and "HIP" not in n and "KNEE"
              not in n and "ANKLE" not in n)  # fmt: skip
    torso = links["PELVIS_S"] + links["WAIST_Y_S"] + links["WAIST_P_S"] + links["WAIST_R_S"]
    assert five.mass[GROUPS.index("left_arm")] == pytest.approx(arm, abs=1e-12)
    assert five.mass[0] == pytest.approx(torso, abs=1e-12)
    assert five.mass.sum() == pytest.approx(model.robot.total_mass, abs=1e-12)
    assert model.robot.total_mass == pytest.approx(62.4, abs=0.05)  # mc_rtc's JVRC-1
