"""Pictures suite: what the report draws of the arm.

The section's ``data`` holds everything the report needs to draw its pictures from the JSON alone
(:mod:`kinverify.report.skeleton`, :mod:`kinverify.report.tree`), so they work without meshes:

- ``frames``/``parents``: the compared frames and each one's nearest compared ancestor (the
  skeleton's bones), from the URDF's kinematic tree (a chain when there is no URDF);
- ``poses``: world poses ``T_world_from_frame`` of every frame at the home pose and at the worst
  configuration, from the reference backend and from ``other`` (the backend that disagrees most
  with it on FK; in file mode the MJCF side, which is drawn ghosted over the URDF side);
- ``disagreements``: per backend whose FK disagrees with the reference, its worst configuration
  and both positions of the frame that differs most there;
- ``tree``: links and joints (name, type, parent, child) for the kinematic-tree diagram.

MuJoCo offscreen renderings (PNG) are added when the MJCF has visible geometry on the arm. They
run in a child process (``python -m kinverify.suites.pictures``) with ``MUJOCO_GL=egl`` unless the
environment already sets it, so a missing or broken GL stack (including one that crashes the
process) turns into a "rendering unavailable" note, never a failed run.
"""

from __future__ import annotations

import base64
import json
import struct
import sys
import zlib

import numpy as np

from kinverify.backends.base import pair_floor
from kinverify.errors import library_reason
from kinverify.suites.base import Figure, Section, Suite, SuiteResult, VerifyContext, tolerance

WIDTH, HEIGHT = 480, 360
TIMEOUT_S = 60
MAX_CONFIGS = 200  # configurations searched for the worst one (edge configurations first)
MJCF_READERS = ("mujoco", "pinocchio-mjcf")  # in file mode: the backends that read the MJCF


def render_pngs(mjcf: str, joint_names, configurations, width: int = WIDTH, height: int = HEIGHT) -> list[bytes]:
    """PNG bytes of the MJCF at each configuration, with body frame triads (in-process; needs a
    working GL). One camera for all pictures, fitted to the arm's bounding box over them (the
    arm's geoms and bodies; the floor and other world geoms do not count)."""
    import mujoco

    model = mujoco.MjModel.from_xml_string(mjcf)
    data = mujoco.MjData(model)
    adr = [model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, j)] for j in joint_names]
    arm = _arm_bodies(model)
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float)
    points, reach = [], np.zeros(2)
    for q in configurations:
        _pose(model, data, adr, q)
        points += [data.xpos[b] for b in arm]
        points += [
            p
            for g in range(model.ngeom)
            if model.geom_bodyid[g] in arm
            for p in data.geom_xpos[g] + model.geom_rbound[g] * corners
        ]
        reach = data.xpos[arm[-1], :2] - data.xpos[arm[0], :2]
    cloud = np.array(points)
    lo, hi = cloud.min(axis=0), cloud.max(axis=0)
    radius = max(float(np.linalg.norm(hi - lo)) / 2, 0.05)
    cam = mujoco.MjvCamera()
    mujoco.mjv_defaultFreeCamera(model, cam)
    cam.lookat[:] = (lo + hi) / 2
    cam.elevation = -20.0
    # look across the arm's reach in the last configuration (the worst), not along it
    cam.azimuth = np.degrees(np.arctan2(reach[1], reach[0])) + 90.0 if np.linalg.norm(reach) > 0.1 * radius else 135.0
    cam.distance = fit_distance(cloud - cam.lookat, cam.azimuth, cam.elevation, model.vis.global_.fovy, width / height)
    option = mujoco.MjvOption()
    option.frame = mujoco.mjtFrame.mjFRAME_BODY
    size = max(model.stat.meansize, 1e-9)  # MuJoCo scales frame triads by the model's mean body size
    model.vis.scale.framelength, model.vis.scale.framewidth = 0.15 * radius / size, 0.015 * radius / size
    out = []
    with mujoco.Renderer(model, height, width) as renderer:
        for q in configurations:
            _pose(model, data, adr, q)
            renderer.update_scene(data, camera=cam, scene_option=option)
            out.append(png_bytes(renderer.render()))
    return out


