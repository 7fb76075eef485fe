"""The findings of the alignment: the world transform, zero offsets, sign flips, axes that still
differ, frame conventions, renamed joints, lengths in other units.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from kinverify.filemode.align.match import Matching
from kinverify.filemode.align.result import Alignment
from kinverify.filemode.findings.couplings import written_alike
from kinverify.filemode.findings.own_zero import sign_flip_finding, zero_offset_finding
from kinverify.filemode.findings.table import finding, fmt, unit_factor
from kinverify.filemode.read.model import ModelDesc
from kinverify.model.transforms import geodesic_distance, matrix_to_rpy
from kinverify.suites.base import Finding


def _angle(t: np.ndarray) -> float:
    return float(geodesic_distance(t[:3, :3], np.eye(3)))


def _downstream(u: ModelDesc, joint: str) -> list[str]:
    """Frames that move with ``joint`` or a joint below it."""
    parent = {j.name: j.parent for j in u.joints}

    def below(owner):
        while owner is not None:
            if owner == joint:
                return True
            owner = parent.get(owner)
        return False

    return [f for f, owner in u.frame_owner.items() if below(owner)]


def origin_findings(att, frames: list[str], names: dict) -> list[Finding]:
    """A joint's frame that sits elsewhere on its parent (see :mod:`kinverify.filemode.align.attribution`):
    one finding for where it moved (the full offset vector, along its axis too), one for how it turned
    (axis and angle: the tilt of its axis and the twist about it together); what it carries moved with it."""
    out = []
    where = f" on {att.parent_frame}" if att.parent_frame else " in the world"
    if att.merged_base:  # both files place the frame from the base: the URDF's link, the MJCF's world
        where += f" (the URDF's on its base link {att.merged_base}, which the MJCF merges into its world"
        # the URDF places that link in its world, the MJCF states no such placement: the placement
        # differing is the same difference, said here rather than as a second finding
        where += ("; equally, where the URDF places that base link in its world" if att.base_placed else "") + ")"
    carried = ": everything it carries moved with it" if len(frames) > 1 else ""
    if att.moved is not None:
        size = float(np.linalg.norm(att.moved))
        out.append(
            finding(
                "joint_origin_moved",
                f"joint {names['joint']}/{names['mjcf_joint']}: its frame sits {size:.4g} m "
                f"from the URDF's{where} (moved by xyz {fmt(att.moved)} m in {att.parent_frame or 'world'} axes)"
                f"{carried}",
                {"xyz": att.moved.tolist(), "distance_m": size, "frames": frames},
                magnitude=size,
                unit="m",
                **names,
            )
        )
    if att.turn is not None:
        angle = float(np.linalg.norm(att.turn))
        axis = att.turn / angle
        tilt, twist = (math.degrees(x) for x in att.tilt_twist)
        folded = f"; the {att.folded:.6g} rad a zero offset would take is part of it" if att.folded else ""
        out.append(
            finding(
                "joint_origin_turned",
                f"joint {names['joint']}/{names['mjcf_joint']}: its frame is turned by "
                f"{angle:.4g} rad ({math.degrees(angle):.4g}°) about {fmt(axis)} (its own axes) from the URDF's{where} "
                f"(its axis tilted {tilt:.4g}° and turned {twist:.4g}° about itself{folded}){carried}",
                {
                    "angle_rad": angle,
                    "axis": axis.tolist(),
                    "rotation_vector": att.turn.tolist(),
                    "tilt_rad": att.tilt_twist[0],
                    "twist_rad": att.tilt_twist[1],
                    "zero_offset": att.folded,
                    "frames": frames,
                },
                magnitude=angle,
                unit="rad",
                **names,
            )
        )
    return out


ALIKE = ("axis_position", "axis_direction", "joint_origin_moved", "joint_origin_turned")


def _alike_axes(findings: list[Finding]) -> list[Finding]:
    """Joints whose axes or frames differ the same way (the four legs of a robot, to 4 significant
    digits) as one finding naming them all (a moved frame's offset vector of each in ``xyz_each``)."""
    groups: dict[tuple, list[Finding]] = {}
    for f in findings:
        if f.kind in ALIKE:
            groups.setdefault((f.kind, float(f"{f.magnitude:.4g}")), []).append(f)
    out = []
    for f in findings:
        same = groups.get((f.kind, float(f"{f.magnitude:.4g}")), [f]) if f.kind in ALIKE else [f]
        if len(same) < 2 or f not in same:
            out.append(f)
        elif f is same[0]:
            joints, others = [x.subject for x in same], [x.other for x in same]
            what = f.message.split(": ", 1)[1]
            values = {**f.values, "frames": [fr for x in same for fr in x.values["frames"]]}
            if f.kind == "joint_origin_moved":
                what = (
                    f"each frame sits {f.magnitude:.4g} m from the URDF's on its parent (xyz "
                    + ", ".join(fmt(x.values["xyz"]) for x in same)
                    + " m in the parents' axes)"
                )
                values["xyz_each"] = [x.values["xyz"] for x in same]
            elif f.kind == "joint_origin_turned":
                what = f"each frame is turned by {f.magnitude:.4g} rad ({math.degrees(f.magnitude or 0.0):.4g}°) from the URDF's"
                values["axis_each"] = [x.values["axis"] for x in same]
            out.append(
                finding(
                    f.kind,
                    f"{len(same)} joints alike: {', '.join(joints)}: {what}",
                    values,
                    magnitude=f.magnitude,
                    unit=f.unit,
                    joint=joints,
                    mjcf_joint=others,
                )
            )
    return out


def alignment_findings(
    u: ModelDesc, m: ModelDesc, matching: Matching, al: Alignment, compared: list[str], tol, limit_tol: float = 1e-9
) -> list[Finding]:
    """One finding per thing alignment solved: the world transform, each zero offset and sign
    flip (the checks compare after them), each axis that still differs (``values["frames"]``: the
    compared frames whose failing checks it explains), the joint-name mapping.
    ``compared``: the URDF frames the kinematics checks compare;
    ``tol(frame)``: (position, rotation) tolerance there; ``limit_tol``: the limits check's."""
    out = []
    coupled = written_alike(u, m, matching, al)
    t = al.T
    dist, ang = float(np.linalg.norm(t[:3, 3])), _angle(t)
    if dist > 1e-9 * max(1.0, dist) or ang > 1e-9:
        noise = 1e-9 * max(1.0, dist)  # double precision at the size of the move: below it a value is zero
        t = np.where(np.abs(t) < noise, 0.0, t)
        xyz = np.where(np.abs(t[:3, 3]) < noise, 0.0, t[:3, 3]).tolist()
        rpy = np.where(np.abs(r := matrix_to_rpy(t[:3, :3])) < noise, 0.0, r).tolist()
        dist = dist if dist >= noise else 0.0
        out.append(
            finding(
                "base_transform",
                f"the MJCF's world is the URDF's moved by xyz = {fmt(xyz)} m, rpy = {fmt(rpy)} rad "
                f"({math.degrees(ang):.4g}° turn): the same joint values put the robot elsewhere in the world; "
                f"fitted over {len(al.frames)} frames and {len(al.joints)} axes, residual {al.residual[0]:.2g} m, "
                f"{al.residual[1]:.2g} rad",
                {
                    "T_mjcf_from_urdf": t.tolist(),
                    "xyz": xyz,
                    "rpy": rpy,
                    "translation_m": dist,
                    "rotation_rad": ang,
                    "residual_m": al.residual[0],
                    "residual_rad": al.residual[1],
                },
                magnitude=max(dist, ang),
                unit="m|rad",
            )
        )
    differs: set[str] = set()
    for j in al.joints:
        names: dict[str, Any] = {"joint": j.urdf, "mjcf_joint": j.mjcf}
        frames = [f for f in _downstream(u, j.urdf) if f in compared]
        if j.sign < 0:
            out.append(sign_flip_finding(u, m, j, frames, names, limit_tol))
        att = al.attribution.get(j.urdf)
        if j.offset:
            out.append(zero_offset_finding(u, m, j, frames, names, limit_tol, coupled))
        uj, mj = u.joint(j.urdf), m.joint(j.mjcf)
        upstream = uj.parent
        while upstream is not None and upstream not in differs:
            upstream = u.joint(upstream).parent
        if uj.type != mj.type:
            differs.add(j.urdf)
            out.append(
                finding(
                    "type_difference",
                    f"joint {j.urdf}/{j.mjcf}: {uj.type} in the URDF, {mj.type} in the MJCF",
                    {"urdf": uj.type, "mjcf": mj.type, "frames": frames},
                    **names,
                )
            )
            continue
        if att is not None and att.changed:
            differs.add(j.urdf)
            out += origin_findings(att, frames, names)
        after = " (and everything it moves with it)" if any(f != uj.child for f in frames) else ""
        angle, distance = att.axis if att is not None else al.axis_errors.get(j.urdf, (0.0, 0.0))
        how = f" after alignment{after}"
        if upstream is not None and att is not None:  # measured in its own right: what the joints above change taken out
            how = f" in its own right, after what {upstream} changes above it{after}"
        ptol, rtol = tol(uj.child)
        if angle > rtol:
            differs.add(j.urdf)
            out.append(
                finding(
                    "axis_direction",
                    f"joint {j.urdf}/{j.mjcf}: the axes differ by {angle:.4g} rad ({math.degrees(angle):.4g}°){how}",
                    {"angle_rad": angle, "frames": frames},
                    magnitude=angle,
                    unit="rad",
                    **names,
                )
            )
        elif distance > ptol:
            differs.add(j.urdf)
            out.append(
                finding(
                    "axis_position",
                    f"joint {j.urdf}/{j.mjcf}: the axis lines are {distance:.4g} m apart{how}",
                    {"distance_m": distance, "frames": frames},
                    magnitude=distance,
                    unit="m",
                    **names,
                )
            )
    out = _alike_axes(out)
    renamed = [(a, b, how) for a, b, how in matching.joints if a != b]
    if renamed:
        hows = sorted({how for _, _, how in renamed})
        out.append(
            finding(
                "joint_names",
                f"{len(renamed)} joints have other names in the MJCF (matched by {', '.join(hows)}): "
                + ", ".join(f"{a}={b}" for a, b, _ in renamed),
                {"pairs": [[a, b, h] for a, b, h in renamed]},
                joint=[a for a, _, _ in renamed],
                mjcf_joint=[b for _, b, _ in renamed],
            )
        )
    return out


def convention_findings(al: Alignment, kinds: dict[str, str], tol, moved=frozenset()) -> list[Finding]:
    """A matched frame whose pose differs by a constant while its joint and motion agree: a link
    frame is the files' choice (info); a named frame (a site, a tool frame) placed elsewhere is a
    difference (error). ``kinds``: URDF frame -> "link" or "site" (from the MJCF side); ``moved``:
    frames a joint that differs already moves (a finding says so: no convention to claim there)."""
    out = []
    for f in al.frames:
        if f.urdf in moved:
            continue
        ptol, rtol = tol(f.urdf)
        if f.position <= ptol and f.rotation <= rtol:
            continue
        if f.residual_position > ptol or f.residual_rotation > rtol:
            continue  # not a constant: an unexplained difference, reported where it starts
        shift = float(np.linalg.norm(f.constant[:3, 3]))
        angle = _angle(f.constant)
        values = {
            "translation_m": shift,
            "rotation_rad": angle,
            "xyz": f.constant[:3, 3].tolist(),
            "rpy": matrix_to_rpy(f.constant[:3, :3]).tolist(),
            "frames": [f.urdf],
        }
        names: dict[str, Any] = {"frame": f.urdf, "mjcf_frame": f.mjcf}
        if kinds.get(f.urdf) == "site" and shift > ptol and f.why in ("same name", "given"):
            out.append(
                finding(
                    "frame_offset",
                    f"frame {f.urdf}/{f.mjcf}: placed {shift:.4g} m and {angle:.4g} rad away from "
                    f"the other file's, on the same link (xyz {fmt(f.constant[:3, 3])} in its own axes)",
                    values,
                    magnitude=shift,
                    unit="m",
                    **names,
                )
            )
        elif kinds.get(f.urdf) == "site" and shift > ptol:  # a name alike is no proof of one frame: said, not blamed
            out.append(
                finding(
                    "frame_twin",
                    f"URDF frame {f.urdf} and the MJCF's site {f.mjcf} have similar names but sit "
                    f"{shift:.4g} m and {angle:.4g} rad apart on the same link: not taken for one frame (compared "
                    "after removing that offset)",
                    values,
                    magnitude=shift,
                    unit="m",
                    **names,
                )
            )
        else:
            out.append(
                finding(
                    "frame_convention",
                    f"frame {f.urdf}/{f.mjcf}: the files define this frame differently, by a "
                    f"constant {angle:.4g} rad ({math.degrees(angle):.4g}°) and {shift:.4g} m (rpy {fmt(values['rpy'])}, "
                    f"xyz {fmt(values['xyz'])}); the joint and its motion agree, so it is compared after removing "
                    "that constant",
                    values,
                    magnitude=angle if angle > rtol else shift,
                    unit="rad" if angle > rtol else "m",
                    **names,
                )
            )
    return out


def length_units(u: ModelDesc, m: ModelDesc, matching: Matching, compared: list[str]) -> list[Finding]:
    """The MJCF's lengths a constant multiple of the URDF's (a units mistake): one finding."""
    lu = lm = 0.0
    for a, b, _ in matching.joints:
        ju, jm = u.joint(a), m.joint(b)
        if ju.parent is not None and jm.parent is not None:
            lu += float(np.linalg.norm(u.frames[ju.child][:3, 3] - u.frames[u.joint(ju.parent).child][:3, 3]))
            lm += float(np.linalg.norm(m.frames[jm.child][:3, 3] - m.frames[m.joint(jm.parent).child][:3, 3]))
    if lu <= 1e-9 or lm <= 1e-9 or abs(lm / lu - 1) < 1e-2:
        return []
    name = unit_factor(lm / lu, "length")
    if name is None:
        return []
    return [
        finding(
            "length_units",
            f"the MJCF's lengths are the URDF's {name}: every link is {lm / lu:.6g} times as long",
            {
                "ratio": lm / lu,
                "frames": compared,
                "checks": [[p, "rigid bodies"] for p in ("inertia.mass", "inertia.com", "inertia.tensor")],
            },
            magnitude=lm / lu,
            unit="",
        )
    ]
