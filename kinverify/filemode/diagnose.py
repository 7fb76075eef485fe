"""Diagnosis: what differs between the URDF's and the MJCF's description, named, with evidence.

Every finding is plain JSON: ``{"kind", "message", "joint"/"link"/"frame" (URDF name) and
"mjcf_joint"/"mjcf_link"/"mjcf_frame", "values": {...}}``. Geometry is compared at q = 0 in the
MJCF's world frame after removing the base transform, and again relative to the joint's parent
frame: a joint is blamed only when both disagree, so one upstream error is not repeated down the
chain (where the disagreement starts is reported once, by frame).
"""

from __future__ import annotations

import math

import numpy as np

from kinverify.model.transforms import invert_transform, rotation_angle, rotation_vee
from kinverify.suites.base import Finding
from kinverify.filemode.describe import ModelDesc
from kinverify.filemode.geometry import angle_between, apply, composite_inertials, frame_pose, line_distance, pose_difference, rpy_string, to_frame
from kinverify.filemode.match import Matching
from kinverify.filemode.rounding import rounded_constants, rounded_from

POS_TOL = 1e-9  # m
ANG_TOL = 1e-9  # rad
REL_TOL = 1e-6  # masses, damping...
INERTIA_REL = 1e-5  # MuJoCo diagonalises inertia tensors to about 1e-6 relative


# Severity of each kind of finding. Errors fail the verdict unless accepted: what the two files
# say differently about the robot's kinematics, limits, inertia or joint dynamics. Warnings: a
# file or value one library cannot read, a quantity one format cannot express. Infos: rounding,
# conventions and known library quirks that change nothing physical.
SEVERITY = {
    "base_transform": "error", "disagreement_starts": "error", "axis_sign_flip": "error", "axis_direction": "error",
    "axis_position": "error", "zero_offset": "error", "frame_offset": "error", "type_difference": "error",
    "limit_difference": "error", "limits_degrees_as_radians": "error", "mass_difference": "error",
    "com_difference": "error", "inertia_difference": "error", "inertia_rotated": "error", "damping_difference": "error",
    "friction_difference": "error", "effort_difference": "error", "armature_difference": "error",
    "unmatched_joint": "error",
    "parser_refused": "warning", "parser_disagreement": "warning", "inexpressible": "warning",
    "velocity_difference": "warning",
    "frame_convention": "info", "rounding": "info", "parser_quirk": "info",
}
SUBJECTS = ("joint", "link", "frame")


def finding(kind: str, message: str, values: dict | None = None, **names) -> Finding:
    """A :class:`Finding` of ``kind`` (severity from ``SEVERITY``); ``names``: ``joint``/``link``/
    ``frame`` (URDF name) and ``mjcf_joint``/``mjcf_link``/``mjcf_frame`` (its MJCF name)."""
    values = dict(values or {})
    subject_type = next((k for k in SUBJECTS if names.get(k) is not None), "file" if "file" in values else "model")
    subject = names.get(subject_type) or str(values.get("file", ""))
    other = names.get(f"mjcf_{subject_type}") or ""
    return Finding(kind, SEVERITY.get(kind, "warning"), message, subject, subject_type, other, values=values)


def base_transform(u: ModelDesc, m: ModelDesc, matching: Matching) -> np.ndarray:
    """T_mjcfworld_from_urdfworld: where each file puts the frame the first common joint hangs from."""
    a, b, _ = matching.joints[0]
    return frame_pose(m, m.joint(b).parent_frame) @ invert_transform(frame_pose(u, u.joint(a).parent_frame))


