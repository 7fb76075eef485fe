"""Report plots drawn with matplotlib (Agg) from result data only, returned as SVG text.

Output is deterministic (fixed hash salt, no date), so re-rendering a saved JSON gives the same
page. Text is drawn as paths (``svg.fonttype = "path"``): names from a model file never appear as
markup in the SVG.
"""

from __future__ import annotations

import base64
import io
from typing import Any

import numpy as np

from kinverify.suites.base import Figure

from kinverify.results import VerifyResult
from kinverify.pipeline.stats import HIST_EDGES

_RC: Any = {"svg.fonttype": "path", "svg.hashsalt": "kinverify", "font.size": 8, "axes.titlesize": 9}
RC = _RC  # for suites drawing their own section figures


def _svg(fig) -> str:
    import matplotlib.pyplot as plt

    buf = io.StringIO()
    fig.savefig(buf, format="svg", bbox_inches="tight", metadata={"Date": None, "Creator": None})
    plt.close(fig)
    text = buf.getvalue()
    return text[text.index("<svg") :]


def figure_entry(fig, title: str, caption: str) -> Figure:
    """A matplotlib figure as a section :class:`~kinverify.suites.base.Figure`: deterministic
    SVG, base64. Draw it inside ``matplotlib.rc_context(RC)`` so text becomes paths."""
    data = base64.b64encode(_svg(fig).encode("utf-8")).decode("ascii")
    return Figure(title, "image/svg+xml", data, caption)


def new_figure(**kwargs):
    """A pyplot figure on the Agg backend (closed by :func:`figure_entry`)."""
    return _figure(**kwargs)


def _figure(**kwargs):
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt.figure(**kwargs)


def error_distributions_svg(result: VerifyResult) -> str | None:
    """One log-scale panel per sampled property: the error histogram of each backend pair (all
    frames pooled), with the tolerance as a dashed line. Single-valued checks (a parameter
    difference, a rate) have no distribution and are left out. None when nothing is sampled."""
    import matplotlib
    import matplotlib.ticker

    props: dict[str, dict[tuple, np.ndarray]] = {}
    tolerance: dict[str, float] = {}
    units: dict[str, str] = {}
    for c in result.checks:
        if c.samples <= 1 or len(c.histogram) != len(HIST_EDGES) - 1 or not any(c.histogram):
            continue
        pairs = props.setdefault(c.property, {})
        pairs[c.backends] = pairs.get(c.backends, 0) + np.asarray(c.histogram)
        tolerance[c.property], units[c.property] = c.tolerance, c.unit
    if not props:
        return None
    with matplotlib.rc_context(_RC):
        cols = 2 if len(props) > 1 else 1
        rows = -(-len(props) // cols)
        fig = _figure(figsize=(4.2 * cols, 2.6 * rows))
        centres = np.sqrt(HIST_EDGES[:-1] * HIST_EDGES[1:])
        for i, (prop, pairs) in enumerate(props.items()):
            ax = fig.add_subplot(rows, cols, i + 1)
            lo, hi = len(centres), 0
            series: dict[str, Any] = {" vs ".join(pair): hist for pair, hist in pairs.items()}
            if len(series) > 6:  # a legend of 25 pairs hides the plot: pool them
                series = {f"{len(series)} backend pairs, pooled": sum(series.values())}
            for label, hist in series.items():
                nz = np.nonzero(hist)[0]
                lo, hi = min(lo, nz.min()), max(hi, nz.max())
                ax.step(centres, np.where(hist > 0, hist, np.nan), where="mid", label=label, lw=1.2)
            ax.axvline(tolerance[prop], color="#c62828", ls="--", lw=1, label="tolerance")
            ax.set_xscale("log")
            ax.set_yscale("log")
            left = min(HIST_EDGES[max(lo - 2, 0)], tolerance[prop] / 10)
            right = max(HIST_EDGES[min(hi + 3, len(HIST_EDGES) - 1)], tolerance[prop] * 10)
            ax.set_xlim(left, right)
            ax.xaxis.set_major_locator(matplotlib.ticker.LogLocator(numticks=7))
            ax.yaxis.set_major_locator(matplotlib.ticker.LogLocator(numticks=5))
            ax.minorticks_off()  # log axes over many decades: minor ticks cost seconds and add nothing
            ax.set_title(prop)
            ax.set_xlabel(
                f"error [{units[prop]}] (errors below 1e-18, incl. 0, in the first bin)" if i == 0 else f"error [{units[prop]}]"
            )
            ax.set_ylabel("samples × frames")
            ax.grid(True, which="major", alpha=0.3)
            ax.legend(fontsize=6, loc="upper right")  # a fixed place: "best" searches the data, seconds per panel
        fig.subplots_adjust(left=0.08, right=0.98, bottom=0.5 / rows, top=1 - 0.25 / rows, wspace=0.3, hspace=0.75)
        return _svg(fig)


def workspace_svg(section: dict) -> str | None:
    """3D point cloud coloured by height and its three projections, from a workspace section."""
    import matplotlib

    points = np.asarray(section.get("points") or [], dtype=float).reshape(-1, 3)
    if len(points) == 0:
        return None
    with matplotlib.rc_context(_RC):
        fig = _figure(figsize=(8.4, 7.0))
        z = points[:, 2]
        ax3 = fig.add_subplot(2, 2, 1, projection="3d")
        sc = ax3.scatter(points[:, 0], points[:, 1], z, c=z, cmap="viridis", s=1, alpha=0.6, rasterized=True)
        ax3.set_xlabel("x [m]")
        ax3.set_ylabel("y [m]")
        ax3.set_zlabel("z [m]")
        ax3.set_title("workspace (3D)")
        mid, half = (points.max(0) + points.min(0)) / 2, np.ptp(points, axis=0).max() / 2
        for setter, m in zip((ax3.set_xlim, ax3.set_ylim, ax3.set_zlim), mid, strict=True):
            setter(m - half, m + half)
        for k, (i, j, name) in enumerate(((0, 1, "top view (x-y)"), (0, 2, "side view (x-z)"), (1, 2, "front view (y-z)"))):
            ax = fig.add_subplot(2, 2, k + 2)
            order = np.argsort(z) if j != 2 else np.arange(len(z))  # top view: highest points drawn last
            ax.scatter(points[order, i], points[order, j], c=z[order], cmap="viridis", s=1, alpha=0.6, rasterized=True)
            ax.set_xlabel(f"{'xyz'[i]} [m]")
            ax.set_ylabel(f"{'xyz'[j]} [m]")
            ax.set_aspect("equal", adjustable="datalim")
            ax.set_title(name)
            ax.grid(True, alpha=0.3)
        fig.subplots_adjust(wspace=0.6, hspace=0.4)  # room for the 3D panel's labels and the projections' titles
        fig.colorbar(sc, ax=fig.axes, shrink=0.6, label="height z [m]")
        return _svg(fig)
