"""Report figures for a set of runs: matplotlib plots as base64 SVG, and the execution as an
animated GIF rendered offscreen by MuJoCo.

Rendering runs in a child process (``python -m kinverify.tracking.figures``) with
``MUJOCO_GL=egl`` unless the environment sets it, as the pictures suite does: a missing or broken
GL stack (even one that kills the process) becomes a "rendering unavailable: <reason>" note,
never a failed run.
"""

from __future__ import annotations

import base64
import io
import json
import os
import sys

import numpy as np

from kinverify.suites.base import Figure
from kinverify.text import literal

from kinverify.tracking.execute import Run

MAX_POINTS = 400  # per curve, to keep the SVG small


def _svg(fig) -> str:
    buf = io.StringIO()
    fig.savefig(buf, format="svg", bbox_inches="tight")
    return base64.b64encode(buf.getvalue().encode()).decode()


def _every(n: int) -> slice:
    return slice(None, None, max(1, n // MAX_POINTS))


def joint_plot(run: Run, joint_names) -> Figure:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s = _every(len(run.t))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
    for j, name in enumerate(joint_names):
        (line,) = ax1.plot(run.t[s], run.q[s, j], label=literal(name))
        ax1.plot(run.plan.t[s], run.plan.q[s, j], "--", color=line.get_color(), linewidth=0.8)
        ax2.plot(run.t[s], run.qd[s, j], color=line.get_color())
    for ax in (ax1, ax2):
        ax.axvline(run.motion_end, color="grey", linewidth=0.6)
        ax.grid(True, linewidth=0.3)
    ax1.set_ylabel("q [rad]  (dashed: plan)")
    ax2.set_ylabel("q̇ [rad/s]")
    ax2.set_xlabel("t [s]  (grey line: end of motion, hold after)")
    ax1.legend(fontsize=7, loc="best")
    fig.suptitle(f"{run.controller}: joint angles and speeds")
    data = _svg(fig)
    plt.close(fig)
    return Figure(
        f"Joint angles and speeds under {run.controller}",
        "image/svg+xml",
        data,
        "executed (solid) vs planned (dashed) joint angles, and executed joint speeds",
    )


def error_plot(runs: list[Run]) -> Figure:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 3.5))
    for run in runs:
        err = np.linalg.norm(run.plan.q[: len(run.q)] - run.q, axis=1)
        s = _every(len(err))
        ax.semilogy(run.t[s], np.maximum(err[s], 1e-16), label=run.controller)
    ax.axvline(runs[0].motion_end, color="grey", linewidth=0.6)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("||q_d − q|| [rad]")
    ax.grid(True, which="both", linewidth=0.3)
    ax.legend(fontsize=7)
    data = _svg(fig)
    plt.close(fig)
    return Figure(
        "Tracking error over time", "image/svg+xml", data, "joint error norm per controller (log scale); grey line: end of motion"
    )


FPS = 8.0  # frames per second of the animation (the run itself is simulated at 1 kHz)
SIZE = (320, 240)  # width, height [px]: about 50 kB of GIF for arm3's 4 s run
TIMEOUT_S = 120


def frame_indices(n: int, dt: float, fps: float = FPS) -> np.ndarray:
    """Indices of ``n`` states ``dt`` s apart, one every ``1/fps`` s, always including the last."""
    step = max(1, int(round(1.0 / (fps * dt))))
    idx = np.arange(0, n, step)
    return idx if n == 0 or idx[-1] == n - 1 else np.append(idx, n - 1)