def diagnose_base(t_base: np.ndarray, residual: tuple[float, float] | None) -> list[dict]:
    dist, ang = float(np.linalg.norm(t_base[:3, 3])), float(rotation_angle(t_base[:3, :3]))
    if dist <= POS_TOL and ang <= ANG_TOL:
        return []
    xyz, rpy = [float(v) for v in t_base[:3, 3]], rpy_string(t_base[:3, :3])
    values = {"xyz": xyz, "rpy": rpy, "translation_m": dist, "rotation_rad": ang}
    msg = (f"constant base transform between the world frames: MJCF world from URDF world xyz = "
           f"[{', '.join(f'{v:.6g}' for v in xyz)}] m, rpy = [{', '.join(f'{v:.6g}' for v in rpy)}] rad")
    if residual is not None:
        values["residual_position_m"], values["residual_rotation_rad"] = residual
        msg += f"; after removing it the frames differ by at most {residual[0]:.3g} m, {residual[1]:.3g} rad"
    return [finding("base_transform", msg, values)]


def _below(u: ModelDesc, joint: str, differing: set) -> bool:
    """Does a compared frame downstream of ``joint``'s moving frame differ (after the base transform)?"""
    parent = {j.name: j.parent for j in u.joints}

    def descends(owner):
        while owner is not None:
            if owner == joint:
                return True
            owner = parent.get(owner)
        return False

    child = u.joint(joint).child
    return any(f != child and descends(u.frame_owner.get(f)) for f in differing)


def diagnose_joints(u: ModelDesc, m: ModelDesc, matching: Matching, t_base: np.ndarray, differing: set) -> list[dict]:
    out = []
    for a, b, _ in matching.joints:
        ju, jm = u.joint(a), m.joint(b)
        names = {"joint": a, "mjcf_joint": b}
        if ju.type != jm.type:
            out.append(finding("type_difference", f"joint {a}/{b}: {ju.type} in the URDF, {jm.type} in the MJCF",
                               {"urdf": ju.type, "mjcf": jm.type}, **names))
        c = frame_pose(m, jm.parent_frame) @ invert_transform(frame_pose(u, ju.parent_frame))
        world_axis, world_anchor = t_base[:3, :3] @ ju.axis, apply(t_base, ju.anchor)
        rel_axis, rel_anchor = c[:3, :3] @ ju.axis, apply(c, ju.anchor)
        world_angle, rel_angle = angle_between(world_axis, jm.axis), angle_between(rel_axis, jm.axis)
        dist_w = line_distance(world_anchor, world_axis, jm.anchor, jm.axis)
        dist_r = line_distance(rel_anchor, rel_axis, jm.anchor, jm.axis)
        flipped = rel_angle > math.pi - 1e-6
        axes = {"urdf_axis": [float(v) for v in rel_axis], "mjcf_axis": [float(v) for v in jm.axis]}
        if flipped and world_angle > math.pi - 1e-6:
            out.append(finding("axis_sign_flip", f"joint {a}/{b}: axis sign flipped (URDF axis {_vec(rel_axis)} is "
                               f"MJCF axis {_vec(jm.axis)} reversed): the same q turns the other way", axes, **names))
        elif rel_angle > ANG_TOL and world_angle > ANG_TOL and not flipped:
            out.append(finding("axis_direction", f"joint {a}/{b}: axis directions differ by {rel_angle:.3g} rad "
                               f"({math.degrees(rel_angle):.3g} deg)", {**axes, "angle_rad": rel_angle}, **names))
        if dist_r > POS_TOL and dist_w > POS_TOL:
            out.append(finding("axis_position", f"joint {a}/{b}: axis lines are {dist_r:.3g} m apart",
                               {"distance_m": dist_r, "urdf_point": [float(v) for v in rel_anchor],
                                "mjcf_point": [float(v) for v in jm.anchor]}, **names))
        # The moving frames at q = 0, relative to the parent frames: a rotation about the joint axis
        # that carries on downstream is a zero offset; otherwise only this frame is defined differently.
        delta = c @ frame_pose(u, ju.child) @ invert_transform(frame_pose(m, jm.child))
        shift, angle = pose_difference(c @ frame_pose(u, ju.child), frame_pose(m, jm.child))
        if angle <= ANG_TOL and shift <= POS_TOL:
            continue
        about_axis = (np.linalg.norm(delta[:3, :3] @ jm.axis - jm.axis) < 1e-6
                      and np.linalg.norm(apply(delta, jm.anchor) - jm.anchor) < 1e-6)
        if ju.type == "revolute" and about_axis and rel_angle < 1e-6 and dist_r < 1e-6 and _below(u, a, differing):
            offset = angle if np.dot(rotation_vee(delta[:3, :3]), jm.axis) >= 0 else -angle
            out.append(finding("zero_offset", f"joint {a}/{b}: zero offset of {offset:.6g} rad ({math.degrees(offset):.4g} deg): "
                               f"at the same q the URDF link is turned by that much about the axis relative to the MJCF body",
                               {"offset_rad": offset, "offset_deg": math.degrees(offset)}, **names))
        elif not _below(u, a, differing):
            out.append(finding("frame_convention", f"joint {a}/{b}: the URDF link frame {ju.child} and the MJCF body frame "
                               f"{jm.child} differ by a constant {angle:.3g} rad, {shift:.3g} m, but the joint and everything "
                               "after it agree: only poses reported in this frame differ",
                               {"rotation_rad": angle, "translation_m": shift, "rpy": rpy_string(delta[:3, :3])}, **names))
    return out


