"""Backend registry: one entry per backend, filled by trying to import its library.

Each entry names the model source it reads (the spec, the URDF, the MJCF, the SDFormat or the USD) and a builder
``build(sources) -> Backend``. Adding a backend is one module plus one line in ``_ENTRIES``.
"""

from __future__ import annotations

import importlib
from importlib import metadata
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, Callable

from kinverify.errors import BackendUnavailable, UnknownNameError
from kinverify.backends.base import Backend, BackendBase, Evaluation, finite_difference_jacobians
from kinverify.backends.function import FunctionBackend
from kinverify.backends.sources import ModelSources

__all__ = [
    "Backend",
    "BackendBase",
    "BackendInfo",
    "Evaluation",
    "FunctionBackend",
    "ModelSources",
    "available_backends",
    "backend_info",
    "build_backend",
    "build_backends",
    "finite_difference_jacobians",
    "libraries",
    "names_reading",
]


@dataclass(frozen=True)
class BackendInfo:
    name: str
    module: str  # kinverify module holding the adapter
    cls: str
    source: str  # "spec", "urdf", "mjcf", "sdf" or "usd"
    available: bool
    reason: str = ""  # why it is unavailable
    extra: str = ""  # the optional extra of kinverify that installs its library
    library: str = ""  # the distribution of the library it runs (its version goes in every report)

    @property
    def backend_class(self) -> type[Any]:
        """The adapter class, which declares the capabilities (library, Jacobians, slow...)."""
        if not self.available:
            raise BackendUnavailable(self.name, self.reason)
        return getattr(importlib.import_module(self.module, __name__), self.cls)

    def build(self, sources: ModelSources) -> Backend:
        return _BUILDERS[self.source](self.backend_class, sources, self.name)


_BUILDERS: dict[str, Callable] = {
    "spec": lambda cls, s, name: cls(s.spec),
    "urdf": lambda cls, s, name: cls.from_urdf(s.urdf, s.joint_names, s.frames, name=name),
    "mjcf": lambda cls, s, name: cls.from_mjcf(s.mjcf, s.mjcf_joint_names or s.joint_names, s.mjcf_frames or s.frames, name=name),
    "sdf": lambda cls, s, name: cls.from_sdf(s.sdf, s.sdf_joint_names or s.joint_names, s.sdf_frames or s.frames, name=name),
    "usd": lambda cls, s, name: cls.from_usd(s.usd, s.usd_joint_names or s.joint_names, s.usd_frames or s.frames, name=name),
}

# name, module, class, source, library[, extra]: a backend is an adapter class reading one model
# source with one library (its distribution's name: its version is read from the installed
# metadata, without importing it); ``extra``: the optional extra of kinverify that installs that
# library. Per source, the first listed is the one file mode takes as that file's primary reader.
_ENTRIES = (
    ("analytic", ".analytic", "AnalyticBackend", "spec", "numpy"),
    ("analytic-dh", ".analytic", "AnalyticDHBackend", "spec", "numpy"),
    ("pinocchio-urdf", ".pinocchio_", "PinocchioBackend", "urdf", "pin"),
    ("pinocchio-mjcf", ".pinocchio_", "PinocchioBackend", "mjcf", "pin"),
    ("mujoco", ".mujoco_", "MujocoBackend", "mjcf", "mujoco"),
    ("yourdfpy", ".yourdfpy_", "YourdfpyBackend", "urdf", "yourdfpy"),
    ("mujoco-urdf", ".mujoco_", "MujocoBackend", "urdf", "mujoco"),
    ("drake-urdf", ".drake_", "DrakeBackend", "urdf", "drake", "drake"),
    ("drake-mjcf", ".drake_", "DrakeBackend", "mjcf", "drake", "drake"),
    ("drake-sdf", ".drake_", "DrakeBackend", "sdf", "drake", "drake"),
    ("usd", ".usd_", "UsdBackend", "usd", "usd-core", "usd"),
    # Newton (float32, Warp on the CPU)
    ("newton-urdf", ".newton_", "NewtonBackend", "urdf", "newton", "newton"),
    ("newton-mjcf", ".newton_", "NewtonBackend", "mjcf", "newton", "newton"),
    ("newton-usd", ".newton_usd", "NewtonUsdBackend", "usd", "newton", "newton"),
)
PRIMARY = {
    "urdf": "pinocchio-urdf",
    "mjcf": "mujoco",
    "sdf": "drake-sdf",
    "usd": "usd",
}  # the reference reader of each file in file mode


@lru_cache(maxsize=None)
def backend_info(name: str) -> BackendInfo:
    """One registered backend, importing its library only (``available`` False where that fails)."""
    entry = next((e for e in _ENTRIES if e[0] == name), None)
    if entry is None:
        raise UnknownNameError("backend", name, [e[0] for e in _ENTRIES])
    name, module, cls, source, library, extra = (*entry, "")[:6]
    try:
        importlib.import_module(module, __name__)
        return BackendInfo(name, module, cls, source, True, extra=extra, library=library)
    except Exception as err:  # ImportError, or e.g. RuntimeError from mujoco for a bad MUJOCO_GL
        hint = f"; pip install 'kinverify[{extra}]' brings it" if extra and isinstance(err, ImportError) else ""
        return BackendInfo(name, module, cls, source, False, f"cannot import: {err}{hint}", extra, library)


def available_backends() -> dict[str, BackendInfo]:
    """Every registered backend, with ``available`` False where its library fails to import."""
    return {e[0]: backend_info(e[0]) for e in _ENTRIES}


def names_reading(source: str) -> tuple[str, ...]:
    """Registered backends that read ``source`` ("spec", "urdf", "mjcf", "sdf" or "usd"), the primary reader first."""
    names = [entry[0] for entry in _ENTRIES if entry[3] == source]
    primary = PRIMARY.get(source)
    return tuple(sorted(names, key=lambda n: n != primary))


def libraries() -> tuple[str, ...]:
    """The distributions behind the registered backends that are installed, in registry order
    (read from the installed metadata: nothing is imported)."""
    out = []
    for dist in dict.fromkeys(entry[4] for entry in _ENTRIES):
        try:
            metadata.version(dist)
        except metadata.PackageNotFoundError:
            continue
        out.append(dist)
    return tuple(out)


def build_backend(name: str, sources: ModelSources) -> Backend:
    """Build one backend (importing only its library)."""
    return backend_info(name).build(sources)


def default_backend_names(sources: ModelSources) -> list[str]:
    """Backends that apply to ``sources``: spec backends need a spec, ``analytic-dh`` a DH table."""
    names = []
    for info in available_backends().values():
        if not info.available or getattr(sources, info.source) is None:
            continue
        if info.name == "analytic-dh" and (sources.spec is None or sources.spec.dh is None or sources.spec.floating):
            continue
        names.append(info.name)
    return names


def build_backends(sources: ModelSources, names=None) -> list[Backend]:
    return [build_backend(n, sources) for n in (names or default_backend_names(sources))]
