"""Support polygons and the margin of a point inside them (Murooka Fig. 3B's check that the
planned ZMP stays in the support region)."""

from __future__ import annotations

import numpy as np
from scipy.spatial import ConvexHull


def support_halfplanes(vertices_xy: np.ndarray) -> np.ndarray:
    """Half-planes (k, 3) [a, b, c] of the convex hull of horizontal points (n, 2) [m]: a point
    p is inside when a p_x + b p_y + c <= 0 for every row (unit normals, so the value is a
    signed distance)."""
    if len(vertices_xy) < 3:
        raise ValueError("a support polygon needs at least 3 vertices")
    return ConvexHull(vertices_xy).equations


def margin_inside(halfplanes: np.ndarray, point_xy: np.ndarray) -> float:
    """Distance [m] of `point_xy` inside the polygon (negative outside: the distance to the
    nearest edge line, a lower bound of the distance to the polygon)."""
    return float(-(halfplanes[:, :2] @ point_xy + halfplanes[:, 2]).max())


def surface_vertices_world(
    half_extents: tuple[float, float], position_world: np.ndarray, rotation_world: np.ndarray
) -> np.ndarray:
    """The 4 corners (4, 3) [m] of a rectangular contact surface in the world."""
    hx, hy = half_extents
    corners = np.array([[hx, hy, 0.0], [-hx, hy, 0.0], [-hx, -hy, 0.0], [hx, -hy, 0.0]])
    return position_world + corners @ rotation_world.T
