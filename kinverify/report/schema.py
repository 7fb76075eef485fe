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


CHECK = _object(
    ["property", "frame", "backends", "max_error", "p99_error", "tolerance", "passed", "worst_q"],
    {
        "property": _STR,
        "frame": _STR,
        "backends": {"type": "array", "items": _STR, "minItems": 2, "maxItems": 2},
        "max_error": _NUM,
        "p99_error": _NUM,
        "tolerance": _NUM,
        "passed": _BOOL,
        "worst_q": _NUMS,
        "unit": _STR,
        "samples": _INT,
        "histogram": {"type": "array", "items": _INT},
        "note": _STR,
        "kind": {"enum": [AGREEMENT, PERFORMANCE, EXPLAINED]},
        "gated": _BOOL,
    },
)

FINDING = _object(
    ["kind", "severity", "message"],
    {
        "kind": _STR,
        "severity": {"enum": list(SEVERITIES)},
        "message": _STR,
        "subject": _STR,
        "subject_type": _STR,
        "other": _STR,
        "property": _STR,
        "values": {"type": "object"},
        "magnitude": {"type": ["number", "null"]},
        "unit": _STR,
        "accepted": _BOOL,
    },
)

_VECTOR = {"type": "array", "items": _NUM, "maxItems": 1024}
_POSE = {
    "type": ["array", "null"],
    "items": {"type": "array", "items": _NUM, "minItems": 4, "maxItems": 4},
    "minItems": 4,
    "maxItems": 4,
}
_NAMES = {"type": "array", "items": _STR, "maxItems": 4096}


def _section(data: dict[str, Any] | None = None) -> dict[str, Any]:
    """A section; ``data``: the schema of the parts of its ``data`` the report reads back (the rest
    is kept as it is)."""
    return _object(
        ["title"],
        {
            "title": _STR,
            "summary": _STR,
            "tables": {
                "type": "array",
                "items": _object(
                    ["title", "columns", "rows"],
                    {"title": _STR, "columns": {"type": "array"}, "rows": {"type": "array", "items": {"type": "array"}}},
                ),
            },
            "figures": {
                "type": "array",
                "items": _object(["mime", "data"], {"title": _STR, "mime": _STR, "data": _STR, "caption": _STR}),
            },
            "notes": _STRS,
            "data": {"type": "object", "properties": data or {}},
        },
    )


SECTION = _section()
# what the report draws from the saved data: the skeleton, the kinematic tree, the failures' values
PICTURES = _section(
    {
        "poses": {
            "type": "object",
            "additionalProperties": {
                "type": "object",
                "additionalProperties": {"type": "array", "items": _POSE, "maxItems": 4096},
            },
        },
        "frames": _NAMES,
        "parents": {"type": "array", "items": {"type": "integer"}, "maxItems": 4096},
        "reference": _STR,
        "other": _STR,
        "worst_label": _STR,
        "configurations": {"type": "object", "additionalProperties": _VECTOR},
        "tree": _object(
            ["links", "joints"],
            {
                "links": _NAMES,
                "joints": {
                    "type": "array",
                    "maxItems": 4096,
                    "items": _object(["name", "parent", "child"], {"name": _STR, "parent": _STR, "child": _STR, "type": _STR}),
                },
            },
        ),
        "disagreements": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["backend", "q", "frame", "reference", "value", "position_error", "rotation_error"],
                "properties": {
                    "backend": _STR,
                    "q": _VECTOR,
                    "frame": _STR,
                    "reference": {"type": "array"},
                    "value": {"type": "array"},
                    "position_error": _NUM,
                    "rotation_error": _NUM,
                },
            },
        },
    }
)
DIAGNOSIS = _section(
    {
        "pairs": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["backends"],
                "properties": {
                    "backends": {"type": "array", "items": _STR, "minItems": 2},
                    "worst": {
                        "type": "array",
                        "items": {
                            "type": "object",
                            "required": ["q", "frame", "position_error", "rotation_error"],
                            "properties": {"q": _VECTOR, "frame": _STR, "position_error": _NUM, "rotation_error": _NUM},
                        },
                    },
                    "hint": {"type": ["object", "null"], "properties": {"text": _STR, "joint": {"type": ["string", "null"]}}},
                },
            },
        }
    }
)
FILEMODE = _section({"alignment": {"type": ["object", "null"], "properties": {"T_mjcf_from_urdf": _POSE}}})
WORKSPACE = _section({"points": {"type": "array", "items": {"type": "array", "items": _NUM, "minItems": 3, "maxItems": 3}}})

