"""`five_mass_pose`'s feed-forward variant (`FreeLimbGravity`): the gravity torques of the limbs
that carry no contact, checked against the statics of each joint's subtree (its mass at its
centre of mass, summed from the bodies' inertias, not the generalised gravity the layer
uses), and nothing on a contact limb's chain."""

import numpy as np
import pinocchio as pin
import pytest

from robots.humanoid import humanoid
from robots.jvrc1 import jvrc1
from robots.model import RobotModel
from wholebody.five_mass_pose import FreeLimbGravity, knee_indices, limb_chains

GRAVITY = np.array([0.0, 0.0, -9.81])


def _subtree_statics(model: RobotModel, q: np.ndarray) -> np.ndarray:
    """Per joint, the torque [N m] about its axis that holds its subtree at rest against
    gravity: -axis . (c - o) x m g, with m and c the subtree's mass and centre of mass summed
    from its bodies' inertias placed by forward kinematics."""
    pin_model = model.model
    data = pin_model.createData()
    pin.computeJointJacobians(pin_model, data, q)  # kinematics; data.J: world axes
    torques = np.zeros(model.robot.n_joints)
    for k, name in enumerate(model.robot.joint_names):
        i = pin_model.getJointId(name)
        bodies = list(pin_model.subtrees[i])
        masses = np.array([pin_model.inertias[b].mass for b in bodies])
        centres = np.array([data.oMi[b].act(pin_model.inertias[b].lever) for b in bodies])
        centre = masses @ centres / masses.sum()
        axis = data.J[3:, pin_model.joints[i].idx_v]  # a revolute joint's axis in the world
        moment = np.cross(centre - data.oMi[i].translation, masses.sum() * GRAVITY)
        torques[k] = -axis @ moment
    return torques


@pytest.mark.parametrize("robot", [humanoid, jvrc1], ids=["humanoid", "jvrc1"])
def test_free_limbs_get_their_subtrees_statics_and_contact_chains_nothing(robot):
    """In a random posture with one foot in contact: every joint off that foot's chain gets
    the torque that holds its subtree (to 1e-9 N m), every joint on it none; the other foot's
    leg and both arms are loaded (more than 1 N m somewhere)."""
    model = RobotModel(robot())
    rng = np.random.default_rng(3)
    q = model.configuration(model.standing_state())
    q[7:] += rng.uniform(-0.3, 0.3, model.robot.n_joints)
    q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(0.1, -0.2, 0.3)).coeffs()
    limbs = model.robot.limb_names
    contact = np.array([name == "left_foot" for name in limbs])
    torques = FreeLimbGravity(model).torques(q, contact)
    chains = limb_chains(model)
    on_contact = np.zeros(model.robot.n_joints, dtype=bool)
    on_contact[chains[limbs.index("left_foot")]] = True
    assert not torques[on_contact].any()
    expected = _subtree_statics(model, q)
    np.testing.assert_allclose(torques[~on_contact], expected[~on_contact], rtol=0, atol=1e-9)
    for limb in ("right_foot", "left_hand", "right_hand"):
        assert np.abs(torques[chains[limbs.index(limb)]]).max() > 1.0


def test_the_chains_run_from_each_limb_to_the_base():
    """The chains as the robots are built: the humanoid's leg from the ankle roll up to the
    hip yaw; JVRC-1's leg (mc_rtc's order from the pelvis: hip pitch, roll, yaw, knee, ankle
    roll, pitch) reversed, and its arm through the three waist joints, which a hand's contact
    loads and a foot's does not; the knee found on a leg is the one `knee_indices` names."""
    model = RobotModel(humanoid())
    names = model.robot.joint_names
    chains = dict(zip(model.robot.limb_names, limb_chains(model), strict=True))
    assert [names[j] for j in chains["left_foot"]] == [
        f"left_{j}"
        for j in ("ankle_roll", "ankle_pitch", "knee", "hip_pitch", "hip_roll", "hip_yaw")
    ]
    assert names[knee_indices(model)["left_foot"]] == "left_knee"
    jvrc = RobotModel(jvrc1())
    names = jvrc.robot.joint_names
    chains = dict(zip(jvrc.robot.limb_names, limb_chains(jvrc), strict=True))
    leg = ["R_HIP_P", "R_HIP_R", "R_HIP_Y", "R_KNEE", "R_ANKLE_R", "R_ANKLE_P"]
    assert [names[j] for j in chains["right_foot"]] == leg[::-1]
    arm = ["WAIST_Y", "WAIST_P", "WAIST_R", "L_SHOULDER_P", "L_SHOULDER_R", "L_SHOULDER_Y"]
    arm += ["L_ELBOW_P", "L_ELBOW_Y", "L_WRIST_R", "L_WRIST_Y"]
    assert [names[j] for j in chains["left_hand"]] == arm[::-1]
    assert names[knee_indices(jvrc)["right_foot"]] == "R_KNEE"
