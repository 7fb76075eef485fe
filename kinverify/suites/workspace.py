"""Workspace suite: Monte-Carlo sampling of the last frame's position (as in the seed tutorial)
with reach statistics.

The points come from the analytic FK on the spec (:func:`kinverify.kinematics.frame_poses`), or
from the reference backend when there is no spec (file mode). They are stored rounded to 0.1 mm
in the section (``points``) so ``kinverify report`` re-draws the plots from the JSON.
"""

from __future__ import annotations

import numpy as np

from kinverify.model.floating import BASE_COORDINATES, has_base
from kinverify.suites.base import Section, Suite, SuiteResult, VerifyContext

N_POINTS = 3000


def sample_workspace(poses_fn, lower, upper, n: int, seed: int) -> np.ndarray:
    """``(n, 3)`` positions of the last frame at uniform configurations inside the limits."""
    rng = np.random.default_rng([seed, 0x5EED])  # independent of the verify samples' stream
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    q = lower + (upper - lower) * rng.random((n, len(lower)))
    return poses_fn(q)[:, -1, :3, 3]


def reach_statistics(points: np.ndarray, base: np.ndarray) -> dict[str, float]:
    """Reach of ``points`` ``(N, 3)`` measured from ``base`` (the first joint's origin) [m]."""
    rel = points - base
    dist = np.linalg.norm(rel, axis=1)
    horizontal = np.linalg.norm(rel[:, :2], axis=1)
    out = {"max_reach": dist.max(), "min_reach": dist.min(), "mean_reach": dist.mean(), "max_horizontal_reach": horizontal.max()}
    for i, axis in enumerate("xyz"):
        out[f"{axis}_min"], out[f"{axis}_max"] = points[:, i].min(), points[:, i].max()
    return {k: float(v) for k, v in out.items()}


def workspace_section(points: np.ndarray, base: np.ndarray, frame: str, source: str) -> Section:
    stats = reach_statistics(points, base)
    rows = [
        ["max reach from the first joint", stats["max_reach"]],
        ["min reach", stats["min_reach"]],
        ["mean reach", stats["mean_reach"]],
        ["max horizontal reach", stats["max_horizontal_reach"]],
    ]
    rows += [[f"{a} range", f"{stats[a + '_min']:.4f} … {stats[a + '_max']:.4f}"] for a in "xyz"]
    rows = [[k, f"{v:.4f}" if isinstance(v, float) else v] for k, v in rows]
    section = Section(
        "Workspace",
        f"{len(points)} uniform random configurations inside the joint limits; position of {frame} "
        f"from {source}, coloured by height. Reach measured from the first joint's origin "
        f"{np.round(base, 4).tolist()} m.",
        data={"frame": frame, "base": [float(v) for v in base], "stats": stats, "points": np.round(points, 4).tolist()},
    )
    section.table("Reach statistics [m]", ["statistic", "value [m]"], rows)
    return section


class WorkspaceSuite(Suite):
    """The workspace section and no checks."""

    name = "workspace"
    title = "Workspace"
    report_only = True

    def run(self, ctx: VerifyContext) -> SuiteResult:
        return workspace(ctx)


def workspace(ctx: VerifyContext) -> SuiteResult:
    from kinverify.model.kinematics import frame_poses, link_poses

    spec, src = ctx.sources.spec, ctx.sources
    # a floating base stays at its home pose: the workspace is the arm's reach from it
    held = len(BASE_COORDINATES) if has_base(src.joint_names) else 0
    home = np.zeros(len(src.joint_names)) if spec is None else spec.home()
    if spec is not None:
        fk, source = (lambda q: frame_poses(spec, q)), "the analytic FK"
        base = (link_poses(spec, home)[0, 0] @ spec.joints[0].origin.transform)[:3, 3]
    else:
        ref = ctx.backends[ctx.options.reference]
        fk, source = ref.poses, ref.name
        base = ref.poses(home[None])[0, 0, :3, 3]
    poses_fn = (lambda q: fk(np.concatenate([np.broadcast_to(home[:held], (len(q), held)), q], axis=1))) if held else fk
    points = sample_workspace(poses_fn, src.lower[held:], src.upper[held:], N_POINTS, ctx.options.seed)
    section = workspace_section(points, base, src.frames[-1], source)
    if held:
        section.summary += " The floating base is held at its home pose."
    return SuiteResult([], section)