_JOINT_INFO = {
    "type": "object",
    "required": ["name", "type", "lower", "upper"],
    "properties": {"name": _STR, "type": _STR, "lower": _NUM, "upper": _NUM, "axis": {"type": ["array", "null"], "items": _NUM}},
}
MODEL_INFO = {
    "type": "object",
    "properties": {
        "joints": {"type": "array", "items": _JOINT_INFO},
        "links": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["name", "mass"],
                "properties": {"name": _STR, "mass": _NUM, "com": {"type": ["array", "null"], "items": _NUM}},
            },
        },
        "urdf": {"type": ["string", "null"]},
        "mjcf": {"type": ["string", "null"]},
        "files": {"type": "object", "additionalProperties": _STR},
        "frame_pairs": {"type": "array", "items": {"type": "array", "items": _STR}},
        "joint_pairs": {"type": "array", "items": {"type": "array", "items": _STR}},
    },
}

RESULTS = _object(
    [
        "schema_version",
        "verdict",
        "model",
        "source",
        "seed",
        "samples",
        "joint_names",
        "frames",
        "backends",
        "checks",
        "versions",
    ],
    {
        "schema_version": {"type": "integer", "minimum": 1, "maximum": SCHEMA_VERSION},
        "verdict": {"enum": list(VERDICTS)},
        "model": _STR,
        "source": _STR,
        "seed": {"type": "integer", "minimum": 0},
        "samples": {"type": "integer", "minimum": 0},
        "joint_names": _STRS,
        "frames": _STRS,
        "backends": _STRS,
        "checks": {"type": "array", "items": CHECK},
        "versions": {"type": "object", "additionalProperties": {"type": ["string", "null"]}},
        "command": _STR,
        "started": _STR,
        "duration_s": _NUM,
        "lower": _NUMS,
        "upper": _NUMS,
        "notes": _STRS,
        "sections": {
            "type": "object",
            "properties": {"pictures": PICTURES, "diagnosis": DIAGNOSIS, "filemode": FILEMODE, "workspace": WORKSPACE},
            "additionalProperties": SECTION,
        },
        "model_info": MODEL_INFO,
        "findings": {"type": "array", "items": FINDING},
        "timings": {"type": "object", "additionalProperties": _NUM},
        "cpu_timings": {"type": "object", "additionalProperties": _NUM},
        "internal_errors": _STRS,
    },
)

_JSON_TYPES = {
    dict: "an object",
    list: "an array",
    str: "a string",
    bool: "a boolean",
    int: "a number",
    float: "a number",
    type(None): "null",
}

_SCHEMA_TYPES = {
    "object": "an object",
    "array": "an array",
    "string": "a string",
    "number": "a number",
    "integer": "a whole number",
    "boolean": "a boolean",
    "null": "null",
}


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
        wanted: list[str] = error.validator_value if isinstance(error.validator_value, list) else [error.validator_value]
        return f"{_field(error)} must be {' or '.join(_SCHEMA_TYPES.get(w, w) for w in wanted)}, got {got}"
    if error.validator == "enum":
        value = repr(error.instance)
        return f"{_field(error)} must be one of {', '.join(map(repr, error.validator_value))}, got {value if len(value) <= 40 else got}"
    message = error.message if len(error.message) <= 200 else error.message[:197] + "..."
    return f"{_field(error)}: {message}"
