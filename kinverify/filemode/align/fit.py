"""Alignment: what two files of one robot differ by that is a choice rather than a different
robot, solved once and reported once.

Unknowns: the world transform ``T`` (``x_mjcf = T · x_urdf``), and per matched joint a sign
``s`` and a zero offset ``o`` (``q_mjcf = s · q_urdf + o``). The fit uses physical features only,
never the orientation of a link frame (which each file chooses freely): the joints' axis lines
and the origins of matched frames, at q = 0 and at sampled configurations.

1. Candidate world transforms: the identity; a least-squares fit over every matched frame origin
   (joints mapped as they are); each root frame both files share; the first joint's axis line
   laid onto the other's.
2. For each candidate, walking the chain from the base: the joint's sign is where its axis points
   (after ``T``); its zero offset is the turn about (or shift along) its axis that carries what
   it moves in one file (the next joints' axis lines, then the frames and centres of mass it
   carries) onto the other's.
3. ``T`` is refitted by least squares over all configurations: axis lines (points projected on
   the other file's line, directions) and the frame origins that agree (a frame that stands out
   is left out and reported on its own), then step 2 runs again.
4. Each candidate is scored by how many features it leaves unexplained, then by how many
   explanations it needs (``T`` not the identity, each offset, each sign flip); ties go to the
   one under which the root frames agree in orientation too, then to a world transform rather
   than a first-joint offset. The best is kept, with its residual.

Frames whose pose then differs by a constant (a frame convention: e.g. a finger frame turned by
π about its joint's axis in one file) are compared after removing that constant.
"""

from __future__ import annotations

import math

import numpy as np

from kinverify.filemode.align.geometry import consensus, foot_on_line, kabsch, planar, project_on_line, rotation_between, wrap
from kinverify.filemode.align.match import Matching
from kinverify.filemode.align.result import Alignment, FrameFit, JointMap, PairPoses
from kinverify.filemode.read.model import ModelDesc
from kinverify.filemode.read.precision import Floors
from kinverify.model.transforms import axis_angle_to_matrix, geodesic_distance, invert_transform, skew

TOL = 1e-9  # m and rad: agreement of exact double-precision readings
LEVER = 1e-4  # a point this near a joint's axis (per metre of robot) gives its zero offset poorly
NEAR_PARALLEL = 0.1  # sin of the angle between two axes below which their common perpendicular is ill-conditioned


def _line_local(desc: ModelDesc, joint: str) -> tuple[np.ndarray, np.ndarray]:
    """A joint's axis direction and a point of its axis in its moving frame (constant)."""
    j = desc.joint(joint)
    t0 = desc.frames[j.child]
    return t0[:3, :3].T @ j.axis, t0[:3, :3].T @ (j.anchor - t0[:3, 3])


