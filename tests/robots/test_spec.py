"""The robot description: geometry, mass distribution, inertia formulas and scaling laws."""

import numpy as np
import pytest

from robots.humanoid import NOMINAL_MASS_KG, humanoid
from robots.inertia import composite_inertial, principal_inertia
from robots.spec import Geometry


def _grid_inertia(inside, bounds, mass: float, n: int = 120) -> np.ndarray:
    """Inertia about the origin of a uniform solid by midpoint integration on a grid."""
    axes = [np.linspace(lo, hi, n, endpoint=False) + (hi - lo) / (2 * n) for lo, hi in bounds]
    x, y, z = np.meshgrid(*axes, indexing="ij")
    keep = inside(x, y, z)
    points = np.stack([x[keep], y[keep], z[keep]], axis=1)
    m = mass / len(points)
    r2 = (points**2).sum(axis=1)
    return m * (r2.sum() * np.eye(3) - points.T @ points)


def test_capsule_inertia_matches_numerical_integration():
    r, h, mass = 0.05, 0.12, 3.0
    analytic = principal_inertia(Geometry("capsule", (r, h)), mass)

    def inside(x, y, z):
        dz = np.maximum(np.abs(z) - h, 0.0)
        return x**2 + y**2 + dz**2 <= r**2

    numeric = _grid_inertia(inside, [(-r, r), (-r, r), (-h - r, h + r)], mass)
    np.testing.assert_allclose(analytic, numeric, rtol=5e-3, atol=1e-9)


def test_box_and_sphere_inertia_textbook_values():
    box = principal_inertia(Geometry("box", (0.1, 0.2, 0.3)), 12.0)
    np.testing.assert_allclose(np.diag(box), [0.4**2 + 0.6**2, 0.2**2 + 0.6**2, 0.2**2 + 0.4**2])
    sphere = principal_inertia(Geometry("sphere", (0.5,)), 2.0)
    np.testing.assert_allclose(sphere, np.eye(3) * 0.4 * 2.0 * 0.25)


def test_composite_uses_parallel_axis_theorem():
    # Two equal spheres 1 m apart along x: Iyy = Izz = 2 (2/5 m r^2) + 2 m (0.5)^2.
    a = Geometry("sphere", (0.1,), (0.5, 0.0, 0.0))
    b = Geometry("sphere", (0.1,), (-0.5, 0.0, 0.0))
    inertial = composite_inertial([a, b], 2.0)
    np.testing.assert_allclose(inertial.com_in_link, [0, 0, 0], atol=1e-15)
    expected_yy = 2 * 0.4 * 1.0 * 0.01 + 2 * 1.0 * 0.25
    np.testing.assert_allclose(np.diag(inertial.inertia_matrix), [0.008, expected_yy, expected_yy])


def test_humanoid_is_adult_size_with_the_required_limbs():
    robot = humanoid()
    assert 50.0 <= robot.total_mass <= 65.0
    assert robot.total_mass == pytest.approx(NOMINAL_MASS_KG)
    assert robot.n_joints == 24
    leg = ["hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle_pitch", "ankle_roll"]
    arm = ["shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist_pitch", "wrist_roll"]
    for side in ("left", "right"):
        for joint in leg + arm:
            assert f"{side}_{joint}" in robot.joint_names
    assert robot.limb_names == ("left_foot", "right_foot", "left_hand", "right_hand")
    foot = robot.limb("left_foot")
    assert 2 * foot.half_extents[0] == pytest.approx(0.22)
    assert 2 * foot.half_extents[1] == pytest.approx(0.12)
    for limb in robot.limbs:
        assert robot.frame(limb.contact_frame).kind == "contact"
        assert robot.frame(limb.sensor_frame).kind == "force_torque"
    assert robot.frame(robot.imu_frame).link == robot.base_link


def test_foot_inertia_has_products_of_inertia():
    # The foot is two offset boxes, so its tensor about the CoM is not diagonal: the identity
    # tests below then check off-diagonal terms too, not zeros only.
    inertia = humanoid().link("left_foot").inertial.inertia_matrix
    assert abs(inertia[0, 2]) > 1e-5


def test_mass_distribution_is_realistic():
    robot = humanoid()
    legs = sum(
        link.inertial.mass
        for link in robot.links
        if any(k in link.name for k in ("hip", "thigh", "shank", "ankle", "foot"))
    )
    torso = robot.link("torso").inertial.mass
    assert 0.35 < legs / robot.total_mass < 0.5
    assert 0.35 < torso / robot.total_mass < 0.5


@pytest.mark.parametrize("scale", [0.5, 1.2])
def test_scaling_is_geometric_similarity(scale):
    base, scaled = humanoid(), humanoid(scale)
    assert scaled.total_mass == pytest.approx(base.total_mass * scale**3)
    for a, b in zip(base.links, scaled.links, strict=True):
        np.testing.assert_allclose(
            b.inertial.inertia_matrix, a.inertial.inertia_matrix * scale**5, rtol=1e-12
        )
        np.testing.assert_allclose(b.inertial.com_in_link, np.array(a.inertial.com_in_link) * scale)
    for a, b in zip(base.joints, scaled.joints, strict=True):
        assert (b.lower, b.upper) == (a.lower, a.upper)
        assert b.torque_limit == pytest.approx(a.torque_limit * scale**4)
        assert b.kp == pytest.approx(a.kp * scale**4)
        assert b.velocity_limit == pytest.approx(a.velocity_limit / np.sqrt(scale))
    assert scaled.fall_height == pytest.approx(base.fall_height * scale)


def test_total_mass_override():
    robot = humanoid(0.56, total_mass=6.6)
    assert robot.total_mass == pytest.approx(6.6)


@pytest.mark.parametrize(
    ("scale", "mass"), [(-1.0, None), (0.0, None), (float("nan"), None), (1.0, -5.0)]
)
def test_bad_scale_or_mass_is_rejected(scale, mass):
    with pytest.raises(ValueError, match="positive"):
        humanoid(scale, total_mass=mass)


def test_right_side_mirrors_left():
    robot = humanoid()
    for joint in robot.joints:
        if not joint.name.startswith("left_"):
            continue
        twin = next(j for j in robot.joints if j.name == joint.name.replace("left_", "right_"))
        mirrored = any(k in joint.name for k in ("roll", "yaw"))
        expected = (-joint.upper, -joint.lower) if mirrored else (joint.lower, joint.upper)
        assert (twin.lower, twin.upper) == expected
        assert twin.origin_in_parent[1] == -joint.origin_in_parent[1]


def test_nominal_posture_balances_over_the_feet():
    # Torso upright, feet flat, CoM above the centre of the soles: standing needs no ankle
    # torque and a planner holding the CoM over the support centre starts at rest.
    from robots.model import RobotModel

    robot = humanoid()
    model = RobotModel(robot)
    state = model.standing_state()
    com = model.com_position_world(state)
    soles = model.frame_positions_world(state, ["left_sole", "right_sole"])
    assert abs(com[0] - soles[:, 0].mean()) < 1e-4
    assert abs(com[1] - soles[:, 1].mean()) < 1e-9
    for name in ("left_sole", "right_sole", "torso"):
        rotation = model.frame_pose(state, name)[1]
        np.testing.assert_allclose(rotation, np.eye(3), atol=1e-12)
