"""The JSON form of a result (schema: :meth:`VerifyResult.to_dict`)."""

from __future__ import annotations

import json
from pathlib import Path

from kinverify.errors import InputError
from kinverify.results import SCHEMA_VERSION, VerifyResult
from kinverify.io.write import write_atomic


def result_json(result: VerifyResult) -> str:
    return json.dumps(result.to_dict(), indent=1, sort_keys=True, allow_nan=True) + "\n"


def write_json(result: VerifyResult, path) -> Path:
    return write_atomic(path, result_json(result))


def load_result_json(path) -> VerifyResult:
    """Read a saved result; one-line :class:`InputError` when it is not one."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as err:
        raise InputError(f"{path}: cannot read: {err.strerror or err}") from None
    except (UnicodeDecodeError, json.JSONDecodeError) as err:
        raise InputError(f"{path}: not a kinverify results JSON ({err})") from None
    if not isinstance(data, dict) or "checks" not in data or "model" not in data:
        raise InputError(f"{path}: not a kinverify results JSON (no 'model'/'checks')")
    if data.get("schema_version", 0) > SCHEMA_VERSION:
        raise InputError(f"{path}: schema_version {data['schema_version']} is newer than this kinverify reads ({SCHEMA_VERSION})")
    try:
        return VerifyResult.from_dict(data)
    except (TypeError, KeyError, ValueError) as err:
        raise InputError(f"{path}: malformed results JSON: {err}") from None
