"""Report figures for a set of runs: matplotlib plots as base64 SVG, and an offscreen-rendered
animated GIF when MuJoCo has a GL backend (``MUJOCO_GL=egl`` or ``osmesa``), else a note."""

from __future__ import annotations

import base64
import io
import os

import numpy as np

from .execute import Run

MAX_POINTS = 400  # per curve, to keep the SVG small


def _svg(fig) -> str:
    buf = io.StringIO()
    fig.savefig(buf, format="svg", bbox_inches="tight")
    return base64.b64encode(buf.getvalue().encode()).decode()


def _every(n: int) -> slice:
    return slice(None, None, max(1, n // MAX_POINTS))


def joint_plot(run: Run, joint_names) -> dict:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s = _every(len(run.t))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
    for j, name in enumerate(joint_names):
        line, = ax1.plot(run.t[s], run.q[s, j], label=name)
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
    return {"title": f"Joint angles and speeds under {run.controller}", "mime": "image/svg+xml", "data": data,
            "caption": "executed (solid) vs planned (dashed) joint angles, and executed joint speeds"}


def error_plot(runs: list[Run]) -> dict:
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
    return {"title": "Tracking error over time", "mime": "image/svg+xml", "data": data,
            "caption": "joint error norm per controller (log scale); grey line: end of motion"}


def gl_available() -> str:
    """'' when offscreen rendering can be tried, else why not."""
    backend = os.environ.get("MUJOCO_GL", "")
    if backend not in ("egl", "osmesa"):
        return f"rendering unavailable: MUJOCO_GL is {backend or 'unset'} (set MUJOCO_GL=egl for offscreen frames)"
    return ""


def animation(run: Run, mjcf: str, qadr, fps: float = 10.0, size=(320, 240)) -> tuple[dict | None, str]:
    """(GIF figure, '') or (None, reason). Frames every 1/fps s of the run, offscreen."""
    reason = gl_available()
    if reason:
        return None, reason
    try:
        import mujoco
        from PIL import Image

        model = mujoco.MjModel.from_xml_string(mjcf)
        data = mujoco.MjData(model)
        renderer = mujoco.Renderer(model, size[1], size[0])
        data.qpos[qadr] = run.q[0]
        mujoco.mj_kinematics(model, data)
        arm = data.xpos[2:]  # bodies after world and the mount
        cam = mujoco.MjvCamera()
        cam.lookat[:] = arm.mean(axis=0)
        cam.distance = 2.5 * float(np.linalg.norm(arm - arm.mean(axis=0), axis=1).max()) + 0.5
        cam.azimuth, cam.elevation = 135.0, -20.0
        step = max(1, int(round(1.0 / (fps * run.plan.dt))))
        frames = []
        for k in range(0, len(run.q), step):
            data.qpos[qadr] = run.q[k]
            mujoco.mj_kinematics(model, data)
            renderer.update_scene(data, cam)
            frames.append(Image.fromarray(renderer.render()))
        renderer.close()
        buf = io.BytesIO()
        frames[0].save(buf, format="GIF", save_all=True, append_images=frames[1:], duration=int(1000 / fps), loop=0)
    except Exception as err:  # no GL context, driver trouble...: a note, never a crash
        return None, f"rendering unavailable: {type(err).__name__}: {err}"
    return ({"title": f"Execution under {run.controller}", "mime": "image/gif",
             "data": base64.b64encode(buf.getvalue()).decode(),
             "caption": f"MuJoCo offscreen frames every {1 / fps:.2g} s ({len(frames)} frames)"}, "")
