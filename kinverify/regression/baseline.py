"""Baselines: what a model computed once, saved so a later version can be checked against it.

A baseline file holds a fixed seeded sample set (edge configurations first, then uniform draws
inside the limits), the *records* computed at those configurations, the spec it was saved from
(canonical form, so changes can be explained parameter by parameter), sha256 fingerprints of
the spec and of the generated URDF and MJCF, and the library versions.

Records are ``{"property", "frame", "sample", "value"}``: ``value`` is a number or nested list
(metres, radians, world-aligned Jacobians ``[linear; angular]``) for configuration
``q[sample]``. Families of records come from ``QUANTITIES``: kinematics (FK of every frame and
its Jacobian, analytic backend), IK results for fixed targets and dynamics (mass matrix and
gravity torques per joint, Pinocchio on the generated URDF; see
:mod:`kinverify.baseline_quantities`). Another property is one function ``(spec, q) -> records``
appended to ``QUANTITIES`` plus its tolerances in ``BASELINE_TOLERANCES`` (and a metric in
``METRICS`` if the Euclidean norm of the difference is not the right one). A quantity that
needs inputs fixed at save time (IK targets in the world) also has ``prepare(spec, q) -> data``:
the data is stored under ``fixed[name]`` and passed back as ``compute(spec, q, data)``.

Format version 2 added ``fixed`` and the ``ik`` and ``dynamics`` records; version 1 files are
still read and checked (their FK and Jacobian records; the check says what they lack).

The file is JSON with sorted keys, one configuration or record per line and floats at full
precision (``repr``), so ``git diff`` of two baselines is readable and re-reading is exact.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np

from kinverify.model.canonical import sha256_text, spec_fingerprint, spec_to_canonical
from kinverify.errors import InputError
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.kinematics import frame_poses, geometric_jacobians
from kinverify.io.write import write_atomic
from kinverify.pipeline.limits import MAX_DATA_BYTES
from kinverify.pipeline.sampling import spec_samples
from kinverify.regression.quantities import dynamics_records, ik_fixed, ik_parse, ik_records
from kinverify.model.spec import ArmSpec
from kinverify.model.transforms import geodesic_distance
from kinverify.suites.registry import properties
from kinverify.versions import library_versions

FORMAT = "kinverify-baseline"
FORMAT_VERSION = 2  # 2: "fixed" (IK targets), ik.* and dynamics.* records
DEFAULT_SAMPLES = 30  # uniform configurations, after the edge configurations
DEFAULT_SEED = 0
# The sections each format version must have, with their JSON types: a section deleted or retyped
# is a malformed baseline (exit 2), never a comparison silently skipped.
SCHEMA: dict[int, dict[str, type | tuple[type, ...]]] = {
    1: {
        "model": str,
        "spec": dict,
        "fingerprints": dict,
        "versions": dict,
        "joint_names": list,
        "frames": list,
        "q": list,
        "records": list,
    },
}
SCHEMA[2] = {**SCHEMA[1], "seed": int, "samples": int, "quantities": list, "fixed": dict}

Record = dict[str, Any]


@dataclass(frozen=True)
class Quantity:
    """A family of baseline records: ``compute(spec, q) -> [record, ...]``, or with ``prepare``
    ``compute(spec, q, prepare(spec, q_at_save_time))``."""

    name: str
    compute: Callable[..., list[Record]]
    prepare: Callable[[ArmSpec, np.ndarray], Any] | None = None


def kinematics_records(spec: ArmSpec, q: np.ndarray) -> list[Record]:
    """FK (position, rotation matrix) and Jacobian (linear, angular rows) of every frame."""
    poses = frame_poses(spec, q)
    jac = geometric_jacobians(spec, poses, q)
    out: list[Record] = []
    for prop, values in (
        ("fk.position", poses[..., :3, 3]),
        ("fk.rotation", poses[..., :3, :3]),
        ("jacobian.linear", jac[..., :3, :]),
        ("jacobian.angular", jac[..., 3:, :]),
    ):
        for f, frame in enumerate(spec.frame_names):
            for s in range(len(q)):
                out.append({"property": prop, "frame": frame, "sample": s, "value": values[s, f].tolist()})
    return out


QUANTITIES: list[Quantity] = [
    Quantity("kinematics", kinematics_records),
    Quantity("ik", ik_records, prepare=ik_fixed),
    Quantity("dynamics", dynamics_records),
]


@dataclass(frozen=True)
class Tolerance:
    """How far a recorded quantity may move between two versions of a model, in ``unit``."""

    value: float
    unit: str


RECORDED = ("fk.position", "fk.rotation", "jacobian.linear", "jacobian.angular", "dynamics.mass_matrix", "dynamics.gravity")
BASELINE_TOLERANCES: dict[str, Tolerance] = {
    # the verify tolerances of the registry for what both record
    **{name: Tolerance(p.tolerance, p.unit) for name, p in properties().items() if name in RECORDED},
    # the solver stops at 1e-12 m / rad of pose error, so its solution is settled far below 1e-8
    "ik.q": Tolerance(1e-8, "rad"),
    "ik.error": Tolerance(1e-9, "m, rad"),
}


def _geodesic(old, new) -> float:
    return float(geodesic_distance(np.asarray(old, float)[None], np.asarray(new, float)[None])[0])


METRICS: dict[str, Callable[[Any, Any], float]] = {"fk.rotation": _geodesic}


def record_delta(prop: str, old, new) -> float:
    """Size of the change of one record's value: the property's metric, else the Euclidean
    (Frobenius) norm of the difference; ``inf`` when the shapes differ."""
    a, b = np.asarray(old, float), np.asarray(new, float)
    if a.shape != b.shape:
        return float("inf")
    if prop in METRICS:
        return METRICS[prop](a, b)
    return float(np.linalg.norm(a - b))


def prepare_fixed(spec: ArmSpec, q: np.ndarray) -> dict[str, Any]:
    """The save-time inputs of the quantities that have a ``prepare``."""
    return {qt.name: qt.prepare(spec, q) for qt in QUANTITIES if qt.prepare is not None}


def compute_records(spec: ArmSpec, q: np.ndarray, fixed: dict[str, Any] | None = None) -> list[Record]:
    """Every quantity's records at ``q``. ``fixed``: the baseline's save-time inputs (default: made
    now from ``spec``); a quantity with ``prepare`` whose input is not in ``fixed`` is skipped."""
    fixed = prepare_fixed(spec, q) if fixed is None else fixed
    out: list[Record] = []
    for quantity in QUANTITIES:
        if quantity.prepare is None:
            out += quantity.compute(spec, q)
        elif quantity.name in fixed:
            out += quantity.compute(spec, q, fixed[quantity.name])
    return out


def build_baseline(spec: ArmSpec, samples: int = DEFAULT_SAMPLES, seed: int = DEFAULT_SEED) -> dict[str, Any]:
    """The baseline data of ``spec``: samples, records, spec, fingerprints, versions."""
    if samples < 0:
        raise InputError(f"--samples must be >= 0, got {samples}")
    q = spec_samples(spec, samples, seed)
    fixed = prepare_fixed(spec, q)
    return {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "model": spec.name,
        "seed": seed,
        "samples": samples,
        "joint_names": list(spec.coordinate_names),  # the columns of q: a floating base's six first
        "frames": list(spec.frame_names),
        "spec": spec_to_canonical(spec),
        "fingerprints": fingerprints(spec),
        "versions": library_versions(),
        "quantities": [qt.name for qt in QUANTITIES],
        "q": q.tolist(),
        "fixed": fixed,
        "records": compute_records(spec, q, fixed),
    }


def fingerprints(spec: ArmSpec) -> dict[str, str]:
    return {"spec": spec_fingerprint(spec), "urdf": sha256_text(generate_urdf(spec)), "mjcf": sha256_text(generate_mjcf(spec))}


def dumps_baseline(data: dict[str, Any]) -> str:
    """Valid JSON, keys sorted, one configuration / record / quantity's fixed inputs per line, other
    values indented."""
    parts = []
    for key in sorted(data):
        value = data[key]
        if key in ("q", "records"):
            lines = ",\n".join("  " + json.dumps(v, sort_keys=True, allow_nan=False) for v in value)
            text = "[\n" + lines + "\n ]" if value else "[]"
        elif key == "fixed":  # one line per quantity's save-time inputs
            lines = ",\n".join(
                f"  {json.dumps(k)}: " + json.dumps(value[k], sort_keys=True, allow_nan=False) for k in sorted(value)
            )
            text = "{\n" + lines + "\n }" if value else "{}"
        else:
            text = json.dumps(value, sort_keys=True, indent=1, allow_nan=False).replace("\n", "\n ")
        parts.append(f" {json.dumps(key)}: {text}")
    return "{\n" + ",\n".join(parts) + "\n}\n"


def read_baseline(path, model: str | None = None, register: bool = True) -> dict[str, Any]:
    """Load and validate a baseline file; one-line :class:`InputError` when it is unreadable (read
    by :mod:`kinverify.io.read`: a regular file of at most ``MAX_DATA_BYTES``), corrupt or
    truncated, not a baseline, from a newer format, or (given ``model``) from another model.
    ``register``: record the file as an input of the run (False: a file about to be replaced)."""
    from kinverify.io.formats import json_loads
    from kinverify.io.read import InputFileError, read_bytes

    label = "--baseline" if register else "--out"
    try:
        text = read_bytes(path, label, MAX_DATA_BYTES, register=register).decode("utf-8")
    except InputFileError as err:
        raise InputError(f"{path}: cannot read baseline: {os.strerror(err.errno)}" if err.errno else str(err)) from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a kinverify baseline (not UTF-8 text)") from None
    try:
        data = json_loads(text, path, label, allow_nan=False)
    except json.JSONDecodeError as err:
        raise InputError(
            f"{path}: corrupt or truncated baseline JSON ({err.msg}: line {err.lineno} column {err.colno})"
        ) from None
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise InputError(f'{path}: not a kinverify baseline (no "format": "{FORMAT}")')
    version = data.get("format_version")
    if not isinstance(version, int) or isinstance(version, bool):
        raise InputError(f"{path}: malformed baseline: format_version must be an integer, got {version!r}")
    if version > FORMAT_VERSION:
        raise InputError(
            f"{path}: baseline format version {version} is newer than this kinverify reads ({FORMAT_VERSION}); upgrade kinverify"
        )
    _validate_schema(path, data, SCHEMA.get(version, SCHEMA[1]))
    if model is not None and data["model"] != model:
        raise InputError(f"{path}: baseline is for model {data['model']!r}, not {model!r}")
    _validate_body(path, data)
    return data


def _validate_schema(path, data: dict[str, Any], schema: dict[str, Any]) -> None:
    """Every section of ``schema`` present with its type; the save-time inputs (``fixed``) of
    every listed quantity that has them present."""
    missing = [k for k in schema if k not in data]
    if missing:
        raise InputError(f"{path}: malformed baseline: missing {', '.join(missing)}")
    for key, kind in schema.items():
        value = data[key]
        if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
            raise InputError(f"{path}: malformed baseline: {key} must be {_JSON_TYPES[kind]}, got {type(value).__name__}")
    if "quantities" in schema:
        listed = data["quantities"]
        if not all(isinstance(n, str) for n in listed):
            raise InputError(f"{path}: malformed baseline: quantities must be a list of names")
        for qt in QUANTITIES:
            if qt.prepare is not None and qt.name in listed and qt.name not in data["fixed"]:
                raise InputError(
                    f"{path}: malformed baseline: fixed.{qt.name} is missing (the {qt.name} inputs the "
                    "baseline was saved with); save the baseline again"
                )


_JSON_TYPES = {str: "a string", dict: "an object", list: "a list", int: "a whole number"}


def finite_numbers(value) -> bool:
    """Is ``value`` a finite number, or a (nested) list of them? Text, booleans and nulls are not."""
    stack = [value]
    while stack:
        item = stack.pop()
        if isinstance(item, list):
            stack.extend(item)
        elif isinstance(item, bool) or not isinstance(item, (int, float)) or not math.isfinite(item):
            return False
    return True


KINEMATICS = ("fk.position", "fk.rotation", "jacobian.linear", "jacobian.angular")  # kinematics_records, per frame and sample


def _validate_body(path, data: dict[str, Any]) -> None:
    for key in ("frames", "joint_names"):
        if not data[key] or not all(isinstance(name, str) for name in data[key]):
            raise InputError(f"{path}: malformed baseline: {key} must be a non-empty list of names")
    if not data["q"] or not all(isinstance(row, list) for row in data["q"]) or not finite_numbers(data["q"]):
        raise InputError(f"{path}: malformed baseline: q must be a non-empty table of finite numbers")
    q = np.asarray(data["q"], dtype=float) if len({len(row) for row in data["q"]}) == 1 else np.zeros((0, 0))
    if q.ndim != 2 or q.shape[1] != len(data["joint_names"]):
        raise InputError(f"{path}: malformed baseline: q must have one column per joint")
    fixed = data.get("fixed", {})
    if not isinstance(fixed, dict):
        raise InputError(f"{path}: malformed baseline: fixed must be an object")
    if "ik" in fixed:
        if not all(
            isinstance(t, dict) and finite_numbers(t.get("pose")) and finite_numbers(t.get("start"))
            for t in (fixed["ik"].get("targets") or [] if isinstance(fixed["ik"], dict) else [None])
        ):
            raise InputError(f"{path}: malformed baseline: fixed.ik targets must hold finite numbers")
        try:
            ik_parse(fixed["ik"], len(q))
        except InputError as err:
            raise InputError(f"{path}: {err}") from None
    if not isinstance(data["records"], list):
        raise InputError(f"{path}: malformed baseline: records must be a list")
    for i, rec in enumerate(data["records"]):
        if (
            not isinstance(rec, dict)
            or not {"property", "frame", "sample", "value"} <= rec.keys()
            or not isinstance(rec["sample"], int)
            or not 0 <= rec["sample"] < len(q)
        ):
            raise InputError(f"{path}: malformed baseline: records[{i}] is not a record of a stored sample")
        if not finite_numbers(rec["value"]) or not isinstance(rec["property"], str) or not isinstance(rec["frame"], str):
            raise InputError(f"{path}: malformed baseline: records[{i}].value is not a finite number or table of numbers")
    _complete(path, data, len(q))


def _complete(path, data: dict[str, Any], samples: int) -> None:
    """Every saved kinematics record is there (each property, frame and sample): a baseline whose
    records were removed would otherwise compare less, or nothing, and pass."""
    if "kinematics" not in data.get("quantities", ["kinematics"]):
        raise InputError(f"{path}: malformed baseline: quantities must list kinematics")
    have: dict[tuple[str, str], int] = {}
    for rec in data["records"]:
        if rec["property"] in KINEMATICS:
            have[(rec["property"], rec["frame"])] = have.get((rec["property"], rec["frame"]), 0) + 1
    for prop in KINEMATICS:
        for frame in data["frames"]:
            if have.get((prop, frame), 0) < samples:
                raise InputError(
                    f"{path}: malformed baseline: records of {prop} at {frame} are missing "
                    f"({have.get((prop, frame), 0)} of {samples} samples); save the baseline again"
                )


def save_baseline(spec: ArmSpec, path, samples: int = DEFAULT_SAMPLES, seed: int = DEFAULT_SEED) -> Path:
    """Write the baseline of ``spec`` to ``path`` atomically. An existing file is replaced only
    if it is a readable baseline of the same model (anything else: InputError, file untouched)."""
    if Path(path).exists():
        try:
            read_baseline(path, model=spec.name, register=False)
        except InputError as err:
            raise InputError(f"refusing to overwrite: {err}") from None
    return write_atomic(path, dumps_baseline(build_baseline(spec, samples, seed)))


def save(spec: ArmSpec, path, samples: int = DEFAULT_SAMPLES, seed: int = DEFAULT_SEED) -> Path:
    """Alias of :func:`save_baseline`."""
    return save_baseline(spec, path, samples, seed)
