"""Deterministic URDF, MJCF, SDFormat and OpenUSD text from an :class:`~kinverify.spec.ArmSpec`.

The files use the same names: URDF link = MJCF body = SDFormat link = USD rigid body, URDF joint
= MJCF joint = SDFormat joint = USD physics joint, and each tool is a URDF link (on a fixed joint
``<tool>_mount``), an MJCF site, an SDFormat ``<frame>`` and a USD ``Xform``. The USD needs
usd-core (the ``usd`` extra): :func:`generate_usd_if_available` gives ``None`` without it.
"""

from __future__ import annotations

import importlib

from kinverify.generate.mjcf import generate_mjcf
from kinverify.generate.sdf import generate_sdf
from kinverify.generate.urdf import generate_urdf
from kinverify.model.spec import ArmSpec

__all__ = ["USD_MISSING", "generate_mjcf", "generate_sdf", "generate_urdf", "generate_usd_if_available"]

USD_MISSING = "usd-core (pxr) is not installed; pip install 'kinverify[usd]' brings it"


def generate_usd_if_available(spec: ArmSpec) -> str | None:
    """The ``.usda`` text of ``spec`` (:func:`kinverify.generate.usd.generate_usd`), or ``None``
    when usd-core's ``pxr`` does not import (the ``usd`` extra is not installed)."""
    try:
        module = importlib.import_module("kinverify.generate.usd")  # imports pxr, which is optional
    except ImportError as err:
        if (err.name or "").partition(".")[0] != "pxr":
            raise
        return None
    return module.generate_usd(spec)
