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
from .parallel import run_chunks
from .sampling import Samples
from .spec import ArmSpec
from .stats import ErrorStats
from .versions import library_versions
from .diagnose import diagnosis_suite
from .pictures import pictures_suite
from .workspace import workspace_suite

REFERENCE = "analytic"


@dataclass
class VerifyOptions:
    """``samples`` uniform configurations (plus edge configurations) drawn with ``seed``;
    ``fd_samples``: how many of them (edges first) get finite-difference Jacobian checks."""

    samples: int = 1000
    seed: int = 0
    backends: list[str] | None = None
    reference: str = REFERENCE
    chunk: int = 2_000  # configurations per chunk: bounds memory; the unit of --jobs work
    fd_samples: int = 200
    tolerances: dict = field(default_factory=lambda: dict(DEFAULT_TOLERANCES))
    suites: list[str] | None = None  # None: every registered suite
    extra: dict[str, Any] = field(default_factory=dict)  # suite-specific options (e.g. ik_targets)
    # Performance and scale (issue 8): see kinverify.parallel.
    jobs: int = 1  # worker processes (or Dask workers of a LocalCluster)
    executor: str = "local"  # "local" or "dask"
    scheduler: str | None = None  # Dask scheduler address; None: a LocalCluster
    slow_samples: int | None = 100_000  # slow backends (yourdfpy) see only the first this many configurations
    on_progress: Callable[[int, int], None] | None = None  # (configurations done, total), not pickled


@dataclass
class VerifyContext:
    sources: ModelSources
    backends: dict[str, Backend]
    q: np.ndarray | Samples  # array-like: len, q[a:b], np.asarray(q); Samples generates rows on demand
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

    def merge(self, other: "_Accumulator") -> None:
        for key, st in other.stats.items():
            if key in self.stats:
                self.stats[key].merge(st)
            else:
                self.stats[key] = st

    def checks(self, frame_order: list[str], notes: dict[tuple[str, str], str],
               pair_notes: dict[tuple[str, str], str] | None = None) -> list[Check]:
        props = list(self.options.tolerances)
        rank = {f: i for i, f in enumerate(frame_order)}
        pair_notes = pair_notes or {}
        out = []
        for (prop, frame, pair), st in sorted(self.stats.items(), key=lambda kv: (props.index(kv[0][0]), kv[0][2], rank.get(kv[0][1], 0))):
            tol = self.options.tolerances[prop]
            limit = tol.value
            note = notes.get(pair, "") if prop in ("jacobian.linear", "jacobian.angular") else ""
            if note:
                limit = self.options.tolerances["jacobian.fd"].value
            note = "; ".join(n for n in (note, pair_notes.get(pair, "")) if n)
            out.append(Check(prop, frame, pair, st.max_error, st.percentile(99), limit, st.max_error <= limit,
                             tuple(st.worst_q.tolist()), tol.unit, st.count, tuple(st.histogram.tolist()), note))
        return out


def _kinematics_chunk(backends: dict[str, Backend], opts: VerifyOptions, q: np.ndarray, start: int) -> _Accumulator:
    """Errors of one chunk (rows ``start:start+len(q)`` of the samples): a pure function of its
    inputs, so chunks can run anywhere (see :mod:`kinverify.parallel`)."""
    acc = _Accumulator(opts)
    fd_rows = slice(0, max(0, min(opts.fd_samples - start, len(q))))
    ref_eval = backends[opts.reference].evaluate(q)
    evaluations = {opts.reference: ref_eval}  # reused below for the finite-difference checks
    for name, backend in backends.items():
        if name == opts.reference:
            continue
        pair = (opts.reference, name)
        rows = _capped_rows(backend, opts, start, len(q))
        if rows.stop == 0:
            continue
        ref = ref_eval if rows.stop == len(q) else _head(ref_eval, rows.stop)
        analytic_jac = backend.jacobian_method == "analytic"
        ev = evaluations[name] = backend.evaluate(q[rows], with_jacobians=analytic_jac)
        acc.add(fk_errors(ref, ev, backend.has_rotation), pair, q[rows])
        if analytic_jac:
            acc.add(jacobian_errors(ref, ev), pair, q[rows])
        elif backend.jacobian_method and min(fd_rows.stop, rows.stop) > 0:
            fd = slice(0, min(fd_rows.stop, rows.stop))
            acc.add(jacobian_errors(ref_eval, backend.evaluate(q[fd]), fd), pair, q[fd])
    for name, backend in backends.items():
        ev = evaluations.get(name)
        if backend.jacobian_method == "analytic" and fd_rows.stop > 0 and ev is not None:
            fd = slice(0, min(fd_rows.stop, len(ev.poses)))
            acc.add(finite_difference_errors(backend, q[fd], ev.jacobians[fd]), (name, "finite-difference"), q[fd])
    return acc


def _capped_rows(backend: Backend, opts: VerifyOptions, start: int, n: int) -> slice:
    """Slow backends (``slow = True``, e.g. yourdfpy) see only the first ``opts.slow_samples`` rows."""
    if not getattr(backend, "slow", False) or opts.slow_samples is None:
        return slice(0, n)
    return slice(0, max(0, min(opts.slow_samples - start, n)))


def _head(ev, k: int):
    return type(ev)(ev.backend, ev.frames, ev.poses[:k], None if ev.jacobians is None else ev.jacobians[:k])


def kinematics_suite(ctx: VerifyContext) -> SuiteResult:
    """FK and Jacobians of every backend against the reference, and each Jacobian against
    finite differences of its own backend's FK. Chunks run through :func:`run_chunks` (this
    process, ``--jobs`` processes or Dask) and merge in chunk order: identical numbers either way."""
    opts = ctx.options
    n, n_fd = len(ctx.q), min(opts.fd_samples, len(ctx.q))
    acc = _Accumulator(opts)
    for part in run_chunks(ctx, _kinematics_chunk, [(a, min(a + opts.chunk, n)) for a in range(0, n, opts.chunk)]):
        acc.merge(part)
    notes, pair_notes = {}, {}
    for name, backend in ctx.backends.items():
        pair = (opts.reference, name)
        if name != opts.reference and backend.jacobian_method == "finite-difference" and n_fd > 0:
            notes[pair] = f"{name} Jacobian is finite-difference: compared at the FD tolerance on {n_fd} samples"
        capped = _capped_rows(backend, opts, 0, n).stop
        if name != opts.reference and capped < n:
            pair_notes[pair] = f"{name} is slow: compared on the first {capped} of {n} configurations (--slow-samples)"
    return SuiteResult(acc.checks(list(ctx.sources.frames), notes, pair_notes))


def _dynamics_suite(ctx: VerifyContext) -> SuiteResult:
    from .checks.dynamics import dynamics_suite

    return dynamics_suite(ctx)


def _tracking_suite(ctx: VerifyContext) -> SuiteResult:
    from .tracking.suite import tracking_suite

    return tracking_suite(ctx)


SUITES: list[tuple[str, Callable[[VerifyContext], SuiteResult]]] = [
    ("kinematics", kinematics_suite),
    ("ik", ik_suite),
    ("dynamics", _dynamics_suite),
    ("tracking", _tracking_suite),
    ("diagnosis", diagnosis_suite),  # report: hints and worst configurations of failing checks
    ("workspace", workspace_suite),  # report: Monte-Carlo workspace
    ("pictures", pictures_suite),  # report: MuJoCo renderings
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
    q = Samples(sources.lower, sources.upper, sources.revolute, options.samples, options.seed)
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
