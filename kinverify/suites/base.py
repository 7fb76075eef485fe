"""The suite contract: what a property suite declares, what it returns, and what it is given.

A suite (in the spirit of mink's ``Task``) is a class with a ``name``, a ``title``, the
:class:`Property` records it reports and ``run(context) -> SuiteResult``. Everything a suite
returns is a dataclass: :class:`Check` (one property measured for one subject between two
views), :class:`Finding` (a named difference with a severity) and :class:`Section` (what the
report shows). The report and the JSON read these dataclasses only; nothing here imports a
backend library.

Verdict semantics (:meth:`Check.counts`): *agreement* properties compare two views of the same
model and decide the verdict; *performance* properties measure a solver or controller against a
goal and are shown, not counted, unless the user gates them (``--gate``). A :class:`Finding` of
severity ``error`` fails the verdict unless it is accepted; warnings and infos never do.
"""

from __future__ import annotations

import builtins
import math
from abc import ABC, abstractmethod
from dataclasses import asdict, dataclass, field, fields, replace
from typing import TYPE_CHECKING, Any, Callable, ClassVar, Literal, cast

import numpy as np

if TYPE_CHECKING:  # only for annotations: suites never need the backends module at import time
    from kinverify.backends import Backend, ModelSources

AGREEMENT: Kind = "agreement"
PERFORMANCE: Kind = "performance"
EXPLAINED = "explained"  # a failing check whose cause a finding reports (file mode): shown, the finding counts
SEVERITIES = ("error", "warning", "info")
Kind = Literal["agreement", "performance"]
Severity = Literal["error", "warning", "info"]


@dataclass(frozen=True)
class Property:
    """One reported property: ``name`` (``suite.measure``), ``unit`` of its error, default
    ``tolerance`` (for a performance property: its goal), ``kind`` and one line saying what is
    compared. ``unit`` may be ``"joint"``: radians for revolute joints, metres for prismatic."""

    name: str
    unit: str
    tolerance: float
    kind: Kind = AGREEMENT
    compares: str = ""


@dataclass(frozen=True)
class Check:
    """One property compared for one subject (frame, joint, link...) between two views.

    Errors are in ``unit``; ``worst_q`` is the configuration of the largest error (rad / m).
    ``passed``: ``max_error <= tolerance``. ``kind`` and ``gated`` say whether it decides the
    verdict (:attr:`counts`)."""

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
    kind: str = AGREEMENT
    gated: bool = False

    @builtins.property  # the field ``property`` shadows the builtin in this class body
    def counts(self) -> bool:
        """Does this check decide the verdict? Agreement always; performance only when gated."""
        return self.kind == AGREEMENT or self.gated

    @builtins.property
    def decisive_failure(self) -> bool:
        return self.counts and not self.passed

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


def within(error: float, tolerance: float) -> bool:
    """The one pass rule of every check and finding threshold: an error equal to the tolerance
    passes; NaN never does."""
    return bool(error <= tolerance)


@dataclass(frozen=True)
class Finding:
    """A named difference: ``kind`` (e.g. ``mass_difference``), ``severity``, the ``subject`` it
    concerns (``subject_type`` joint, link, frame, model or file; ``other`` is its name in the
    second file when it differs), the ``property`` it bears on, both values, its ``magnitude`` in
    ``unit`` and a one-line ``message``. ``accepted``: listed in the user's accepted-differences
    file, so it no longer fails the verdict."""

    kind: str
    severity: Severity
    message: str
    subject: str = ""
    subject_type: str = "model"
    other: str = ""
    property: str = ""
    values: dict[str, Any] = field(default_factory=dict)
    magnitude: float | None = None
    unit: str = ""
    accepted: bool = False

    def __post_init__(self) -> None:
        if self.severity not in SEVERITIES:
            raise ValueError(f"severity must be one of {SEVERITIES}, got {self.severity!r}")

    @builtins.property  # the field 'property' shadows the builtin in this class body
    def fails(self) -> bool:
        return self.severity == "error" and not self.accepted

    @builtins.property
    def label(self) -> str:
        """``joint j1`` or ``link l2 / body2`` (the second name when the files differ)."""
        if not self.subject:
            return self.subject_type
        other = f" / {self.other}" if self.other and self.other != self.subject else ""
        return f"{self.subject_type} {self.subject}{other}"

    def to_dict(self) -> dict[str, Any]:
        return _plain(asdict(self))

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Finding":
        return cls(**{k: v for k, v in d.items() if k in cls.__dataclass_fields__})


