"""Each file read by a second (and third) library: a library that reads the same file differently
is named once and left out of the comparison between the files, so a verdict of "disagree" is
about the files, never about a parser.

URDF: Pinocchio (the reference), yourdfpy, MuJoCo's URDF import. MJCF: MuJoCo (the reference),
Pinocchio's MJCF parser, which drops the pose of a top-level body under ``<worldbody>``
(pinocchio#2782): that quirk is recognised, measured, reported as information and corrected.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from kinverify.backends import names_reading
from kinverify.errors import library_reason
from kinverify.filemode.findings.table import finding
from kinverify.model.transforms import geodesic_distance, invert_transform

URDF_SIDE = names_reading("urdf")  # every library that reads each file, the primary reader first
MJCF_SIDE = names_reading("mjcf")
QUIRK_ISSUE = "https://github.com/stack-of-tasks/pinocchio/issues/2782"


def pose_errors(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Max over samples, per frame: position [m] and rotation [rad] between pose batches (N, F, 4, 4)."""
    pos = np.linalg.norm(a[..., :3, 3] - b[..., :3, 3], axis=-1).max(axis=0)
    rot = geodesic_distance(a[..., :3, :3], b[..., :3, :3]).max(axis=0)
    return pos, rot


def top_level_pose(mjcf_text: str) -> np.ndarray | None:
    """World pose of the top-level body holding the robot when it is not the identity, else None."""
    m = mujoco.MjModel.from_xml_string(mjcf_text)
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    for b in range(1, m.nbody):
        if m.body_parentid[b] == 0 and any(m.body_parentid[c] == b for c in range(b + 1, m.nbody)):
            t = np.eye(4)
            t[:3, :3], t[:3, 3] = d.xmat[b].reshape(3, 3), d.xpos[b]
            return None if np.allclose(t, np.eye(4), atol=1e-15) else t
    return None


def cross_check(backends: dict, q: np.ndarray, tol, t_base: np.ndarray, top_pose: np.ndarray | None, rebuild):
    """Compare each secondary library with the reference reading of the same file.

    ``backends``: name -> aligned backend; ``tol``: (position, rotation) tolerance; ``rebuild(backend,
    left)``: that aligned backend with another left transform. Returns (the backends to
    compare between the files, findings, table rows)."""
    findings, rows, keep = [], [], dict(backends)
    ptol, rtol = tol
    for side, names in (("URDF", URDF_SIDE), ("MJCF", MJCF_SIDE)):
        loaded = [n for n in names if n in backends]
        if len(loaded) < 2:
            continue
        ref = backends[loaded[0]]
        p_ref = ref.poses(q)
        for name in loaded[1:]:
            common = [(i, ref.frames.index(f)) for i, f in enumerate(backends[name].frames) if f in ref.frames]
            p0 = p_ref[:, [j for _, j in common]]
            try:
                p1 = backends[name].poses(q)[:, [i for i, _ in common]]
            except Exception as err:  # the library fails on this file: a finding, not a crash
                keep.pop(name)
                findings.append(finding("parser_refused", f"{name} cannot evaluate the {side}: {library_reason(err)}",
                                        {"file": side, "backend": name}))
                continue
            pos, rot = pose_errors(p0, p1)
            rows.append([side, f"{loaded[0]} vs {name}", float(pos.max()), float(rot.max())])
            if pos.max() <= ptol and rot.max() <= rtol:
                continue
            values = {"file": side, "backends": [loaded[0], name], "position_m": float(pos.max()), "rotation_rad": float(rot.max())}
            if name == "pinocchio-mjcf" and top_pose is not None:
                fixed = rebuild(backends[name], invert_transform(t_base) @ top_pose)
                cpos, crot = pose_errors(p0, fixed.poses(q)[:, [i for i, _ in common]])
                if cpos.max() <= ptol and crot.max() <= rtol:
                    keep[name] = fixed
                    shift = float(np.linalg.norm(top_pose[:3, 3]))
                    angle = float(geodesic_distance(top_pose[:3, :3], np.eye(3)))
                    rows[-1] += [f"corrected: {float(cpos.max()):.2g} m, {float(crot.max()):.2g} rad"]
                    findings.append(finding(
                        "parser_quirk", f"Pinocchio's MJCF parser drops the pose of the top-level body ({shift:.4g} m, "
                        f"{angle:.4g} rad = {math.degrees(angle):.4g}°): its reading of the MJCF is off by that much "
                        f"everywhere (pinocchio#2782, {QUIRK_ISSUE}); kinverify puts the pose back before comparing",
                        {**values, "top_level_xyz": top_pose[:3, 3].tolist(), "issue": QUIRK_ISSUE},
                        magnitude=max(shift, angle), unit="m|rad"))
                    continue
            keep.pop(name)
            findings.append(finding("parser_disagreement", f"the {side} is read differently by {loaded[0]} and {name}: up to "
                                    f"{float(pos.max()):.3g} m, {float(rot.max()):.3g} rad on the same file; {name} is left out "
                                    "of the comparison between the files", values,
                                    magnitude=float(max(pos.max(), rot.max())), unit="m|rad"))
    return keep, findings, rows