def _vec(v) -> str:
    return "[" + ", ".join(f"{x:.4g}" + "" for x in np.where(np.abs(v) < 5e-13, 0.0, v)) + "]"


def diagnose_limits(u: ModelDesc, m: ModelDesc, matching: Matching) -> list[dict]:
    out = []
    for a, b, _ in matching.joints:
        ju, jm = u.joint(a), m.joint(b)
        names = {"joint": a, "mjcf_joint": b}
        for side, x, y in (("lower", ju.lower, jm.lower), ("upper", ju.upper, jm.upper)):
            if x == y or (math.isfinite(x) and math.isfinite(y) and abs(x - y) <= 1e-9):
                continue
            values = {"bound": side, "urdf": x, "mjcf": y}
            if not (math.isfinite(x) and math.isfinite(y)):
                out.append(finding("limit_difference", f"joint {a}/{b}: {side} limit {x:.6g} in the URDF, {y:.6g} in the MJCF "
                                   "(one file leaves the joint unlimited)", values, **names))
            elif any(abs(_ratio(y, x) / t - 1) < 2e-3 for t in (math.degrees(1.0), math.radians(1.0))):
                which = "MJCF" if abs(y) > abs(x) else "URDF"
                out.append(finding("limits_degrees_as_radians", f"joint {a}/{b}: {side} limit {x:.6g} (URDF) vs {y:.6g} (MJCF): "
                                   f"the {which} value is the other in degrees, read as radians", values, **names))
            elif (r := rounded_from(x, y)) is not None:
                out.append(finding("rounding", f"joint {a}/{b}: {side} limit {r['rounded']} is {r['exact']!r} rounded to "
                                   f"{r['decimals']} decimals (difference {abs(x - y):.2g})", {**values, **r}, **names))
            else:
                out.append(finding("limit_difference", f"joint {a}/{b}: {side} limit {x:.6g} in the URDF, {y:.6g} in the MJCF "
                                   f"(difference {y - x:+.3g})", values, **names))
    return out


def _ratio(y: float, x: float) -> float:
    return abs(y / x) if x != 0 else math.inf