@dataclass(frozen=True)
class Table:
    title: str
    columns: list[str]
    rows: list[list[Any]]


@dataclass(frozen=True)
class Figure:
    """An image for the report: ``data`` base64 of ``mime`` (SVG, PNG, GIF)."""

    title: str
    mime: str
    data: str
    caption: str = ""


@dataclass
class Section:
    """What a suite shows in the report: a title, a one-line summary, tables, figures and notes;
    ``data`` keeps whatever the suite needs to redraw its figures from the JSON alone."""

    title: str
    summary: str = ""
    tables: list[Table] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    data: dict[str, Any] = field(default_factory=dict)

    def table(self, title: str, columns, rows) -> None:
        self.tables.append(Table(title, list(columns), [list(r) for r in rows]))

    def to_dict(self) -> dict[str, Any]:
        return _plain(
            {
                "title": self.title,
                "summary": self.summary,
                "tables": [asdict(t) for t in self.tables],
                "figures": [asdict(f) for f in self.figures],
                "notes": list(self.notes),
                "data": self.data,
            }
        )

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Section":
        return cls(
            title=str(d.get("title", "")),
            summary=str(d.get("summary", "")),
            tables=[
                Table(str(t.get("title", "")), list(t.get("columns") or []), list(t.get("rows") or []))
                for t in d.get("tables") or []
                if isinstance(t, dict)
            ],
            figures=[
                Figure(**{k: f[k] for k in ("title", "mime", "data", "caption") if k in f})
                for f in d.get("figures") or []
                if isinstance(f, dict) and {"mime", "data"} <= set(f) and isinstance(f.get("data"), str)
            ],
            notes=[str(n) for n in d.get("notes") or []],
            data=dict(d.get("data") or {}),
        )


@dataclass
class SuiteResult:
    checks: list[Check] = field(default_factory=list)
    section: Section | None = None
    findings: list[Finding] = field(default_factory=list)


@dataclass
class VerifyOptions:
    """``samples`` uniform configurations (plus edge configurations) drawn with ``seed``;
    ``fd_samples``: how many of them (edges first) get finite-difference Jacobian checks (fewer
    for long chains and slow backends: see :func:`kinverify.suites.kinematics.fd_samples`).
    ``tolerances``: overrides by property name (values in the property's unit); ``gates``:
    performance properties that decide the verdict, with their goal (None: the default goal)."""

    samples: int = 1000
    seed: int = 0
    backends: list[str] | None = None
    reference: str = "analytic"
    chunk: int = 2_000  # configurations per chunk: bounds memory; the unit of --jobs work
    fd_samples: int = 200
    tolerances: dict[str, float] = field(default_factory=dict)
    gates: dict[str, float | None] = field(default_factory=dict)
    suites: list[str] | None = None  # None: every registered suite
    extra: dict[str, Any] = field(default_factory=dict)  # suite-specific options (e.g. ik_targets)
    jobs: int = 1  # worker processes (or Dask workers of a LocalCluster); see kinverify.pipeline.parallel
    executor: str = "local"  # "local" or "dask"
    scheduler: str | None = None  # Dask scheduler address; None: a LocalCluster
    slow_samples: int | None = 2_000  # slow backends (yourdfpy) see only the first this many configurations
    on_progress: Callable[[int, int], None] | None = None  # (done, total) of the running suite's work, not pickled


@dataclass
class VerifyContext:
    """What every suite is given: the model texts, the built backends, the sampled
    configurations (``q``: array-like, ``len``, ``q[a:b]``) and the options."""

    sources: "ModelSources"
    backends: dict[str, "Backend"]
    q: Any
    options: VerifyOptions


