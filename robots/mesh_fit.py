"""Primitive collision shapes fitted to a robot's meshes, once, by reading COLLADA (.dae) files
with the standard library's XML parser (no mesh library).

The fit is the mesh's axis-aligned bounding box in its link's frame (the URDF's <collision>
origin applied). A third-party robot's adapter commits the boxes as numbers
(`robots.jvrc1_shapes`), so that nothing reads a mesh at run time; `python -m robots.mesh_fit`
prints them again from the installed package, and a test checks that the committed numbers are
what the installed meshes give.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

_NS = {"c": "http://www.collada.org/2005/11/COLLADASchema"}


def _floats(text: str | None) -> np.ndarray:
    return np.array((text or "").split(), dtype=float)


def collada_vertices(path: Path) -> np.ndarray:
    """Every vertex (n, 3) [m] of the COLLADA file's visual scene, in the file's root frame:
    each <instance_geometry>'s positions through the <matrix> transforms of the <node>s above
    it, times the <unit> (meters per unit). Raises ValueError for a file without geometry."""
    root = ET.parse(path).getroot()
    unit = root.find("c:asset/c:unit", _NS)
    meters = float(unit.get("meter", "1")) if unit is not None else 1.0
    positions: dict[str, np.ndarray] = {}
    for geometry in root.findall("c:library_geometries/c:geometry", _NS):
        mesh = geometry.find("c:mesh", _NS)
        vertices = mesh.find("c:vertices", _NS)
        source_id = next(
            i.get("source")[1:]
            for i in vertices.findall("c:input", _NS)
            if i.get("semantic") == "POSITION"
        )
        source = mesh.find(f"c:source[@id='{source_id}']", _NS)
        positions[geometry.get("id")] = _floats(source.find("c:float_array", _NS).text).reshape(
            -1, 3
        )
    points: list[np.ndarray] = []

    def visit(node: ET.Element, transform: np.ndarray) -> None:
        matrix = node.find("c:matrix", _NS)
        if matrix is not None:
            transform = transform @ _floats(matrix.text).reshape(4, 4)
        for instance in node.findall("c:instance_geometry", _NS):
            local = positions[instance.get("url")[1:]]
            points.append(local @ transform[:3, :3].T + transform[:3, 3])
        for child in node.findall("c:node", _NS):
            visit(child, transform)

    for scene in root.findall("c:library_visual_scenes/c:visual_scene", _NS):
        for node in scene.findall("c:node", _NS):
            visit(node, np.eye(4))
    if not points:
        raise ValueError(f"{path}: no geometry in its visual scene")
    return np.vstack(points) * meters


def vertices_in_link(path: Path, xyz: np.ndarray, rpy: np.ndarray) -> np.ndarray:
    """The mesh's vertices (n, 3) [m] in its link's frame, the URDF origin (xyz [m], fixed-axis
    roll-pitch-yaw [rad]) applied."""
    rotation = Rotation.from_euler("xyz", rpy).as_matrix()
    return collada_vertices(path) @ rotation.T + np.asarray(xyz, dtype=float)


def bounding_box(points: np.ndarray) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Centre and half extents [m] of the axis-aligned box around `points` (n, 3), rounded to
    0.1 mm (the numbers a module commits)."""
    low, high = points.min(axis=0), points.max(axis=0)
    centre = tuple(round(float(x), 4) for x in 0.5 * (low + high))
    half = tuple(round(float(x), 4) for x in 0.5 * (high - low))
    return centre, half


def urdf_collision_boxes(urdf: Path) -> dict[str, tuple[tuple[float, ...], tuple[float, ...]]]:
    """Per link of `urdf` with a mesh <collision>: the bounding box (centre, half extents) [m]
    of its meshes in the link frame. Mesh file names are looked up beside the URDF, in
    `../meshes/` (a ROS package's layout)."""
    meshes = urdf.parent.parent / "meshes"
    boxes = {}
    for link in ET.parse(urdf).getroot().findall("link"):
        points = []
        for collision in link.findall("collision"):
            mesh = collision.find("geometry/mesh")
            if mesh is None:
                continue
            origin = collision.find("origin")
            xyz = _floats(origin.get("xyz", "0 0 0")) if origin is not None else np.zeros(3)
            rpy = _floats(origin.get("rpy", "0 0 0")) if origin is not None else np.zeros(3)
            path = meshes / Path(mesh.get("filename")).name
            points.append(vertices_in_link(path, xyz, rpy))
        if points:
            boxes[link.get("name")] = bounding_box(np.vstack(points))
    return boxes


if __name__ == "__main__":  # print the JVRC-1 boxes as `robots.jvrc1_shapes` commits them
    from robots.jvrc1 import urdf_path

    for name, (centre, half) in urdf_collision_boxes(urdf_path()).items():
        print(f'    "{name}": ({centre}, {half}),')