def _apply(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """One transform (4, 4) applied to points (..., 3)."""
    return x @ t[:3, :3].T + t[:3, 3]


def _crossing(point: np.ndarray, normal: np.ndarray, p: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Where the line ``p + s·d`` crosses the plane through ``point`` normal to ``normal``."""
    return p + float((point - p) @ normal) / float(d @ normal) * d


def _carry(poses: np.ndarray, x: np.ndarray) -> np.ndarray:
    """A local point (3,) carried by poses (N, 4, 4): (N, 3)."""
    return poses[:, :3, :3] @ x + poses[:, :3, 3]


def _gauss_newton(feats, t: np.ndarray, iterations: int = 4) -> np.ndarray:
    """Refine T by Gauss-Newton on the features' errors, each scaled by its tolerance (a turn
    that only a few rounded points pin down converges as accurately as one that exact axes do,
    where a single weighted Kabsch fit would lose it in round-off). A turn the features leave free
    stays as it is (the minimum-norm step)."""
    for _ in range(iterations):
        rows, res = [], []
        rot = t[:3, :3]
        for _, kind, a, b, (ptol, rtol) in feats:
            if kind == "point":
                pt = _apply(t, a)
                rows.append(np.concatenate([-skew(pt), np.broadcast_to(np.eye(3), pt.shape[:-1] + (3, 3))], axis=-1) / ptol)
                res.append((pt - b) / ptol)
                continue
            (ua, up), (ma, mp) = a, b
            pt, dt = _apply(t, up), ua @ rot.T
            perp = np.eye(3) - ma[..., :, None] * ma[..., None, :]
            jp = np.concatenate([-skew(pt), np.broadcast_to(np.eye(3), pt.shape[:-1] + (3, 3))], axis=-1)
            rows.append(perp @ jp / ptol)
            res.append(np.einsum("nij,nj->ni", perp, pt - mp) / ptol)
            rows.append(np.concatenate([-skew(dt), np.zeros(dt.shape[:-1] + (3, 3))], axis=-1) / rtol)
            res.append((dt - ma) / rtol)
        j = np.concatenate([r.reshape(-1, 6) for r in rows])
        e = np.concatenate([r.reshape(-1) for r in res])
        a, g = j.T @ j, j.T @ e  # normal equations, scaled to unit diagonal (each iteration refines)
        d = np.sqrt(np.maximum(np.diag(a), 1e-300))
        step = np.linalg.lstsq(a / np.outer(d, d), -g / d, rcond=1e-14)[0] / d
        if not np.all(np.isfinite(step)) or np.abs(step).max() < 1e-16:
            break
        dr = axis_angle_to_matrix(step[:3] / (np.linalg.norm(step[:3]) or 1.0), np.array([np.linalg.norm(step[:3])]))[0]
        new = np.eye(4)
        new[:3, :3], new[:3, 3] = dr @ rot, dr @ t[:3, 3] + step[3:]
        t = new
    return t


class Aligner:
    def __init__(self, poses: PairPoses, matching: Matching, floors: Floors, samples: np.ndarray) -> None:
        self.p, self.matching, self.floors = poses, matching, floors
        u, m = poses.u, poses.m
        self.pairs = [(a, b) for a, b, _ in matching.joints]
        self.types = {a: u.joint(a).type for a, _ in self.pairs}
        self.lines_u = {a: _line_local(u, a) for a, _ in self.pairs}
        self.lines_m = {b: _line_local(m, b) for _, b in self.pairs}
        self.children = {a: [c for c, _ in self.pairs if u.joint(c).parent == a] for a, _ in self.pairs}
        self.frame_pairs = [(fu, fm, why) for fu, fm, why in matching.frames if fu in poses.ui and fm in poses.mi]
        # bodies both files give the same mass: their centres of mass are evidence (a body whose
        # mass differs is a different inertial, not a displaced one)
        self.bodies = [
            (bu, bm)
            for fu, fm, _ in self.frame_pairs
            for bu, bm in [(u.body(fu), m.body(fm))]
            if bu is not None and bm is not None and abs(bu.mass - bm.mass) <= 1e-3 * max(bu.mass, bm.mass)
        ]
        base = Alignment(
            np.eye(4), [JointMap(a, b, self.types[a]) for a, b in self.pairs], matching.couplings, matching.independent
        )
        self.template = base
        zero = np.zeros((1, len(base.independent)))
        self.q = np.vstack([zero, samples]) if len(samples) else zero
        self.full = base.expand(self.q)
        self.pu = poses.urdf(self.full)  # (N, F_u, 4, 4): the URDF never moves with the alignment
        self.scale = max(1.0, float(np.abs(self.pu[:, :, :3, 3]).max()))

    # --- tolerances ---------------------------------------------------------------------------
    def tol(self, frame: str) -> tuple[float, float]:
        pos, rot = self.floors.frame(frame)
        return TOL * self.scale + 2 * pos, TOL + 2 * rot

    def carried_tol(self, joint: str) -> tuple[float, float]:
        """The loosest tolerance of the frames a joint carries and of the next joints' frames (its
        zero offset is measured on them, the next axes first)."""
        carried = [f for f, owner in self.p.u.frame_owner.items() if owner == joint] or [self.p.u.joint(joint).child]
        carried += [self.p.u.joint(c).child for c in self.children.get(joint, [])]
        tols = [self.tol(f) for f in carried]
        return max(t[0] for t in tols), max(t[1] for t in tols)

    # --- state of the MJCF under a hypothesis -------------------------------------------------
    def mjcf_poses(self, signs: dict, offsets: dict, rows=None) -> np.ndarray:
        s = np.array([signs[a] for a, _ in self.pairs], dtype=float)
        o = np.array([offsets[a] for a, _ in self.pairs], dtype=float)
        full = self.full if rows is None else self.full[rows]
        return self.p.mjcf(full * s + o)

    def line(self, side: str, joint: str, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World axis directions and points (N, 3) of a joint over configurations."""
        desc = self.p.u if side == "u" else self.p.m
        idx = self.p.ui if side == "u" else self.p.mi
        a_loc, p_loc = (self.lines_u if side == "u" else self.lines_m)[joint]
        frame = poses[:, idx[desc.joint(joint).child]]
        return frame[:, :3, :3] @ a_loc, frame[:, :3, :3] @ p_loc + frame[:, :3, 3]

    # --- step 2: signs and zero offsets along the chain ---------------------------------------
    def solve_joints(self, t: np.ndarray) -> tuple[dict, dict]:
        signs = {a: 1 for a, _ in self.pairs}
        offsets = {a: 0.0 for a, _ in self.pairs}
        pu0 = self.pu[:1]
        for a, b in self.pairs:
            pm0 = self.mjcf_poses(signs, offsets, rows=slice(0, 1))
            au, pu = self.line("u", a, pu0)
            am, pm = self.line("m", b, pm0)
            au, pu = au[0] @ t[:3, :3].T, _apply(t, pu[0])
            am, pm = am[0], pm[0]
            signs[a] = 1 if float(au @ am) >= 0 else -1
            offset = self._offset(a, b, t, pu0, pm0, au, pu, am, pm)
            ptol, rtol = self.carried_tol(a)
            offsets[a] = offset if abs(offset) > (ptol if self.types[a] == "prismatic" else rtol) else 0.0
        return signs, offsets

    def _features(self, a: str, b: str, t: np.ndarray, pu0, pm0, au, pu, am, pm):
        """(primary, secondary) lists of (mjcf point, urdf point mapped by t), and direction pairs,
        of what joint a/b moves: next joints' axis lines first, then frames and centres of mass."""
        points, dirs, extra = [], [], []
        for c in self.children[a]:
            cm = self.matching.mjcf_name(c)
            cu_a, cu_p = self.line("u", c, pu0)
            cm_a, cm_p = self.line("m", cm, pm0)
            cu_a, cu_p = cu_a[0] @ t[:3, :3].T, _apply(t, cu_p[0])
            if max(np.linalg.norm(np.cross(am, cm_a[0])), np.linalg.norm(np.cross(am, cu_a))) < NEAR_PARALLEL:
                # nearly parallel: the foot of the common perpendicular is ill-conditioned; both
                # lines are taken where they cross one plane across the axis (through the MJCF's anchor)
                points.append((_crossing(pm, am, cm_p[0], cm_a[0]), _crossing(pm, am, cu_p, cu_a)))
            else:
                points.append((foot_on_line(pm, am, cm_p[0], cm_a[0]), foot_on_line(pu, au, cu_p, cu_a)))
            dirs.append((cm_a[0], cu_a))
        for fu, fm, _ in self.frame_pairs:
            if self.p.u.frame_owner.get(fu) == a and self.p.m.frame_owner.get(fm) == b:
                extra.append((pm0[0, self.p.mi[fm], :3, 3], _apply(t, pu0[0, self.p.ui[fu], :3, 3])))
        for bu, bm in self.bodies:
            if bu.owner == a and bm.owner == b:
                xu = _apply(pu0[0, self.p.ui[bu.name]], bu.com_local)
                xm = _apply(pm0[0, self.p.mi[bm.name]], bm.com_local)
                extra.append((xm, _apply(t, xu)))
        return points, dirs, extra

    def _offset(self, a, b, t, pu0, pm0, au, pu, am, pm) -> float:
        """The zero offset of joint a/b that makes what it moves agree, or 0 when no single turn
        (shift) about its axis does."""
        points, dirs, extra = self._features(a, b, t, pu0, pm0, au, pu, am, pm)
        ptol, rtol = self.carried_tol(a)
        if self.types[a] == "prismatic":  # a next axis parallel to it says nothing about a shift along it
            # how far each point moves per metre of shift: along the axis, but where a nearly parallel
            # next axis is taken where it crosses a plane across this one, only the part of the shift
            # across that axis shows (am − dm / (dm·am))
            moved = []
            for pt, (dm, du) in zip(points, dirs, strict=True):
                if np.linalg.norm(np.cross(dm, am)) <= 1e-6:
                    continue
                near = max(np.linalg.norm(np.cross(am, dm)), np.linalg.norm(np.cross(am, du))) < NEAR_PARALLEL
                moved.append((pt, am - dm / float(dm @ am) if near else am))
            pairs = moved + [(pt, am) for pt in extra]
            if all(np.linalg.norm(xm - xu) <= ptol for (xm, xu), _ in pairs):  # agree as they are: no shift needed
                return 0.0
            # the next axes decide when one of them shows the shift in full (as for a turn); frames
            # and centres of mass, which may differ for reasons of their own, only otherwise
            telling = [(x, v) for x, v in moved if float(v @ v) > 0.25]
            judged = moved if telling else pairs
            telling = telling or [(x, v) for x, v in pairs if float(v @ v) > 0.25] or pairs
            shift = consensus([float((xu - xm) @ v) / float(v @ v) for (xm, xu), v in telling], [1.0] * len(telling), linear=True)
            ok = all(np.linalg.norm(xm + shift * v - xu) <= ptol for (xm, xu), v in judged)
            return shift if ok else 0.0
        candidates = []
        for group in (points, extra):
            angles, weights, used = [], [], []
            for xm, xu in group:
                vm, vu = planar(xm - pm, am), planar(xu - pm, am)
                rm, ru = float(np.linalg.norm(vm)), float(np.linalg.norm(vu))
                if min(rm, ru) > 1e-6 * self.scale and abs(rm - ru) <= ptol:
                    angles.append(math.atan2(float(am @ np.cross(vm, vu)), float(vm @ vu)))
                    weights.append(rm * ru)
                    used.append((xm, xu))
            if angles:
                candidates.append((angles, weights, used))
        # the next axes first; but points that near the axis give the angle poorly (an error ε at
        # radius r is ε/r rad): then what it carries further out decides
        usable = [c for c in candidates if max(c[1]) > (LEVER * self.scale) ** 2] or candidates[:1]
        if usable:
            angles, weights, used = usable[0]
            if self._turns_onto(used, 0.0, am, pm, ptol):  # agree within the written precision as they are
                return 0.0  # (a point near the axis turns a rounding error into a large angle)
            theta = consensus(angles, weights)
            return theta if self._turns_onto(used, theta, am, pm, ptol) else 0.0
        # everything it moves is on its axis: the next axes' directions, whose sign is the next
        # joints' own convention, so the smaller of the two turns
        found = []
        for dm, du in dirs:
            vm, vu = planar(dm, am), planar(du, am)
            if np.linalg.norm(vm) > 1e-6 and np.linalg.norm(vu) > 1e-6:
                th = math.atan2(float(am @ np.cross(vm, vu)), float(vm @ vu))
                found.append(min((th, wrap(th + math.pi)), key=abs))
        if found and all(min(np.linalg.norm(dm - du), np.linalg.norm(dm + du)) <= rtol for dm, du in dirs):
            return 0.0
        if found:
            theta = consensus(found, [1.0] * len(found))
            turned = [axis_angle_to_matrix(am, np.array([theta]))[0] @ dm for dm, _ in dirs]
            ok = all(min(np.linalg.norm(x - du), np.linalg.norm(x + du)) <= rtol for x, (_, du) in zip(turned, dirs, strict=True))
            return theta if ok else 0.0
        return 0.0

    @staticmethod
    def _turns_onto(pairs, theta: float, axis, point, tol: float) -> bool:
        """Whether turning by ``theta`` about the axis carries each MJCF point onto its URDF twin,
        across the axis (a turn moves nothing along it; and where a next axis is nearly parallel
        to this one, the foot of their common perpendicular is known across the axis only)."""
        rot = axis_angle_to_matrix(axis, np.array([theta]))[0]
        return all(np.linalg.norm(planar(rot @ (xm - point) + point - xu, axis)) <= tol for xm, xu in pairs)

    # --- step 3: least-squares world transform ------------------------------------------------
    def refit(self, t: np.ndarray, signs: dict, offsets: dict) -> tuple[np.ndarray, list[str]]:
        """Weighted least squares over frame origins and axis lines at every configuration (each
        feature weighted by 1 / its tolerance², so values the files round count less). Features
        that disagree (a frame placed differently, an axis moved) are left out one at a time, the
        worst relative to its tolerance first, until the rest agree."""
        pm = self.mjcf_poses(signs, offsets)
        feats: list[tuple] = []  # (name, kind, urdf data, mjcf data, tolerance)
        for fu, fm, _ in self.frame_pairs:
            feats.append((fu, "point", self.pu[:, self.p.ui[fu], :3, 3], pm[:, self.p.mi[fm], :3, 3], self.tol(fu)))
        for a, b in self.pairs:
            (ua, up), (ma, mp) = self.line("u", a, self.pu), self.line("m", b, pm)
            feats.append((a, "line", (signs[a] * ua, up), (ma, mp), self.tol(self.p.u.joint(a).child)))
        t_all, keep = self._eliminate(feats, list(range(len(feats))), t)
        lines = [i for i, f in enumerate(feats) if f[1] == "line"]
        if 2 * len(keep) < len(feats) and len(lines) >= 2:
            # most features left out: the few kept may be frames that only seem twins (the same name
            # at the root, placed differently). The joints' axis lines alone say where the other
            # file's world is; the larger set of features that agree wins.
            t_lines, _ = self._eliminate(feats, lines, t)
            agree = [i for i in range(len(feats)) if self._residual(feats[i], t_lines) <= 1.0]
            if len(agree) > len(keep):
                t_agree, kept = self._eliminate(feats, agree, t_lines)
                if len(kept) > len(keep):
                    return t_agree, [feats[i][0] for i in kept if feats[i][1] == "point"]
        return t_all, [feats[i][0] for i in keep if feats[i][1] == "point"]

    def _eliminate(self, feats, keep: list[int], t: np.ndarray) -> tuple[np.ndarray, list[int]]:
        """Fit over ``keep``, leaving out the worst feature (relative to its tolerance) one at a
        time until the rest agree or two are left."""
        keep = list(keep)
        while True:
            t = self._fit([feats[i] for i in keep], t)
            ratios = {i: self._residual(feats[i], t) for i in keep}
            worst = max(keep, key=lambda i: ratios[i], default=None)
            if worst is None or ratios[worst] <= 1.0 or len(keep) <= 2:
                return t, keep
            keep.remove(worst)

    @staticmethod
    def _fit(feats, t: np.ndarray) -> np.ndarray:
        src, dst, wp, dsrc, ddst, wd = [], [], [], [], [], []
        for _, kind, a, b, (ptol, rtol) in feats:
            if kind == "point":
                src.append(a)
                dst.append(b)
                wp.append(np.full(len(a), ptol**-2))
            else:
                (ua, up), (ma, mp) = a, b
                src.append(up)
                dst.append(project_on_line(_apply(t, up), mp, ma))
                wp.append(np.full(len(up), ptol**-2))
                dsrc.append(ua)
                ddst.append(ma)
                wd.append(np.full(len(ua), rtol**-2))
        if not src:
            return t
        p, w = np.concatenate(src), np.concatenate(wp)
        # turns the features leave free (all on one axis, all at one point) stay as they are: the
        # current rotation's axes, weighted far below anything the features say
        centre = (w[:, None] * p).sum(axis=0) / w.sum()
        scale = float((w * np.sum((p - centre) ** 2, axis=1)).sum()) + float(sum(x.sum() for x in wd))
        dsrc.append(np.eye(3))
        ddst.append(t[:3, :3].T)
        wd.append(np.full(3, 1e-10 * scale + 1e-300))
        first = kabsch(p, np.concatenate(dst), w, np.concatenate(dsrc), np.concatenate(ddst), np.concatenate(wd))
        return _gauss_newton(feats, first)

    @staticmethod
    def _residual(feat, t: np.ndarray) -> float:
        """A feature's largest error under T, relative to its tolerance."""
        _, kind, a, b, (ptol, rtol) = feat
        if kind == "point":
            return float(np.linalg.norm(_apply(t, a) - b, axis=-1).max()) / ptol
        (ua, up), (ma, mp) = a, b
        up_t = _apply(t, up)
        dist = float(np.linalg.norm(up_t - project_on_line(up_t, mp, ma), axis=-1).max())
        ua_t = ua @ t[:3, :3].T
        angle = float(np.arctan2(np.linalg.norm(np.cross(ua_t, ma), axis=-1), np.sum(ua_t * ma, axis=-1)).max())
        return max(dist / ptol, angle / rtol)

    # --- step 4: scoring ----------------------------------------------------------------------
    def evaluate(self, t: np.ndarray, signs: dict, offsets: dict) -> tuple[int, list[FrameFit], dict]:
        pm = self.mjcf_poses(signs, offsets)
        bad = 0
        axis_errors = {}
        for a, b in self.pairs:
            (ua, up), (ma, mp) = self.line("u", a, self.pu), self.line("m", b, pm)
            ua, up = signs[a] * ua @ t[:3, :3].T, _apply(t, up)
            angle = float(np.arctan2(np.linalg.norm(np.cross(ua, ma), axis=-1), np.sum(ua * ma, axis=-1)).max())
            dist = float(np.linalg.norm(up - project_on_line(up, mp, ma), axis=-1).max())
            axis_errors[a] = (angle, dist)
            ptol, rtol = self.tol(self.p.u.joint(a).child)
            bad += (angle > rtol) + (dist > ptol)
        fits = []
        tinv = invert_transform(t)
        for fu, fm, why in self.frame_pairs:
            a_pose = self.pu[:, self.p.ui[fu]]
            b_pose = tinv @ pm[:, self.p.mi[fm]]
            pos = float(np.linalg.norm(a_pose[:, :3, 3] - b_pose[:, :3, 3], axis=-1).max())
            rot = float(geodesic_distance(a_pose[:, :3, :3], b_pose[:, :3, :3]).max())
            const = invert_transform(b_pose[0]) @ a_pose[0]
            c_pose = b_pose @ const
            rpos = float(np.linalg.norm(a_pose[:, :3, 3] - c_pose[:, :3, 3], axis=-1).max())
            rrot = float(geodesic_distance(a_pose[:, :3, :3], c_pose[:, :3, :3]).max())
            ptol, _ = self.tol(fu)
            bad += pos > ptol
            fits.append(FrameFit(fu, fm, why, pos, rot, const, rpos, rrot, False))
        for bu, bm in self.bodies:
            xu = _carry(self.pu[:, self.p.ui[bu.name]], bu.com_local)
            xm = _carry(tinv @ pm[:, self.p.mi[bm.name]], bm.com_local)
            bad += float(np.linalg.norm(xu - xm, axis=-1).max()) > self.tol(bu.name)[0] + self.floors.com * 2
        return int(bad), fits, axis_errors

    def root_orientation_mismatch(self, t: np.ndarray) -> int:
        out = 0
        tinv = invert_transform(t)
        for fu, fm, _ in self.frame_pairs:
            if self.p.u.frame_owner.get(fu) is None and self.p.m.frame_owner.get(fm) is None:
                rot = float(geodesic_distance((tinv @ self.p.m.frames[fm])[:3, :3], self.p.u.frames[fu][:3, :3]))
                out += rot > self.tol(fu)[1]
        return out

    def candidates(self) -> list[tuple[str, np.ndarray]]:
        out = [("identity", np.eye(4))]
        zero = {a: 1 for a, _ in self.pairs}
        pm = self.mjcf_poses(zero, {a: 0.0 for a, _ in self.pairs})
        if self.frame_pairs:
            src = np.concatenate([self.pu[:, self.p.ui[fu], :3, 3] for fu, _, _ in self.frame_pairs])
            dst = np.concatenate([pm[:, self.p.mi[fm], :3, 3] for _, fm, _ in self.frame_pairs])
            if len(src) >= 3:
                out.append(("least squares over frame origins", kabsch(src, dst)))
        for fu, fm, _ in self.frame_pairs:
            if self.p.u.frame_owner.get(fu) is None and self.p.m.frame_owner.get(fm) is None:
                out.append((f"root frame {fu}", self.p.m.frames[fm] @ invert_transform(self.p.u.frames[fu])))
        roots = [(a, b) for a, b in self.pairs if self.p.u.joint(a).parent is None]
        if roots:
            a, b = roots[0]
            (ua, up), (ma, mp) = self.line("u", a, self.pu[:1]), self.line("m", b, pm[:1])
            for sign in (1, -1):
                rot = rotation_between(ua[0], sign * ma[0])
                t = np.eye(4)
                t[:3, :3] = rot
                t[:3, 3] = mp[0] - rot @ up[0]
                out.append((f"axis of {a}" + (" reversed" if sign < 0 else ""), t))
        return out

    def simplest(self, t: np.ndarray, signs: dict, offsets: dict, keep_t: bool = False):
        """Drop each explanation (the world transform unless ``keep_t``, a zero offset) that the
        features do not need: rounding must not pass for a turn of the world or of a joint, nor a
        joint's other difference (its axis tilted) for a zero offset. An explanation is kept only
        where dropping it leaves more differences: the tie goes to the fewer explanations."""
        if _is_identity(t, self.scale) and not keep_t:
            t = np.eye(4)
        bad, fits, axis_errors = self.evaluate(t, signs, offsets)
        if not keep_t and not _is_identity(t, self.scale):
            trial = self.evaluate(np.eye(4), signs, offsets)
            if trial[0] <= bad:
                t, (bad, fits, axis_errors) = np.eye(4), trial
        for a in [a for a, o in offsets.items() if o]:
            trial_offsets = {**offsets, a: 0.0}
            trial = self.evaluate(t, signs, trial_offsets)
            if trial[0] <= bad:
                offsets, (bad, fits, axis_errors) = trial_offsets, trial
        return t, offsets, bad, fits, axis_errors

    def solve(self, candidates=None, refit: bool = True) -> Alignment:
        """The best of ``candidates`` (default :meth:`candidates`), each refined by refitting ``T``
        (``refit``; else ``T`` is kept as given and only the joints are solved)."""
        best, best_key = None, None
        for label, t in candidates or self.candidates():
            signs, offsets = self.solve_joints(t)
            used = [fu for fu, _, _ in self.frame_pairs]
            if refit:
                for _ in range(2):
                    t, used = self.refit(t, signs, offsets)
                    signs, offsets = self.solve_joints(t)
                t, used = self.refit(t, signs, offsets)
                t, offsets, bad, fits, axis_errors = self.simplest(t, signs, offsets)
                if _is_identity(t, self.scale):  # solved again on the exact T, not the refit's round-off,
                    # each offset again kept only where it explains a difference (the tie goes to none)
                    signs2, offsets2 = self.solve_joints(t)
                    _, offsets2, *trial = self.simplest(t, signs2, offsets2)
                    if trial[0] <= bad:
                        signs, offsets, (bad, fits, axis_errors) = signs2, offsets2, trial
            else:
                t, offsets, bad, fits, axis_errors = self.simplest(t, signs, offsets, keep_t=True)
            n_explain = (
                int(not _is_identity(t, self.scale))
                + sum(s < 0 for s in signs.values())
                + sum(abs(o) > TOL for o in offsets.values())
            )
            root_offsets = sum(abs(offsets[a]) > TOL for a, _ in self.pairs if self.p.u.joint(a).parent is None)
            key = (
                bad,
                n_explain,
                self.root_orientation_mismatch(t),
                root_offsets,
                float(geodesic_distance(t[:3, :3], np.eye(3))),
            )
            if best_key is None or key < best_key:
                best_key = key
                used_set = set(used)
                for f in fits:
                    f.in_fit = f.urdf in used_set
                joints = [JointMap(a, b, self.types[a], signs[a], offsets[a]) for a, b in self.pairs]
                kept = [f for f in fits if f.in_fit]
                residual = (
                    max([f.position for f in kept] + [e[1] for e in axis_errors.values()], default=0.0),
                    max([e[0] for e in axis_errors.values()], default=0.0),
                )
                best = Alignment(
                    t, joints, self.matching.couplings, self.matching.independent, fits, axis_errors, residual, label, bad
                )
        assert best is not None  # candidates() is never empty (identity first)
        return best


def _is_identity(t: np.ndarray, scale: float) -> bool:
    return float(np.abs(t[:3, 3]).max()) <= TOL * scale and float(geodesic_distance(t[:3, :3], np.eye(3))) <= TOL


def align(poses: PairPoses, matching: Matching, floors: Floors, samples: np.ndarray, base_fixes_frame: bool = False) -> Alignment:
    """The best alignment of the MJCF onto the URDF (see the module docstring). ``base_fixes_frame``
    (both files float): the base bodies fix the frame, both at the same base coordinates, so ``T``
    stays the identity unless another transform explains every feature (a base frame the files
    define differently); a fit that leaves differences would only move them from leg to leg."""
    aligner = Aligner(poses, matching, floors, samples)
    if not base_fixes_frame:
        return aligner.solve()
    fixed = aligner.solve(candidates=[("base frames", np.eye(4))], refit=False)
    if fixed.unexplained == 0:
        return fixed
    fitted = aligner.solve()
    return fitted if fitted.unexplained == 0 else fixed
