"""Mass properties derived from a link's geometry (solid, uniform density).

Used when a spec gives no inertial data: the result is a physically valid
:class:`~kinverify.spec.Inertial` about the centre of mass, in link-frame axes.
"""

from __future__ import annotations

import numpy as np

from kinverify.model.spec import Geometry, Inertial

DEFAULT_DENSITY = 1000.0  # kg/m³, MuJoCo's default geom density (water)


def _segment_frame(fromto) -> tuple[np.ndarray, np.ndarray, float]:
    a, b = np.asarray(fromto[:3]), np.asarray(fromto[3:])
    axis = b - a
    length = float(np.linalg.norm(axis))
    return (a + b) / 2, axis / length, length


def _axisymmetric(axis: np.ndarray, i_axial: float, i_radial: float) -> np.ndarray:
    """Inertia tensor with moment ``i_axial`` about unit ``axis`` and ``i_radial`` across it."""
    outer = np.outer(axis, axis)
    return i_axial * outer + i_radial * (np.eye(3) - outer)


def volume(geom: Geometry) -> float:
    r = geom.radius
    if geom.shape == "sphere":
        return 4.0 / 3.0 * np.pi * r**3
    if geom.shape == "box":
        assert geom.size is not None  # a box states its size
        return float(np.prod(geom.size))
    cylinder = np.pi * r**2 * geom.length
    return cylinder + (4.0 / 3.0 * np.pi * r**3 if geom.shape == "capsule" else 0.0)


def inertial_from_geometry(geom: Geometry, mass: float | None = None, density: float = DEFAULT_DENSITY) -> Inertial:
    """Inertial of a solid ``geom``; scaled to ``mass`` [kg] when given, else ``density`` [kg/m³]."""
    total = mass if mass is not None else density * volume(geom)
    r = geom.radius
    if geom.shape == "sphere":
        i = 0.4 * total * r**2
        return Inertial(total, geom.pos, (i, i, i, 0.0, 0.0, 0.0))
    if geom.shape == "box":
        assert geom.size is not None  # a box states its size
        x, y, z = geom.size
        k = total / 12.0
        return Inertial(total, geom.pos, (k * (y * y + z * z), k * (x * x + z * z), k * (x * x + y * y), 0.0, 0.0, 0.0))
    centre, axis, length = _segment_frame(geom.fromto)
    if geom.shape == "cylinder":
        tensor = _axisymmetric(axis, total * r**2 / 2, total * (3 * r**2 + length**2) / 12)
    else:
        # Capsule: cylinder plus two hemispheres (each 83/320 m r² about its own centre of
        # mass, which sits 3r/8 from the flat face).
        v_cyl, v_sph = np.pi * r**2 * length, 4.0 / 3.0 * np.pi * r**3
        m_cyl, m_hemi = total * v_cyl / (v_cyl + v_sph), total * v_sph / (v_cyl + v_sph) / 2
        i_axial = m_cyl * r**2 / 2 + 2 * m_hemi * 0.4 * r**2
        offset = length / 2 + 3 * r / 8
        i_radial = m_cyl * (3 * r**2 + length**2) / 12 + 2 * m_hemi * (83 / 320 * r**2 + offset**2)
        tensor = _axisymmetric(axis, i_axial, i_radial)
    inertia = (
        float(tensor[0, 0]),
        float(tensor[1, 1]),
        float(tensor[2, 2]),
        float(tensor[0, 1]),
        float(tensor[0, 2]),
        float(tensor[1, 2]),
    )
    return Inertial(total, tuple(centre), inertia)
