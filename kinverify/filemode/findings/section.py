"""The file-mode report section: tables to read, and data for the report to draw from
(``data["alignment"]["T_mjcf_from_urdf"]`` as a 4x4 list, per-finding values side by side,
findings grouped by subject)."""

from __future__ import annotations

import math

from kinverify.suites.base import Finding, Section


def _num(x):
    return None if x is None else (str(x) if isinstance(x, float) and math.isinf(x) else x)


def build_section(urdf, mjcf, info, findings: list[Finding], notes, parser_rows) -> Section:
    al, matching = info.alignment, info.matching
    failing = sum(f.fails for f in findings)
    summary = (
        f"{urdf.path} vs {mjcf.path}: {len(matching.joints)} joints matched, "
        f"{len(matching.unmatched_urdf) + len(matching.unmatched_mjcf)} in one file only; "
        + (f"{len(findings)} findings, {failing} failing" if findings else "no differences found")
    )
    section = Section("File mode: URDF vs MJCF", summary, notes=list(notes))
    section.table(
        "Findings",
        ["severity", "kind", "subject", "magnitude", "finding"],
        [
            [
                ("accepted " if f.accepted else "") + f.severity,
                f.kind,
                f.label,
                "" if f.magnitude is None else f"{f.magnitude:.4g} {f.unit}".strip(),
                f.message,
            ]
            for f in findings
        ],
    )
    section.table(
        "Joint map (q_mjcf = sign · q_urdf + offset)",
        ["URDF joint", "MJCF joint", "matched by", "sign", "offset"],
        [[a, b, how, al.joint(a).sign, al.joint(a).offset] for a, b, how in matching.joints],
    )
    section.table(
        "Frames after alignment (max over the fit's configurations)",
        [
            "frame (URDF / MJCF)",
            "why compared",
            "position [m]",
            "rotation [rad]",
            "after removing a constant [m, rad]",
            "in the fit",
        ],
        [
            [f"{f.urdf} / {f.mjcf}", f.why, f.position, f.rotation, [f.residual_position, f.residual_rotation], f.in_fit]
            for f in al.frames
        ],
    )
    section.table(
        "Each file read by two libraries",
        ["file", "backends", "max position [m]", "max rotation [rad]", "note"],
        [r + [""] * (5 - len(r)) for r in parser_rows],
    )
    by_subject: dict[str, list[int]] = {}
    for i, f in enumerate(findings):
        by_subject.setdefault(f.label, []).append(i)
    section.data.update(
        {
            "alignment": {
                "T_mjcf_from_urdf": al.T.tolist(),
                "residual_m": al.residual[0],
                "residual_rad": al.residual[1],
                "candidate": al.candidate,
                "unexplained_features": al.unexplained,
                "joints": [
                    {"urdf": j.urdf, "mjcf": j.mjcf, "type": j.type, "sign": j.sign, "offset": j.offset} for j in al.joints
                ],
                "couplings": [
                    {
                        "follower": c.follower,
                        "leader": c.leader,
                        "multiplier": c.multiplier,
                        "offset": c.offset,
                        "source": c.source,
                    }
                    for c in al.couplings.values()
                ],
                "frames": [
                    {
                        "urdf": f.urdf,
                        "mjcf": f.mjcf,
                        "why": f.why,
                        "position_m": f.position,
                        "rotation_rad": f.rotation,
                        "residual_m": f.residual_position,
                        "residual_rad": f.residual_rotation,
                        "in_fit": f.in_fit,
                    }
                    for f in al.frames
                ],
            },
            "findings": [
                {
                    "kind": f.kind,
                    "severity": f.severity,
                    "subject": f.label,
                    "accepted": f.accepted,
                    "magnitude": _num(f.magnitude),
                    "unit": f.unit,
                    "urdf": f.values.get("urdf"),
                    "mjcf": f.values.get("mjcf"),
                }
                for f in findings
            ],
            "findings_by_subject": by_subject,
            "precision": {"urdf": info.precision[0].describe(), "mjcf": info.precision[1].describe()},
            "total_mass": {"urdf": info.u.total_mass, "mjcf": info.m.total_mass},
            "floating_base": info.floating,
            "unmatched": {"urdf": list(matching.unmatched_urdf), "mjcf": list(matching.unmatched_mjcf)},
        }
    )
    return section
