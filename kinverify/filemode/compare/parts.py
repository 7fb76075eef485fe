"""What one file has and the other lacks: joints, masses, frames, merged links, each said once.

- ``extra_parts`` (error): the joints one file has and the other lacks, with the bodies they
  move, and bodies with no twin whose mass explains why a rigid body differs (a gripper in one
  file only, rotor masses): listed with the rigid body they join and the mass they add.
- ``lumped_links`` (info): bodies with no twin in a rigid body that agrees all the same (one
  file keeps a fixed link the other merged into its parent).
- ``world_parts`` (info) and ``base_inertial_difference`` (warning): bodies welded to the world of
  a fixed-base robot, which cannot move it.
- ``frame_twin`` (info): a frame one file has and the other names differently or lacks, matched
  by position on the same rigid body, with the offset to the nearest frame of the other file.
- ``total_mass`` (info): the two totals, and which findings account for the difference.
"""

from __future__ import annotations

import math

import numpy as np

from kinverify.filemode.compare.context import aligned_poses
from kinverify.filemode.compare.inertials import uniform_mass_ratio
from kinverify.filemode.findings.table import finding
from kinverify.model.transforms import geodesic_distance, invert_transform


def _side(g, side):
    return g.group.urdf if side == "URDF" else g.group.mjcf


def part_findings(info, results, tol_mass: float) -> list:
    """``results``: :func:`kinverify.filemode.compare.inertials.analyse` of the two files."""
    out = []
    moved_by = {"URDF": _moved_by(info.u, info.matching.unmatched_urdf), "MJCF": _moved_by(info.m, info.matching.unmatched_mjcf)}
    for side, unmatched in (("URDF", info.matching.unmatched_urdf), ("MJCF", info.matching.unmatched_mjcf)):
        other = "MJCF" if side == "URDF" else "URDF"
        parts, groups = [], []
        for r in results:
            twinless = [p for p in r.moved if any(p is x for x in _side(r, side))]
            if r.status == "explained" and not r.group.fixed_base_root:
                twinless += [p for p in r.extra if any(p is x for x in _side(r, side))]
            if twinless:
                groups.append(r.group.key)
            for p in twinless:
                how = f"moved by {moved_by[side][p.name]}" if p.name in moved_by[side] else f"fixed to {r.label}"
                parts.append({"name": p.name, "mass": p.mass, "body": r.label, "how": how})
        if not unmatched and not parts:
            continue
        mass = sum(p["mass"] for p in parts)
        text = []
        if unmatched:
            text.append(f"joint{'s' if len(unmatched) > 1 else ''} {', '.join(unmatched)}")
        if parts:
            brief = len(parts) > 4  # many parts: the joints that move them are named above already
            text.append(
                "link"
                + ("s " if len(parts) > 1 else " ")
                + ", ".join(
                    f"{p['name']} ({p['mass']:.6g} kg)"
                    if brief and p["how"].startswith("moved by")
                    else f"{p['name']} ({p['mass']:.6g} kg, {p['how']})"
                    for p in parts
                )
            )
        msg = (
            f"the {side} has parts the {other} lacks: {'; '.join(text)}"
            + (
                f": {mass:.6g} kg in all, left out when comparing the rigid bodies they join "
                f"({', '.join(sorted(set(p['body'] for p in parts)))})"
                if parts
                else ""
            )
            + (" (not compared; held at zero)" if unmatched else "")
        )
        out.append(
            finding(
                "extra_parts",
                msg,
                {
                    "file": side,
                    "joints": list(unmatched),
                    "links": parts,
                    "mass_kg": mass,
                    "groups": groups,
                    "checks": [[p, "rigid bodies"] for p in ("inertia.mass", "inertia.com", "inertia.tensor")],
                },
                magnitude=mass if parts else len(unmatched),
                unit="kg" if parts else "joints",
                joint=list(unmatched) or None,
                link=None if unmatched else [p["name"] for p in parts],
            )
        )
    out += _unset_inertials(results)
    out += _unknown_masses(results)
    out += _lumped(results)
    out += _world(results, tol_mass)
    return out


INERTIA_CHECKS = [[p, "rigid bodies"] for p in ("inertia.mass", "inertia.com", "inertia.tensor")]


