"""pinocchio, MuJoCo and PyBullet read the same robot: masses, centres of mass, inertia tensors,
joint order and limits to 1e-9, and the same contact-frame positions by each library's own
forward kinematics."""

import numpy as np
import pytest

from bench.robot_check import all_mass_properties, discrepancy
from robots.humanoid import humanoid
from robots.model import RobotModel
from robots.robot_registry import make_robot
from robots.scene import Scene
from robots.types import RobotState
from sims.base import make_simulator

TOL = 1e-9


@pytest.fixture(
    scope="module",
    params=[("centrobench_humanoid", 1.0), ("centrobench_humanoid", 1.2), ("jvrc1", 1.0)],
    ids=["humanoid-scale1", "humanoid-scale1.2", "jvrc1"],
)
def robot(request):
    return make_robot(*request.param)


@pytest.fixture(scope="module")
def properties(robot):
    return {p.source: p for p in all_mass_properties(robot)}


@pytest.mark.parametrize("other", ["mujoco", "pybullet"])
def test_mass_properties_identical(robot, properties, other):
    reference = properties["pinocchio"]
    assert reference.total_mass == pytest.approx(robot.total_mass, rel=TOL)
    assert properties[other].total_mass == pytest.approx(robot.total_mass, rel=TOL)
    gap = discrepancy(reference, properties[other])
    assert gap.same_bodies
    assert set(reference.body_names) == set(robot.link_names)
    assert gap.mass_rel <= TOL
    assert gap.com_m <= TOL
    assert gap.inertia_rel <= TOL


@pytest.mark.parametrize("source", ["pinocchio", "mujoco", "pybullet"])
def test_each_model_matches_the_description(robot, properties, source):
    props = properties[source]
    assert props.joint_names == robot.joint_names
    np.testing.assert_allclose(props.joint_lower, robot.array("lower"), atol=TOL)
    np.testing.assert_allclose(props.joint_upper, robot.array("upper"), atol=TOL)
    for name, mass, com, inertia in zip(
        props.body_names, props.mass, props.com_in_body, props.inertia_at_com_in_body, strict=True
    ):
        spec = robot.link(name).inertial
        assert mass == pytest.approx(spec.mass, rel=TOL)
        np.testing.assert_allclose(com, spec.com_in_link, atol=TOL)
        scale = np.abs(spec.inertia_matrix).max()
        np.testing.assert_allclose(inertia, spec.inertia_matrix, atol=TOL * scale)


def _random_states(robot, n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        quaternion = rng.normal(size=4)
        yield RobotState.at_rest(
            rng.uniform(-1.0, 1.0, 3) + np.array([0.0, 0.0, 1.5]),
            quaternion / np.linalg.norm(quaternion),
            rng.uniform(robot.array("lower"), robot.array("upper")),
        )


@pytest.mark.parametrize("sim_name", ["mujoco", "pybullet"])
def test_frame_positions_identical_for_random_configurations(robot, sim_name):
    model = RobotModel(robot)
    names = [f.name for f in robot.frames]
    sim = make_simulator(sim_name)
    try:
        sim.reset(robot, Scene(ground=False, gravity=0.0), model.standing_state())
        for state in _random_states(robot, 20, seed=7):
            sim.set_state(state)
            expected = model.frame_positions_world(state, names)
            np.testing.assert_allclose(sim.frame_positions_world(names), expected, rtol=0, atol=TOL)
            # and the simulator reads back the state it was given
            back = sim.ground_truth()
            np.testing.assert_allclose(
                back.base_position_world, state.base_position_world, rtol=0, atol=TOL
            )
            sign = np.sign(back.base_orientation_world @ state.base_orientation_world)
            np.testing.assert_allclose(
                sign * back.base_orientation_world, state.base_orientation_world, rtol=0, atol=TOL
            )
            np.testing.assert_allclose(back.joint_position, state.joint_position, rtol=0, atol=TOL)
    finally:
        sim.close()


def test_frame_positions_agree_with_the_description_in_the_zero_posture():
    # An independent check of the forward kinematics: in the zero posture every joint frame
    # is a pure translation, so a frame sits at the sum of the joint origins above it.
    robot = humanoid()
    model = RobotModel(robot)
    state = RobotState.at_rest(np.zeros(3), np.array([1.0, 0, 0, 0]), np.zeros(robot.n_joints))
    parent_of = {j.child: j for j in robot.joints}
    for frame in robot.frames:
        position = np.array(frame.position_in_link)
        link = frame.link
        while link in parent_of:
            position += parent_of[link].origin_in_parent
            link = parent_of[link].parent
        np.testing.assert_allclose(
            model.frame_positions_world(state, [frame.name])[0], position, atol=1e-12
        )


def test_the_urdf_writes_every_inertia_in_its_principal_axes(robot):
    """Off-diagonal products of inertia are zero in the generated URDF (PyBullet need not
    diagonalise a tensor itself); a link whose tensor is not diagonal in its own frame (merged
    or offset parts) has its inertial frame rotated onto the principal axes, and the tensor
    rotated back equals the description's."""
    import xml.etree.ElementTree as ET

    from scipy.spatial.transform import Rotation

    from robots.build import generate

    root = ET.parse(generate(robot).urdf).getroot()
    rotated = 0
    for element in root.findall("link"):
        inertial = element.find("inertial")
        attributes = inertial.find("inertia").attrib
        assert attributes["ixy"] == attributes["ixz"] == attributes["iyz"] == "0"
        if element.get("name") not in robot.link_names:
            continue  # a frame's massless link
        spec = robot.link(element.get("name")).inertial.inertia_matrix
        rpy = [float(v) for v in inertial.find("origin").get("rpy").split()]
        axes = Rotation.from_euler("xyz", rpy).as_matrix()
        moments = np.diag([float(attributes[k]) for k in ("ixx", "iyy", "izz")])
        np.testing.assert_allclose(axes @ moments @ axes.T, spec, rtol=0, atol=1e-15)
        rotated += any(rpy)
    off_diagonal = sum(
        bool(np.any(link.inertial.inertia_matrix - np.diag(np.diag(link.inertial.inertia_matrix))))
        for link in robot.links
    )
    assert rotated == off_diagonal > 0
