"""Contact wrench cones (eq. 8) and the projection / distribution QP (eqs. 9, 13) with every
backend."""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from centroidal.contacts import ContactSurface, contact_set, generator_matrix, ridges_in_frame
from centroidal.projection import BACKEND_NAMES, WrenchProjector

PROJECTORS = {name: WrenchProjector(name) for name in BACKEND_NAMES}


@st.composite
def contact_sets(draw):
    n = draw(st.integers(1, 3))
    surfaces, positions, rotations = [], [], []
    for _ in range(n):
        half = (draw(st.floats(0.03, 0.15)), draw(st.floats(0.03, 0.1)))
        surfaces.append(
            ContactSurface.rectangle(
                *half, friction=draw(st.floats(0.3, 1.0)), grasp=draw(st.booleans())
            )
        )
        positions.append(np.array([draw(st.floats(-0.8, 0.8)) for _ in range(3)]))
        tilt = [draw(st.floats(-1.2, 1.2)), draw(st.floats(-1.2, 1.2)), draw(st.floats(-3, 3))]
        rotations.append(Rotation.from_euler("xyz", tilt).as_matrix())
    return contact_set([f"c{k}" for k in range(n)], surfaces, positions, rotations)


def _wrench(draw_floats, scale=600.0):
    return np.array([draw_floats() * scale for _ in range(6)])


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(contacts=contact_sets(), data=st.data(), feasible=st.booleans())
def test_all_backends_agree(contacts, data, feasible):
    G = contacts.matrix
    if feasible:
        ridge = np.array([data.draw(st.floats(0.0, 100.0)) for _ in range(G.shape[1])])
        w = G @ ridge
        true_ridge_norm = np.linalg.norm(ridge)
    else:
        w = np.array([data.draw(st.floats(-1.0, 1.0)) * 600.0 for _ in range(6)])
    results = {name: p.project(G, w)[0] for name, p in PROJECTORS.items()}
    reference = results["daqp"]
    for name, projected in results.items():
        np.testing.assert_allclose(projected[:3], reference[:3], atol=1e-4, err_msg=name)
        np.testing.assert_allclose(projected[3:], reference[3:], atol=1e-4, err_msg=name)
    if feasible:
        # With the regularisation eps, ||G l_eps - w||^2 + eps ||l_eps||^2 <= eps ||l*||^2 for
        # any feasible w = G l*: the projection moves a feasible wrench by at most
        # sqrt(eps) ||l*|| (on tiny contacts near the moment origin this reaches 1e-4 N m;
        # realistic contact sets are checked to 1e-6 relative in the next test).
        bound = np.sqrt(PROJECTORS["daqp"].regularization) * true_ridge_norm
        assert np.linalg.norm(reference - w) <= bound + 1e-9


@pytest.mark.parametrize("layout", ["one sole", "two soles", "soles and palms on a wall"])
def test_feasible_wrench_unchanged_on_robot_contact_sets(layout):
    sole, palm = (
        ContactSurface.rectangle(0.11, 0.06, 0.6),
        ContactSurface.rectangle(0.05, 0.04, 0.6),
    )
    wall = np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
    surfaces, positions, rotations = {
        "one sole": ([sole], [[0.3, 0.1, 0.0]], [np.eye(3)]),
        "two soles": ([sole, sole], [[0.3, 0.1, 0.0], [0.4, -0.1, 0.0]], [np.eye(3)] * 2),
        "soles and palms on a wall": (
            [sole, sole, palm, palm],
            [[0.3, 0.1, 0.0], [0.4, -0.1, 0.0], [0.8, 0.3, 1.0], [0.8, -0.3, 1.0]],
            [np.eye(3), np.eye(3), wall, wall],
        ),
    }[layout]
    contacts = contact_set(
        [f"c{k}" for k in range(len(surfaces))],
        surfaces,
        [np.array(p) for p in positions],
        rotations,
    )
    rng = np.random.default_rng(3)
    for name, projector in PROJECTORS.items():
        for _ in range(5):
            w = contacts.matrix @ rng.uniform(0.0, 50.0, contacts.matrix.shape[1])
            projected, _ = projector.project(contacts.matrix, w)
            np.testing.assert_allclose(projected, w, rtol=1e-6, atol=1e-6, err_msg=name)


@settings(max_examples=40, deadline=None)
@given(contacts=contact_sets(), data=st.data())
def test_projection_is_the_nearest_feasible_wrench(contacts, data):
    G = contacts.matrix
    w = np.array([data.draw(st.floats(-1.0, 1.0)) * 600.0 for _ in range(6)])
    projected, forces = WrenchProjector().project(G, w)
    assert np.all(forces >= 0)
    np.testing.assert_allclose(projected, G @ forces)  # in the cone by construction
    distance = np.linalg.norm(projected - w)
    rng = np.random.default_rng(0)
    for _ in range(200):  # no other feasible wrench is nearer
        other = G @ (forces + rng.exponential(5.0, G.shape[1]) * (rng.random(G.shape[1]) < 0.3))
        assert distance <= np.linalg.norm(other - w) + 1e-6


