"""xacro input: a ``.xacro`` URDF compiled to plain URDF text with xacrodoc (no ROS needed).

``$(find pkg)`` and ``package://pkg/...`` are resolved from ``--package NAME=PATH`` options, then
from package folders found walking up from the file (ROS style). ``<xacro:arg>`` values come from
``--xacro-arg NAME=VALUE``. Anything xacro cannot resolve (an unknown macro, package or
argument, a malformed expression) is a one-line :class:`~kinverify.errors.InputError`.

xacro evaluates the ``${...}`` expressions a file contains: compile only files you trust.
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


def compile_xacro(path: str | Path, packages: dict[str, str] | None = None,
                  args: dict[str, str] | None = None) -> tuple[str, list[str]]:
    """The URDF text ``path`` compiles to, and the warnings xacro printed while compiling."""
    found = {}
    for name, folder in (packages or {}).items():
        folder_path = Path(folder).expanduser()
        if not folder_path.is_dir():
            raise InputError(f"--package {name}={folder}: not a folder")
        found[name] = str(folder_path.resolve())
    xpackages.reset()
    xpackages.update_package_cache(found)


    printed = io.StringIO()  # xacro prints its warnings: keep them for the report, off the terminal
    try:
        # the file and everything it includes are read by kinverify's reader (bounded, no FIFO)
        with contextlib.redirect_stderr(printed), contextlib.redirect_stdout(printed), \
                library_reads((xacro, xacrodoc.xacrodoc), f"{path}: xacro include"):
            text = XacroDoc.from_file(str(path), subargs=dict(args or {}), walk_up=True).to_urdf_string()
    except InputError:
        raise
    except Exception as err:  # xacro raises XacroException, NameError, KeyError... for bad files
        missing = re.search(r"Package not found: (\S+)", str(err))
        if missing:
            raise InputError(f"{path}: xacro package {missing[1]!r} not found (give it with --package NAME=PATH)") from None
        raise InputError(f"{path}: xacro cannot compile it: {library_reason(err)}") from None
    finally:
        xpackages.reset()
    warnings = [f"xacro: {line.strip()}" for line in printed.getvalue().splitlines() if line.strip().startswith("warning")]
    return text, warnings
