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
    """Read a saved result (by :mod:`kinverify.io.read`: a regular file of at most
    ``MAX_DATA_BYTES``) and validate it strictly (:mod:`kinverify.report.schema`); one-line
    :class:`InputError` naming the field when it is not a results file kinverify wrote."""
    from kinverify.io.formats import json_loads
    from kinverify.io.read import read_bytes
    from kinverify.pipeline.limits import MAX_DATA_BYTES
    from kinverify.report.schema import schema_problem

    data = read_bytes(path, "RESULTS", MAX_DATA_BYTES)
    try:
        data = json_loads(data.decode("utf-8"), path, "RESULTS")
    except (UnicodeDecodeError, json.JSONDecodeError) as err:
        raise InputError(f"{path}: not a kinverify results JSON ({err})") from None
    if not isinstance(data, dict) or "checks" not in data or "model" not in data:
        raise InputError(f"{path}: not a kinverify results JSON (no 'model'/'checks')")
    version = data.get("schema_version")
    if isinstance(version, int) and not isinstance(version, bool) and version > SCHEMA_VERSION:
        raise InputError(f"{path}: schema_version {version} is newer than this kinverify reads ({SCHEMA_VERSION})")
    problem = schema_problem(data)
    if problem is not None:
        raise InputError(f"{path}: not a valid kinverify results JSON: {problem}")
    try:
        result = VerifyResult.from_dict(data)
    except (TypeError, KeyError, ValueError) as err:
        raise InputError(f"{path}: malformed results JSON: {err}") from None
    if result.verdict != data["verdict"]:
        raise InputError(
            f"{path}: the saved verdict is {data['verdict']!r} but its checks and findings give "
            f"{result.verdict!r}: the file was changed after kinverify wrote it"
        )
    return result
