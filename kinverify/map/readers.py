"""Which reader takes which file: one registry line per format.

A reader is ``read(path, options) -> Side`` (:mod:`kinverify.map.side`). A file's format comes
from its suffix; an ``.xml`` file is an MJCF or a URDF by its root element. To add a format (the
USD reader, say ``kinverify/map/usd.py`` built on ``kinverify.filemode.read.describe_usd``: its
joint order as the articulation gives it, drive stiffness/damping per degree converted with
:func:`kinverify.map.side.to_radian`), add its module and one line to :data:`READERS` and its
suffixes to :data:`SUFFIXES`. USD (:mod:`kinverify.map.usd`) is read that way."""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from kinverify.errors import InputError
from kinverify.io.read import read_head
from kinverify.map.mjcf import read_mjcf
from kinverify.map.sdf import read_sdf
from kinverify.map.side import Side
from kinverify.map.urdf import read_urdf
from kinverify.map.usd import read_usd

READERS: dict[str, Callable[[str, object], Side]] = {
    "urdf": read_urdf,  # also xacro: load_urdf compiles it
    "mjcf": read_mjcf,
    "sdf": read_sdf,
    "usd": read_usd,  # .usd, .usda, .usdc: pxr (the extra "usd")
}
SUFFIXES = {".urdf": "urdf", ".xacro": "urdf", ".mjcf": "mjcf", ".sdf": "sdf", ".usd": "usd", ".usda": "usd", ".usdc": "usd"}
ROOTS = {b"<mujoco": "mjcf", b"<robot": "urdf", b"<sdf": "sdf"}


def format_of(path: str) -> str:
    """``urdf``, ``mjcf``, ``sdf``, ``usd`` (or another registered format) for ``path``; :class:`InputError`
    for a file no reader takes."""
    head = read_head(path, 4096, "FILE")  # absent, a folder or a FIFO: refused here, named as the user gave it
    suffix = Path(path).suffix.lower()
    if suffix in SUFFIXES:
        return SUFFIXES[suffix]
    for root, kind in ROOTS.items():
        if root in head:
            return kind
    known = ", ".join(sorted(set(SUFFIXES) | {".xml"}))
    raise InputError(f"{path}: not a model kinverify map reads (suffixes {known}; an .xml file must be an MJCF or a URDF)")


def read_side(path: str, options) -> Side:
    return READERS[format_of(path)](path, options)
