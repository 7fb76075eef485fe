"""Accepted differences: a small reviewed TOML file next to the models.

Each ``[[accepted]]`` entry names a finding by ``kind`` and ``subject`` (as the report shows
them) and records its ``magnitude`` (and ``unit``); ``reason`` says why it is accepted. A finding
that matches an entry, with a magnitude within tolerance of the recorded one, is accepted: shown
greyed, it no longer fails the verdict. A finding with no entry, or whose magnitude moved, fails
as before (the message says what it was accepted at). ``kinverify verify --write-accepted FILE``
writes every error finding of the run as entries, to review and keep beside the models::

    # kinverify accepted differences (reviewed)
    [[accepted]]
    kind = "damping_difference"
    subject = "panda_joint1, panda_joint2"
    magnitude = 0.997
    unit = "N·m·s/rad"
    reason = "the MJCF's damping is a simulation-stability value"
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from pathlib import Path

from kinverify.errors import InputError
from kinverify.io.formats import toml_loads
from kinverify.io.read import read_text
from kinverify.io.write import write_atomic
from kinverify.suites.base import Finding
from kinverify.text import toml_comment, toml_string

DEFAULT_NAME = "kinverify-accepted.toml"
RELATIVE = 1e-6  # a recorded magnitude still matches within this fraction (or the property's tolerance)


@dataclasses.dataclass(frozen=True)
class Entry:
    kind: str
    subject: str
    magnitude: float | None
    unit: str = ""
    reason: str = ""


def default_path(urdf_path: str) -> Path | None:
    """``kinverify-accepted.toml`` beside the URDF, when there is one (a FIFO or a folder of that
    name is there too: :func:`load` refuses it)."""
    p = Path(urdf_path).resolve().parent / DEFAULT_NAME
    return p if p.exists() else None


def load(path, label: str = "--accept") -> list[Entry]:
    """The entries of an accepted-differences file (read by :mod:`kinverify.io.read`, so it is an
    input no output may replace); :class:`InputError` naming what is wrong."""
    try:
        data = toml_loads(read_text(path, label), path, label)
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"{label}: {path} is not TOML: {err}") from None
    entries = data.get("accepted", [])
    if not isinstance(entries, list):
        raise InputError(f"{label}: {path}: 'accepted' must be an array of tables ([[accepted]])")
    out = []
    for i, e in enumerate(entries):
        if not isinstance(e, dict) or not isinstance(e.get("kind"), str) or not isinstance(e.get("subject", ""), str):
            raise InputError(f'{label}: {path}: accepted[{i}] needs kind = "..." and subject = "..."')
        magnitude = e.get("magnitude")
        if magnitude is not None and (
            not isinstance(magnitude, (int, float)) or isinstance(magnitude, bool) or math.isnan(magnitude)
        ):
            raise InputError(f"{label}: {path}: accepted[{i}].magnitude must be a number")
        out.append(
            Entry(
                e["kind"],
                e.get("subject", ""),
                None if magnitude is None else float(magnitude),
                str(e.get("unit", "")),
                str(e.get("reason", "")),
            )
        )
    return out


def _same(recorded: float | None, now: float | None, tol: float) -> bool:
    if recorded is None or now is None:
        return recorded is None and now is None
    if math.isinf(recorded) or math.isinf(now):
        return recorded == now
    return abs(recorded - now) <= max(tol, RELATIVE * abs(recorded))


def apply(findings: list[Finding], entries: list[Entry], tolerance_of) -> list[Finding]:
    """Findings with ``accepted`` set where an entry matches; ``tolerance_of(finding)``: how far
    its magnitude may move and still be the accepted difference."""
    out = []
    for f in findings:
        matches = [e for e in entries if e.kind == f.kind and e.subject == f.subject]
        if matches:
            e = matches[0]
            if _same(e.magnitude, f.magnitude, tolerance_of(f)):
                f = dataclasses.replace(f, accepted=True, values={**f.values, "accepted_reason": e.reason})
            else:
                f = dataclasses.replace(
                    f,
                    message=f"{f.message} (changed: accepted at {_size(e.magnitude, e.unit)}, now {_size(f.magnitude, f.unit)})",
                    values={**f.values, "accepted_magnitude": e.magnitude},
                )
        out.append(f)
    return out


def _size(magnitude: float | None, unit: str) -> str:
    return "no size" if magnitude is None else f"{magnitude:g} {unit}".rstrip()


def write(path, findings: list[Finding], source: str) -> Path:
    """Write the error findings as entries (to review: fill in each ``reason``)."""
    lines = [
        toml_comment(f"kinverify accepted differences for {source}"),
        "# Each entry accepts one finding (kind + subject) at its magnitude; review every one and say why.",
        "",
    ]
    for f in findings:
        if f.severity != "error":
            continue
        lines += ["[[accepted]]", f"kind = {toml_string(f.kind)}", f"subject = {toml_string(f.subject)}"]
        if f.magnitude is not None:
            lines.append(f"magnitude = {'inf' if math.isinf(f.magnitude) else repr(float(f.magnitude))}")
        if f.unit:
            lines.append(f"unit = {toml_string(f.unit)}")
        lines += [toml_comment(f.message), 'reason = ""', ""]

    return Path(write_atomic(path, "\n".join(lines)))
