"""Pictures suite: MuJoCo offscreen renderings of the generated MJCF at the home pose and at the
worst configuration, stored base64 (PNG) as section figures.

Rendering runs in a child process (``python -m kinverify.suites.pictures``) with ``MUJOCO_GL=egl``
unless the environment already sets it, so a missing or broken GL stack (including one that
crashes the process) turns into a "rendering unavailable" note, never a failed run.
"""

from __future__ import annotations

import base64
import json
import struct
import sys
import zlib
import numpy as np

from kinverify.suites.base import Figure, Section, Suite, SuiteResult, VerifyContext

WIDTH, HEIGHT = 480, 360
TIMEOUT_S = 60


def render_pngs(mjcf: str, joint_names, configurations, width: int = WIDTH, height: int = HEIGHT) -> list[bytes]:
    """PNG bytes of the MJCF at each configuration (in-process; needs a working GL)."""
    import mujoco

    model = mujoco.MjModel.from_xml_string(mjcf)
    data = mujoco.MjData(model)
    adr = [model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, j)] for j in joint_names]
    mujoco.mj_forward(model, data)
    body = data.xpos[1:]
    size = float(np.ptp(body, axis=0).max())  # the arm's extent at the home pose
    cam = mujoco.MjvCamera()
    mujoco.mjv_defaultFreeCamera(model, cam)
    cam.lookat[:] = (body.min(axis=0) + body.max(axis=0)) / 2  # centred on the home pose
    cam.elevation, cam.distance = -20.0, 1.6 * size + 0.6
    out = []
    with mujoco.Renderer(model, height, width) as renderer:
        for q in configurations:
            data.qpos[:] = model.qpos0
            data.qpos[adr] = q
            mujoco.mj_forward(model, data)
            reach = data.xpos[-1, :2] - data.xpos[1, :2]  # look across the arm, not along it
            cam.azimuth = np.degrees(np.arctan2(reach[1], reach[0])) + 90.0 if np.linalg.norm(reach) > 0.05 * size else 135.0
            renderer.update_scene(data, camera=cam)
            out.append(png_bytes(renderer.render()))
    return out


def png_bytes(rgb: np.ndarray) -> bytes:
    """A minimal PNG encoder for ``(H, W, 3)`` uint8 images (zlib only: no imaging library)."""
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + row.tobytes() for row in np.ascontiguousarray(rgb, dtype=np.uint8))

    def chunk(tag: bytes, payload: bytes) -> bytes:
        return struct.pack(">I", len(payload)) + tag + payload + struct.pack(">I", zlib.crc32(tag + payload) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def render_in_child(mjcf: str, joint_names, configurations) -> tuple[list[bytes], str]:
    """``(pngs, "")`` or ``([], reason)`` when rendering is unavailable."""
    from kinverify.mujoco_gl import render_in_child as run_child

    request = {"mjcf": mjcf, "joints": list(joint_names), "q": [list(map(float, q)) for q in configurations]}
    return run_child("kinverify.suites.pictures", request, TIMEOUT_S)


def worst_configuration(ctx, max_configs: int = 200) -> tuple[np.ndarray, str]:
    """The configuration with the largest FK position error against the reference (first
    ``max_configs`` samples, edge configurations first) and a label."""
    ref = ctx.backends[ctx.options.reference]
    q = ctx.q[:max_configs]
    best, where = -1.0, ""
    index = 0
    ref_poses = ref.poses(q)
    for name, backend in ctx.backends.items():
        if name == ref.name:
            continue
        cols = [list(ref.frames).index(f) for f in backend.frames if f in ref.frames]
        own = [i for i, f in enumerate(backend.frames) if f in ref.frames]
        err = np.linalg.norm(ref_poses[:, cols][..., :3, 3] - backend.poses(q)[:, own][..., :3, 3], axis=-1)
        i, f = np.unravel_index(int(np.argmax(err)), err.shape)
        if err[i, f] > best:
            best, index, where = float(err[i, f]), int(i), f"{ref.name} vs {name} at {backend.frames[own[f]]}"
    return q[index], f"largest FK position error among the first {len(q)} configurations: {best:.3g} m ({where})"


class PicturesSuite(Suite):
    """MuJoCo renderings (or a note) and no checks."""

    name = "pictures"
    title = "Pictures of the arm"
    report_only = True

    def run(self, ctx: VerifyContext) -> SuiteResult:
        section = Section(self.title)
        if not ctx.sources.mjcf or len(ctx.q) == 0:
            section.notes.append("rendering unavailable: no MJCF model or no configurations")
            return SuiteResult([], section)
        home = np.clip(np.zeros(len(ctx.sources.joint_names)), ctx.sources.lower, ctx.sources.upper)
        worst, label = worst_configuration(ctx)
        pngs, reason = render_in_child(ctx.sources.mjcf, ctx.sources.mjcf_joint_names or ctx.sources.joint_names, [home, worst])
        section.summary = "MuJoCo offscreen renderings of the MJCF."
        section.data["configurations"] = {"home": home.tolist(), "worst": worst.tolist()}
        if reason:
            section.notes.append(reason)
        for png, (title, q, caption) in zip(pngs, [("home pose", home, "q = 0 (clipped into the limits)"),
                                                   ("worst configuration", worst, label)]):
            qs = ", ".join(f"{v:.4f}" for v in q)
            section.figures.append(Figure(title, "image/png", base64.b64encode(png).decode("ascii"), f"{caption}; q = [{qs}] rad"))
        return SuiteResult([], section)


def _main() -> int:  # child process: JSON request on stdin, JSON list of base64 PNGs on stdout
    request = json.load(sys.stdin)
    pngs = render_pngs(request["mjcf"], request["joints"], [np.asarray(q) for q in request["q"]])
    json.dump([base64.b64encode(p).decode("ascii") for p in pngs], sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(_main())
