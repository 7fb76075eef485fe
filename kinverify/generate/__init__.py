"""Deterministic URDF, MJCF and SDFormat text from an :class:`~kinverify.spec.ArmSpec`.

The files use the same names: URDF link = MJCF body = SDFormat link, URDF joint = MJCF joint =
SDFormat joint, and each tool is a URDF link (on a fixed joint ``<tool>_mount``), an MJCF site and
an SDFormat ``<frame>``.
"""

from kinverify.generate.mjcf import generate_mjcf
from kinverify.generate.sdf import generate_sdf
from kinverify.generate.urdf import generate_urdf

__all__ = ["generate_mjcf", "generate_sdf", "generate_urdf"]
