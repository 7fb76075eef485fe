"""Hypothesis strategies that mangle kinverify's inputs: spec files (as TOML data), URDF and MJCF
(as XML trees). Each draws 1-3 mutations: drop, duplicate or retype an element, replace a number
with NaN / inf / a huge or malformed value, give a name a hostile value, or make an element refer
to itself. The result is text written to a file for the CLI.
"""

from __future__ import annotations

import copy
import json
import math
import re
import xml.etree.ElementTree as ET

from hypothesis import strategies as st

BAD_NUMBERS = ["nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "0", "-1", "", "abc", "1 2", "0x10", "1e999"]
HOSTILE_NAMES = [
    "",
    " ",
    "a" * 300,
    "<b>&amp;\"'",
    "ℓink ünïcode",
    "../../etc/passwd",
    "name with spaces",
    "world",
    "universe",
    "null\x01byte",
    "-",
    "0",
]
URDF_JOINT_TYPES = ["revolute", "continuous", "prismatic", "fixed", "floating", "planar", "spherical", "", "hinge"]
MJCF_JOINT_TYPES = ["hinge", "slide", "ball", "free", "", "revolute"]
NUMBER = re.compile(r"-?\d+(\.\d+)?([eE][-+]?\d+)?")


# ---------------------------------------------------------------- XML (URDF, MJCF)


def _parents(root: ET.Element) -> dict[ET.Element, ET.Element]:
    return {child: parent for parent in root.iter() for child in parent}


@st.composite
def _xml_mutation(draw, root: ET.Element, kind: str) -> str:
    parents = _parents(root)
    elements = list(parents)
    op = draw(st.sampled_from(["drop", "duplicate", "retype", "number", "name", "self_reference", "tag"]))
    el = draw(st.sampled_from(elements))
    if op == "drop":
        parents[el].remove(el)
    elif op == "duplicate":
        parents[el].append(copy.deepcopy(el))
    elif op == "retype":
        joints = [e for e in elements if e.tag == "joint"] or elements
        el = draw(st.sampled_from(joints))
        el.set("type", draw(st.sampled_from(URDF_JOINT_TYPES if kind == "urdf" else MJCF_JOINT_TYPES)))
    elif op == "number":
        numeric = [(e, a) for e in elements for a, v in e.attrib.items() if NUMBER.search(v)]
        if numeric:
            el, attr = draw(st.sampled_from(numeric))
            matches = list(NUMBER.finditer(el.get(attr)))
            m = draw(st.sampled_from(matches))
            value = el.get(attr)
            el.set(attr, value[: m.start()] + draw(st.sampled_from(BAD_NUMBERS)) + value[m.end() :])
    elif op == "name":
        named = [
            (e, a) for e in elements for a in ("name", "link", "joint", "body", "class", "mesh", "childclass") if a in e.attrib
        ]
        if named:
            el, attr = draw(st.sampled_from(named))
            others = [e.get("name") for e in elements if e.get("name")]
            el.set(attr, draw(st.sampled_from(HOSTILE_NAMES + others)))
    elif op == "self_reference":
        _self_reference(draw, root, elements, kind)
    else:  # retype an element: another tag of the same file
        tags = sorted({e.tag for e in elements})
        el.tag = draw(st.sampled_from(tags))
    return op


def _self_reference(draw, root, elements, kind: str) -> None:
    if kind == "urdf":
        joints = [j for j in elements if j.tag == "joint" and j.find("parent") is not None and j.find("child") is not None]
        if joints:
            j = draw(st.sampled_from(joints))
            which = draw(st.sampled_from(["child=parent", "parent=child", "name=child", "name=parent"]))
            if which == "child=parent":
                j.find("child").set("link", j.find("parent").get("link", ""))
            elif which == "parent=child":
                j.find("parent").set("link", j.find("child").get("link", ""))
            else:
                j.set("name", j.find(which.split("=")[1]).get("link", ""))
    else:
        bodies = [b for b in elements if b.tag == "body"]
        if bodies:
            b = draw(st.sampled_from(bodies))
            inner = [e for e in b.iter() if e is not b and e.get("name") is not None]
            if inner and draw(st.booleans()):
                draw(st.sampled_from(inner)).set("name", b.get("name", ""))  # a joint or site named like its body
            else:
                ancestor = draw(st.sampled_from(bodies))
                if ancestor is not b and b not in ancestor.iter():
                    b.append(copy.deepcopy(ancestor))  # a body that holds a copy of another (names twice)


@st.composite
def mangled_xml(draw, text: str, kind: str) -> tuple[str, list[str]]:
    """``text`` (a URDF when ``kind`` is ``urdf``, else an MJCF) with 1-3 mutations, and their names."""
    root = ET.fromstring(text)
    ops = [draw(_xml_mutation(root, kind)) for _ in range(draw(st.integers(1, 3)))]
    return ET.tostring(root, encoding="unicode"), ops


# ---------------------------------------------------------------- spec files (TOML)


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(x)}" for k, x in v.items()) + "}"


def _toml_key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else json.dumps(k)


def to_toml(data: dict) -> str:
    """TOML text of ``data`` (every table inline)."""
    return "".join(f"{_toml_key(k)} = {_toml_value(v)}\n" for k, v in data.items())


def _slots(value, path=()):
    """Every (container, key) in a nested dict/list, with its path."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield value, k
            yield from _slots(v, path + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield value, i
            yield from _slots(v, path + (i,))


REPLACEMENTS = [
    math.nan,
    math.inf,
    -math.inf,
    1e308,
    -1e308,
    1e-320,
    0,
    -1,
    0.0,
    True,
    False,
    "1",
    "text",
    [],
    {},
    [1.0, 2.0],
    [True, False, True],
    ["1", "2", "3"],
    2**70,
    -(2**70),
]


@st.composite
def mangled_spec(draw, data: dict) -> tuple[str, list[str]]:
    """A spec's TOML data with 1-3 mutations (drop, duplicate, retype, bad number, hostile name,
    self-reference), as TOML text, and the mutations' names."""
    data = copy.deepcopy(data)
    ops = []
    for _ in range(draw(st.integers(1, 3))):
        slots = list(_slots(data))
        container, key = draw(st.sampled_from(slots))
        op = draw(st.sampled_from(["drop", "duplicate", "retype", "name", "self_reference"]))
        ops.append(op)
        if op == "drop":
            del container[key]
        elif op == "duplicate":
            if isinstance(container, list):
                container.append(copy.deepcopy(container[key]))
            else:
                container[f"{key}_copy"] = copy.deepcopy(container[key])
        elif op == "retype":
            container[key] = draw(st.sampled_from(REPLACEMENTS))
        elif op == "name":
            container[key] = draw(st.sampled_from(HOSTILE_NAMES))
        else:
            names = [c[k] for c, k in _slots(data) if k in ("name", "parent") and isinstance(c[k], str)]
            if names:
                container[key] = draw(st.sampled_from(names))
    return to_toml(data), ops
