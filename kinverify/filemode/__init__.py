"""File mode: cross-validate an existing URDF against an existing MJCF (not implemented yet)."""

from __future__ import annotations

from ..errors import InputError


def verify_files(urdf: str, mjcf: str, options, frames=(), joints=(), command: str = ""):
    raise InputError("file mode (--urdf/--mjcf) is not implemented yet")
