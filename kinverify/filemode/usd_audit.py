"""The one-file audit of a USD robot (``kinverify verify --usd R.usda`` alone): what the file states,
what it leaves unset, what cannot be read. usd-core (pxr) is the only library here that reads
USD: its FK (the joint frames composed) is checked against finite differences, and this section
lists, joint by joint and body by body, the values a simulator would take from the file."""

from __future__ import annotations

import math

from kinverify.filemode.findings.table import finding
from kinverify.suites.base import Section

ONLY_READER = (
    "usd-core (pxr) is the only library here that reads USD: this audit is its reading alone, its FK and "
    "Jacobians checked against finite differences of its own FK; no other library's reading to compare it with"
)


def _value(x, unit: str = "") -> str:
    if x is None:
        return "unset"
    if isinstance(x, float) and math.isinf(x):
        return "unbounded" if x > 0 else "-inf"
    return f"{x:.6g}" + (f" {unit}" if unit else "")


def statements(desc, loaded) -> tuple[Section, list]:
    """The section listing what the USD states and leaves unset, and the findings it gives rise to
    (a force bound kept only as a custom attribute; absent layers)."""
    robot = desc.native
    section = Section(
        "USD: what the file states",
        f"{loaded.path}: {len(desc.joints)} movable joints, {len(robot.bodies)} "
        f"rigid bodies, root {robot.names[robot.root]} ({'floating' if robot.floating else 'fixed to the world'}); "
        f"metersPerUnit {robot.meters:g}, kilogramsPerUnit {robot.kilograms:g}, upAxis {robot.up}",
    )
    rows = []
    for j in desc.joints:
        ext = desc.extensions.get(j.name, {})
        unit = "N·m" if j.type == "revolute" else "N"
        drive = ext.get("drive")
        rows.append(
            [
                j.name,
                j.type,
                f"[{_value(j.lower)}, {_value(j.upper)}]",
                _value(j.effort, unit),
                j.effort_how,
                *(_value(getattr(j, v)) if v in j.stated else "unset" for v in ("damping", "friction", "armature")),
                _value(j.velocity),
                "none"
                if drive is None
                else ", ".join(f"{k} {_value(v) if not isinstance(v, str) else v}" for k, v in drive.items() if v is not None),
                _value(ext.get("initial")),
            ]
        )
    section.table(
        "Joints (SI units, radians; 'unset': the file leaves it to the simulator's default)",
        [
            "joint",
            "type",
            "limits",
            "force bound",
            "force bound from",
            "damping",
            "friction",
            "armature",
            "velocity limit",
            "drive (per radian)",
            "initial position",
        ],
        rows,
    )
    section.table(
        "Rigid bodies",
        ["body", "mass [kg]", "centre of mass and inertia"],
        [
            [
                name,
                _value(b.mass) if (b := desc.body(name)) else "unset (no MassAPI mass)",
                ("stated" if b.com_known else "unset (derived from the colliders)") if b else "unset",
            ]
            for name in (robot.names[p] for p in robot.bodies)
        ],
    )
    if desc.couplings:
        section.table(
            "Couplings",
            ["follower", "leader", "multiplier", "offset", "schema"],
            [[c.follower, c.leader, f"{c.multiplier:g}", f"{c.offset:g}", c.source] for c in desc.couplings],
        )
    section.notes += list(loaded.warnings) + desc.skipped
    found = []
    custom = [j for j in desc.joints if j.effort is None and desc.extensions.get(j.name, {}).get("custom_effort") is not None]
    if custom:
        found.append(
            finding(
                "effort_unset",
                f"the USD states no force bound on {len(custom)} joints (no drive): the effort "
                "survives only as the custom attribute urdf:limit:effort, which no simulator reads: "
                + ", ".join(f"{j.name} {desc.extensions[j.name]['custom_effort']:g}" for j in custom),
                {"file": "USD", "unset_in": "USD", "custom": {j.name: desc.extensions[j.name]["custom_effort"] for j in custom}},
                prop="limits.effort",
                joint=[j.name for j in custom],
            )
        )
    unset = sorted(desc.no_inertial)
    if unset:
        found.append(
            finding(
                "inertial_unset",
                f"the USD states no mass for {len(unset)} bodies (no MassAPI mass: the "
                "simulator derives it from the colliders' volume): " + ", ".join(unset),
                {"file": "USD", "bodies": unset},
                link=unset,
            )
        )
    return section, found
