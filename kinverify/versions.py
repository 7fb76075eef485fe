"""Versions of the libraries behind a run, recorded in every report."""

from __future__ import annotations

import platform
from importlib import metadata

DISTRIBUTIONS = ("kinverify", "numpy", "pin", "mujoco", "yourdfpy")


def library_versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for dist in DISTRIBUTIONS:
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "not installed"
    return out