def fit_distance(points: np.ndarray, azimuth: float, elevation: float, fovy: float, aspect: float, margin: float = 1.08) -> float:
    """Camera distance from the look-at point at which every point (relative to it) is in view
    of a camera at ``azimuth``/``elevation`` [deg] with vertical field of view ``fovy`` [deg]."""
    az, el = np.radians(azimuth), np.radians(elevation)
    forward = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    right = np.array([np.sin(az), -np.cos(az), 0.0])
    up = np.cross(right, forward)
    tan_v = np.tan(np.radians(fovy) / 2)
    depth = points @ forward  # towards the back of the scene
    need = np.maximum(np.abs(points @ right) / (tan_v * aspect), np.abs(points @ up) / tan_v) - depth
    return margin * float(max(need.max(), 1e-3))


def _pose(model, data, adr, q) -> None:
    import mujoco

    data.qpos[:] = model.qpos0
    data.qpos[adr] = q
    mujoco.mj_forward(model, data)


def _arm_bodies(model) -> list[int]:
    """The bodies of the arm: the parent of the first jointed body and everything below it."""
    jointed = [b for b in range(1, model.nbody) if model.body_jntnum[b] > 0]
    root = int(model.body_parentid[jointed[0]]) if jointed else 0
    below = [b for b in range(1, model.nbody) if _descends(model, b, root)]
    return ([root] if root else []) + [b for b in below if b != root]


def _descends(model, body: int, root: int) -> bool:
    while body > 0:
        if body == root:
            return True
        body = int(model.body_parentid[body])
    return root == 0


def visible_arm_geoms(mjcf: str) -> int:
    """How many visible geoms hang on the arm (0: nothing MuJoCo could draw but the floor)."""
    import mujoco

    model = mujoco.MjModel.from_xml_string(mjcf)
    arm = set(_arm_bodies(model))
    return sum(1 for g in range(model.ngeom) if model.geom_bodyid[g] in arm and model.geom_rgba[g, 3] > 0)


def png_bytes(rgb: np.ndarray) -> bytes:
    """A minimal PNG encoder for ``(H, W, 3)`` uint8 images (zlib only: no imaging library)."""
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + row.tobytes() for row in np.ascontiguousarray(rgb, dtype=np.uint8))

    def chunk(tag: bytes, payload: bytes) -> bytes:
        return struct.pack(">I", len(payload)) + tag + payload + struct.pack(">I", zlib.crc32(tag + payload) & 0xFFFFFFFF)

    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
        + chunk(b"IDAT", zlib.compress(raw, 6))
        + chunk(b"IEND", b"")
    )


def render_in_child(mjcf: str, joint_names, configurations) -> tuple[list[bytes], str]:
    """``(pngs, "")`` or ``([], reason)`` when rendering is unavailable."""
    from kinverify.mujoco_gl import render_in_child as run_child

    request = {"mjcf": mjcf, "joints": list(joint_names), "q": [list(map(float, q)) for q in configurations]}
    return run_child("kinverify.suites.pictures", request, TIMEOUT_S)


