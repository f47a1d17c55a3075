"""cone_faces: the face form of a contact wrench cone against physical facts about a foot
(centre of pressure inside the sole, friction pyramid) and against an independent membership
test (non-negative least squares on the ridges)."""

import numpy as np
import pytest
from scipy.optimize import nnls
from scipy.spatial.transform import Rotation

from centroidal.cone_faces import cone_faces
from centroidal.contacts import ContactSurface, contact_set, generator_matrix

HALF_X, HALF_Y, MU = 0.1, 0.05, 0.7


def _inside(faces: np.ndarray, wrench: np.ndarray) -> bool:
    return bool(np.all(faces @ wrench <= 1e-9 * np.linalg.norm(wrench)))


@pytest.fixture(scope="module")
def foot():
    surface = ContactSurface.rectangle(HALF_X, HALF_Y, MU)
    return cone_faces(generator_matrix(surface, np.zeros(3), np.eye(3)))


@pytest.mark.parametrize("fraction_x", [-1.2, -0.9, -0.3, 0.0, 0.5, 0.95, 1.05, 1.5])
@pytest.mark.parametrize("fraction_y", [-1.1, -0.8, 0.0, 0.6, 0.99, 1.3])
def test_a_vertical_force_is_in_the_cone_iff_its_pressure_centre_is_on_the_sole(
    foot, fraction_x, fraction_y
):
    force_z = 300.0  # N
    cop = np.array([fraction_x * HALF_X, fraction_y * HALF_Y, 0.0])
    moment = np.cross(cop, [0.0, 0.0, force_z])  # about the sole's centre (the origin)
    wrench = np.r_[0.0, 0.0, force_z, moment]
    assert _inside(foot, wrench) == (abs(fraction_x) <= 1 and abs(fraction_y) <= 1)


@pytest.mark.parametrize(
    ("tangential", "inside"),
    [
        ((0.9 * MU, 0.0), True),
        ((-1.1 * MU, 0.0), False),
        ((0.0, -0.95 * MU), True),
        ((0.45 * MU, 0.45 * MU), True),  # the 4-ridge pyramid is a diamond: |fx| + |fy| <= mu fz
        ((0.55 * MU, -0.55 * MU), False),
    ],
)
def test_forces_at_the_centre_follow_the_friction_pyramid(foot, tangential, inside):
    wrench = np.r_[tangential[0], tangential[1], 1.0, 0.0, 0.0, 0.0] * 400.0
    assert _inside(foot, wrench) == inside


def test_two_feet_match_an_independent_membership_test():
    """Two feet, one turned and raised: a wrench satisfies the faces exactly when non-negative
    ridge forces produce it (NNLS residual zero)."""
    surface = ContactSurface.rectangle(HALF_X, HALF_Y, MU)
    contacts = contact_set(
        ["left", "right"],
        [surface, surface],
        [np.array([0.02, 0.1, 0.0]), np.array([0.2, -0.1, 0.05])],
        [np.eye(3), Rotation.from_euler("z", 0.4).as_matrix()],
    )
    faces = cone_faces(contacts.matrix)
    assert np.max(faces @ contacts.matrix) <= 1e-9  # every ridge satisfies every face
    rng = np.random.default_rng(3)
    agree = inside = 0
    for _ in range(400):
        wrench = rng.normal(size=6) * [80.0, 80.0, 80.0, 40.0, 40.0, 15.0]
        wrench[2] = 400.0 + abs(wrench[2])
        _, residual = nnls(contacts.matrix, wrench)
        in_cone = residual < 1e-7 * np.linalg.norm(wrench)
        inside += in_cone
        agree += _inside(faces, wrench) == in_cone
    assert 40 < inside < 360  # both outcomes are exercised
    assert agree == 400


def test_a_point_contact_has_no_face_form():
    """One vertex: the cone has dimension 3 in wrench space, so it has no 6-D face form."""
    point = ContactSurface(np.zeros((1, 2)), MU)
    with pytest.raises(ValueError, match="dimension 3 < 6"):
        cone_faces(generator_matrix(point, np.zeros(3), np.eye(3)))


