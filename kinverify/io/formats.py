"""Parsing what :mod:`kinverify.io.read` read, with bounded nesting.

A JSON array nested 100,000 deep, a TOML value nested 5,000 deep or an XML element nested 1,000
deep would otherwise raise ``RecursionError`` in the parser or in whatever walks the result later
(a kinverify bug, exit 3): each is a one-line :class:`~kinverify.io.read.InputFileError` here
(exit 2). Decoding errors of the format itself (``json.JSONDecodeError``,
``tomllib.TOMLDecodeError``) are left to the caller, which knows what the file was meant to be.
"""

from __future__ import annotations

import io
import json
import tomllib
import xml.etree.ElementTree as ET
from typing import Any

import defusedxml
import defusedxml.ElementTree as DET

from kinverify.io.read import InputFileError
from kinverify.pipeline.limits import MAX_JSON_DEPTH, MAX_XML_DEPTH


def _too_deep(path, label: str, limit: int) -> InputFileError:
    return InputFileError(path, f"nests values more than {limit} levels deep (see docs/robustness.md)", label)


def check_depth(value: Any, path, label: str = "", limit: int = MAX_JSON_DEPTH) -> Any:
    """``value`` (nested dicts and lists) if it nests at most ``limit`` levels."""
    stack = [(value, 1)]
    while stack:
        item, depth = stack.pop()
        if depth > limit:
            raise _too_deep(path, label, limit)
        children = item.values() if isinstance(item, dict) else item
        stack.extend((c, depth + 1) for c in children if isinstance(c, (dict, list)))
    return value


def _no_constant(name: str):
    raise ValueError(f"{name} is not a number here")


def json_loads(text: str | bytes, path, label: str = "", allow_nan: bool = True) -> Any:
    """``json.loads`` with bounded nesting; ``allow_nan=False`` refuses ``NaN`` and ``Infinity``
    (files kinverify writes without them)."""
    try:
        value = json.loads(text, parse_constant=None if allow_nan else _no_constant)
    except RecursionError:
        raise _too_deep(path, label, MAX_JSON_DEPTH) from None
    except ValueError as err:
        if isinstance(err, json.JSONDecodeError):
            raise
        raise InputFileError(path, f"holds {str(err).split()[0]}, which is not a number this file may hold", label) from None
    return check_depth(value, path, label) if isinstance(value, (dict, list)) else value


def toml_loads(text: str, path, label: str = "") -> dict[str, Any]:
    """``tomllib.loads`` with bounded nesting."""
    try:
        value = tomllib.loads(text)
    except RecursionError:
        raise _too_deep(path, label, MAX_JSON_DEPTH) from None
    return check_depth(value, path, label)


def npy_load(data: bytes, path, label: str = ""):
    """The array an ``.npy`` file holds (no pickles, no ``.npz`` archives)."""
    import numpy as np

    try:
        array = np.load(io.BytesIO(data), allow_pickle=False)
    except (OSError, ValueError, EOFError):
        raise InputFileError(path, "is not an .npy file (an array written by numpy.save)", label) from None
    if not isinstance(array, np.ndarray):
        raise InputFileError(path, "must hold a real-valued array (an .npz archive or object array is not one)", label)
    return array


def xml_parse(data: bytes, path, label: str = "", limit: int = MAX_XML_DEPTH) -> ET.Element:
    """The root element of untrusted XML: a DTD with entities (external, or an expansion bomb) is
    refused, and so is an element nested more than ``limit`` deep (checked while parsing, before
    the rest of the file is read into a tree)."""
    depth = 0
    root = None
    try:
        for event, element in DET.iterparse(
            io.BytesIO(data), events=("start", "end"), forbid_dtd=False, forbid_entities=True, forbid_external=True
        ):
            if event == "start":
                depth += 1
                if root is None:
                    root = element
                if depth > limit:
                    raise InputFileError(path, f"nests elements more than {limit} levels deep (see docs/robustness.md)", label)
            else:
                depth -= 1
    except defusedxml.EntitiesForbidden:
        raise InputFileError(
            path, "declares XML entities (external entities and entity expansion are refused for safety; remove the DTD)", label
        ) from None
    except (defusedxml.DTDForbidden, defusedxml.ExternalReferenceForbidden, defusedxml.NotSupportedError) as err:
        raise InputFileError(path, f"is unsafe XML, refused ({type(err).__name__})", label) from None
    except ET.ParseError as err:
        raise InputFileError(path, f"is not XML: {err}", label) from None
    if root is None:
        raise InputFileError(path, "is not XML: no element found", label)
    return root
