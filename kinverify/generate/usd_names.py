"""USD prim names of a spec's links, joints and tools (no usd-core needed, so the model sources
can name them without importing ``pxr``).

A kinverify name is letters, digits, ``_ . -``; a USD prim name is an identifier (letters,
digits, ``_``, not starting with a digit). Valid names are kept; in the others every ``.`` and
``-`` becomes ``_``, suffixed ``_1``, ``_2``... where that would repeat a name.
"""

from __future__ import annotations

import re

from kinverify.model.spec import ArmSpec

BASE_JOINT = "world_to_base"  # the generated URDF's and SDFormat's name for the base weld
_IDENTIFIER = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def identifier(name: str) -> str:
    """``name`` made a valid USD identifier (as ``Tf.MakeValidIdentifier`` does for these names)."""
    out = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return out if _IDENTIFIER.match(out) else "_" + out


def unique(name: str, taken: set) -> str:
    """``name``, or ``name_1``, ``name_2``... the first not in ``taken`` (which it joins)."""
    candidate, k = name, 0
    while candidate in taken:
        k += 1
        candidate = f"{name}_{k}"
    taken.add(candidate)
    return candidate


def prim_names(spec: ArmSpec) -> dict[str, str]:
    """kinverify name -> USD prim name, for every link, joint and tool, and (key ``world_to_base``)
    the fixed base's joint to the world."""
    names = (*spec.link_names, *spec.joint_names, *spec.tool_names)
    out = {n: n for n in names if _IDENTIFIER.match(n)}
    taken = set(out.values())
    for name in [n for n in names if n not in out] + ([] if spec.floating else [BASE_JOINT]):
        out[name] = unique(identifier(name), taken)
    return out