def test_ridges_lie_on_the_friction_cone():
    mu = 0.6
    for ridge in ridges_in_frame(mu):
        assert np.linalg.norm(ridge) == pytest.approx(1.0)
        assert np.hypot(ridge[0], ridge[1]) / ridge[2] == pytest.approx(mu)


def test_single_sole_wrench_cone_facts():
    """One 0.22 x 0.12 sole at the origin: a vertical force through any point of the sole is
    feasible; a pull, a force outside the friction cone, or a CoP outside the sole is not."""
    sole = ContactSurface.rectangle(0.11, 0.06, friction=0.6)
    G = generator_matrix(sole, np.zeros(3), np.eye(3))
    projector = WrenchProjector()

    def feasible(w):
        return np.linalg.norm(projector.project(G, w)[0] - w) < 1e-3

    fz = 500.0
    assert feasible(np.array([0, 0, fz, 0, 0, 0]))
    assert feasible(np.array([0, 0, fz, 0.05 * fz, -0.10 * fz, 0]))  # CoP (0.10, 0.05)
    assert not feasible(np.array([0, 0, fz, 0, -0.12 * fz, 0]))  # CoP x = 0.12 > 0.11
    assert feasible(np.array([0.55 * fz, 0, fz, 0, 0, 0]))  # inside the pyramid (mu 0.6)
    assert not feasible(np.array([0.65 * fz, 0, fz, 0, 0, 0]))
    assert not feasible(np.array([0, 0, -fz, 0, 0, 0]))  # pulling
    # a grasp can pull
    grasp = generator_matrix(
        ContactSurface.rectangle(0.05, 0.04, 0.6, grasp=True), np.zeros(3), np.eye(3)
    )
    pull = np.array([0, 0, -fz, 0, 0, 0])
    assert np.linalg.norm(projector.project(grasp, pull)[0] - pull) < 1e-3


def test_a_surface_in_its_own_frame_is_that_frame_s_plain_surface():
    """`ContactSurface.rotation_in_frame` / `origin_in_frame`: the limb's contact frame at
    (p_c, R_c) carrying a surface at (o, R_s) in it gives the generator of the plain surface at
    (p_c + R_c o, R_c R_s); a surface turned 90 deg about x holds a push along the contact
    frame's -y, which the frame's own surface cannot."""
    from dataclasses import replace

    from scipy.spatial.transform import Rotation

    surface = ContactSurface.rectangle(0.03, 0.01, 0.6)
    r_c = Rotation.from_euler("zyx", [30, -20, 50], degrees=True).as_matrix()
    p_c = np.array([0.3, -0.2, 1.1])
    r_s = Rotation.from_euler("x", 90, degrees=True).as_matrix()
    o = np.array([0.01, -0.02, -0.05])
    turned = replace(surface, rotation_in_frame=r_s, origin_in_frame=o)
    np.testing.assert_allclose(
        generator_matrix(turned, p_c, r_c),
        generator_matrix(surface, p_c + r_c @ o, r_c @ r_s),
        atol=1e-15,
    )
    projector = WrenchProjector()
    force = np.array([0.0, -100.0, 0.0])  # along -y of an upright frame, through o
    push = np.concatenate([force, np.cross(o, force)])
    for candidate, held in ((replace(surface, origin_in_frame=o), False), (turned, True)):
        g = generator_matrix(candidate, np.zeros(3), np.eye(3))
        error = np.linalg.norm(projector.project(g, push)[0] - push)
        assert (error < 1e-6) == held


def test_contact_set_reads_back_each_limb_wrench():
    surfaces = [ContactSurface.rectangle(0.11, 0.06, 0.6)] * 2
    contacts = contact_set(
        ["left", "right"],
        surfaces,
        [np.array([0, 0.1, 0]), np.array([0, -0.1, 0])],
        [np.eye(3)] * 2,
    )
    w = np.array([0, 0, 600.0, 0, 0, 0])
    _, forces = WrenchProjector().project(contacts.matrix, w)
    left, right = contacts.wrench_of("left", forces), contacts.wrench_of("right", forces)
    np.testing.assert_allclose(left + right, w, atol=1e-6)
    assert left[2] == pytest.approx(300.0, abs=1e-3)  # symmetric: half each


def test_upper_bounds_and_errors():
    G = generator_matrix(ContactSurface.rectangle(0.11, 0.06, 0.6), np.zeros(3), np.eye(3))
    w = np.array([0, 0, 600.0, 0, 0, 0])
    upper = np.full(G.shape[1], 10.0)
    for name in ("daqp", "osqp", "cvxpy", "casadi"):
        _, forces = WrenchProjector(name).project(G, w, upper)
        assert forces.max() <= 10.0 + 1e-6
    with pytest.raises(ValueError, match="no upper bounds"):
        WrenchProjector("nnls").project(G, w, upper)
    with pytest.raises(KeyError, match="choose one of: nnls, daqp"):
        WrenchProjector("gurobi")


