"""Each file read by a second (and third, fourth) library: a library that reads the same file
differently is named once and left out of the comparison between the files, so a verdict of
"disagree" is about the files, never about a parser. With three readings or more, the finding
says which libraries agree with each other (the majority) and which one stands apart, by how much.

URDF: Pinocchio (the reference), yourdfpy, MuJoCo's URDF import, Drake. MJCF: MuJoCo (the
reference), Pinocchio's MJCF parser, which drops the pose of a top-level body under
``<worldbody>`` (pinocchio#2782): that quirk is recognised, measured, reported as information and
corrected; Drake's MJCF parser, which reads a subset of MJCF (what it ignores is a warning,
element by element). SDFormat: Drake alone.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from kinverify.backends import names_reading
from kinverify.backends.base import pair_floor
from kinverify.errors import library_reason
from kinverify.filemode.findings.table import finding
from kinverify.model.transforms import geodesic_distance, invert_transform

URDF_SIDE = names_reading("urdf")  # every library that reads each file, the primary reader first
MJCF_SIDE = names_reading("mjcf")
SIDES = (("URDF", URDF_SIDE), ("MJCF", MJCF_SIDE), ("SDF", names_reading("sdf")), ("USD", names_reading("usd")))
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


COMPARED = (
    "<site>",
    "<frame>",
    "<inertial>",
    "<equality>",
    "<tendon>",
    "in <equality>",
    "body@",
    "inertial@",
    "joint@range",
    "joint@ref",
    "joint@axis",
    "joint@pos",
    "joint@limited",
    "geom@mass",
    "geom@density",
)


def refusal_findings(backends: dict, kinds) -> list:
    """What a library that loaded a file says it ignores (Drake's MJCF parser: ``<site>``,
    ``frictionloss``, ``<light>``...), naming the elements, per library: a ``parser_refused`` warning
    for what the comparison reads through that library (frames, sites, inertials, couplings, joint
    placement and limits), a ``parser_ignores`` info for the rest (lights, keyframes, solver options,
    joint friction, actuators: nothing kinverify compares through it)."""
    out = []
    for name, backend in backends.items():
        inner = getattr(backend, "inner", backend)
        ignored = inner.refused_elements(inner.parser_warnings) if hasattr(inner, "refused_elements") else []
        if not ignored:
            continue
        side = next((label for label, names in SIDES if name in names and label.lower() in kinds), "file")
        matters = [e for e in ignored if any(key in e for key in COMPARED)]
        rest = [e for e in ignored if e not in matters]
        if matters:
            out.append(
                finding(
                    "parser_refused",
                    f"{name} ignores part of the {side} that is compared: {', '.join(matters)} "
                    "(unsupported by its parser; the rest is read and compared)",
                    {"file": side, "backend": name, "elements": matters},
                )
            )
        if rest:
            out.append(
                finding(
                    "parser_ignores",
                    f"{name} ignores {', '.join(rest)} in the {side} (unsupported by its parser; "
                    "nothing compared through it depends on them)",
                    {"file": side, "backend": name, "elements": rest},
                )
            )
    return out


def majority(poses: dict, tol, backends=None) -> tuple[list[str], dict[str, tuple[float, float]]]:
    """``(agree, apart)``: the largest group of readings that agree with each other within ``tol``
    (the first listed reading's group on a tie), and each other reading with its largest position
    [m] and rotation [rad] difference from that group's first member. ``poses``: name -> (N, F, 4, 4)
    on the same frames, in reading order; ``backends``: name -> backend, whose agreement floor
    (a float32 library's) raises ``tol`` for the pairs it is in."""
    names = list(poses)
    backends = backends or {}

    def close(a, b) -> bool:
        pos, rot = pose_errors(poses[a], poses[b])
        ptol, rtol = floored_tol(tol, backends.get(a), backends.get(b))
        return bool(pos.max() <= ptol and rot.max() <= rtol)

    # a reading with an agreement floor (float32) does not vote: it cannot tell apart readings closer than its floor
    voters = [n for n in names if not getattr(backends.get(n), "agreement_floor", None)] or names
    groups = [[b for b in voters if b == a or close(a, b)] for a in voters]
    agree = max(groups, key=len)  # max keeps the first of equal sizes: the reference's group on a tie
    apart = {}
    for name in names:
        if name not in agree and (name in voters or not close(agree[0], name)):
            pos, rot = pose_errors(poses[agree[0]], poses[name])
            apart[name] = (float(pos.max()), float(rot.max()))
    # a float32 reading close to the majority is named with it when it tells each reading apart from it
    agree += [
        n for n in names if n not in voters and n not in apart and n not in agree and all(not close(n, other) for other in apart)
    ]
    return agree, apart


def floored_tol(tol, *backends) -> tuple[float, float]:
    """``tol`` (position, rotation) raised to the agreement floor of ``backends``."""
    return max(tol[0], pair_floor("fk.position", *backends)), max(tol[1], pair_floor("fk.rotation", *backends))


def cross_check(backends: dict, q: np.ndarray, tol, t_base: np.ndarray, top_pose: np.ndarray | None, rebuild):
    """Compare the libraries reading each file: each with the reference reading (the table's rows),
    then all together, for the majority.

    ``backends``: name -> aligned backend; ``tol``: (position, rotation) tolerance; ``rebuild(backend,
    left)``: that aligned backend with another left transform. Returns (the backends to compare
    between the files: a reading standing apart from the majority is left out, findings, table rows)."""
    findings, rows, keep = [], [], dict(backends)
    ptol, rtol = tol
    for side, names in SIDES:
        loaded = [n for n in names if n in backends]
        if len(loaded) < 2:
            continue
        ref = backends[loaded[0]]
        common = [f for f in ref.frames if all(f in backends[n].frames for n in loaded)]
        readings = {loaded[0]: ref.poses(q)[:, [ref.frames.index(f) for f in common]]}
        for name in loaded[1:]:
            cols = [backends[name].frames.index(f) for f in common]
            try:
                p1 = backends[name].poses(q)[:, cols]
            except Exception as err:  # the library fails on this file: a finding, not a crash
                keep.pop(name)
                findings.append(
                    finding(
                        "parser_refused",
                        f"{name} cannot evaluate the {side}: {library_reason(err)}",
                        {"file": side, "backend": name},
                    )
                )
                continue
            pos, rot = pose_errors(readings[loaded[0]], p1)
            rows.append([side, f"{loaded[0]} vs {name}", float(pos.max()), float(rot.max())])
            if name == "pinocchio-mjcf" and top_pose is not None and (pos.max() > ptol or rot.max() > rtol):
                fixed = rebuild(backends[name], invert_transform(t_base) @ top_pose)
                p_fixed = fixed.poses(q)[:, cols]
                cpos, crot = pose_errors(readings[loaded[0]], p_fixed)
                if cpos.max() <= ptol and crot.max() <= rtol:
                    keep[name], p1 = fixed, p_fixed
                    shift = float(np.linalg.norm(top_pose[:3, 3]))
                    angle = float(geodesic_distance(top_pose[:3, :3], np.eye(3)))
                    rows[-1] += [f"corrected: {float(cpos.max()):.2g} m, {float(crot.max()):.2g} rad"]
                    findings.append(
                        finding(
                            "parser_quirk",
                            f"Pinocchio's MJCF parser drops the pose of the top-level body ({shift:.4g} m, "
                            f"{angle:.4g} rad = {math.degrees(angle):.4g}°): its reading of the MJCF is off by that much "
                            f"everywhere (pinocchio#2782, {QUIRK_ISSUE}); kinverify puts the pose back before comparing",
                            {
                                "file": side,
                                "backends": [loaded[0], name],
                                "position_m": float(pos.max()),
                                "rotation_rad": float(rot.max()),
                                "top_level_xyz": top_pose[:3, 3].tolist(),
                                "issue": QUIRK_ISSUE,
                            },
                            magnitude=max(shift, angle),
                            unit="m|rad",
                        )
                    )
            readings[name] = p1
        agree, apart = majority(readings, tol, backends)
        for name, (pos, rot) in apart.items():  # type: ignore[assignment]  # floats here, arrays above
            keep.pop(name, None)
            values = {
                "file": side,
                "backends": [agree[0], name],
                "agree": agree,
                "apart": name,
                "position_m": pos,
                "rotation_rad": rot,
            }
            if len(agree) > 1:
                message = (
                    f"the {side} is read alike by {_listed(agree)}, and differently by {name}: up to {pos:.3g} m, "
                    f"{rot:.3g} rad on the same file; {name} stands apart and is left out of the comparison "
                    "between the files"
                )
            else:
                message = (
                    f"the {side} is read differently by {agree[0]} and {name}: up to {pos:.3g} m, {rot:.3g} rad on the "
                    f"same file (no third reading agrees with either); {name} is left out of the comparison "
                    "between the files"
                )
            findings.append(finding("parser_disagreement", message, values, magnitude=float(max(pos, rot)), unit="m|rad"))
    return keep, findings, rows


def _listed(names) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
