"""The arm drawn as a skeleton from FK alone (no meshes needed): frame origins joined along the
kinematic tree, short RGB frame triads (x red, y green, z blue), at the home pose and at the worst
configuration. The reference backend is drawn solid; the backend that disagrees with it (in file
mode, the MJCF side) ghosted over it. With a file-mode alignment ``T_mjcf_from_urdf`` that is not
the identity, the MJCF side is also drawn mapped back through it ("bases aligned"), so a turned or
shifted base shows in the first panel and an offset link in the others.

Drawn with matplotlib from the pictures section's data only; returns SVG text (text as paths).
"""

from __future__ import annotations

import numpy as np

from kinverify.report.plots import RC, _figure, _svg
from kinverify.text import literal

REF_COLOUR, OTHER_COLOUR = "#263238", "#d32f2f"
AXES = ("#e53935", "#43a047", "#1e88e5")


def _poses(raw) -> list[np.ndarray | None]:
    return [None if p is None else np.asarray(p, float) for p in raw]


def _moved(poses, t: np.ndarray):
    """Each pose moved by ``t`` (left-multiplied)."""
    return [None if p is None else t @ p for p in poses]


def panels(data: dict, alignment=None, keys=("home", "worst")) -> list[tuple[str, dict[str, list]]]:
    """(title, {backend: poses}) per panel: each configuration of ``keys``; with an alignment
    (file mode, where the MJCF side arrives already mapped into the URDF's world), the first also
    as written: the MJCF side moved back by ``T_mjcf_from_urdf``."""
    poses = data.get("poses") or {}
    out = []
    t = None if alignment is None else np.asarray(alignment, float)
    moved = t is not None and t.shape == (4, 4) and not np.allclose(t, np.eye(4), atol=1e-9)
    other = data.get("other") or ""
    titles = {"home": "home pose", "worst": "worst configuration"}
    for key in keys:
        if key not in poses:
            continue
        title = titles[key]
        drawn = {b: _poses(p) for b, p in poses[key].items()}
        if moved and other in drawn:
            assert t is not None  # moved: an alignment was given
            if key == keys[0]:
                out.append((f"{title}, as written", {**drawn, other: _moved(drawn[other], t)}))
            title += ", bases aligned"
        out.append((title, drawn))
    return out


def _view(points: np.ndarray) -> float:
    """Azimuth [deg] that looks across the arm's main horizontal extent."""
    xy = points[:, :2] - points[:, :2].mean(axis=0)
    if len(xy) < 2 or np.abs(xy).max() < 1e-6:
        return -60.0
    w, v = np.linalg.eigh(xy.T @ xy)
    main = v[:, int(np.argmax(w))]
    return float(np.degrees(np.arctan2(main[1], main[0]))) - 90.0


def skeleton_svg(
    data: dict, alignment=None, marks: dict[str, str] | None = None, keys=("home", "worst"), width: float = 3.5
) -> str | None:
    """The skeleton figure of a pictures section (``None`` without poses): one panel per
    configuration of ``keys``, ``width`` inches each."""
    import matplotlib
    from matplotlib.lines import Line2D

    frames, parents = list(data.get("frames") or []), list(data.get("parents") or [])
    todo = panels(data, alignment, keys)
    ref, other = data.get("reference", ""), data.get("other", "")
    if not frames or not todo:
        return None
    points = np.array([p[:3, 3] for _, drawn in todo for poses in drawn.values() for p in poses if p is not None])
    if not len(points):
        return None
    lo, hi = points.min(axis=0), points.max(axis=0)
    span = max(float((hi - lo).max()), 1e-3)
    pad = 0.08 * span
    grow = np.maximum(0.0, 0.45 * span - (hi - lo)) / 2  # a straight or flat arm still gets some room around it
    lo, hi = lo - pad - grow, hi + pad + grow
    triad = 0.09 * span
    azim = _view(points)
    marks = marks or {}
    with matplotlib.rc_context(RC):
        fig = _figure(figsize=(width * len(todo), width * 1.05))
        for k, (title, drawn) in enumerate(todo):
            ax = fig.add_subplot(1, len(todo), k + 1, projection="3d")
            for backend, poses in drawn.items():
                ghost = backend != ref
                colour, alpha = (OTHER_COLOUR, 0.55) if ghost else (REF_COLOUR, 1.0)
                for i, p in enumerate(poses):
                    if p is None:
                        continue
                    j = parents[i] if i < len(parents) else -1
                    if 0 <= j < len(poses) and poses[j] is not None:
                        seg = np.array([poses[j][:3, 3], p[:3, 3]])
                        ax.plot(
                            seg[:, 0],
                            seg[:, 1],
                            seg[:, 2],
                            color=colour,
                            alpha=alpha,
                            lw=2.4 if not ghost else 2.0,
                            ls="-" if not ghost else (0, (4, 2)),
                        )
                    for axis in range(3):
                        tip = p[:3, 3] + triad * p[:3, axis]
                        ax.plot(
                            *zip(p[:3, 3], tip, strict=True),
                            color=AXES[axis],
                            alpha=1.0 if not ghost else 0.45,
                            lw=1.3 if not ghost else 1.0,
                        )
                origins = np.array([p[:3, 3] for p in poses if p is not None])
                ax.scatter(*origins.T, color=colour, alpha=alpha, s=10 if not ghost else 8, depthshade=False)
                if not ghost:
                    for i, p in enumerate(poses):
                        name = frames[i] if i < len(frames) else ""  # a saved file's lists may disagree
                        if p is not None and (i in (0, len(poses) - 1) or marks.get(name) == "error"):
                            ax.text(
                                *p[:3, 3],
                                " " + literal(name),
                                fontsize=6.5,
                                color="#b71c1c" if marks.get(name) == "error" else "#37474f",
                            )
            ax.set_xlim(lo[0], hi[0])
            ax.set_ylim(lo[1], hi[1])
            ax.set_zlim(lo[2], hi[2])
            ax.set_box_aspect(hi - lo)
            ax.view_init(elev=22, azim=azim)
            ax.set_title(literal(title), pad=0)
            for _name, axis in (("x", ax.xaxis), ("y", ax.yaxis), ("z", ax.zaxis)):
                axis.set_major_locator(matplotlib.ticker.MaxNLocator(3))
                axis.set_tick_params(labelsize=5.5, pad=0)
                axis.pane.set_alpha(0.15)
            ax.set_xlabel("x [m]", fontsize=6, labelpad=-6)
            ax.set_ylabel("y [m]", fontsize=6, labelpad=-6)
            ax.set_zlabel("z [m]", fontsize=6, labelpad=-6)
        handles = [Line2D([], [], color=REF_COLOUR, lw=2.4, label=f"{literal(ref)} (solid)")]
        if other and any(other in drawn for _, drawn in todo):
            handles.append(
                Line2D([], [], color=OTHER_COLOUR, lw=2.0, ls=(0, (4, 2)), alpha=0.6, label=f"{literal(other)} (ghosted)")
            )
        handles += [Line2D([], [], color=c, lw=1.3, label=f"frame {a}") for c, a in zip(AXES, "xyz", strict=True)]
        fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=6.5, frameon=False)
        fig.subplots_adjust(left=0.0, right=1.0, top=0.93, bottom=0.1, wspace=0.05)
        return _svg(fig)
