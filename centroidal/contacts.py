"""Contact surfaces and their wrench cones (Murooka et al. 2022, Sec. III-B1, eq. 8).

A contact surface is a polygon in its contact frame (z axis = the direction in which the
environment can push the limb) with a Coulomb friction coefficient mu. At each vertex p_j a
friction pyramid of 4 ridges approximates the cone (ours: eq. 8 does not count them; these
lie on the cone, an inscribed pyramid):
    rho_k = (n + mu t_k) / ||n + mu t_k||,  t_k in {+t1, -t1, +t2, -t2},
with n, t1, t2 the contact frame's z, x, y axes in the world. The contact wrench (force, and
moment about the world origin) is w_i = G_i lambda_i with lambda_i >= 0 and
    G_i = [ ... rho_{j,k} ... ; ... p_j x rho_{j,k} ... ]      (eq. 8)
A grasp contact (Fig. 4C: a hand around a rung) adds, at each vertex, the opposing pyramid
(normal -n), so the limb can pull as well as push.

A surface may lie elsewhere than in the limb's contact frame (`ContactSurface.rotation_in_frame`,
`origin_in_frame`): a hand resting on a rail in the pose that grasps it touches the rail's top,
whose normal is not the hand frame's z axis. Its polygon and pyramids are then those of the
surface's own frame, placed by the limb's pose.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from centroidal.wrench import cross


@dataclass(frozen=True)
class ContactSurface:
    """vertices_in_frame (J, 2) [m] in the surface frame's x-y plane; mu; grasp. The surface
    frame is the limb's contact frame unless `rotation_in_frame` (3, 3) / `origin_in_frame` (3,)
    [m] give its orientation and origin in the contact frame (its z axis is the normal)."""

    vertices_in_frame: np.ndarray
    friction: float
    grasp: bool = False
    rotation_in_frame: np.ndarray | None = None
    origin_in_frame: np.ndarray | None = None

    @staticmethod
    def rectangle(
        half_x: float, half_y: float, friction: float, grasp: bool = False, margin: float = 0.0
    ) -> ContactSurface:
        """A rectangle centred on the frame origin, shrunk by `margin` [m] on every side (the
        paper's "contact polygon vertices with inner margins", Fig. 3)."""
        hx, hy = half_x - margin, half_y - margin
        if hx <= 0 or hy <= 0:
            raise ValueError("margin leaves no contact area")
        vertices = np.array([[hx, hy], [-hx, hy], [-hx, -hy], [hx, -hy]])
        return ContactSurface(vertices, friction, grasp)

    @property
    def n_ridges(self) -> int:
        return len(self.vertices_in_frame) * 4 * (2 if self.grasp else 1)


def ridges_in_frame(friction: float) -> np.ndarray:
    """The 4 unit ridge vectors (4, 3) of a pyramid with normal +z, in the contact frame."""
    ridges = np.array([[friction, 0, 1], [-friction, 0, 1], [0, friction, 1], [0, -friction, 1]])
    return ridges / np.linalg.norm(ridges, axis=1, keepdims=True)


def generator_matrix(
    surface: ContactSurface, position_world: np.ndarray, rotation_world: np.ndarray
) -> np.ndarray:
    """G_i (6, n_ridges) of eq. 8 for a surface whose contact frame has this pose: columns
    [rho; p x rho] in world coordinates, moments about the world origin."""
    if surface.origin_in_frame is not None:
        position_world = position_world + rotation_world @ surface.origin_in_frame
    if surface.rotation_in_frame is not None:
        rotation_world = rotation_world @ surface.rotation_in_frame
    ridges = ridges_in_frame(surface.friction) @ rotation_world.T  # (4, 3) world
    if surface.grasp:
        ridges = np.vstack([ridges, -ridges])
    vertices = np.column_stack(
        [surface.vertices_in_frame, np.zeros(len(surface.vertices_in_frame))]
    )
    points = position_world + vertices @ rotation_world.T  # (J, 3)
    forces = np.tile(ridges, (len(points), 1))  # vertex-major: J blocks of ridges
    where = np.repeat(points, len(ridges), axis=0)
    return np.vstack([forces.T, cross(where, forces).T])


@dataclass(frozen=True)
class ContactSet:
    """The contacts active together: names, and the stacked G of eq. 9 with the column range
    of each contact (to read each limb's lambda_i back, eq. 14)."""

    names: tuple[str, ...]
    matrix: np.ndarray  # (6, n)
    slices: tuple[slice, ...]

    def wrench_of(self, name: str, ridge_forces: np.ndarray) -> np.ndarray:
        """w_i = G_i lambda_i (eq. 14): force and moment about the world origin."""
        k = self.names.index(name)
        return self.matrix[:, self.slices[k]] @ ridge_forces[self.slices[k]]


def contact_set(
    names: Sequence[str],
    surfaces: Sequence[ContactSurface],
    positions_world: Sequence[np.ndarray],
    rotations_world: Sequence[np.ndarray],
) -> ContactSet:
    blocks, slices, start = [], [], 0
    for surface, position, rotation in zip(surfaces, positions_world, rotations_world, strict=True):
        block = generator_matrix(surface, np.asarray(position, dtype=float), rotation)
        blocks.append(block)
        slices.append(slice(start, start + block.shape[1]))
        start += block.shape[1]
    matrix = np.hstack(blocks) if blocks else np.zeros((6, 0))
    return ContactSet(tuple(names), matrix, tuple(slices))
