"""The file-mode report section (schema in kinverify/results.py), plain JSON data."""

from __future__ import annotations


def _subject(f: dict) -> str:
    for key in ("joint", "link", "frame"):
        if key in f:
            other = f.get(f"mjcf_{key}")
            return f"{key} {f[key]}" + (f" / {other}" if other and other != f[key] else "")
    return f["values"].get("file", "model") if isinstance(f.get("values"), dict) else "model"


def build_section(urdf, mjcf, matching, findings, notes, residual_rows, parser_rows, link_rows, ref, other) -> dict:
    summary = (f"{urdf.path} vs {mjcf.path}: {len(matching.joints)} joints matched, "
               f"{len(matching.unmatched_urdf) + len(matching.unmatched_mjcf)} unmatched; "
               + (f"{len(findings)} findings" if findings else "no differences found"))
    return {
        "title": "File mode: URDF vs MJCF",
        "summary": summary,
        "tables": [
            {"title": "Findings", "columns": ["kind", "subject", "finding"],
             "rows": [[f["kind"], _subject(f), f["message"]] for f in findings]},
            {"title": "Joint pairs", "columns": ["URDF joint", "MJCF joint", "matched by"],
             "rows": [list(p) for p in matching.joints]},
            {"title": f"Frame residuals ({ref} vs {other}, q = 0 and random configurations)",
             "columns": ["frame (URDF / MJCF)", "position [m]", "rotation [rad]", "position after base [m]",
                         "rotation after base [rad]"], "rows": residual_rows},
            {"title": "Each file read by two libraries", "columns": ["file", "backends", "max position [m]", "max rotation [rad]"],
             "rows": parser_rows},
            {"title": "Links (what moves with each joint, in its moving frame)",
             "columns": ["URDF link", "MJCF body", "URDF mass [kg]", "MJCF mass [kg]", "CoM distance [m]", "inertia difference [kg m²]"],
             "rows": link_rows},
        ],
        "figures": [],
        "notes": list(notes),
        "findings": findings,
    }