class Suite(ABC):
    """A property suite: ``name`` (for ``--skip``), ``title``, the properties it reports and
    ``run``. A suite with no properties only adds a report section (diagnosis, pictures)."""

    name: ClassVar[str]
    title: str  # a class attribute; a suite made per file may set its own
    properties: ClassVar[tuple[Property, ...]] = ()
    report_only: ClassVar[bool] = False  # only a report section (skipped by --no-report-suites)

    @abstractmethod
    def run(self, ctx: VerifyContext) -> SuiteResult:
        """Measure every property this suite reports on the context's model."""

    @classmethod
    def property(cls, name: str) -> Property:
        return next(p for p in cls.properties if p.name == name)

    @classmethod
    def check(
        cls,
        options: VerifyOptions | None,
        prop: str,
        subject: str,
        pair: tuple[str, str],
        stats,
        note: str = "",
        unit: str | None = None,
    ) -> Check:
        return stats_check(cls.property(prop), options, subject, pair, stats, note, unit)

    @classmethod
    def value_check(
        cls,
        options: VerifyOptions | None,
        prop: str,
        subject: str,
        pair: tuple[str, str],
        error: float,
        worst_q=(),
        note: str = "",
        unit: str | None = None,
        samples: int = 1,
    ) -> Check:
        return value_check(cls.property(prop), options, subject, pair, error, worst_q, note, unit, samples)


def stats_check(
    p: Property,
    options: VerifyOptions | None,
    subject: str,
    pair: tuple[str, str],
    stats,
    note: str = "",
    unit: str | None = None,
) -> Check:
    """A :class:`Check` of ``p`` from streamed :class:`~kinverify.pipeline.stats.ErrorStats`,
    with the tolerance, kind and gate the property has under ``options``."""
    tol = tolerance(options, p)
    worst = tuple(stats.worst_q.tolist()) if stats.worst_q is not None else ()
    return Check(
        p.name,
        subject,
        cast(tuple[str, str], tuple(pair)),
        stats.max_error,
        stats.percentile(99),
        tol,
        within(stats.max_error, tol),
        worst,
        unit or p.unit,
        stats.count,
        tuple(stats.histogram.tolist()),
        note,
        p.kind,
        gated(options, p),
    )


def value_check(
    p: Property,
    options: VerifyOptions | None,
    subject: str,
    pair: tuple[str, str],
    error: float,
    worst_q=(),
    note: str = "",
    unit: str | None = None,
    samples: int = 1,
) -> Check:
    """A :class:`Check` of ``p`` from one measured value (a parameter difference, a fraction)."""
    tol = tolerance(options, p)
    error = float(error)
    return Check(
        p.name,
        subject,
        cast(tuple[str, str], tuple(pair)),
        error,
        error,
        tol,
        within(error, tol),
        tuple(float(v) for v in worst_q),
        unit or p.unit,
        samples,
        (),
        note,
        p.kind,
        gated(options, p),
    )


def floored(check: Check, backends) -> Check:
    """``check`` held to the agreement floor of a backend of its pair whose library computes in
    lower precision (:attr:`~kinverify.backends.base.BackendBase.agreement_floor`), when above its tolerance."""
    floors = [(float(getattr(b, "agreement_floor", {}).get(check.property, 0.0)), b.name) for b in backends if b is not None]
    floor, name = max(floors, default=(0.0, ""))
    if floor <= check.tolerance:
        return check
    note = f"tolerance raised to {name}'s agreement floor ({floor:.2g}: its library computes in float32)"
    return replace(
        check, tolerance=floor, passed=within(check.max_error, floor), note="; ".join(x for x in (check.note, note) if x)
    )


def tolerance(options: VerifyOptions | None, prop: Property) -> float:
    """The tolerance (or goal) in effect: a ``--gate`` goal, a ``--tolerance`` override, or the default."""
    if options is not None:
        gate = options.gates.get(prop.name)
        if gate is not None:
            return float(gate)
        if prop.name in options.tolerances:
            return float(options.tolerances[prop.name])
    return prop.tolerance


def gated(options: VerifyOptions | None, prop: Property) -> bool:
    return prop.kind == PERFORMANCE and options is not None and prop.name in options.gates


def joint_unit(revolute) -> str:
    """Unit of a joint-space error: rad (all revolute), m (all prismatic) or ``rad|m`` (mixed,
    each joint in its own unit)."""
    revolute = list(revolute)
    if all(revolute):
        return "rad"
    if not any(revolute):
        return "m"
    return "rad|m"


def _plain(value):
    """Numpy scalars/arrays and dataclasses to plain Python for JSON."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    if hasattr(value, "__dataclass_fields__") and not isinstance(value, type):
        return _plain({f.name: getattr(value, f.name) for f in fields(value)})
    if isinstance(value, float) and math.isnan(value):
        return value
    return value
