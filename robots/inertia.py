"""Mass properties of primitive solids of uniform density, and of their unions.

Used to give every generated link a physically consistent inertia tensor; the generators then
write that tensor verbatim into the URDF and MJCF, so every simulator reads the same numbers.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy.spatial.transform import Rotation

from robots.spec import Geometry, Inertial


def volume(geometry: Geometry) -> float:
    """Volume of a primitive [m^3]."""
    if geometry.kind == "box":
        hx, hy, hz = geometry.size
        return 8.0 * hx * hy * hz
    if geometry.kind == "sphere":
        (r,) = geometry.size
        return 4.0 / 3.0 * np.pi * r**3
    if geometry.kind == "capsule":
        r, h = geometry.size
        return np.pi * r**2 * 2.0 * h + 4.0 / 3.0 * np.pi * r**3
    raise ValueError(f"unknown geometry kind {geometry.kind!r}")


def principal_inertia(geometry: Geometry, mass: float) -> np.ndarray:
    """Inertia tensor [kg m^2] of a uniform solid of `mass` [kg] about its centre, in its own
    axes (capsule and cylinder axis along z)."""
    if geometry.kind == "box":
        hx, hy, hz = geometry.size
        a, b, c = 2 * hx, 2 * hy, 2 * hz
        return np.diag([b * b + c * c, a * a + c * c, a * a + b * b]) * mass / 12.0
    if geometry.kind == "sphere":
        (r,) = geometry.size
        return np.eye(3) * 0.4 * mass * r * r
    if geometry.kind == "capsule":
        # Cylinder of length 2h plus two hemispheres, split by volume.
        r, h = geometry.size
        length = 2.0 * h
        v_cyl = np.pi * r * r * length
        v_hemis = 4.0 / 3.0 * np.pi * r**3
        m_cyl = mass * v_cyl / (v_cyl + v_hemis)
        m_hs = mass - m_cyl  # both hemispheres together
        i_axial = 0.5 * m_cyl * r * r + 0.4 * m_hs * r * r
        # Each hemisphere: I about its own centre of mass, shifted to the capsule centre.
        # Hemisphere (mass m/2): I_base_diameter = 2/5 (m/2) r^2, com at 3r/8 from the base.
        i_cyl_transverse = m_cyl * (3 * r * r + length * length) / 12.0
        m_h = m_hs / 2.0
        i_h_base = 0.4 * m_h * r * r
        d_com = 3.0 * r / 8.0
        i_h_com = i_h_base - m_h * d_com * d_com
        i_h_center = i_h_com + m_h * (h + d_com) ** 2
        i_transverse = i_cyl_transverse + 2.0 * i_h_center
        return np.diag([i_transverse, i_transverse, i_axial])
    raise ValueError(f"unknown geometry kind {geometry.kind!r}")


def composite_inertial(geometries: Sequence[Geometry], mass: float) -> Inertial:
    """Mass properties of the union of `geometries` [link frame] with total `mass` [kg] split
    by volume: centre of mass and the inertia about it (parallel-axis theorem) in the link
    frame."""
    volumes = np.array([volume(g) for g in geometries])
    masses = mass * volumes / volumes.sum()
    positions = np.array([g.position_in_link for g in geometries], dtype=float)
    com = masses @ positions / mass
    inertia = np.zeros((3, 3))
    for g, m, p in zip(geometries, masses, positions, strict=True):
        rotation = Rotation.from_euler("xyz", g.rpy_in_link).as_matrix()
        inertia += rotation @ principal_inertia(g, m) @ rotation.T
        d = p - com
        inertia += m * (d @ d * np.eye(3) - np.outer(d, d))
    inertia = 0.5 * (inertia + inertia.T)
    return Inertial(
        mass=float(mass),
        com_in_link=tuple(float(x) for x in com),
        inertia_at_com=tuple(tuple(float(x) for x in row) for row in inertia),
    )


def combined_inertial(parts: Sequence[tuple[Inertial, Sequence[float]]]) -> Inertial:
    """Mass properties of rigidly joined bodies, each (its `Inertial` in its own frame, the
    offset [m] of that frame in the combined body's frame; axes aligned): total mass, centre
    of mass, and inertia about it (parallel-axis theorem) in the combined frame."""
    masses = np.array([inertial.mass for inertial, _ in parts], dtype=float)
    coms = np.array(
        [np.add(inertial.com_in_link, offset) for inertial, offset in parts], dtype=float
    )
    mass = float(masses.sum())
    com = masses @ coms / mass
    inertia = np.zeros((3, 3))
    for (inertial, _), m, c in zip(parts, masses, coms, strict=True):
        d = c - com
        inertia += inertial.inertia_matrix + m * (d @ d * np.eye(3) - np.outer(d, d))
    inertia = 0.5 * (inertia + inertia.T)
    return Inertial(
        mass=mass,
        com_in_link=tuple(float(x) for x in com),
        inertia_at_com=tuple(tuple(float(x) for x in row) for row in inertia),
    )
