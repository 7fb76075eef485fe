"""FK-based evidence: per-frame residuals after removing the base transform (where the
disagreement starts), and each file read by two libraries (parser cross-check)."""

from __future__ import annotations

import numpy as np

from kinverify.backends import names_reading
from kinverify.model.transforms import geodesic_distance, invert_transform
from kinverify.filemode.describe import ModelDesc
from kinverify.filemode.diagnose import ANG_TOL, POS_TOL, finding

URDF_SIDE = names_reading("urdf")  # every library that reads each file, the primary reader first
MJCF_SIDE = names_reading("mjcf")


def pose_errors(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Max over samples, per frame: position [m] and rotation [rad] between pose batches (N, F, 4, 4)."""
    pos = np.linalg.norm(a[..., :3, 3] - b[..., :3, 3], axis=-1).max(axis=0)
    rot = geodesic_distance(a[..., :3, :3], b[..., :3, :3]).max(axis=0)
    return pos, rot


def frame_residuals(ref, other, q: np.ndarray, t_base: np.ndarray, frames) -> tuple[list[list], dict | None, tuple[float, float]]:
    """Rows (frame, raw position, raw rotation, after-base position, after-base rotation), the
    'disagreement starts' finding, and the overall residual after removing the base transform."""
    pu, pm = ref.poses(q), other.poses(q)
    raw = pose_errors(pu, pm)
    based = pose_errors(t_base @ pu, pm)
    rows = [[f"{fu} / {fm}", float(raw[0][i]), float(raw[1][i]), float(based[0][i]), float(based[1][i])]
            for i, (fu, fm, _) in enumerate(frames)]
    start = None
    for i, (fu, fm, why) in enumerate(frames):
        if based[0][i] > POS_TOL or based[1][i] > ANG_TOL:
            start = finding("disagreement_starts", f"the kinematic disagreement starts at frame {fu}/{fm} ({why}): "
                            f"{based[0][i]:.3g} m, {based[1][i]:.3g} rad after removing the base transform "
                            f"({ref.name} vs {other.name}, {len(q)} configurations)",
                            {"position_m": float(based[0][i]), "rotation_rad": float(based[1][i]), "index": i},
                            frame=fu, mjcf_frame=fm)
            break
    return rows, start, (float(based[0].max()), float(based[1].max()))


def parser_checks(backends: dict, q: np.ndarray, mjcf: ModelDesc | None, top_pose: np.ndarray | None) -> tuple[list[dict], list[list]]:
    """Each file through its two (or three) libraries: constant offsets and disagreements named."""
    out, rows = [], []
    for side, names in (("URDF", URDF_SIDE), ("MJCF", MJCF_SIDE)):
        loaded = [n for n in names if n in backends]
        if len(loaded) < 2:
            continue
        first = backends[loaded[0]]
        p0 = first.poses(q)
        for name in loaded[1:]:
            p1 = backends[name].poses(q)
            pos, rot = pose_errors(p0, p1)
            rows.append([side, f"{loaded[0]} vs {name}", float(pos.max()), float(rot.max())])
            if pos.max() <= POS_TOL and rot.max() <= ANG_TOL:
                continue
            offset = p0[0, 0] @ invert_transform(p1[0, 0])  # constant transform between the two readings?
            cpos, crot = pose_errors(p0, offset @ p1)
            constant = cpos.max() <= 1e-9 and crot.max() <= 1e-9
            values = {"file": side, "backends": [loaded[0], name], "position_m": float(pos.max()), "rotation_rad": float(rot.max())}
            if constant and name == "pinocchio-mjcf" and top_pose is not None and np.allclose(offset, top_pose, atol=1e-9):
                out.append(finding("parser_quirk", "Pinocchio's MJCF parser ignores the pos/quat of the top-level body under "
                                   f"<worldbody>: pinocchio-mjcf places the whole arm {np.linalg.norm(top_pose[:3, 3]):.3g} m / "
                                   f"{float(geodesic_distance(top_pose[:3, :3], np.eye(3))):.3g} rad away from MuJoCo's reading "
                                   "of the same file (known quirk, kinverify/backends/quirks.py)", values))
            else:
                what = "by a constant transform" if constant else f"by up to {pos.max():.3g} m, {rot.max():.3g} rad"
                out.append(finding("parser_disagreement", f"the {side} is read differently by {loaded[0]} and {name} {what}", values))
    return out, rows


def top_level_pose(mjcf_text: str) -> np.ndarray | None:
    """World pose of the top-level body holding the arm when it is not the identity, else None."""
    import mujoco

    m = mujoco.MjModel.from_xml_string(mjcf_text)
    for b in range(1, m.nbody):
        if m.body_parentid[b] == 0 and m.body_jntnum[b] == 0 and _has_descendants(m, b):
            t = np.eye(4)
            d = mujoco.MjData(m)
            mujoco.mj_kinematics(m, d)
            t[:3, :3], t[:3, 3] = d.xmat[b].reshape(3, 3), d.xpos[b]
            return None if np.allclose(t, np.eye(4), atol=1e-12) else t
    return None


def _has_descendants(m, b: int) -> bool:
    return any(m.body_parentid[c] == b for c in range(b + 1, m.nbody))