def _unset_inertials(results) -> list:
    """Links one file gives no ``<inertial>`` (massless by default) while the other states one."""
    out = []
    for side, other in (("URDF", "MJCF"), ("MJCF", "URDF")):
        parts = [(p, r) for r in results if r.status == "unset" for p in r.extra if any(p is x for x in _side(r, other))]
        if not parts:
            continue
        out.append(
            finding(
                "inertial_unset",
                f"the {side} leaves the inertial of {len(parts)} link{'s' if len(parts) > 1 else ''} "
                f"unset (massless by default); the {other} states it: "
                + ", ".join(f"{p.unset_twin} ({p.mass:.6g} kg in the {other})" for p, _ in parts),
                {
                    "unset_in": side,
                    "links": [{"name": p.unset_twin, "other": p.name, "mass": p.mass, "body": r.label} for p, r in parts],
                    "checks": INERTIA_CHECKS,
                },
                magnitude=sum(p.mass for p, _ in parts),
                unit="kg",
                link=[p.unset_twin for p, _ in parts],
            )
        )
    return out


def _unknown_masses(results) -> list:
    """Rigid bodies part of whose mass came from a mesh file that is absent: not compared."""
    unknown = [r for r in results if r.status == "unknown"]
    if not unknown:
        return []
    parts = [(side, p.name) for r in unknown for side in ("URDF", "MJCF") for p in _side(r, side) if not p.known]
    return [
        finding(
            "mass_unknown",
            f"{len(unknown)} rigid bod{'ies' if len(unknown) > 1 else 'y'} not compared: part of the mass "
            "comes from mesh files that are absent (MuJoCo computes a body's mass from its geoms when it has no "
            "<inertial>): " + ", ".join(f"{name} ({side})" for side, name in parts),
            {"bodies": [r.label for r in unknown], "parts": [[s, n] for s, n in parts], "checks": INERTIA_CHECKS},
            link=[r.group.urdf_link for r in unknown],
        )
    ]


def _moved_by(desc, unmatched) -> dict[str, str]:
    """Body -> the joint in one file only that moves it (its nearest unmatched ancestor)."""
    parent = {j.name: j.parent for j in desc.joints}
    out = {}
    for b in desc.bodies:
        owner = b.owner
        while owner is not None and owner not in unmatched:
            owner = parent.get(owner)
        if owner is not None:
            out[b.name] = owner
    return out


def _lumped(results) -> list:
    out = []
    for side in ("URDF", "MJCF"):
        other_side = "MJCF" if side == "URDF" else "URDF"
        found = [
            (p, r)
            for r in results
            if r.status in ("agree", "rounding") and not r.group.fixed_base_root
            for p in _side(r, side)
            if p.twin is None
            and p.mass > 0
            and p.name not in {o.name for o in _side(r, other_side)}
            and not any(p is x for x in r.moved)
        ]  # a same-named body in the same rigid body is its twin; what a joint in one file only moves is that joint's (extra_parts)
        if found:
            other = "MJCF" if side == "URDF" else "URDF"
            out.append(
                finding(
                    "lumped_links",
                    f"the {side} keeps as separate fixed links what the {other} merges into one body "
                    "(the rigid bodies agree): " + ", ".join(f"{p.name} ({p.mass:.6g} kg) in {r.label}" for p, r in found),
                    {"file": side, "links": [{"name": p.name, "mass": p.mass, "body": r.label} for p, r in found]},
                    magnitude=sum(p.mass for p, _ in found),
                    unit="kg",
                    link=[p.name for p, _ in found],
                )
            )
    return out


def _world(results, tol_mass: float) -> list:

    out: list = []
    if uniform_mass_ratio(results) is not None:
        return out  # a units mistake, said once by the inertia suite
    for r in results:
        if not r.group.fixed_base_root or r.status in ("agree", "rounding", "unset", "unknown"):
            continue
        parts = [(side, p) for side in ("URDF", "MJCF") for p in _side(r, side) if p.twin is None and p.mass > 0]
        if r.status == "explained":
            out.append(
                finding(
                    "world_parts",
                    "bodies welded to the world of this fixed-base robot in one file only: "
                    + ", ".join(f"{p.name} ({p.mass:.6g} kg, {side})" for side, p in parts)
                    + ": part of the world, they cannot move the robot",
                    {"links": [{"file": s, "name": p.name, "mass": p.mass} for s, p in parts]},
                    magnitude=sum(p.mass for _, p in parts),
                    unit="kg",
                    link=[p.name for _, p in parts],
                )
            )
        else:
            out.append(
                finding(
                    "base_inertial_difference",
                    f"the base ({r.label}, welded to the world) weighs {r.urdf.mass:.6g} kg "
                    f"in the URDF and {r.mjcf.mass:.6g} kg in the MJCF, centres of mass {r.diff.com:.3g} m apart, "
                    f"ΔI {r.diff.tensor:.3g} kg·m²: a fixed base cannot move, so this changes no joint force",
                    {"urdf": r.urdf.mass, "mjcf": r.mjcf.mass, "com_m": r.diff.com, "inertia_kgm2": r.diff.tensor},
                    magnitude=r.diff.mass if r.diff.mass > tol_mass else r.diff.tensor,
                    unit="kg" if r.diff.mass > tol_mass else "kg·m²",
                    link=r.group.urdf_link,
                )
            )
    return out