def kinematic_tree(urdf: str | None, frames, joint_names) -> dict:
    """Links and joints of the URDF (``{"links": [...], "joints": [{name, type, parent, child}]}``);
    without a URDF, a chain of the compared frames joined by the compared joints."""
    if urdf:
        from defusedxml.ElementTree import fromstring

        try:
            root = fromstring(urdf)
        except Exception:  # an unreadable URDF never gets this far; stay drawable regardless
            root = None
        if root is not None:
            joints = [
                {
                    "name": j.get("name", ""),
                    "type": j.get("type", ""),
                    "parent": (j.find("parent").get("link", "") if j.find("parent") is not None else ""),
                    "child": (j.find("child").get("link", "") if j.find("child") is not None else ""),
                }
                for j in root.iter("joint")
                if j.find("parent") is not None and j.find("child") is not None
            ]
            return {"links": [el.get("name", "") for el in root.iter("link")], "joints": joints}
    names = list(joint_names) + [""] * len(frames)
    return {
        "links": list(frames),
        "joints": [
            {"name": names[i] or f"{a}-{b}", "type": "", "parent": a, "child": b}
            for i, (a, b) in enumerate(zip(frames, frames[1:], strict=False))
        ],
    }


def frame_parents(frames, tree: dict) -> list[int]:
    """Index of each frame's nearest ancestor among ``frames`` in the tree (-1: none)."""
    parent = {j["child"]: j["parent"] for j in tree["joints"]}
    index = {f: i for i, f in enumerate(frames)}
    out = []
    for f in frames:
        p, seen = parent.get(f), set()
        while p is not None and p not in index and p not in seen:
            seen.add(p)
            p = parent.get(p)
        out.append(index.get(p, -1) if p is not None else -1)
    return out


def _errors(ref_poses, poses):
    from kinverify.model.transforms import geodesic_distance

    pos = np.linalg.norm(ref_poses[..., :3, 3] - poses[..., :3, 3], axis=-1)
    return pos, geodesic_distance(ref_poses[..., :3, :3], poses[..., :3, :3])


def _poses_by_frame(backend, frames, q) -> list:
    """``backend``'s poses of ``frames`` at one configuration, ``None`` for a frame it lacks."""
    own = list(backend.frames)
    poses = backend.poses(np.asarray(q, float)[None])[0]
    return [np.round(poses[own.index(f)], 12).tolist() if f in own else None for f in frames]


def skeleton_data(ctx: VerifyContext, home: np.ndarray) -> dict:
    """Frames, tree, poses at home and at the worst configuration, and each disagreement."""
    from kinverify.suites.kinematics import KinematicsSuite

    opts, src = ctx.options, ctx.sources
    ref = ctx.backends[opts.reference]
    tree = kinematic_tree(src.urdf, src.frames, src.joint_names)
    frames = [f for f in src.frames if f in ref.frames]
    tol_p = tolerance(opts, KinematicsSuite.property("fk.position"))
    tol_r = tolerance(opts, KinematicsSuite.property("fk.rotation"))
    q = np.asarray(ctx.q[:MAX_CONFIGS])
    ref_poses = ref.poses(q)
    score, disagreements, overall = {}, [], (-1.0, 0)
    for name, backend in ctx.backends.items():
        common = [f for f in backend.frames if f in ref.frames]
        if name == ref.name or not common:
            continue
        ri, oi = [list(ref.frames).index(f) for f in common], [list(backend.frames).index(f) for f in common]
        pos, rot = _errors(ref_poses[:, ri], backend.poses(q)[:, oi])
        if not backend.has_rotation:
            rot = np.zeros_like(rot)
        tp, tr = max(tol_p, pair_floor("fk.position", ref, backend)), max(tol_r, pair_floor("fk.rotation", ref, backend))
        worst_ratio = max(float(pos.max()) / tp, float(rot.max()) / tr)
        # the worst configuration is where the frames are farthest apart (a visible difference)
        # unless only orientations differ
        ratio = pos / tp if pos.max() > tp else rot / tr
        i, f = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
        overall = max(overall, (float(pos[i, f]), int(i)))
        if worst_ratio > 1:
            score[name] = worst_ratio
            disagreements.append(
                {
                    "backend": name,
                    "q": q[i].tolist(),
                    "frame": common[f],
                    "reference": ref_poses[i, ri[f], :3, 3].tolist(),
                    "value": backend.poses(q[i : i + 1])[0, oi[f], :3, 3].tolist(),
                    "position_error": float(pos[i, f]),
                    "rotation_error": float(rot[i, f]),
                }
            )
    other = max(score, key=score.__getitem__) if score else ""
    if src.spec is None:  # file mode: the MJCF as MuJoCo reads it is drawn over the URDF side, agreeing or not
        readers = [n for n in MJCF_READERS if n in ctx.backends and n != ref.name]
        other = next((n for n in readers if n in score or not score), other)
    if other in score:
        d = next(d for d in disagreements if d["backend"] == other)
        worst, label = (
            np.asarray(d["q"]),
            (
                f"largest FK disagreement of {other} with {ref.name} among the first {len(q)} "
                f"configurations: {d['position_error']:.3g} m, {d['rotation_error']:.3g} rad at {d['frame']}"
            ),
        )
    else:
        worst = q[overall[1]] if len(q) else home
        label = f"largest FK position difference among the first {len(q)} configurations: {max(overall[0], 0.0):.3g} m"
    drawn = [b for b in (ref.name, other) if b]
    poses = {
        key: {b: _poses_by_frame(ctx.backends[b], frames, cfg) for b in drawn} for key, cfg in (("home", home), ("worst", worst))
    }
    return {
        "frames": frames,
        "parents": frame_parents(frames, tree),
        "reference": ref.name,
        "other": other,
        "configurations": {"home": home.tolist(), "worst": np.asarray(worst).tolist()},
        "worst_label": label,
        "poses": poses,
        "disagreements": disagreements,
        "tree": tree,
    }


