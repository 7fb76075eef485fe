"""The alignment stage: the configurations it fits over, the fit itself (compared unaligned, with
an internal error, should it fail), and every frame of both files at the aligned zero."""

from __future__ import annotations

import copy
import dataclasses
import math

import numpy as np

from kinverify.errors import KinverifyError
from kinverify.filemode.align.attribution import attribute, findings_count
from kinverify.filemode.align.fit import TOL, Aligner, align
from kinverify.filemode.align.match import Matching
from kinverify.filemode.align.result import Alignment, FrameFit, JointMap, PairPoses
from kinverify.filemode.read.model import ModelDesc

OPEN_RANGE = {"revolute": math.pi, "prismatic": 0.5}  # sampled range of a joint without limits


def sample_ranges(u: ModelDesc, joints) -> tuple[list, list, list]:
    lower, upper, revolute = [], [], []
    for name in joints:
        j = u.joint(name)
        span = OPEN_RANGE[j.type]
        lo, up = (j.lower, j.upper) if math.isfinite(j.lower) and math.isfinite(j.upper) and j.lower < j.upper else (-span, span)
        lower.append(lo)
        upper.append(up)
        revolute.append(j.type == "revolute")
    return lower, upper, revolute


def identity_alignment(u: ModelDesc, matching: Matching) -> Alignment:
    return Alignment(
        np.eye(4), [JointMap(a, b, u.joint(a).type) for a, b, _ in matching.joints], matching.couplings, matching.independent
    )


def run_alignment(
    u, m, matching, urdf_text, mjcf_text, library, floors, samples, internal: list, base_fixes_frame: bool = False
) -> tuple[Alignment, PairPoses]:
    poses = PairPoses(u, m, matching, urdf_text, mjcf_text, library)
    try:
        return align(poses, matching, floors, samples, base_fixes_frame), poses
    except (KinverifyError, KeyboardInterrupt):
        raise
    except Exception as err:  # our bug: compare unaligned, say so
        internal.append(f"alignment: {type(err).__name__}: {err}")
        return identity_alignment(u, matching), poses


def zero_poses(poses: PairPoses, al: Alignment) -> tuple[dict, dict]:
    """Every frame of each file at the aligned zero (the MJCF's in its own world)."""
    zero = al.expand(np.zeros((1, len(al.independent))))
    pu, pm = poses.urdf(zero)[0], poses.mjcf(al.to_mjcf(zero))[0]
    return {f: pu[i] for f, i in poses.ui.items()}, {f: pm[i] for f, i in poses.mi.items()}


def add_frames(al: Alignment, pairs) -> None:
    """Frames matched after the alignment (same place, no same-named twin): they coincide."""
    for fu, fm, why in pairs:
        al.frames.append(FrameFit(fu, fm, why, 0.0, 0.0, np.eye(4), 0.0, 0.0, False))


def unmoved_world(info, poses: PairPoses, samples: np.ndarray):
    """``info`` (:class:`kinverify.filemode.compare.context.FileModeInfo`), or the same files aligned
    with the worlds as they are (no world transform) when that leaves fewer differences to report:
    a fixed-base robot whose base the MJCF merges into its world has nothing but its joints to
    place that world by, and a fitted turn may only stand for the first joint's own change (its
    axis tilted, its frame moved), which attribution then says once.

    Ties: where a frame that no joint moves is matched in both files (the base link has a body of
    its own in each), the fit is kept: a file places the robot elsewhere. Where the base link has
    no frame of its own in one file (merged into its world, as MuJoCo writes a fixed base), both
    files state the first bodies' poses from the base link, that is the world: what differs is
    those joints' frames, and the worlds as they are win."""
    t = info.alignment.T
    if float(np.abs(t[:3, 3]).max()) <= TOL and float(np.abs(t[:3, :3] - np.eye(3)).max()) <= TOL:
        return info
    alt = Aligner(poses, info.matching, info.floors, samples).solve(candidates=[("identity", np.eye(4))], refit=False)
    other = dataclasses.replace(info, alignment=alt, notes=list(info.notes))
    other.poses_u, other.poses_m = zero_poses(poses, alt)
    mine, fitted = _count(other), _count(info)
    return other if mine < fitted or (mine == fitted and not base_in_both(info)) else info


def base_in_both(info) -> bool:
    """Whether a frame that no joint moves in either file (a fixed base's link, body or site) is
    matched in both: the base has a frame of its own in each, to place the world by."""
    u, m = info.u, info.m
    return any(u.frame_owner.get(fu, "") is None and m.frame_owner.get(fm, "") is None for fu, fm, _ in info.matching.frames)


def _count(info) -> int:
    """:func:`findings_count` of ``info``, its alignment left as it is (attribution may fold a zero offset)."""
    trial = dataclasses.replace(info, alignment=copy.deepcopy(info.alignment))
    trial.alignment.attribution = attribute(trial)
    return findings_count(trial)