def diagnose_dynamics(u: ModelDesc, m: ModelDesc, matching: Matching) -> tuple[list[dict], list[str]]:
    """Joint damping, friction, armature, effort and velocity limits; notes for what a format cannot carry."""
    out, notes = [], []
    cannot: dict[str, list[str]] = {}
    for a, b, _ in matching.joints:
        ju, jm = u.joint(a), m.joint(b)
        names = {"joint": a, "mjcf_joint": b}
        for prop, x, y in (("damping", ju.damping, jm.damping), ("friction", ju.friction, jm.friction),
                           ("effort", ju.effort, jm.effort), ("armature", ju.armature, jm.armature),
                           ("velocity", ju.velocity, jm.velocity)):
            if x is None or y is None:
                known, side = (y, "URDF") if x is None else (x, "MJCF")
                if known:
                    why = {"armature": "URDF has no armature field", "velocity": "MJCF has no joint velocity limit"}.get(prop, "not given")
                    cannot.setdefault(f"{prop} only in the {'MJCF' if side == 'URDF' else 'URDF'} ({why})", []).append(f"{a}={known:g}")
                    if prop == "armature":
                        out.append(finding("inexpressible", f"joint {a}/{b}: MJCF armature {known:g} (rotor inertia) "
                                           "has no URDF equivalent: the URDF's dynamics lack it", {"property": prop, "mjcf": known}, **names))
                continue
            if abs(x - y) > REL_TOL * max(abs(x), abs(y), 1e-12):
                label = {"friction": "friction (URDF friction vs MJCF frictionloss)"}.get(prop, prop)
                out.append(finding(f"{prop}_difference", f"joint {a}/{b}: {label} {x:g} in the URDF, {y:g} in the MJCF",
                                   {"property": prop, "urdf": x, "mjcf": y}, **names))
    for what, items in cannot.items():
        notes.append(f"{what}: {', '.join(items)}")
    return out, notes


def diagnose_links(u: ModelDesc, m: ModelDesc, matching: Matching) -> tuple[list[dict], list[list]]:
    """Mass, CoM and inertia of what moves with each common joint (fixed links fused, unmatched
    joints' bodies included at q = 0), compared in each joint's moving frame."""
    cu = composite_inertials(u, {a: a for a, _, _ in matching.joints})
    cm = composite_inertials(m, {b: a for a, b, _ in matching.joints})
    out, rows = [], []
    for a, b, _ in matching.joints:
        ju, jm = u.joint(a), m.joint(b)
        names = {"link": ju.child, "mjcf_link": jm.child}
        folded = [f"{n} (URDF only)" for n in matching.unmatched_urdf if _nearest_matched(u, n, {p[0] for p in matching.joints}) == a]
        folded += [f"{n} (MJCF only)" for n in matching.unmatched_mjcf if _nearest_matched(m, n, {p[1] for p in matching.joints}) == b]
        incl = f" (including the bodies of unmatched joint {', '.join(folded)}, held at zero)" if folded else ""
        if a not in cu and a not in cm:
            continue
        if a not in cu or a not in cm:
            side, (mass, _, _) = ("URDF", cm[a]) if a not in cu else ("MJCF", cu[a])
            out.append(finding("mass_difference", f"link {ju.child}/{jm.child}: no mass in the {side}, {mass:.6g} kg in the other file",
                               {"urdf": cu.get(a, (0.0,))[0], "mjcf": cm.get(a, (0.0,))[0]}, **names))
            continue
        mu, comu, iu = cu[a]
        mm, comm, im = cm[a]
        comu, iu = to_frame(frame_pose(u, ju.child), comu, iu)
        comm, im = to_frame(frame_pose(m, jm.child), comm, im)
        dcom = float(np.linalg.norm(comu - comm))
        di = float(np.linalg.norm(iu - im))
        rows.append([ju.child, jm.child, mu, mm, dcom, di])
        if abs(mu - mm) > REL_TOL * max(mu, mm) and (r := rounded_from(mu, mm)) is not None:
            out.append(finding("rounding", f"link {ju.child}/{jm.child}: mass {r['rounded']!r} kg is {r['exact']!r} kg rounded "
                               f"to {r['decimals']} decimals", {"property": "mass", "urdf": mu, "mjcf": mm, **r}, **names))
        elif abs(mu - mm) > REL_TOL * max(mu, mm):
            out.append(finding("mass_difference", f"link {ju.child}/{jm.child}: mass {mu:.6g} kg in the URDF, {mm:.6g} kg in the MJCF{incl}",
                               {"urdf": mu, "mjcf": mm}, **names))
        if dcom > 1e-6:
            out.append(finding("com_difference", f"link {ju.child}/{jm.child}: centre of mass {dcom:.3g} m apart "
                               f"(URDF {_vec(comu)}, MJCF {_vec(comm)} in the link frame)",
                               {"distance_m": dcom, "urdf": comu.tolist(), "mjcf": comm.tolist()}, **names))
        if di > INERTIA_REL * max(np.linalg.norm(iu), np.linalg.norm(im), 1e-12):
            eu, em = np.linalg.eigvalsh(iu), np.linalg.eigvalsh(im)
            values = {"urdf": iu.tolist(), "mjcf": im.tolist(), "urdf_principal": eu.tolist(), "mjcf_principal": em.tolist()}
            if np.linalg.norm(eu - em) <= 1e-6 * max(np.linalg.norm(em), 1e-12):
                out.append(finding("inertia_rotated", f"link {ju.child}/{jm.child}: same principal moments "
                                   f"{_vec(em)} but different principal axes (swapped or rotated inertia tensor)", values, **names))
            else:
                out.append(finding("inertia_difference", f"link {ju.child}/{jm.child}: principal moments {_vec(eu)} (URDF) vs "
                                   f"{_vec(em)} (MJCF) kg·m²", values, **names))
    return out, rows


