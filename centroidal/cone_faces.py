"""The face form (H-representation) of a contact wrench cone given by its ridges (eq. 8's
G lambda, lambda >= 0): the rows F with F w <= 0 exactly for w in cone(G) (Minkowski-Weyl).

Caron, Pham, Nakamura 2015 ("Leveraging cone double description for multi-contact stability
of humanoids with applications to statics and dynamics") use this conversion to replace the
ridge coefficients of a multi-contact QP by the resultant wrench, which has a fixed size (6)
whatever the number of contacts. They compute it with the double-description method (cdd); here
Qhull (`scipy.spatial.ConvexHull`) does it: near the origin, the polytope
conv({0} u {g_i / ||g_i||}) coincides with the cone, so the hull's facets through the origin are
the cone's facets. Qhull triangulates, so coplanar pieces of one facet come out as several
equal rows; they are merged.
"""

from __future__ import annotations

import contextlib
import functools

import numpy as np
from scipy.spatial import ConvexHull, QhullError

_THROUGH_ORIGIN = 1e-9  # facet offset (for unit generators) below which it contains the origin
_SAME_FACE = 1e-7  # unit normals closer than this are one facet
_HOLDS = 1e-9  # largest F g of a unit generator g: every generator is inside every face
_WIDE_MERGE = "Qx Q12"  # scipy adds its defaults (Qbb Qc Qt); Q12: merge wide dupridges
_JOGGLE = "QJ"  # joggled input: simplicial facets, no merging


def cone_faces(generators: np.ndarray) -> np.ndarray:
    """F (m, d) with unit rows such that {w : F w <= 0} = {G lambda : lambda >= 0}, for the
    generators G (d, n) of a full-dimensional cone (d = 6 for contact wrenches: force [N] and
    moment [N m], so the rows mix units; only their signs matter). A cone that is the whole
    space (a grasp's facing pyramids, Murooka Sec. III-B1: it holds any wrench) has no faces:
    F is (0, d). ValueError if the cone is not full-dimensional."""
    g = np.asarray(generators, dtype=float)
    if g.ndim != 2 or g.shape[1] == 0:
        raise ValueError(f"cone_faces needs a (d, n) generator matrix with n >= 1, got {g.shape}")
    return _faces_of_exact(g.shape, g.tobytes()).copy()


@functools.lru_cache(maxsize=256)
def _faces_of_exact(shape: tuple[int, int], data: bytes) -> np.ndarray:
    """The faces of the generators with exactly these bytes (kept: every episode of a sweep
    worker that stands on the same feet has the same G, and Qhull plus the merge cost ~60 ms)."""
    g = np.frombuffer(data, dtype=float).reshape(shape)
    dimension = g.shape[0]
    rank = np.linalg.matrix_rank(g)
    if rank < dimension:
        raise ValueError(
            f"the cone spanned by these {g.shape[1]} generators has dimension {rank} < "
            f"{dimension}: its face form needs a full-dimensional cone (use the ridge form)"
        )
    unit = g / np.linalg.norm(g, axis=0)
    points = np.vstack([np.zeros(dimension), unit.T])
    faces = None
    try:
        faces = _hull_faces(ConvexHull(points), dimension)
    except QhullError:
        # Many generators lie on each facet through the origin, and Qhull can stop at a
        # "dupridge" it cannot merge within its default bound (JVRC-1's two soles, measured):
        # option Q12 lets it merge wider. The first attempt keeps Qhull's defaults so that
        # cones it could enumerate before give the same faces.
        with contextlib.suppress(QhullError):
            faces = _hull_faces(ConvexHull(points, qhull_options=_WIDE_MERGE), dimension)
    if faces is not None and _outside(faces, unit) <= _HOLDS:
        return faces
    # A wide merge can also give faces that cut into the cone (Fig. 4 (A): a sole on level
    # ground and a palm on a side wall, a generator 6.2e-3 outside, measured): joggle the
    # points (QJ), which makes every facet a simplex, and take the facets at the origin, a
    # complete fan around it; the check below still holds them to every generator.
    try:
        hull = ConvexHull(points, qhull_options=_JOGGLE)
    except QhullError as exc:
        raise ValueError(f"Qhull could not enumerate the cone's faces: {exc}") from exc
    faces = _merged(hull.equations[np.any(hull.simplices == 0, axis=1), :dimension])
    if _outside(faces, unit) > _HOLDS:
        raise ValueError(
            f"Qhull's faces leave a generator {_outside(faces, unit):.1e} outside the cone "
            f"(more than {_HOLDS:g}): no face form"
        )
    return faces


def _hull_faces(hull: ConvexHull, dimension: int) -> np.ndarray:
    """The hull's facets through the origin, merged (none: the cone is the whole space)."""
    normals, offsets = hull.equations[:, :dimension], hull.equations[:, dimension]
    through_origin = np.abs(offsets) < _THROUGH_ORIGIN
    if not np.any(through_origin):  # the origin is interior: the cone is the whole space
        return np.zeros((0, dimension))
    return _merged(normals[through_origin])


def _merged(normals: np.ndarray) -> np.ndarray:
    """Unit rows, Qhull's coplanar triangles merged: a face is kept unless one kept before it
    is within _SAME_FACE in every component."""
    faces = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    distance = np.abs(faces[:, None, :] - faces[None, :, :]).max(axis=2)
    kept: list[int] = []
    for i in range(len(faces)):
        if not kept or distance[i, kept].min() >= _SAME_FACE:
            kept.append(i)
    return faces[kept]


def _outside(faces: np.ndarray, unit: np.ndarray) -> float:
    """The largest F g over the unit generators (0 without faces)."""
    return float((faces @ unit).max()) if len(faces) else 0.0
