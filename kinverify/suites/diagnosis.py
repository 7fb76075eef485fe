"""Diagnosis suite: for each backend that disagrees with the reference on FK, the worst
configurations and a short hint when the pattern is recognisable.

Patterns are tested on the run's own configurations (the edge configurations first), from the
poses both backends compute, in this order:

- ``joint-sign-flip``: the backend agrees with the reference once one joint's value is negated
  (that joint's axis, or its angle, has the opposite sign);
- ``mirror-axis``: the backend's positions are the reference's with one world coordinate negated;
- ``constant-offset``: the position difference is the same vector in the world, or in the
  frame's own axes (a link length or joint origin differs), or the rotation difference is the
  same rotation in the frame's axes (a joint zero or frame orientation differs);
- ``grows-with-joint``: the error rises with ``|q[k]|`` for exactly one joint ``k``.

The section stores plain JSON (the hints, worst configurations, per-pair summary) so
``kinverify report`` re-renders the page without the backends.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from kinverify.backends.base import pair_floor
from kinverify.model.transforms import geodesic_distance, rotation_log
from kinverify.suites.base import Section, Suite, SuiteResult, VerifyContext, tolerance

MAX_CONFIGS = 500  # configurations the diagnosis evaluates (edges first): bounded cost
N_WORST = 5
MATCH = 1e-6  # a pattern explains the error when its residual is below this fraction of the error


def _ranks(x: np.ndarray) -> np.ndarray:
    r = np.empty(len(x))
    r[np.argsort(x, kind="stable")] = np.arange(len(x))
    return r


def spearman(a: np.ndarray, b: np.ndarray) -> float:
    """Rank correlation of two samples (0 when either is constant)."""
    ra, rb = _ranks(a), _ranks(b)
    sa, sb = ra.std(), rb.std()
    if sa == 0 or sb == 0 or np.ptp(a) == 0 or np.ptp(b) == 0:
        return 0.0
    return float(((ra - ra.mean()) * (rb - rb.mean())).mean() / (sa * sb))


def _errors(ref_poses: np.ndarray, poses: np.ndarray, with_rotation: bool) -> tuple[np.ndarray, np.ndarray]:
    pos = np.linalg.norm(ref_poses[..., :3, 3] - poses[..., :3, 3], axis=-1)
    rot = geodesic_distance(ref_poses[..., :3, :3], poses[..., :3, :3]) if with_rotation else np.zeros_like(pos)
    return pos, rot


def _fmt(v) -> str:
    v = np.asarray(v, float)
    v = np.where(np.abs(v) < 1e-12 * max(np.abs(v).max(), 1e-300), 0.0, v)  # round-off to 0
    return "[" + ", ".join(f"{x:.6g}" for x in v + 0.0) + "]"


def find_hint(
    ref,
    other_poses: np.ndarray,
    q: np.ndarray,
    frame: int,
    frames,
    joint_names,
    with_rotation: bool,
    tol_pos: float,
    tol_rot: float,
) -> dict[str, Any] | None:
    """The first recognised pattern for the disagreement at ``frame`` (index), or None.

    ``ref`` is the reference backend (re-evaluated for the sign-flip test); ``other_poses`` are
    the other backend's poses ``(N, F, 4, 4)`` at ``q``."""
    ref_poses = ref.poses(q)
    pos, rot = _errors(ref_poses, other_poses, with_rotation)
    scale_p, scale_r = max(pos.max(), tol_pos), max(rot.max(), tol_rot)
    name = frames[frame]

    def explained(p, r) -> bool:
        return p.max() <= max(MATCH * scale_p, tol_pos) and r.max() <= max(MATCH * scale_r, tol_rot)

    for k, joint in enumerate(joint_names):  # one joint negated
        flipped = q.copy()
        flipped[:, k] *= -1
        if np.ptp(q[:, k]) == 0:
            continue
        if explained(*_errors(ref.poses(flipped), other_poses, with_rotation)):
            return {
                "kind": "joint-sign-flip",
                "joint": joint,
                "frame": name,
                "text": f"sign flip of joint {joint}: this backend agrees with the reference when q[{joint}] is "
                f"negated, so the joint's axis (or its angle) has the opposite sign in one model",
            }
    p_ref, p_oth = ref_poses[:, frame, :3, 3], other_poses[:, frame, :3, 3]
    for axis, label in enumerate("xyz"):  # one world coordinate mirrored
        mirrored = p_ref.copy()
        mirrored[:, axis] *= -1
        if np.ptp(p_ref[:, axis]) > 0 and np.linalg.norm(mirrored - p_oth, axis=-1).max() <= max(MATCH * scale_p, tol_pos):
            return {
                "kind": "mirror-axis",
                "axis": label,
                "frame": name,
                "text": f"sign flip on the world {label} axis: at frame {name} this backend's positions are the "
                f"reference's with {label} negated",
            }
    d = p_oth - p_ref

    def spread(v):
        return np.linalg.norm(v - v.mean(axis=0), axis=-1).max()

    tol_c = max(1e-3 * np.linalg.norm(d, axis=-1).max(), tol_pos)
    rot_ok = rot[:, frame].max() <= tol_rot
    if pos[:, frame].max() > tol_pos and spread(d) <= tol_c and rot_ok:
        return {
            "kind": "constant-offset",
            "frame": name,
            "offset": d.mean(axis=0).tolist(),
            "axes": "world",
            "text": f"constant offset at frame {name}: {_fmt(d.mean(axis=0))} m in world axes in every configuration",
        }
    for j in range(frame, -1, -1):  # the same vector in some frame's axes, nearest the error first
        d_local = np.einsum("nji,nj->ni", ref_poses[:, j, :3, :3], d)
        if pos[:, frame].max() > tol_pos and spread(d_local) <= tol_c and rot_ok:
            return {
                "kind": "constant-offset",
                "frame": name,
                "offset": d_local.mean(axis=0).tolist(),
                "axes": frames[j],
                "text": f"constant offset at frame {name}: {_fmt(d_local.mean(axis=0))} m in {frames[j]}'s axes in "
                f"every configuration (a link length or joint origin differs)",
            }
    r_ref = ref_poses[:, frame, :3, :3]
    if with_rotation and rot[:, frame].max() > tol_rot:
        rel = rotation_log(np.swapaxes(r_ref, -1, -2) @ other_poses[:, frame, :3, :3])  # (N, 3), frame axes
        if spread(rel) <= max(1e-3 * np.linalg.norm(rel, axis=-1).max(), tol_rot):
            w = rel.mean(axis=0)
            angle = float(np.linalg.norm(w))
            return {
                "kind": "constant-offset",
                "frame": name,
                "rotation": w.tolist(),
                "axes": "frame",
                "text": f"constant rotation offset at frame {name}: {angle:.6g} rad ({np.degrees(angle):.4g} deg) "
                f"about {_fmt(w / angle)} in the frame's own axes (a joint zero or frame orientation differs)",
            }
    err = np.maximum(pos[:, frame] / scale_p, rot[:, frame] / scale_r)
    corr = np.array([spearman(np.abs(q[:, k]), err) for k in range(q.shape[1])])
    runner_up = np.sort(corr)[-2] if len(corr) > 1 else 0.0
    if len(corr) and corr.max() >= 0.8 and runner_up < 0.4:
        k = int(np.argmax(corr))
        joint = joint_names[k]
        return {
            "kind": "grows-with-joint",
            "joint": joint,
            "frame": name,
            "correlation": float(corr[k]),
            "text": f"error at frame {name} grows with |q[{joint}]| (rank correlation {corr[k]:.2f}; other joints "
            f"below 0.4): look at joint {joint}'s scale, axis or limits",
        }
    return None


