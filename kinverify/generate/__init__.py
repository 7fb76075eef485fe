"""Deterministic URDF and MJCF text from an :class:`~kinverify.spec.ArmSpec`.

Both files use the same names: URDF link = MJCF body, URDF joint = MJCF joint, and each tool is a
URDF link (on a fixed joint ``<tool>_mount``) and an MJCF site.
"""

from kinverify.generate.mjcf import generate_mjcf
from kinverify.generate.urdf import generate_urdf

__all__ = ["generate_mjcf", "generate_urdf"]