class PicturesSuite(Suite):
    """The arm drawn as a skeleton (from the backends' FK), its kinematic tree, and MuJoCo
    renderings when the MJCF has visible geometry; no checks."""

    name = "pictures"
    title = "Pictures of the arm"
    report_only = True

    def run(self, ctx: VerifyContext) -> SuiteResult:
        section = Section(self.title)
        src = ctx.sources
        if len(ctx.q) == 0 or ctx.options.reference not in ctx.backends:
            section.notes.append("pictures unavailable: no configurations")
            return SuiteResult([], section)
        home = np.clip(np.zeros(len(src.joint_names)), src.lower, src.upper)
        section.data.update(skeleton_data(ctx, home))
        worst = np.asarray(section.data["configurations"]["worst"])
        label = section.data["worst_label"]
        section.summary = "The arm's frames from the backends' FK (skeleton with frame triads) and its kinematic tree."
        if not src.mjcf:
            return SuiteResult([], section)
        try:
            visible = visible_arm_geoms(src.mjcf)
        except Exception as err:  # MuJoCo refuses the MJCF: the skeleton still stands
            visible, reason = 0, f"rendering unavailable: MuJoCo cannot load the MJCF ({library_reason(err)})"
        else:
            reason = "" if visible else "no MuJoCo rendering: the MJCF has no visible geometry on the arm (meshes are not loaded)"
        pngs: list = []
        if visible:
            pngs, reason = render_in_child(src.mjcf, src.mjcf_joint_names or src.joint_names, [home, worst])
        if reason:
            section.notes.append(reason)
        for png, (title, q, caption) in zip(
            pngs,
            [("MuJoCo: home pose", home, "q = 0 (clipped into the limits)"), ("MuJoCo: worst configuration", worst, label)],
            strict=False,
        ):
            qs = ", ".join(f"{v:.4f}" for v in q)
            section.figures.append(Figure(title, "image/png", base64.b64encode(png).decode("ascii"), f"{caption}; q = [{qs}]"))
        return SuiteResult([], section)


def _main() -> int:  # child process: JSON request on stdin, JSON list of base64 PNGs on stdout
    request = json.load(sys.stdin)
    pngs = render_pngs(request["mjcf"], request["joints"], [np.asarray(q) for q in request["q"]])
    json.dump([base64.b64encode(p).decode("ascii") for p in pngs], sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(_main())
