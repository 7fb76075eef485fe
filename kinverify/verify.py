"""The verify pipeline: sources -> backends -> samples -> checks -> :class:`VerifyResult`.

Property suites are registered in ``SUITES``: a suite takes the :class:`VerifyContext` and
returns checks plus an optional report section. Kinematics (FK + Jacobians) is built in; a new
property is one module and one line in ``SUITES``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from datetime import datetime, timezone
from typing import Any, Callable

import numpy as np

from .backends import Backend, ModelSources, build_backends
from .checks import DEFAULT_TOLERANCES
from .checks.fk import fk_errors
from .checks.jacobian import finite_difference_errors, jacobian_errors
from .errors import InputError
from .ik.suite import ik_suite
from .results import Check, VerifyResult
from .sampling import sample_configurations
from .spec import ArmSpec
from .stats import ErrorStats
from .versions import library_versions

REFERENCE = "analytic"


@dataclass
class VerifyOptions:
    """``samples`` uniform configurations (plus edge configurations) drawn with ``seed``;
    ``fd_samples``: how many of them (edges first) get finite-difference Jacobian checks."""

    samples: int = 1000
    seed: int = 0
    backends: list[str] | None = None
    reference: str = REFERENCE
    chunk: int = 10_000
    fd_samples: int = 200
    tolerances: dict = field(default_factory=lambda: dict(DEFAULT_TOLERANCES))
    suites: list[str] | None = None  # None: every registered suite
    extra: dict[str, Any] = field(default_factory=dict)  # suite-specific options (e.g. ik_targets)


@dataclass
class VerifyContext:
    sources: ModelSources
    backends: dict[str, Backend]
    q: np.ndarray
    options: VerifyOptions


@dataclass
class SuiteResult:
    checks: list[Check]
    section: dict[str, Any] | None = None


class _Accumulator:
    """ErrorStats per (property, frame, backend pair), turned into Checks at the end."""

    def __init__(self, options: VerifyOptions) -> None:
        self.options = options
        self.stats: dict[tuple[str, str, tuple[str, str]], ErrorStats] = {}

    def add(self, errors: dict[tuple[str, str], np.ndarray], pair: tuple[str, str], q: np.ndarray) -> None:
        for (prop, frame), err in errors.items():
            self.stats.setdefault((prop, frame, pair), ErrorStats()).update(err, q)

    def checks(self, frame_order: list[str], notes: dict[tuple[str, str], str]) -> list[Check]:
        props = list(self.options.tolerances)
        rank = {f: i for i, f in enumerate(frame_order)}
        out = []
        for (prop, frame, pair), st in sorted(self.stats.items(), key=lambda kv: (props.index(kv[0][0]), kv[0][2], rank.get(kv[0][1], 0))):
            tol = self.options.tolerances[prop]
            limit = tol.value
            note = notes.get(pair, "") if prop in ("jacobian.linear", "jacobian.angular") else ""
            if note:
                limit = self.options.tolerances["jacobian.fd"].value
            out.append(Check(prop, frame, pair, st.max_error, st.percentile(99), limit, st.max_error <= limit,
                             tuple(st.worst_q.tolist()), tol.unit, st.count, tuple(st.histogram.tolist()), note))
        return out


def kinematics_suite(ctx: VerifyContext) -> SuiteResult:
    """FK and Jacobians of every backend against the reference, and each Jacobian against
    finite differences of its own backend's FK."""
    opts = ctx.options
    ref = ctx.backends[opts.reference]
    acc = _Accumulator(opts)
    notes = {}
    n_fd = min(opts.fd_samples, len(ctx.q))
    for start in range(0, len(ctx.q), opts.chunk):
        q = ctx.q[start : start + opts.chunk]
        fd_rows = slice(0, max(0, min(n_fd - start, len(q))))
        ref_eval = ref.evaluate(q)
        for name, backend in ctx.backends.items():
            if name == opts.reference:
                continue
            pair = (opts.reference, name)
            analytic_jac = backend.jacobian_method == "analytic"
            ev = backend.evaluate(q, with_jacobians=analytic_jac)
            acc.add(fk_errors(ref_eval, ev, backend.has_rotation), pair, q)
            if analytic_jac:
                acc.add(jacobian_errors(ref_eval, ev), pair, q)
            elif backend.jacobian_method and fd_rows.stop > 0:
                notes[pair] = f"{name} Jacobian is finite-difference: compared at the FD tolerance on {n_fd} samples"
                fd_eval = backend.evaluate(q[fd_rows])
                acc.add(jacobian_errors(ref_eval, fd_eval, fd_rows), pair, q[fd_rows])
        for name, backend in ctx.backends.items():
            if backend.jacobian_method == "analytic" and fd_rows.stop > 0:
                jac = backend.jacobians(q[fd_rows])
                acc.add(finite_difference_errors(backend, q[fd_rows], jac), (name, "finite-difference"), q[fd_rows])
    return SuiteResult(acc.checks(list(ctx.sources.frames), notes))


