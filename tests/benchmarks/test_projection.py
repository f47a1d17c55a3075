"""Projection backends side by side at 16, 32 and 64 ridges (one sole; two soles; two soles
and two palms on a wall), on an infeasible wanted wrench (constraints active)."""

import numpy as np
import pytest

from centroidal.contacts import ContactSurface, contact_set
from centroidal.projection import BACKEND_NAMES, WrenchProjector

SOLE = ContactSurface.rectangle(0.11, 0.06, 0.6)
PALM = ContactSurface.rectangle(0.05, 0.04, 0.6)
WALL = np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])  # normal along -x
LAYOUTS = {
    16: ([SOLE], [[0.0, 0.1, 0.0]], [np.eye(3)]),
    32: ([SOLE, SOLE], [[0.0, 0.1, 0.0], [0.0, -0.1, 0.0]], [np.eye(3)] * 2),
    64: (
        [SOLE, SOLE, PALM, PALM],
        [[0.0, 0.1, 0.0], [0.0, -0.1, 0.0], [0.4, 0.3, 1.0], [0.4, -0.3, 1.0]],
        [np.eye(3), np.eye(3), WALL, WALL],
    ),
}


@pytest.mark.benchmark(group="projection", min_rounds=200, warmup=True)
@pytest.mark.parametrize("ridges", sorted(LAYOUTS))
@pytest.mark.parametrize("backend", BACKEND_NAMES)
def test_projection(benchmark, backend, ridges):
    surfaces, positions, rotations = LAYOUTS[ridges]
    contacts = contact_set(
        [f"c{k}" for k in range(len(surfaces))],
        surfaces,
        [np.array(p) for p in positions],
        rotations,
    )
    assert contacts.matrix.shape[1] == ridges
    wanted = np.array([150.0, 40.0, 570.0, 30.0, -60.0, 10.0])  # too much shear and moment
    projector = WrenchProjector(backend)
    projector.project(contacts.matrix, wanted)  # build once (cvxpy, casadi)
    projected, _ = benchmark(projector.project, contacts.matrix, wanted)
    assert np.all(np.isfinite(projected))
