"""xacro input: a ``.xacro`` URDF compiled to plain URDF text with xacrodoc (no ROS needed).

``$(find pkg)`` and ``package://pkg/...`` are resolved from ``--package NAME=PATH`` options, then
from package folders found walking up from the file (ROS style). ``<xacro:arg>`` values come from
``--xacro-arg NAME=VALUE``. Anything xacro cannot resolve (an unknown macro, package or
argument, a malformed expression) is a one-line :class:`~kinverify.errors.InputError`.

xacro evaluates the ``${...}`` expressions a file contains: it runs in a child process bounded in
memory and time (:mod:`kinverify.io.isolate`), so an expression that runs away ends there, as a
one-line error naming the file; still, compile only files you trust.
"""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import xacro
import xacrodoc.xacrodoc
from xacrodoc import XacroDoc
from xacrodoc import packages as xpackages

from kinverify.errors import InputError, library_reason
from kinverify.io.isolate import LibraryDied, in_child
from kinverify.io.plan import note_input
from kinverify.io.read import library_reads

XACRO_NAMESPACE = "http://www.ros.org/wiki/xacro"


COMMENT = re.compile(r"<!--.*?-->", re.S)
XACRO_USE = re.compile(r"<\w+:(include|macro|property|arg|if|unless|call|element|attribute|insert_block)\b|\$[({]")


def is_xacro(path: str | Path, text: str | None = None) -> bool:
    """A ``.xacro`` file, or a URDF that declares the xacro namespace and uses it (macros,
    properties, ``${...}``, ``$(...)``): xacro's own output keeps the declaration and is plain URDF."""
    if str(path).endswith(".xacro"):
        return True
    if text is None or XACRO_NAMESPACE not in text[:4096]:
        return False
    return XACRO_USE.search(COMMENT.sub("", text)) is not None  # a use inside a comment is no use


def parse_pairs(items, flag: str) -> dict[str, str]:
    """``["a=1", "b=2"]`` -> ``{"a": "1", "b": "2"}``; a malformed item is an InputError naming ``flag``."""
    out = {}
    for item in items or ():
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or not value:
            raise InputError(f"{flag}: expected NAME=VALUE, got {item!r}")
        out[name.strip()] = value
    return out


def compile_xacro(
    path: str | Path, packages: dict[str, str] | None = None, args: dict[str, str] | None = None
) -> tuple[str, list[str]]:
    """The URDF text ``path`` compiles to, and the warnings xacro printed while compiling."""
    found = {}
    for name, folder in (packages or {}).items():
        folder_path = Path(folder).expanduser()
        if not folder_path.is_dir():
            raise InputError(f"--package {name}={folder}: not a folder")
        found[name] = str(folder_path.resolve())
    xpackages.reset()
    xpackages.update_package_cache(found)

    try:  # xacro evaluates the file's expressions: in a child process bounded in memory and time
        text, printed, read = in_child(lambda: _compile(path, args))
    except LibraryDied as err:
        raise InputError(f"{path}: xacro cannot compile it: its evaluation {err.reason} (see docs/robustness.md)") from None
    finally:
        xpackages.reset()
    for name in read:  # what the child read is an input of this run too
        note_input(name, f"{path}: xacro include")
    warnings = [f"xacro: {line.strip()}" for line in printed.splitlines() if line.strip().startswith("warning")]
    return text, warnings


def _compile(path, args) -> tuple[str, str, list[str]]:
    """The URDF text, what xacro printed and the files it read (run in the child)."""
    read: list[str]
    printed, read = io.StringIO(), []  # xacro prints its warnings: keep them for the report, off the terminal
    # xacro resolves a relative include beside the file on top of its module-global stack: start it
    # with this file, as the xacro command does (else beside the working folder, or beside the file
    # of an earlier compile that failed inside an include)
    xacro.init_stacks(str(path))
    try:
        # the file and everything it includes are read by kinverify's reader (bounded, no FIFO)
        with (
            contextlib.redirect_stderr(printed),
            contextlib.redirect_stdout(printed),
            library_reads(
                (xacro, xacrodoc.xacrodoc), f"{path}: xacro include", record=read, files="the xacro file and its includes"
            ),
        ):
            text = XacroDoc.from_file(str(path), subargs=dict(args or {}), walk_up=True).to_urdf_string()
    except InputError as err:
        raise InputError(str(err)) from None  # as a plain InputError: it crosses back to the parent
    except Exception as err:  # xacro raises XacroException, NameError, KeyError... for bad files
        if _out_of_memory(err):
            raise MemoryError from None
        missing = re.search(r"Package not found: (\S+)", str(err))
        if missing:
            raise InputError(f"{path}: xacro package {missing[1]!r} not found (give it with --package NAME=PATH)") from None
        raise InputError(f"{path}: xacro cannot compile it: {library_reason(err)}") from None
    return text, printed.getvalue(), read


def _out_of_memory(err: BaseException | None) -> bool:
    """Whether a MemoryError is behind ``err`` (xacro wraps what an expression raises)."""
    seen = 0
    while err is not None and seen < 20:
        if isinstance(err, MemoryError):
            return True
        err, seen = err.__cause__ or err.__context__, seen + 1
    return False