def _nearest_matched(desc: ModelDesc, joint: str, matched: set) -> str | None:
    parent = desc.joint(joint).parent
    while parent is not None and parent not in matched:
        parent = desc.joint(parent).parent
    return parent


def diagnose_frames(u: ModelDesc, m: ModelDesc, matching: Matching) -> list[dict]:
    """Frames that are not a joint's moving frame: their pose relative to that moving frame."""
    out = []
    child_of = {a: (u.joint(a).child, m.joint(b).child) for a, b, _ in matching.joints}
    for fu, fm, why in matching.frames:
        owner = u.frame_owner.get(fu)
        if owner not in child_of or (fu, fm) == child_of[owner]:
            continue
        cu, cm = child_of[owner]
        lu = invert_transform(frame_pose(u, cu)) @ frame_pose(u, fu)
        lm = invert_transform(frame_pose(m, cm)) @ frame_pose(m, fm)
        dp, da = pose_difference(lu, lm)
        if dp > POS_TOL or da > ANG_TOL:
            out.append(finding("frame_offset", f"frame {fu}/{fm}: placed differently on link {cu}/{cm}: "
                               f"{dp:.3g} m and {da:.3g} rad apart", {"position_m": dp, "rotation_rad": da,
                               "urdf_xyz": lu[:3, 3].tolist(), "mjcf_xyz": lm[:3, 3].tolist()}, frame=fu, mjcf_frame=fm))
    return out


def diagnose_rounding(findings: list[dict], urdf_text: str, mjcf_text: str, u: ModelDesc, m: ModelDesc, matching: Matching) -> list[dict]:
    """Rounded constants (1.5708 for π/2) in the origin of a joint that disagrees."""
    kinds = ("axis_direction", "axis_position", "zero_offset", "frame_offset", "frame_convention")
    blamed = {f.subject for f in findings if f.kind in kinds}
    blamed |= {f.other for f in findings if f.kind in kinds and f.subject_type == "frame"}
    body_to_joint = {m.joint(b).child: a for a, b, _ in matching.joints}
    out, seen = [], set()
    for side, where, value, exact, decimals in rounded_constants(urdf_text, mjcf_text):
        joint = where if side == "URDF" else body_to_joint.get(where, where)
        if joint not in blamed or (joint, value) in seen:
            continue
        seen.add((joint, value))
        out.append(finding("rounding", f"{joint}: the {side} writes {value} for {exact[1]} = {exact[0]!r} "
                           f"(rounded to {decimals} decimals)", {"file": side, "written": value, "constant": exact[1],
                           "exact": exact[0]}, joint=joint))
    return out
