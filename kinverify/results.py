"""The outcome of one ``kinverify verify`` run: everything a report shows, and nothing from a
backend library.

``VerifyResult.to_dict()`` is the JSON schema (``verdict``, ``versions``, ``checks``,
``findings``, ``sections``...); ``VerifyResult.from_dict()`` reads it back, so a saved JSON
re-renders the same report.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from kinverify.suites.base import EXPLAINED, PERFORMANCE, Check, Finding, Section, _plain

SCHEMA_VERSION = 3  # 3: ik.success_rate (which held the fraction NOT solved) is named ik.failure_rate
# Properties renamed since an earlier schema: a saved JSON that uses the old name still reads
# (same values, the new name); on the command line the old name is an error naming the new one.
RENAMED_PROPERTIES = {"ik.success_rate": "ik.failure_rate"}
VERDICTS = {"pass": 0, "fail": 1, "error": 3}  # verdict -> exit code (2 is bad input, before any result)


@dataclass
class VerifyResult:
    """The outcome of one ``kinverify verify`` run.

    ``verdict``: ``pass`` when every check that counts is within tolerance and no error finding
    stands; ``fail`` when the models disagree; ``error`` when kinverify itself failed
    (``internal_errors``), in which case what was computed is still here."""

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
    sections: dict[str, Section] = field(default_factory=dict)  # by suite name, in report order
    model_info: dict[str, Any] = field(default_factory=dict)  # joint table, masses, URDF/MJCF text
    findings: list[Finding] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)  # suite -> seconds
    cpu_timings: dict[str, float] = field(default_factory=dict)  # suite -> CPU seconds (this process + waited-for children)
    internal_errors: list[str] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return self.verdict == "pass"

    @property
    def verdict(self) -> str:
        if self.internal_errors:
            return "error"
        if any(c.decisive_failure for c in self.checks) or any(f.fails for f in self.findings):
            return "fail"
        return "pass"

    @property
    def exit_code(self) -> int:
        return VERDICTS[self.verdict]

    @property
    def failed(self) -> list[Check]:
        """Checks that decide the verdict and failed."""
        return [c for c in self.checks if c.decisive_failure]

    @property
    def missed_goals(self) -> list[Check]:
        """Performance checks below their goal that do not decide the verdict."""
        return [c for c in self.checks if not c.passed and not c.counts and c.kind == PERFORMANCE]

    @property
    def explained(self) -> list[Check]:
        """Failing checks whose cause a finding reports (the finding decides the verdict)."""
        return [c for c in self.checks if not c.passed and c.kind == EXPLAINED]

    @property
    def failing_findings(self) -> list[Finding]:
        return [f for f in self.findings if f.fails]

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
        d = {k: getattr(self, k) for k in self.__dataclass_fields__ if k not in ("checks", "sections", "findings")}
        d["schema_version"] = SCHEMA_VERSION
        d["verdict"] = self.verdict
        d["checks"] = [c.to_dict() for c in self.checks]
        d["findings"] = [f.to_dict() for f in self.findings]
        d["sections"] = {name: s.to_dict() for name, s in self.sections.items()}
        return _plain(d)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "VerifyResult":
        skip = ("checks", "sections", "findings")
        kwargs = {k: v for k, v in d.items() if k in cls.__dataclass_fields__ and k not in skip}
        return cls(
            checks=[Check.from_dict(_renamed(c)) for c in d.get("checks", [])],
            findings=[Finding.from_dict(f) for f in d.get("findings", []) if isinstance(f, dict)],
            sections={k: Section.from_dict(s) for k, s in (d.get("sections") or {}).items() if isinstance(s, dict)},
            **kwargs,
        )


def _renamed(check: dict[str, Any]) -> dict[str, Any]:
    """A saved check under its property's current name (:data:`RENAMED_PROPERTIES`)."""
    name = check.get("property") if isinstance(check, dict) else None
    return {**check, "property": RENAMED_PROPERTIES[name]} if name in RENAMED_PROPERTIES else check