SUITES: list[tuple[str, Callable[[VerifyContext], SuiteResult]]] = [
    ("kinematics", kinematics_suite),
    ("ik", ik_suite),
]


def model_info(sources: ModelSources) -> dict[str, Any]:
    """Joint table, link masses and the model texts, for the report."""
    info: dict[str, Any] = {"urdf": sources.urdf or "", "mjcf": sources.mjcf or ""}
    info["joints"] = [
        {"name": n, "type": "revolute" if r else "prismatic", "lower": lo, "upper": up}
        for n, r, lo, up in zip(sources.joint_names, sources.revolute, sources.lower, sources.upper)
    ]
    if sources.spec is not None:
        for row, joint in zip(info["joints"], sources.spec.joints):
            row["axis"] = list(joint.axis)
        links = [sources.spec.base_link] + [j.link for j in sources.spec.joints]
        info["links"] = [{"name": l.name, "mass": l.inertial.mass, "com": list(l.inertial.com)} for l in links]
    return info


def verify(sources: ModelSources, options: VerifyOptions | None = None, extra_backends=(), source: str = "",
           command: str = "", progress: Callable[[str], None] | None = None) -> VerifyResult:
    """Run every registered suite on ``sources`` and return the results."""
    options = options or VerifyOptions()
    if options.samples < 0:
        raise InputError(f"--samples must be >= 0, got {options.samples}")
    started, t0 = datetime.now(timezone.utc), time.perf_counter()
    backends = {b.name: b for b in build_backends(sources, options.backends)}
    for b in extra_backends:
        backends[b.name] = b
    if options.reference not in backends:
        raise InputError(f"reference backend {options.reference!r} is not among {', '.join(backends)}")
    q = sample_configurations(sources.lower, sources.upper, sources.revolute, options.samples, options.seed)
    ctx = VerifyContext(sources, backends, q, options)
    checks, sections = [], {}
    for name, suite in SUITES:
        if options.suites is not None and name not in options.suites:
            continue
        if progress:
            progress(name)
        result = suite(ctx)
        checks += result.checks
        if result.section is not None:
            sections[name] = result.section
    return VerifyResult(
        model=sources.name, source=source, seed=options.seed, samples=len(q), joint_names=list(sources.joint_names),
        frames=list(sources.frames), backends=list(backends), checks=checks, versions=library_versions(),
        command=command, started=started.isoformat(timespec="seconds"), duration_s=time.perf_counter() - t0,
        lower=list(sources.lower), upper=list(sources.upper), sections=sections, model_info=model_info(sources),
    )


def verify_spec(spec: ArmSpec, options: VerifyOptions | None = None, **kwargs) -> VerifyResult:
    return verify(ModelSources.from_spec(spec), options, **kwargs)