def render_gifs(mjcf: str, qadr, clips, fps: float = FPS, size=SIZE) -> list[bytes]:
    """GIF bytes per clip (a list of configurations), in-process: needs a working GL. One camera
    for all clips, framing every pose of every clip and looking across the arm's final reach."""
    import mujoco
    from PIL import Image

    model = mujoco.MjModel.from_xml_string(mjcf)
    data = mujoco.MjData(model)
    qadr = np.asarray(qadr, dtype=int)
    parts: list[np.ndarray] = []
    for q in (q for clip in clips for q in clip):
        data.qpos[qadr] = q
        mujoco.mj_kinematics(model, data)
        parts.append(data.xpos[1:].copy())
    points = np.concatenate(parts) if parts else np.zeros((1, 3))
    lo, hi = points.min(axis=0), points.max(axis=0)
    cam = mujoco.MjvCamera()
    mujoco.mjv_defaultFreeCamera(model, cam)
    cam.lookat[:] = (lo + hi) / 2
    cam.distance = 1.2 * float(np.linalg.norm(hi - lo)) + 0.4
    reach = points[-1, :2] - points[0, :2]  # last body of the last pose, from the first body
    cam.azimuth = float(np.degrees(np.arctan2(reach[1], reach[0]))) + 90.0 if np.linalg.norm(reach) > 0.05 else 135.0
    cam.elevation = -20.0
    out = []
    with mujoco.Renderer(model, size[1], size[0]) as renderer:
        for clip in clips:
            frames = []
            for q in clip:
                data.qpos[qadr] = q
                mujoco.mj_forward(model, data)  # not only kinematics: lights follow the scene too
                renderer.update_scene(data, cam)
                renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = False  # 15x faster in software GL
                frames.append(Image.fromarray(renderer.render()))
            buf = io.BytesIO()
            frames[0].save(buf, format="GIF", save_all=True, append_images=frames[1:], duration=int(round(1000 / fps)), loop=0)
            out.append(buf.getvalue())
    return out


def animations(runs: list[Run], mjcf: str, qadr, fps: float = FPS, size=SIZE) -> tuple[list[Figure], str]:
    """(GIF figures, '') or ([], "rendering unavailable: <reason>"), rendered in a child process."""
    clips = [run.q[frame_indices(len(run.q), run.plan.dt, fps)] for run in runs]
    clips = [c[np.isfinite(c).all(axis=1)] for c in clips]  # a diverged run: up to its last finite state
    runs, clips = [r for r, c in zip(runs, clips, strict=True) if len(c)], [c for c in clips if len(c)]
    if not runs:
        return [], "rendering unavailable: no finite executed states to show"
    from kinverify.mujoco_gl import render_in_child

    request = {"mjcf": mjcf, "qadr": [int(a) for a in qadr], "clips": [c.tolist() for c in clips], "fps": fps, "size": list(size)}
    gifs, reason = render_in_child("kinverify.tracking.figures", request, TIMEOUT_S)
    if reason:
        return [], reason
    if len(gifs) != len(runs) or not all(g.startswith(b"GIF8") for g in gifs):
        return [], "rendering unavailable: the renderer returned no GIF"
    return [
        Figure(
            f"Execution under {run.controller}",
            "image/gif",
            base64.b64encode(gif).decode("ascii"),
            f"MuJoCo offscreen rendering of the executed joint states, a frame every {1 / fps:.3g} s of "
            f"simulated time ({len(clip)} frames, {size[0]}×{size[1]} px, loops)",
        )
        for run, clip, gif in zip(runs, clips, gifs, strict=True)
    ], ""


def animation(run: Run, mjcf: str, qadr, fps: float = FPS, size=SIZE) -> tuple[Figure | None, str]:
    """(GIF figure, '') or (None, reason) for one run."""
    figs, reason = animations([run], mjcf, qadr, fps, size)
    return (figs[0] if figs else None), reason


def _main() -> int:  # child process: JSON request on stdin, JSON list of base64 GIFs on stdout
    from kinverify import mujoco_gl

    if mujoco_gl.IMPORT_ERROR:  # kinverify imported MuJoCo without GL (see mujoco_gl.py): say why, not what broke
        gl = os.environ.get("MUJOCO_GL", "")
        if not mujoco_gl.accepted(gl):
            sys.exit(f"{gl!r} is not a GL backend MuJoCo knows (use egl or osmesa for offscreen rendering)")
        sys.exit(f"the {gl} GL backend did not load: {mujoco_gl.IMPORT_ERROR}")
    request = json.load(sys.stdin)
    clips = [np.asarray(c, dtype=float) for c in request["clips"]]
    gifs = render_gifs(request["mjcf"], request["qadr"], clips, request["fps"], tuple(request["size"]))
    json.dump([base64.b64encode(g).decode("ascii") for g in gifs], sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(_main())