def diagnose_pair(ref, other, q: np.ndarray, frames, joint_names, tol_pos: float, tol_rot: float) -> dict[str, Any] | None:
    """Worst configurations and hint for one backend against the reference; None when they agree."""
    common = [f for f in other.frames if f in ref.frames]
    ri = [list(ref.frames).index(f) for f in common]
    oi = [list(other.frames).index(f) for f in common]
    other_poses = other.poses(q)[:, oi]

    class _Ref:  # the reference restricted to the frames the other backend reports
        poses = staticmethod(lambda qq: ref.poses(qq)[:, ri])

    pos, rot = _errors(_Ref.poses(q), other_poses, other.has_rotation)
    bad = (pos > tol_pos) | (rot > tol_rot)
    if not bad.any():
        return None
    first = int(np.argmax(bad.any(axis=0)))
    score = np.maximum(pos / tol_pos, rot / tol_rot).max(axis=1)
    worst: list[dict[str, Any]] = []
    for i in np.argsort(-score, kind="stable"):
        row = [round(float(v), 12) for v in q[i]]
        if row in [w["q"] for w in worst]:
            continue
        f = int(np.argmax(np.maximum(pos[i] / tol_pos, rot[i] / tol_rot)))
        worst.append({"q": row, "frame": common[f], "position_error": float(pos[i, f]), "rotation_error": float(rot[i, f])})
        if len(worst) == N_WORST:
            break
    hint = find_hint(_Ref, other_poses, q, first, common, joint_names, other.has_rotation, tol_pos, tol_rot)
    return {
        "backends": [ref.name, other.name],
        "first_frame": common[first],
        "worst": worst,
        "hint": hint,
        "configurations": int(len(q)),
    }


class DiagnosisSuite(Suite):
    """Diagnose every backend whose FK disagrees with the reference (no checks of its own)."""

    name = "diagnosis"
    title = "Diagnosis"
    report_only = True

    def run(self, ctx: VerifyContext) -> SuiteResult:
        return diagnosis(ctx)


def diagnosis(ctx: VerifyContext) -> SuiteResult:
    from kinverify.suites.kinematics import KinematicsSuite

    opts = ctx.options
    ref = ctx.backends[opts.reference]
    q = ctx.q[:MAX_CONFIGS]
    tol_pos = tolerance(opts, KinematicsSuite.property("fk.position"))
    tol_rot = tolerance(opts, KinematicsSuite.property("fk.rotation"))
    pairs = []
    for name, backend in ctx.backends.items():
        if name == opts.reference or len(q) == 0:
            continue
        found = diagnose_pair(
            ref,
            backend,
            q,
            ctx.sources.frames,
            list(ctx.sources.joint_names),
            max(tol_pos, pair_floor("fk.position", ref, backend)),
            max(tol_rot, pair_floor("fk.rotation", ref, backend)),
        )
        if found is not None:
            pairs.append(found)
    hints = [f"{' vs '.join(p['backends'])}: {p['hint']['text']}" for p in pairs if p["hint"]]
    summary = (
        f"{len(pairs)} backend(s) disagree with {opts.reference} on FK over the first {len(q)} configurations"
        if pairs
        else f"every backend agrees with {opts.reference} on FK over the first {len(q)} configurations"
    )
    return SuiteResult([], Section("Diagnosis", summary, notes=hints, data={"pairs": pairs}))
