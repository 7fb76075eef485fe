"""Backend registry: one entry per backend, filled by trying to import its library.

Each entry names the model source it reads (the spec, the URDF or the MJCF) and a builder
``build(sources) -> Backend``. Adding a backend is one module plus one line in ``_ENTRIES``.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from functools import lru_cache
from typing import Callable

from kinverify.errors import BackendUnavailable, UnknownNameError
from kinverify.backends.base import Backend, BackendBase, Evaluation, finite_difference_jacobians
from kinverify.backends.function import FunctionBackend
from kinverify.backends.sources import ModelSources

__all__ = ["Backend", "BackendBase", "BackendInfo", "Evaluation", "FunctionBackend", "ModelSources",
           "available_backends", "backend_info", "build_backend", "build_backends", "finite_difference_jacobians"]


@dataclass(frozen=True)
class BackendInfo:
    name: str
    module: str  # kinverify module holding the adapter
    cls: str
    source: str  # "spec", "urdf" or "mjcf"
    library: str  # distribution whose version the report records
    available: bool
    reason: str = ""  # why it is unavailable

    def build(self, sources: ModelSources) -> Backend:
        if not self.available:
            raise BackendUnavailable(self.name, self.reason)
        cls = getattr(importlib.import_module(self.module, __name__), self.cls)
        return _BUILDERS[self.source](cls, sources, self.name)


_BUILDERS: dict[str, Callable] = {
    "spec": lambda cls, s, name: cls(s.spec),
    "urdf": lambda cls, s, name: cls.from_urdf(s.urdf, s.joint_names, s.frames, name=name),
    "mjcf": lambda cls, s, name: cls.from_mjcf(s.mjcf, s.mjcf_joint_names or s.joint_names, s.mjcf_frames or s.frames, name=name),
}

# name, module, class, source, library
_ENTRIES = (
    ("analytic", ".analytic", "AnalyticBackend", "spec", "numpy"),
    ("analytic-dh", ".analytic", "AnalyticDHBackend", "spec", "numpy"),
    ("pinocchio-urdf", ".pinocchio_", "PinocchioBackend", "urdf", "pin"),
    ("pinocchio-mjcf", ".pinocchio_", "PinocchioBackend", "mjcf", "pin"),
    ("mujoco", ".mujoco_", "MujocoBackend", "mjcf", "mujoco"),
    ("yourdfpy", ".yourdfpy_", "YourdfpyBackend", "urdf", "yourdfpy"),
    ("mujoco-urdf", ".mujoco_", "MujocoBackend", "urdf", "mujoco"),
)


@lru_cache(maxsize=None)
def backend_info(name: str) -> BackendInfo:
    """One registered backend, importing its library only (``available`` False where that fails)."""
    entry = next((e for e in _ENTRIES if e[0] == name), None)
    if entry is None:
        raise UnknownNameError("backend", name, [e[0] for e in _ENTRIES])
    name, module, cls, source, library = entry
    try:
        importlib.import_module(module, __name__)
        return BackendInfo(name, module, cls, source, library, True)
    except Exception as err:  # ImportError, or e.g. RuntimeError from mujoco for a bad MUJOCO_GL
        return BackendInfo(name, module, cls, source, library, False, f"cannot import: {err}")


def available_backends() -> dict[str, BackendInfo]:
    """Every registered backend, with ``available`` False where its library fails to import."""
    return {e[0]: backend_info(e[0]) for e in _ENTRIES}


def build_backend(name: str, sources: ModelSources) -> Backend:
    """Build one backend (importing only its library)."""
    return backend_info(name).build(sources)


def default_backend_names(sources: ModelSources) -> list[str]:
    """Backends that apply to ``sources``: spec backends need a spec, ``analytic-dh`` a DH table."""
    names = []
    for info in available_backends().values():
        if not info.available or getattr(sources, info.source) is None:
            continue
        if info.name == "analytic-dh" and sources.spec.dh is None:
            continue
        names.append(info.name)
    return names


def build_backends(sources: ModelSources, names=None) -> list[Backend]:
    return [build_backend(n, sources) for n in (names or default_backend_names(sources))]
