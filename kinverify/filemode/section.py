"""The file-mode report section."""

from __future__ import annotations

from kinverify.suites.base import Section


def build_section(urdf, mjcf, matching, findings, notes, residual_rows, parser_rows, link_rows, ref, other) -> Section:
    summary = (f"{urdf.path} vs {mjcf.path}: {len(matching.joints)} joints matched, "
               f"{len(matching.unmatched_urdf) + len(matching.unmatched_mjcf)} unmatched; "
               + (f"{len(findings)} findings" if findings else "no differences found"))
    section = Section("File mode: URDF vs MJCF", summary, notes=list(notes))
    section.table("Findings", ["severity", "kind", "subject", "finding"], [[f.severity, f.kind, f.label, f.message] for f in findings])
    section.table("Joint pairs", ["URDF joint", "MJCF joint", "matched by"], matching.joints)
    section.table(f"Frame residuals ({ref} vs {other}, q = 0 and random configurations)",
                  ["frame (URDF / MJCF)", "position [m]", "rotation [rad]", "position after base [m]", "rotation after base [rad]"],
                  residual_rows)
    section.table("Each file read by two libraries", ["file", "backends", "max position [m]", "max rotation [rad]"], parser_rows)
    section.table("Links (what moves with each joint, in its moving frame)",
                  ["URDF link", "MJCF body", "URDF mass [kg]", "MJCF mass [kg]", "CoM distance [m]", "inertia difference [kg m²]"],
                  link_rows)
    return section
