"""The verify pipeline: sources -> backends -> samples -> suites -> :class:`VerifyResult`.

Suites are listed in :mod:`kinverify.suites.registry`; each gets the :class:`VerifyContext`
and returns checks, findings and a report section. A suite that raises an unexpected exception
is kinverify's own bug: it is recorded as an internal error (verdict ``error``), and the other
suites still run, so what was computed is still reported.
"""

from __future__ import annotations

import dataclasses
import time
import traceback
from datetime import datetime, timezone
from typing import Any, Callable

from kinverify.backends import ModelSources, build_backends
from kinverify import interrupts
from kinverify.errors import InputError, KinverifyError
from kinverify.model.spec import ArmSpec
from kinverify.pipeline.limits import MAX_CHUNK, MAX_SAMPLES, cap_jobs, check_count, check_seed, chunk_for
from kinverify.pipeline.parallel import check_executor_options
from kinverify.pipeline.sampling import Samples
from kinverify.results import VerifyResult
from kinverify.suites.base import SuiteResult, VerifyContext, VerifyOptions
from kinverify.suites.registry import SUITES
from kinverify.versions import library_versions

__all__ = ["VerifyContext", "VerifyOptions", "SuiteResult", "model_info", "verify", "verify_spec"]


def model_info(sources: ModelSources) -> dict[str, Any]:
    """Joint table, link masses and the model texts, for the report."""
    info: dict[str, Any] = {"urdf": sources.urdf or "", "mjcf": sources.mjcf or ""}
    info["joints"] = [
        {"name": n, "type": "revolute" if r else "prismatic", "lower": lo, "upper": up}
        for n, r, lo, up in zip(sources.joint_names, sources.revolute, sources.lower, sources.upper, strict=True)
    ]
    if sources.spec is not None:
        rows = info["joints"][len(info["joints"]) - len(sources.spec.joints) :]  # after a floating base's six coordinates
        for row, joint in zip(rows, sources.spec.joints, strict=True):
            row["axis"] = list(joint.axis)
        links = [sources.spec.base_link] + [j.link for j in sources.spec.joints]
        info["links"] = [{"name": link.name, "mass": link.inertial.mass, "com": list(link.inertial.com)} for link in links]
    return info


def internal_error(where: str, err: BaseException) -> str:
    """One line for an internal error: where, the exception, and the file:line that raised it."""
    tb = traceback.extract_tb(err.__traceback__)
    at = f" ({tb[-1].filename.rsplit('/', 1)[-1]}:{tb[-1].lineno})" if tb else ""
    return f"{where}: {type(err).__name__}: {err}{at}"


def verify(
    sources: ModelSources,
    options: VerifyOptions | None = None,
    extra_backends=(),
    source: str = "",
    command: str = "",
    progress: Callable[[str], None] | None = None,
) -> VerifyResult:
    """Run every registered suite on ``sources`` and return the results."""
    options = options or VerifyOptions()
    check_count(options.samples, "--samples", MAX_SAMPLES)
    check_seed(options.seed)
    check_count(options.chunk, "--chunk", MAX_CHUNK, minimum=1)
    check_executor_options(options)
    notes = []
    if options.executor == "local" or not options.scheduler:  # a remote scheduler has its own cores
        jobs, note = cap_jobs(options.jobs)
        if note:
            options, notes = dataclasses.replace(options, jobs=jobs), [note]
    started, t0 = datetime.now(timezone.utc), time.perf_counter()
    backends = {b.name: b for b in build_backends(sources, options.backends)}
    interrupts.check()
    for b in extra_backends:
        backends[b.name] = b
    if options.reference not in backends:
        if not options.backends or options.reference != VerifyOptions.reference:
            raise InputError(f"reference backend {options.reference!r} is not among {', '.join(backends)}")
        # --backends without the default reference: compare against the first one given
        options = dataclasses.replace(options, reference=next(iter(backends)))
        notes.append(f"reference backend: {options.reference} (the first of --backends; analytic was not selected)")
    chunk, note = chunk_for(options.chunk, len(sources.frames), len(sources.joint_names), len(backends))
    if note:
        options, notes = dataclasses.replace(options, chunk=chunk), notes + [note]
    q = Samples(sources.lower, sources.upper, sources.revolute, options.samples, options.seed)
    ctx = VerifyContext(sources, backends, q, options)
    checks, sections, findings, timings, cpu, internal = [], {}, [], {}, {}, []
    for suite_cls in SUITES:
        if options.suites is not None and suite_cls.name not in options.suites:
            continue
        interrupts.check()  # a signal a library swallowed (e.g. while importing it) stops the run here
        if progress:
            progress(suite_cls.name)
        t_suite, c_suite = time.perf_counter(), cpu_seconds()
        try:
            result = suite_cls().run(ctx)
        except (KinverifyError, KeyboardInterrupt):
            raise
        except Exception as err:  # our own bug: say so, keep what the other suites compute
            internal.append(internal_error(f"suite {suite_cls.name}", err))
            result = SuiteResult()
        timings[suite_cls.name] = time.perf_counter() - t_suite
        cpu[suite_cls.name] = cpu_seconds() - c_suite
        checks += result.checks
        findings += result.findings
        if result.section is not None:
            sections[suite_cls.name] = result.section
    return VerifyResult(
        model=sources.name,
        source=source,
        seed=options.seed,
        samples=len(q),
        joint_names=list(sources.joint_names),
        frames=list(sources.frames),
        backends=list(backends),
        checks=checks,
        versions=library_versions(),
        command=command,
        started=started.isoformat(timespec="seconds"),
        duration_s=time.perf_counter() - t0,
        lower=list(sources.lower),
        upper=list(sources.upper),
        sections=sections,
        model_info=model_info(sources),
        findings=findings,
        timings=timings,
        cpu_timings=cpu,
        internal_errors=internal,
        notes=notes,
    )


def cpu_seconds() -> float:
    """CPU time of this process and of its children that have been waited for (renderers, workers)."""
    import resource

    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


def verify_spec(spec: ArmSpec, options: VerifyOptions | None = None, **kwargs) -> VerifyResult:
    return verify(ModelSources.from_spec(spec), options, **kwargs)
