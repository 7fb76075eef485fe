"""Versions of the libraries behind a run, recorded in every report."""

from __future__ import annotations

import platform
from importlib import metadata


def library_versions() -> dict[str, str]:
    """kinverify, Python, numpy and the library of every registered backend that is installed (its line of
    the registry, read from the installed metadata: nothing is imported), e.g. ``{"kinverify": "0.1.0", "python": "3.11.7", "numpy": ..., "pin": ...}``."""
    from kinverify.backends import libraries

    out = {"python": platform.python_version()}
    for dist in dict.fromkeys(("kinverify", "numpy") + libraries()):
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "not installed"
    return out