def test_the_authors_ridge_bounds_keep_every_ridge_inside_them():
    """`ridge_bounds` = the authors' [3, 1000] N: every ridge force within them, and the answer
    is that of the bounded least squares as `WrenchProjector` states it (min ||G l - w||^2 +
    eps ||l - lower||^2, lower <= l <= ceiling), solved directly by proxqp with bounds lb, ub
    instead of through the shift."""
    import qpsolvers

    from centroidal.projection import AUTHORS_RIDGE_BOUNDS

    lower, upper = AUTHORS_RIDGE_BOUNDS
    contacts = contact_set(
        ["left", "right"],
        [ContactSurface.rectangle(0.11, 0.06, 0.6)] * 2,
        [np.array([0.0, 0.1, 0.0]), np.array([0.05, -0.1, 0.0])],
        [np.eye(3)] * 2,
    )
    G = contacts.matrix
    n = G.shape[1]
    rng = np.random.default_rng(3)
    wanted = [
        np.array([0.0, 0.0, 580.0, 0.0, 0.0, 0.0]) + rng.normal(0.0, [60, 60, 200, 40, 40, 5])
        for _ in range(20)
    ]
    wanted.append(np.array([0.0, 0.0, 40000.0, 0.0, 0.0, 0.0]))  # over 32 ridges x 1000 N
    for w in wanted:
        for name in ("daqp_native", "quadprog"):
            projector = WrenchProjector(name, ridge_bounds=AUTHORS_RIDGE_BOUNDS)
            forces = projector.ridge_forces(G, w)
            assert forces.min() >= lower - 1e-9
            assert forces.max() <= upper + 1e-9
            if w[2] > 30000.0:
                assert forces.min() == pytest.approx(upper)  # every ridge at the ceiling
            eps = projector.regularization
            reference = qpsolvers.solve_qp(
                G.T @ G + eps * np.eye(n),
                -G.T @ w - eps * lower * np.ones(n),
                lb=np.full(n, lower),
                ub=np.full(n, upper),
                solver="proxqp",
                eps_abs=1e-12,
                eps_rel=0.0,
            )
            np.testing.assert_allclose(G @ forces, G @ reference, atol=1e-8, err_msg=name)


def test_a_floor_on_every_ridge_keeps_the_cop_off_the_soles_edge():
    """A vertical force through the sole's edge is feasible with lambda >= 0 (the paper's) but
    not with every ridge at 3 N or more: the bounded projection's CoP stays inside the edge."""
    from centroidal.projection import AUTHORS_RIDGE_BOUNDS

    sole = ContactSurface.rectangle(0.11, 0.06, friction=0.6)
    G = generator_matrix(sole, np.zeros(3), np.eye(3))
    fz = 500.0
    edge = np.array([0.0, 0.0, fz, 0.0, -0.11 * fz, 0.0])  # CoP x = 0.11, the front edge
    paper = WrenchProjector().project(G, edge)[0]
    bounded = WrenchProjector(ridge_bounds=AUTHORS_RIDGE_BOUNDS).project(G, edge)[0]
    assert np.linalg.norm(paper - edge) < 1e-3
    cop_x = -bounded[4] / bounded[2]
    assert cop_x < 0.11 - 1e-3


def test_a_callers_upper_bound_below_the_ceiling_binds_with_the_floor():
    """`upper` [N] per ridge from the caller (here 20 N, under the authors' 1000 N) is kept with
    the 3 N floor: a 600 N load needs more than 16 ridges x 20 N can give upward, so every
    ridge ends at 20 N and the vertical force falls short by the rest."""
    from centroidal.projection import AUTHORS_RIDGE_BOUNDS

    G = generator_matrix(ContactSurface.rectangle(0.11, 0.06, 0.6), np.zeros(3), np.eye(3))
    upper = np.full(G.shape[1], 20.0)
    forces = WrenchProjector(ridge_bounds=AUTHORS_RIDGE_BOUNDS).ridge_forces(
        G, np.array([0, 0, 600.0, 0, 0, 0]), upper
    )
    np.testing.assert_allclose(forces, upper, atol=1e-9)
    assert (G @ forces)[2] == pytest.approx(G[2].sum() * 20.0)
    assert (G @ forces)[2] < 600.0


def test_ridge_bounds_are_checked():
    with pytest.raises(ValueError, match="0 <= lower < upper"):
        WrenchProjector(ridge_bounds=(5.0, 3.0))
    with pytest.raises(ValueError, match="nnls backend has no upper bounds"):
        WrenchProjector("nnls", ridge_bounds=(3.0, 1000.0))
    G = generator_matrix(ContactSurface.rectangle(0.11, 0.06, 0.6), np.zeros(3), np.eye(3))
    projector = WrenchProjector(ridge_bounds=(3.0, 1000.0))
    with pytest.raises(ValueError, match="at or below the lower one"):
        projector.ridge_forces(G, np.array([0, 0, 600.0, 0, 0, 0]), np.full(G.shape[1], 2.0))
