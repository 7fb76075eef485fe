"""Canonical plain-data form of an :class:`~kinverify.spec.ArmSpec`, its fingerprint, and back.

The canonical form is ``dataclasses.asdict`` of the (already normalised) spec, serialised as
JSON with sorted keys and full float precision (``repr``), so equal specs give equal bytes and
equal sha256 fingerprints. :func:`spec_from_canonical` rebuilds the spec, so a baseline file can
carry the spec it was saved from and explain later changes parameter by parameter.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import asdict
from typing import Any

from kinverify.errors import InputError, SpecError
from kinverify.model.spec import ArmSpec, DHRow, DHTable, Geometry, Inertial, Joint, Limits, Link, Origin, Tool


def spec_to_canonical(spec: ArmSpec) -> dict[str, Any]:
    """Plain JSON data (lists instead of tuples) describing ``spec`` completely."""
    return json.loads(canonical_json(asdict(spec)))


def canonical_json(data: Any) -> str:
    """Compact JSON, sorted keys, floats at full precision; NaN/inf refused (never in a spec)."""
    return json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=False)


def sha256_text(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def spec_fingerprint(spec: ArmSpec) -> str:
    """sha256 of the canonical JSON of the spec's dataclasses."""
    return sha256_text(canonical_json(asdict(spec)))


def _origin(d) -> Origin:
    return Origin(tuple(d["xyz"]), tuple(d["rpy"]))


def _link(d) -> Link:
    geometry = d.get("geometry")
    if geometry is not None:
        fields: dict[str, Any] = {k: tuple(v) if isinstance(v, list) else v for k, v in geometry.items()}
        geometry = Geometry(**fields)
    inertial = d["inertial"]
    return Link(d["name"], Inertial(inertial["mass"], tuple(inertial["com"]), tuple(inertial["inertia"])), geometry)


def _joint(d) -> Joint:
    joint = Joint(
        d["name"],
        d["type"],
        _origin(d["origin"]),
        tuple(d["axis"]),
        Limits(**d["limits"]),
        _link(d["link"]),
        d.get("damping", 0.0),
        d.get("friction", 0.0),
        d.get("armature", 0.0),
        d.get("parent"),
    )
    stored = tuple(float(x) for x in d["axis"])
    if abs(math.fsum(x * x for x in stored) - 1.0) < 1e-12:
        # The stored axis was normalised already; normalising again could change its last bit.
        object.__setattr__(joint, "axis", stored)
    return joint


def spec_from_canonical(data: dict[str, Any], where: str = "spec") -> ArmSpec:
    """Rebuild the spec from :func:`spec_to_canonical` data; ``InputError`` naming ``where`` if
    the data is not a valid spec."""
    try:
        joints = tuple(_joint(j) for j in data["joints"])
        tools = tuple(Tool(t["name"], t["parent"], _origin(t["origin"])) for t in data.get("tools", ()))
        dh = data.get("dh")
        if dh is not None:
            dh = DHTable(dh["convention"], tuple(DHRow(**row) for row in dh["rows"]))
        return ArmSpec(
            data["name"],
            _origin(data["base_origin"]),
            _link(data["base_link"]),
            joints,
            tools,
            dh,
            tuple(data.get("gravity", (0.0, 0.0, -9.81))),
            data.get("floating", False),
        )
    except SpecError as err:
        raise InputError(f"{where}: invalid stored spec: {err}") from None
    except (KeyError, TypeError, ValueError, AttributeError) as err:
        raise InputError(f"{where}: malformed stored spec ({type(err).__name__}: {err})") from None