def total_mass_finding(info, findings: list, tol: float):
    mu, mm = info.u.total_mass, info.m.total_mass
    if abs(mu - mm) <= max(tol, info.floors.relative * max(mu, mm)):
        return None
    causes = [
        f
        for f in findings
        if f.kind in ("extra_parts", "mass_difference", "mass_units", "world_parts", "base_inertial_difference")
    ]
    if causes and all(f.kind == "world_parts" for f in causes):
        return None  # bodies welded to the world, already said
    return finding(
        "total_mass",
        f"total mass {mu:.6g} kg (URDF), {mm:.6g} kg (MJCF): {mm - mu:+.6g} kg"
        + (", from " + "; ".join(f"{f.kind} ({f.label})" for f in causes) if causes else ""),
        {"urdf": mu, "mjcf": mm, "difference_kg": mm - mu, "causes": [f.kind for f in causes]},
        magnitude=abs(mm - mu),
        unit="kg",
    )


FAR = 0.01  # m: a frame farther than this from every frame of the other file on its body has no twin there


def frame_twins(info, tol) -> tuple[list, list[tuple[str, str, str]]]:
    """Frames one file has with no same-named twin: matched by position on the same rigid body
    (at the aligned zero). Returns the findings and the new frame pairs that coincide."""
    matched_u = {a for a, _, _ in info.matching.frames}
    matched_m = {b for _, b, _ in info.matching.frames}
    to_m = {a: b for a, b, _ in info.matching.joints}
    gone_u = set(_moved_by(info.u, info.matching.unmatched_urdf))
    gone_m = set(_moved_by(info.m, info.matching.unmatched_mjcf))
    pm = aligned_poses(info.alignment, info.poses_m)
    out, pairs, used = [], [], set()
    for f, pose in info.poses_u.items():
        owner = info.u.frame_owner.get(f)
        if f in matched_u or f in gone_u or (owner is not None and owner not in to_m) or _is_world(info.u, f, pose):
            continue
        if info.u.body(f) is not None:  # a link with mass: the rigid-body comparison reports it
            continue
        cands = [
            g for g in info.m.frames if info.m.frame_owner.get(g) == (to_m.get(owner) if owner else None) and g not in gone_m
        ]
        if not cands:
            continue
        scored = sorted(
            cands,
            key=lambda g: (
                float(np.linalg.norm(pm[g][:3, 3] - pose[:3, 3])),
                float(geodesic_distance(pm[g][:3, :3], pose[:3, :3])),
                g in matched_m,
            ),
        )
        g = scored[0]
        rel = invert_transform(pm[g]) @ pose
        dist, angle = float(np.linalg.norm(rel[:3, 3])), float(geodesic_distance(rel[:3, :3], np.eye(3)))
        ptol, rtol = tol(f)
        same = dist <= ptol and angle <= rtol
        if same and g not in matched_m and g not in used:
            pairs.append((f, g, "same place (no same-named twin)"))
            used.add(g)
        what = ("is" if same else "is not") + f" the MJCF's {info.m.frame_kind.get(g, 'frame')} {g}"
        offset = (
            ""
            if same
            else (
                f": nearest, {dist:.4g} m away (xyz {np.round(rel[:3, 3], 6).tolist()} in {g}'s axes)"
                + (f" and turned {math.degrees(angle):.4g}°" if angle > rtol else "")
            )
        )
        if dist > FAR:  # nothing of the MJCF is near it: no twin to name
            what, offset = "has no twin in the MJCF", f" (the nearest MJCF frame on its body, {g}, is {dist:.4g} m away)"
        out.append(
            finding(
                "frame_twin",
                f"URDF frame {f} (no same-named MJCF frame) {what}{offset}",
                {"mjcf_frame": g, "distance_m": dist, "rotation_rad": angle, "xyz": rel[:3, 3].tolist()},
                magnitude=dist,
                unit="m",
                frame=f,
                mjcf_frame=g,
            )
        )
    return out, pairs


def _is_world(desc, name: str, pose) -> bool:
    """A massless root link at the origin: the world frame itself, not part of the robot."""
    return (
        desc.frame_owner.get(name) is None
        and desc.body(name) is None
        and desc.frame_depth.get(name, 0) <= 1
        and np.allclose(pose, np.eye(4), atol=1e-12)
    )