def test_kept_faces_are_the_callers_own_copy():
    """Faces are kept per exact generator matrix across calls; a caller changing its result
    must not change what the next caller gets."""
    g = generator_matrix(ContactSurface.rectangle(HALF_X, HALF_Y, MU), np.zeros(3), np.eye(3))
    first = cone_faces(g)
    expected = first.copy()
    first[:] = 0.0
    np.testing.assert_array_equal(cone_faces(g.copy()), expected)
    assert not np.array_equal(expected, 0.0)


def test_a_grasps_cone_is_the_whole_space_and_has_no_faces():
    """A grasp (Murooka Sec. III-B1: the friction pyramids facing each other at every vertex
    of the hand's rectangle) holds any wrench: its cone is the whole space, whose face form
    has no rows; every wrench is a non-negative combination of its ridges (checked by NNLS)."""
    grasp = ContactSurface.rectangle(0.05, 0.04, 0.6, grasp=True)
    generators = generator_matrix(grasp, np.array([0.3, 0.4, 1.1]), np.eye(3))
    faces = cone_faces(generators)
    assert faces.shape == (0, 6)
    rng = np.random.default_rng(3)
    for wrench in rng.normal(size=(20, 6)) * [100, 100, 100, 10, 10, 10]:
        _, residual = nnls(generators, wrench)
        assert residual < 1e-6 * np.linalg.norm(wrench)


def test_a_cone_qhull_stops_on_by_default_gets_its_faces_with_wider_merges():
    """JVRC-1's two soles in a walk (the generators `linear_mpc` built at 0-3 s in MuJoCo, kept
    in tests/data): Qhull's default options stop at a "dupridge"; `cone_faces` retries with
    option Q12, checks that every ridge satisfies every face, and its faces agree with the
    independent membership test (NNLS on the ridges)."""
    from pathlib import Path

    from scipy.spatial import ConvexHull, QhullError

    g = np.load(Path(__file__).parents[1] / "data" / "jvrc1_dupridge_cone.npy")
    unit = g / np.linalg.norm(g, axis=0)
    with pytest.raises(QhullError, match="dupridge"):
        ConvexHull(np.vstack([np.zeros(6), unit.T]))
    faces = cone_faces(g)
    assert np.max(faces @ g) <= 1e-9
    _assert_membership_agrees_with_nnls(g, faces, seed=5)


def test_a_cone_whose_wide_merge_cuts_into_it_gets_its_faces_from_joggled_points():
    """A sole on level ground and the right palm on its wall (Fig. 4 (A): the generators
    `linear_mpc` built for `hand_wall`, kept in tests/data): Qhull's defaults stop at a
    dupridge and its wide merge (Q12) gives faces that leave a ridge 6e-3 outside; `cone_faces`
    then joggles the points, and its faces hold every ridge and agree with the independent
    membership test (NNLS on the ridges)."""
    from pathlib import Path

    from scipy.spatial import ConvexHull, QhullError

    g = np.load(Path(__file__).parents[1] / "data" / "hand_wall_wide_merge_cone.npy")
    unit = g / np.linalg.norm(g, axis=0)
    points = np.vstack([np.zeros(6), unit.T])
    with pytest.raises(QhullError, match="dupridge"):
        ConvexHull(points)
    merged = ConvexHull(points, qhull_options="Qx Q12")
    at_origin = merged.equations[np.abs(merged.equations[:, 6]) < 1e-9, :6]
    assert np.max(at_origin @ unit) > 1e-3  # the wide merge cuts into the cone
    faces = cone_faces(g)
    assert np.max(faces @ unit) <= 1e-9
    _assert_membership_agrees_with_nnls(g, faces, seed=7)


def _assert_membership_agrees_with_nnls(g: np.ndarray, faces: np.ndarray, seed: int) -> None:
    """400 wrenches near the cone (non-negative ridge combinations plus noise): the faces
    hold exactly those that non-negative ridge forces produce (NNLS residual zero), and both
    outcomes are exercised."""
    rng = np.random.default_rng(seed)
    agree = inside = 0
    for _ in range(400):
        wrench = g @ rng.uniform(0.0, 1.0, g.shape[1]) * 50.0 + rng.normal(size=6) * 30.0
        _, residual = nnls(g, wrench)
        in_cone = residual < 1e-7 * np.linalg.norm(wrench)
        inside += in_cone
        agree += _inside(faces, wrench) == in_cone
    assert 40 < inside < 360
    assert agree == 400
