"""Assertion helpers for a user's own pytest suite (also used by kinverify's).

Each helper takes a *model*: an :class:`~kinverify.spec.ArmSpec` (every available backend is
built from it, cached), a :class:`~kinverify.backends.ModelSources` (e.g. a URDF/MJCF pair), or a
list of already-built backends (the first is the reference). A failure raises ``AssertionError``
whose message names the property, the frame (the first disagreeing one along the chain), the
backends, the error, the tolerance and the failing configuration as a line ready to paste::

    kinverify: fk.position disagrees at frame 'link2' (first along the chain): analytic vs mujoco
      error 1.000e-03 m > tolerance 1e-09 m
      failing configuration (joint1, joint2, joint3), paste to reproduce:
        q = [0.0, 1.5707963267948966, 0.0]
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import Sequence

import numpy as np

from kinverify.backends import Backend, ModelSources, build_backends
from kinverify.backends.base import pair_floor
from kinverify.filemode.pipeline import verify_files
from kinverify.run import VerifyOptions
from kinverify.suites.measures import fk_errors
from kinverify.suites.measures import jacobian_errors
from kinverify.suites.kinematics import KinematicsSuite
from kinverify.model.spec import ArmSpec
from kinverify.model.transforms import geodesic_distance

FD_TOLERANCE = KinematicsSuite.property("jacobian.fd").tolerance
FILE_SUITES = ("kinematics", "limits", "inertia", "dynamics")  # file mode without its drawings


@lru_cache(maxsize=32)
def _cached_backends(sources: ModelSources, names: tuple[str, ...] | None) -> tuple[Backend, ...]:
    return tuple(build_backends(sources, list(names) if names else None))


def resolve_backends(model, backends: Sequence[str] | None = None) -> list[Backend]:
    """Backends for ``model`` (spec, sources or list of backends), reference first; built once
    per model and cached."""
    names = tuple(backends) if backends else None
    if isinstance(model, ArmSpec):
        return list(_cached_backends(_sources(model), names))
    if isinstance(model, ModelSources):
        return list(_cached_backends(model, names))
    built = list(model)
    if not built or not all(isinstance(b, Backend) for b in built):
        raise TypeError("model must be an ArmSpec, a ModelSources or a non-empty list of backends")
    return [b for b in built if names is None or b.name in names]


@lru_cache(maxsize=32)
def _sources(spec: ArmSpec) -> ModelSources:
    return ModelSources.from_spec(spec)


def format_q(q, joint_names: Sequence[str]) -> str:
    """The configuration as two lines: joint names, then ``q = [...]`` at full precision."""
    values = ", ".join(repr(float(v)) for v in np.asarray(q, float).ravel())
    return f"  failing configuration ({', '.join(joint_names)}), paste to reproduce:\n    q = [{values}]"


def _failure(
    prop: str, frame: str, pair: str, error: float, tol: float, unit: str, q, joint_names, others: list[str], detail: str = ""
) -> AssertionError:
    lines = [
        f"kinverify: {prop} disagrees at frame {frame!r} (first along the chain): {pair}",
        f"  error {error:.3e} {unit} > tolerance {tol:.0e} {unit}{detail}",
        format_q(q, joint_names),
    ]
    if others:
        lines.append(f"  also failing: {'; '.join(others[:8])}" + (f" (+{len(others) - 8} more)" if len(others) > 8 else ""))
    return AssertionError("\n".join(lines))


def _raise_first(errors: list[tuple], frames: Sequence[str], q: np.ndarray, joint_names) -> None:
    """``errors``: (prop, frame, pair, err array, tol, unit, detail). Raise for the earliest frame."""
    __tracebackhide__ = True
    bad = [e for e in errors if not np.all(e[3] <= e[4])]
    if not bad:
        return
    rank = {f: i for i, f in enumerate(frames)}
    bad.sort(key=lambda e: (rank.get(e[1], len(rank)), e[0]))
    prop, frame, pair, err, tol, unit, detail = bad[0]
    worst = int(np.nanargmax(np.where(np.isnan(err), np.inf, err)))
    others = [f"{p} at {f!r} ({pr})" for p, f, pr, *_ in bad[1:]]
    raise _failure(prop, frame, pair, float(err[worst]), tol, unit, q[worst], joint_names, others, detail)


def _q2d(q, n: int) -> np.ndarray:
    q = np.atleast_2d(np.asarray(q, dtype=float))
    if q.ndim != 2 or q.shape[1] != n:
        raise ValueError(f"expected q of shape (n,) or (N, n) with n = {n}, got {np.shape(q)}")
    return q


def assert_fk_agree(
    model, q, *, backends: Sequence[str] | None = None, position_tol: float = 1e-9, rotation_tol: float = 1e-9
) -> None:
    """Every backend's FK of every frame matches the reference's at ``q`` ((n,) or (N, n))."""
    __tracebackhide__ = True  # pytest shows the caller's line, not this helper's
    built = resolve_backends(model, backends)
    ref = built[0]
    q = _q2d(q, len(ref.joint_names))
    ref_eval = ref.evaluate(q, with_jacobians=False)
    errors = []
    for b in built[1:]:
        errs = fk_errors(ref_eval, b.evaluate(q, with_jacobians=False), b.has_rotation)
        for (prop, frame), err in errs.items():
            tol = max(position_tol if prop == "fk.position" else rotation_tol, pair_floor(prop, b))  # its floor (float32)
            errors.append((prop, frame, f"{ref.name} vs {b.name}", err, tol, "m" if prop == "fk.position" else "rad", ""))
    _raise_first(errors, ref.frames, q, ref.joint_names)


def assert_jacobians_agree(model, q, *, backends: Sequence[str] | None = None, tol: float = 1e-9) -> None:
    """Every backend's Jacobian of every frame (world-aligned, at the frame origin, [linear;
    angular]) matches the reference's. Finite-difference Jacobians (yourdfpy) are held to the
    finite-difference tolerance 1e-6; backends without Jacobians are skipped."""
    __tracebackhide__ = True  # pytest shows the caller's line, not this helper's
    built = resolve_backends(model, backends)
    ref = built[0]
    q = _q2d(q, len(ref.joint_names))
    ref_eval = ref.evaluate(q)
    errors = []
    for b in built[1:]:
        if not b.jacobian_method:
            continue
        fd = b.jacobian_method != "analytic"
        limit, detail = (FD_TOLERANCE, f" ({b.name} Jacobian is finite-difference)") if fd else (tol, "")
        for (prop, frame), err in jacobian_errors(ref_eval, b.evaluate(q)).items():
            unit = "m/rad" if prop == "jacobian.linear" else "rad/rad"
            errors.append((prop, frame, f"{ref.name} vs {b.name}", err, max(limit, pair_floor(prop, b)), unit, detail))
    _raise_first(errors, ref.frames, q, ref.joint_names)


def assert_ik_valid(
    model,
    q,
    target,
    frame: str | None = None,
    *,
    backends: Sequence[str] | None = None,
    position_tol: float = 1e-6,
    rotation_tol: float = 1e-6,
    check_limits: bool = True,
) -> None:
    """An IK solution ``q`` (n,) reaches ``target`` (a 4×4 pose ``T_world_from_frame`` or a
    position (3,)) for ``frame`` (default: the last frame) in *every* backend (each to the larger
    of the tolerance and its own agreement floor), inside the joint limits."""
    __tracebackhide__ = True  # pytest shows the caller's line, not this helper's
    built = resolve_backends(model, backends)
    ref = built[0]
    q = _q2d(q, len(ref.joint_names))
    if len(q) != 1:
        raise ValueError("assert_ik_valid checks one solution q of shape (n,)")
    frame = frame or ref.frames[-1]
    target = np.asarray(target, dtype=float)
    if target.shape not in ((4, 4), (3,)):
        raise ValueError(f"target must be a 4x4 pose or a position (3,), got shape {target.shape}")
    goal_p = target[:3, 3] if target.shape == (4, 4) else target
    lower, upper = _limits(model)
    if check_limits and lower is not None:
        outside = (q[0] < lower - 1e-12) | (q[0] > upper + 1e-12)
        if outside.any():
            j = int(np.argmax(outside))
            raise AssertionError(
                f"kinverify: ik.limits: joint {ref.joint_names[j]!r} at {float(q[0, j])!r} is outside "
                f"[{float(lower[j])!r}, {float(upper[j])!r}]\n" + format_q(q[0], ref.joint_names)
            )
    target_text = np.array2string(target, precision=17, separator=", ").replace("\n", "")
    for b in built:
        if frame not in b.frames:
            continue
        pose = b.poses(q)[0, list(b.frames).index(frame)]
        # a backend computing in lower precision (float32) reaches the target only to its own floor
        tol_p, tol_r = max(position_tol, pair_floor("fk.position", b)), max(rotation_tol, pair_floor("fk.rotation", b))
        checks = [("ik.position", float(np.linalg.norm(pose[:3, 3] - goal_p)), tol_p, "m")]
        if target.shape == (4, 4) and b.has_rotation:
            checks.append(("ik.rotation", float(geodesic_distance(pose[None, :3, :3], target[None, :3, :3])[0]), tol_r, "rad"))
        for prop, err, tol, unit in checks:
            if not err <= tol:
                raise AssertionError(
                    f"kinverify: {prop}: frame {frame!r} misses the target in backend {b.name}\n"
                    f"  error {err:.3e} {unit} > tolerance {tol:.0e} {unit}\n"
                    f"  target = {target_text}\n" + format_q(q[0], ref.joint_names)
                )


def _limits(model):
    if isinstance(model, (ArmSpec, ModelSources)):
        return np.asarray(model.lower, float), np.asarray(model.upper, float)
    return None, None


def assert_matches_baseline(spec: ArmSpec, path, *, update: bool = False, tolerance: float | None = None):
    """``spec`` computes what the baseline at ``path`` recorded (FK and Jacobians at its sample
    set, dynamics quantities and fixed IK targets: see :data:`kinverify.baseline.QUANTITIES`). ``update=True`` rewrites the baseline instead (pytest ``--kinverify-update-baselines``).
    Returns the :class:`~kinverify.baseline_check.BaselineCheck`, or None after an update."""
    __tracebackhide__ = True  # pytest shows the caller's line, not this helper's
    from kinverify.regression.baseline import BASELINE_TOLERANCES, Tolerance, save_baseline
    from kinverify.regression.check import check
    from kinverify.report.regression import show_values

    path = Path(path)
    if update:
        save_baseline(spec, path)
        return None
    if not path.exists():
        raise AssertionError(
            f"kinverify: no baseline for {spec.name!r} at {path}; create it deliberately with "
            f"`pytest --kinverify-update-baselines` (or `kinverify baseline save MODEL --out {path}`)"
        )
    tolerances = None if tolerance is None else {k: Tolerance(tolerance, t.unit) for k, t in BASELINE_TOLERANCES.items()}
    result = check(spec, path, tolerances)
    if result.passed:
        return result
    lines = [f"kinverify: {spec.name} does not match baseline {path}: {len(result.moved)} quantities moved beyond tolerance"]
    for m in result.moved[:10]:
        old, new = show_values(m.old, m.new)
        lines.append(
            f"  {m.property} at frame {m.frame!r}: old {old} new {new}, delta {m.delta:.3e} {m.unit} "
            f"> tolerance {m.tolerance:.0e} {m.unit} ({m.count}/{m.of} samples)"
        )
    if len(result.moved) > 10:
        lines.append(f"  ... and {len(result.moved) - 10} more")
    for frames, what in ((result.frames_removed, "removed"), (result.frames_added, "added")):
        if frames:
            lines.append(f"  frames {what}: {', '.join(frames)}")
    if result.moved:
        lines.append(format_q(result.moved[0].q, spec.joint_names))
    lines += [f"  why: {e}" for e in result.explanations]
    lines.append("  if the change is intended, rewrite the baseline: pytest --kinverify-update-baselines")
    raise AssertionError("\n".join(lines))


def assert_files_agree(urdf, mjcf, *, accept=None, backends: Sequence[str] | None = None, samples: int = 50, seed: int = 0):
    """File mode's verdict on a URDF/MJCF pair (``kinverify verify --urdf URDF --mjcf MJCF``) as an
    assertion: the failure message lists every error finding (kind, subject, size, message).
    ``accept``: an accepted-differences TOML file (default: ``kinverify-accepted.toml`` beside the
    URDF, when there is one); ``backends``: the libraries that read the files (default: every one
    installed); ``samples``: configurations the suites check. Returns the
    :class:`~kinverify.results.VerifyResult` when the files agree; a file that cannot be read
    raises :class:`~kinverify.errors.InputError` as the command exits 2."""
    __tracebackhide__ = True  # pytest shows the caller's line, not this helper's
    options = VerifyOptions(
        samples=samples,
        fd_samples=min(samples, 10),
        seed=seed,
        backends=list(backends) if backends else None,
        suites=list(FILE_SUITES),
        extra={"dynamics_samples": min(samples, 20)},
    )
    result = verify_files(str(urdf), str(mjcf), options, accept=str(accept) if accept else None)
    if result.passed:
        return result
    lines = [f"kinverify: {urdf} and {mjcf} disagree ({result.verdict})"]
    if result.internal_errors:
        lines += [f"  kinverify's own error: {e}" for e in result.internal_errors]
    failing = result.failing_findings
    lines.append(f"  {len(failing)} error finding{'s' * (len(failing) != 1)}:")
    for f in failing:
        size = "" if f.magnitude is None else f" ({f.magnitude:.6g} {f.unit})".replace(" )", ")")
        lines.append(f"    {f.kind} {f.subject}{size}: {f.message}")
    if not failing and result.failed:
        lines += [f"    check {c.property} at {c.frame!r} ({' vs '.join(c.backends)}) failed" for c in result.first_failures()]
    lines.append("  accept a reviewed difference in kinverify-accepted.toml (kinverify verify --write-accepted FILE)")
    raise AssertionError("\n".join(lines))
