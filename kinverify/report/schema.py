"""The JSON Schema of a results file (:meth:`kinverify.results.VerifyResult.to_dict`), checked
strictly when ``kinverify report`` reads one back.

Every field has its type, no field is unknown, and the verdict saved in the file must be the
verdict its checks and findings give: a results file edited (findings turned into strings or
dropped, a check's error set to null, the model name to null) is refused in one line naming the
field (exit 2) instead of being rendered, possibly as a PASS it was not.
"""

from __future__ import annotations

from typing import Any

from kinverify.results import SCHEMA_VERSION, VERDICTS
from kinverify.suites.base import AGREEMENT, EXPLAINED, PERFORMANCE, SEVERITIES

_STR = {"type": "string"}
_NUM = {"type": "number"}
_INT = {"type": "integer"}
_BOOL = {"type": "boolean"}
_STRS = {"type": "array", "items": _STR}
_NUMS = {"type": "array", "items": _NUM}


def _object(required: list[str], properties: dict[str, Any]) -> dict[str, Any]:
    return {"type": "object", "required": required, "properties": properties, "additionalProperties": False}


CHECK = _object(["property", "frame", "backends", "max_error", "p99_error", "tolerance", "passed", "worst_q"], {
    "property": _STR, "frame": _STR, "backends": {"type": "array", "items": _STR, "minItems": 2, "maxItems": 2},
    "max_error": _NUM, "p99_error": _NUM, "tolerance": _NUM, "passed": _BOOL, "worst_q": _NUMS, "unit": _STR,
    "samples": _INT, "histogram": {"type": "array", "items": _INT}, "note": _STR,
    "kind": {"enum": [AGREEMENT, PERFORMANCE, EXPLAINED]}, "gated": _BOOL})

FINDING = _object(["kind", "severity", "message"], {
    "kind": _STR, "severity": {"enum": list(SEVERITIES)}, "message": _STR, "subject": _STR, "subject_type": _STR,
    "other": _STR, "property": _STR, "values": {"type": "object"}, "magnitude": {"type": ["number", "null"]}, "unit": _STR,
    "accepted": _BOOL})

SECTION = _object(["title"], {
    "title": _STR, "summary": _STR,
    "tables": {"type": "array", "items": _object(["title", "columns", "rows"], {
        "title": _STR, "columns": {"type": "array"}, "rows": {"type": "array", "items": {"type": "array"}}})},
    "figures": {"type": "array", "items": _object(["mime", "data"], {"title": _STR, "mime": _STR, "data": _STR, "caption": _STR})},
    "notes": _STRS, "data": {"type": "object"}})

RESULTS = _object(["schema_version", "verdict", "model", "source", "seed", "samples", "joint_names", "frames", "backends",
                   "checks", "versions"], {
    "schema_version": {"type": "integer", "minimum": 1, "maximum": SCHEMA_VERSION}, "verdict": {"enum": list(VERDICTS)},
    "model": _STR, "source": _STR, "seed": {"type": "integer", "minimum": 0}, "samples": {"type": "integer", "minimum": 0},
    "joint_names": _STRS, "frames": _STRS, "backends": _STRS, "checks": {"type": "array", "items": CHECK},
    "versions": {"type": "object", "additionalProperties": {"type": ["string", "null"]}}, "command": _STR, "started": _STR,
    "duration_s": _NUM, "lower": {"type": "array", "items": {"type": ["number", "null"]}},
    "upper": {"type": "array", "items": {"type": ["number", "null"]}}, "notes": _STRS,
    "sections": {"type": "object", "additionalProperties": SECTION}, "model_info": {"type": "object"},
    "findings": {"type": "array", "items": FINDING}, "timings": {"type": "object", "additionalProperties": _NUM},
    "cpu_timings": {"type": "object", "additionalProperties": _NUM}, "internal_errors": _STRS})

_JSON_TYPES = {dict: "an object", list: "an array", str: "a string", bool: "a boolean", int: "a number", float: "a number",
               type(None): "null"}

_SCHEMA_TYPES = {"object": "an object", "array": "an array", "string": "a string", "number": "a number",
                 "integer": "a whole number", "boolean": "a boolean", "null": "null"}


def _field(error) -> str:
    path = "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in error.absolute_path)
    return path.lstrip(".") or "the top level"


def schema_problem(data: Any) -> str | None:
    """The first way ``data`` breaks :data:`RESULTS`, as ``field: what`` (None: it does not)."""
    import jsonschema

    error = jsonschema.exceptions.best_match(jsonschema.Draft202012Validator(RESULTS).iter_errors(data))
    if error is None:
        return None
    got = _JSON_TYPES.get(type(error.instance), type(error.instance).__name__)
    if error.validator == "type":
        wanted = error.validator_value if isinstance(error.validator_value, list) else [error.validator_value]
        return f"{_field(error)} must be {' or '.join(_SCHEMA_TYPES.get(w, w) for w in wanted)}, got {got}"
    if error.validator == "enum":
        value = repr(error.instance)
        return f"{_field(error)} must be one of {', '.join(map(repr, error.validator_value))}, got {value if len(value) <= 40 else got}"
    message = error.message if len(error.message) <= 200 else error.message[:197] + "..."
    return f"{_field(error)}: {message}"
