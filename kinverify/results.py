"""Result dataclasses: everything a report shows, and nothing from a backend library.

``VerifyResult.to_dict()`` is the JSON schema (``verdict``, ``versions``, ``checks``...);
``VerifyResult.from_dict()`` reads it back, so a saved JSON re-renders the same report.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

SCHEMA_VERSION = 1


@dataclass(frozen=True)
class Check:
    """One property compared for one frame between two backends (or a backend and its own
    finite differences). Errors are in ``unit``; ``worst_q`` is in radians/metres."""

    property: str
    frame: str
    backends: tuple[str, str]
    max_error: float
    p99_error: float
    tolerance: float
    passed: bool
    worst_q: tuple[float, ...]
    unit: str = ""
    samples: int = 0
    histogram: tuple[int, ...] = ()
    note: str = ""

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["backends"] = list(self.backends)
        d["worst_q"] = list(self.worst_q)
        d["histogram"] = list(self.histogram)
        return d

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Check":
        d = dict(d)
        d["backends"] = tuple(d["backends"])
        d["worst_q"] = tuple(d.get("worst_q") or ())
        d["histogram"] = tuple(d.get("histogram") or ())
        return cls(**{k: v for k, v in d.items() if k in cls.__dataclass_fields__})


@dataclass
class VerifyResult:
    """The outcome of one ``kinverify verify`` run."""

    model: str
    source: str
    seed: int
    samples: int
    joint_names: list[str]
    frames: list[str]
    backends: list[str]
    checks: list[Check]
    versions: dict[str, str]
    command: str = ""
    started: str = ""
    duration_s: float = 0.0
    lower: list[float] = field(default_factory=list)
    upper: list[float] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    # Extra report sections keyed by suite name (ik, tracking, ...). Each is plain JSON data:
    # {"title": str, "summary": str,
    #  "tables": [{"title": str, "columns": [str], "rows": [[...]]}],
    #  "figures": [{"title": str, "mime": "image/svg+xml"|"image/png"|"image/gif", "data": base64, "caption": str}],
    #  "notes": [str], ...any further keys a suite keeps for re-rendering}
    sections: dict[str, Any] = field(default_factory=dict)
    model_info: dict[str, Any] = field(default_factory=dict)  # joint table, masses, URDF/MJCF text
    # File mode: what differs between a URDF and an MJCF, [{"kind", "message", "joint"/"link"/"frame", "values"}]
    findings: list[dict[str, Any]] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks)

    @property
    def verdict(self) -> str:
        return "pass" if self.passed else "fail"

    @property
    def failed(self) -> list[Check]:
        return [c for c in self.checks if not c.passed]

    def first_failures(self) -> list[Check]:
        """Per failing (property, backend pair): the failing check on the earliest frame of the
        chain, i.e. where the disagreement starts."""
        order = {f: i for i, f in enumerate(self.frames)}
        first: dict[tuple, Check] = {}
        for c in self.failed:
            key = (c.property, c.backends)
            if key not in first or order.get(c.frame, 1 << 30) < order.get(first[key].frame, 1 << 30):
                first[key] = c
        return list(first.values())

    def to_dict(self) -> dict[str, Any]:
        d = {k: v for k, v in asdict(self).items() if k != "checks"}
        d["schema_version"] = SCHEMA_VERSION
        d["verdict"] = self.verdict
        d["checks"] = [c.to_dict() for c in self.checks]
        return _plain(d)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "VerifyResult":
        fields = {k: v for k, v in d.items() if k in cls.__dataclass_fields__ and k != "checks"}
        return cls(checks=[Check.from_dict(c) for c in d.get("checks", [])], **fields)


def _plain(value):
    """Numpy scalars/arrays to plain Python for JSON."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    return value
