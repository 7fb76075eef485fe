"""Physically impossible inertial data in a user's URDF or MJCF, as error findings.

Pinocchio loads a URDF link with mass −1 and MuJoCo repairs some inertias (``balanceinertia``),
so neither library's reading can be trusted to refuse them: the file's own ``<inertial>``
elements are checked here. An inertial is non-physical when

- its mass is negative, not finite, or zero while the inertia is not zero;
- its inertia tensor (about the centre of mass) is not finite or not positive semi-definite
  (a principal moment below ``-TOL`` times the largest);
- its principal moments break the triangle inequality ``A + B >= C`` by more than ``TOL``
  times ``C`` (no rigid body has them).

A zero inertia with a positive mass (a point mass) and a thin rod (``A = 0, B = C``) are the
physical limits and are accepted. Each problem is one :class:`~kinverify.suites.base.Finding`
of kind ``nonphysical_inertia``, severity ``error``, naming the file and the link (URDF) or
body (MJCF).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np

from kinverify.suites.base import Finding

TOL = 1e-6  # relative: inertias written with 7 significant digits still pass
KIND = "nonphysical_inertia"


def inertial_problem(mass: float, inertia: np.ndarray | None) -> str | None:
    """What is non-physical about ``mass`` [kg] and the 3×3 ``inertia`` [kg·m²] (None: not given),
    or None when they can belong to a rigid body."""
    if not math.isfinite(mass):
        return f"mass {mass} is not finite"
    if mass < 0:
        return f"mass {mass:g} kg is negative"
    if inertia is None:
        return None
    if not np.all(np.isfinite(inertia)):
        return "inertia has non-finite entries"
    if mass == 0 and np.any(inertia != 0):
        return "mass is zero but the inertia is not"
    moments = np.linalg.eigvalsh((inertia + inertia.T) / 2)  # ascending
    scale = max(abs(moments).max(), 1e-300)
    if moments[0] < -TOL * scale:
        return f"inertia is not positive semi-definite (principal moments {', '.join(f'{v:.6g}' for v in moments)} kg·m²)"
    a, b, c = moments
    if a + b < c - TOL * scale:
        return (
            f"principal moments {a:.6g}, {b:.6g}, {c:.6g} kg·m² break the triangle inequality A + B >= C (no rigid body has them)"
        )
    return None


def _float(el: ET.Element | None, attr: str, default: float | None = None) -> float | None:
    if el is None or el.get(attr) is None:
        return default
    try:
        return float(el.get(attr))  # type: ignore[arg-type]  # None returned above
    except ValueError:
        return None  # unreadable: the libraries report it


def _floats(text: str | None, n: int) -> list[float] | None:
    if text is None:
        return None
    try:
        values = [float(v) for v in text.split()]
    except ValueError:
        return None
    return values if len(values) == n else None


def urdf_problems(text: str) -> list[tuple[str, float, np.ndarray | None, str]]:
    """``(link, mass, inertia, problem)`` for each non-physical ``<inertial>`` of a URDF."""
    out = []
    for link in ET.fromstring(text).iter("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        mass = _float(inertial.find("mass"), "value")
        el = inertial.find("inertia")
        keys = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
        values = [_float(el, k, 0.0) for k in keys] if el is not None else None
        if mass is None or (values is not None and None in values):
            continue
        inertia = None
        if values is not None:
            ixx, ixy, ixz, iyy, iyz, izz = values
            inertia = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        problem = inertial_problem(mass, inertia)
        if problem:
            out.append((link.get("name") or "?", mass, inertia, problem))
    return out


def mjcf_problems(text: str) -> list[tuple[str, float, np.ndarray | None, str]]:
    """``(body, mass, inertia, problem)`` for each non-physical ``<inertial>`` of an MJCF.
    With ``<compiler balanceinertia="true">`` MuJoCo repairs the moments, so only the mass is
    checked."""
    root = ET.fromstring(text)
    balance = any((c.get("balanceinertia") or "").lower() == "true" for c in root.iter("compiler"))
    out = []
    for body in root.iter("body"):
        inertial = body.find("inertial")
        if inertial is None:
            continue
        mass = _float(inertial, "mass")
        if mass is None:
            continue
        inertia = None
        diag, full = _floats(inertial.get("diaginertia"), 3), _floats(inertial.get("fullinertia"), 6)
        if diag is not None:
            inertia = np.diag(diag)
        elif full is not None:
            ixx, iyy, izz, ixy, ixz, iyz = full
            inertia = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        problem = inertial_problem(mass, None if balance else inertia)
        if problem:
            out.append((body.get("name") or "?", mass, inertia, problem))
    return out


def _findings(kind: str, path: str, problems) -> list[Finding]:
    label = kind.upper()
    element = "link" if kind == "urdf" else "body"
    return [
        Finding(
            KIND,
            "error",
            f"{label} {path}: {element} {name}: non-physical inertial: {problem}",
            subject=name,
            subject_type="link",
            property="dynamics",
            values={
                "file": label,
                "path": path,
                "mass": mass,
                "inertia": None if inertia is None else inertia.tolist(),
                "problem": problem,
            },
        )
        for name, mass, inertia, problem in problems
    ]


def validate_inertials(urdf, mjcf) -> list[Finding]:
    """Error findings for the non-physical inertials of the loaded URDF and MJCF
    (:class:`~kinverify.filemode.read.loading.LoadedFile`)."""
    return _findings("urdf", urdf.path, urdf_problems(urdf.text)) + _findings("mjcf", mjcf.path, mjcf_problems(mjcf.text))
