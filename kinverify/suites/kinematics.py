"""Suite ``kinematics``: FK and Jacobians of every backend against the reference, frame by
frame, and each analytic Jacobian against finite differences of its own backend's FK.

Chunks of configurations run through :func:`~kinverify.pipeline.parallel.run_chunks` (this
process, ``--jobs`` processes or Dask) and merge in chunk order: identical numbers either way.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from kinverify.backends.base import Backend
from kinverify.pipeline.parallel import run_chunks
from kinverify.pipeline.sampling import ChunkRanges
from kinverify.pipeline.stats import ErrorStats
from kinverify.suites.base import Property, Suite, SuiteResult, VerifyContext, VerifyOptions, floored, tolerance, within
from kinverify.suites.measures import finite_difference_errors, fk_errors, jacobian_errors


class Accumulator:
    """ErrorStats per (property, frame, backend pair)."""

    def __init__(self) -> None:
        self.stats: dict[tuple[str, str, tuple[str, str]], ErrorStats] = {}

    def add(self, errors: dict[tuple[str, str], np.ndarray], pair: tuple[str, str], q: np.ndarray) -> None:
        for (prop, frame), err in errors.items():
            self.stats.setdefault((prop, frame, pair), ErrorStats()).update(err, q)

    def merge(self, other: "Accumulator") -> None:
        for key, st in other.stats.items():
            if key in self.stats:
                self.stats[key].merge(st)
            else:
                self.stats[key] = st


# FK evaluations (2n + 1 per configuration) one backend's finite-difference checks may take: the
# checks cover opts.fd_samples configurations up to 7 joints and fewer beyond, so their cost does
# not grow with the chain's length
FD_EVALUATIONS = 3_000
SLOW_FD_EVALUATIONS = 300  # a slow backend's (yourdfpy: 20 configurations for 7 joints)


def capped_rows(backend: Backend, opts: VerifyOptions, start: int, n: int) -> slice:
    """Slow backends (``slow = True``, e.g. yourdfpy) see only the first ``opts.slow_samples`` rows."""
    if not backend.slow or opts.slow_samples is None:
        return slice(0, n)
    return slice(0, max(0, min(opts.slow_samples - start, n)))


def fd_samples(backend: Backend, opts: VerifyOptions) -> int:
    """Configurations (the first ones, edges first) where ``backend``'s finite differences are
    checked: ``opts.fd_samples``, or fewer when that would take more than the FK budget."""
    budget = SLOW_FD_EVALUATIONS if getattr(backend, "slow", False) else FD_EVALUATIONS
    return min(opts.fd_samples, max(1, budget // (2 * len(backend.joint_names) + 1)))


def _head(ev, k: int):
    return type(ev)(ev.backend, ev.frames, ev.poses[:k], None if ev.jacobians is None else ev.jacobians[:k])


def kinematics_chunk(backends: dict[str, Backend], opts: VerifyOptions, q: np.ndarray, start: int) -> Accumulator:
    """Errors of one chunk (rows ``start:start+len(q)`` of the samples): a pure function of its
    inputs, so chunks can run anywhere (see :mod:`kinverify.pipeline.parallel`)."""
    acc = Accumulator()
    fd_stop = {name: max(0, min(fd_samples(b, opts) - start, len(q))) for name, b in backends.items()}
    ref_eval = backends[opts.reference].evaluate(q)
    evaluations = {opts.reference: ref_eval}  # reused below for the finite-difference checks
    for name, backend in backends.items():
        if name == opts.reference:
            continue
        pair = (opts.reference, name)
        rows = capped_rows(backend, opts, start, len(q))
        if rows.stop == 0:
            continue
        ref = ref_eval if rows.stop == len(q) else _head(ref_eval, rows.stop)
        analytic_jac = backend.jacobian_method == "analytic"
        ev = evaluations[name] = backend.evaluate(q[rows], with_jacobians=analytic_jac)
        acc.add(fk_errors(ref, ev, backend.has_rotation), pair, q[rows])
        if analytic_jac:
            acc.add(jacobian_errors(ref, ev), pair, q[rows])
        elif backend.jacobian_method and min(fd_stop[name], rows.stop) > 0:
            fd = slice(0, min(fd_stop[name], rows.stop))
            acc.add(jacobian_errors(ref_eval, backend.evaluate(q[fd]), fd), pair, q[fd])
    for name, backend in backends.items():
        found = evaluations.get(name)
        if backend.jacobian_method == "analytic" and fd_stop[name] > 0 and found is not None:
            assert found.jacobians is not None  # evaluated with Jacobians
            fd = slice(0, min(fd_stop[name], len(found.poses)))
            acc.add(finite_difference_errors(backend, q[fd], found.jacobians[fd]), (name, "finite-difference"), q[fd])
    return acc


class KinematicsSuite(Suite):
    name = "kinematics"
    title = "Forward kinematics and Jacobians"
    properties = (
        Property("fk.position", "m", 1e-9, compares="distance between frame origins"),
        Property("fk.rotation", "rad", 1e-9, compares="geodesic angle of R_refᵀ R (atan2 form, accurate near 0)"),
        Property("jacobian.linear", "m/rad", 1e-9, compares="Frobenius norm of the 3×n difference of the linear rows"),
        Property("jacobian.angular", "rad/rad", 1e-9, compares="Frobenius norm of the 3×n difference of the angular rows"),
        # central differences (step 1e-6): truncation ~1e-12, round-off ~1e-10, so 1e-6 flags
        # only a wrong Jacobian, never numerical noise
        Property(
            "jacobian.fd", "norm", 1e-6, compares="a backend's Jacobian against central differences (step 1e-6) of its own FK"
        ),
    )

    def run(self, ctx: VerifyContext) -> SuiteResult:
        opts = ctx.options
        n = len(ctx.q)
        acc = Accumulator()
        for part in run_chunks(ctx, kinematics_chunk, ChunkRanges(n, opts.chunk)):
            acc.merge(part)
        fd_pairs, capped = {}, {}
        for name, backend in ctx.backends.items():
            pair = (opts.reference, name)
            n_fd = min(n, fd_samples(backend, opts))
            if name != opts.reference and backend.jacobian_method == "finite-difference" and n_fd > 0:
                fd_pairs[pair] = f"{name} Jacobian is finite-difference: compared at the FD tolerance on {n_fd} samples"
            rows = capped_rows(backend, opts, 0, n).stop
            if name != opts.reference and getattr(backend, "slow", False):
                capped[pair] = (
                    f"{name} is slow: compared on a fixed subset, the first {rows} of {n} configurations "
                    f"(at most --slow-samples {opts.slow_samples})"
                )
        order = [p.name for p in self.properties]
        rank = {f: i for i, f in enumerate(ctx.sources.frames)}
        checks = []
        for (prop, frame, pair), st in sorted(
            acc.stats.items(), key=lambda kv: (order.index(kv[0][0]), kv[0][2], rank.get(kv[0][1], 0))
        ):
            fd_note = fd_pairs.get(pair, "") if prop.startswith("jacobian.") and prop != "jacobian.fd" else ""
            note = "; ".join(x for x in (fd_note, capped.get(pair, "")) if x)
            check = self.check(ctx.options, prop, frame, pair, st, note)
            if fd_note:  # a finite-difference Jacobian is held to the finite-difference tolerance
                tol = tolerance(opts, self.property("jacobian.fd"))
                check = dataclasses.replace(check, tolerance=tol, passed=within(check.max_error, tol))
            checks.append(floored(check, [ctx.backends.get(n) for n in pair]))
        return SuiteResult(checks)
