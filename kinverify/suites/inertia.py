"""Suite ``inertia``: the mass, centre of mass and inertia tensor of each rigid body, URDF
(Pinocchio) against MJCF (MuJoCo), in one frame (see :mod:`kinverify.filemode.compare.inertials`).

- ``inertia.mass``: |Δm| of each rigid body (fixed links merged);
- ``inertia.com``: distance between the centres of mass, in the common frame at the zero
  configuration;
- ``inertia.tensor``: the largest eigenvalue (in magnitude) of the difference of the inertia
  tensors about the centres of mass, in the common frame: independent of either file's choice
  of link frame, zero when the tensors are the same, the size of a swapped or rotated one.

Bodies welded to the world of a fixed-base robot are not compared here (they cannot move it).
In file mode each rigid body that differs is one finding (bodies that differ the same way, like
mirrored legs, are one finding), and inertials rounded at the written precision are one
``rounding`` finding.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from kinverify.filemode.compare.context import file_view
from kinverify.filemode.compare.inertials import analyse, rounded_side, uniform_mass_ratio
from kinverify.filemode.findings.table import finding, unit_factor
from kinverify.suites.base import Finding, Property, Section, Suite, SuiteResult, VerifyContext, tolerance, within

PROPS = ("inertia.mass", "inertia.com", "inertia.tensor")


class InertiaSuite(Suite):
    name = "inertia"
    title = "Mass and inertia of each rigid body: URDF vs MJCF"
    properties = (
        Property("inertia.mass", "kg", 1e-9, compares="|Δ mass| of each rigid body (links joined by fixed joints merged)"),
        Property("inertia.com", "m", 1e-9, compares="distance between the centres of mass, common frame, zero configuration"),
        Property(
            "inertia.tensor",
            "kg·m²",
            1e-9,
            compares="largest |eigenvalue| of the difference of the inertia tensors about the CoM, common frame",
        ),
    )

    def run(self, ctx: VerifyContext) -> SuiteResult:

        info = file_view(ctx)
        if info is None:
            return SuiteResult([], Section(self.title, "skipped: needs both a URDF and an MJCF"))
        defaults = tuple(tolerance(ctx.options, self.property(p)) for p in PROPS)
        results = analyse(info, defaults)
        moving = [r for r in results if not r.group.fixed_base_root]
        checks = []
        for k, prop in enumerate(PROPS):
            if not moving:
                continue
            worst = max(moving, key=lambda r: r.ratio(k))
            error = (worst.diff.mass, worst.diff.com, worst.diff.tensor)[k]
            raised = worst.tol[k] > defaults[k]
            note = f"largest (relative to its tolerance) at {worst.label}" + (
                f"; tolerance raised to the written precision ({worst.tol[k]:.2g})" if raised else ""
            )
            check = self.value_check(ctx.options, prop, "rigid bodies", ("urdf", "mjcf"), error, note=note, samples=len(moving))
            checks.append(dataclasses.replace(check, tolerance=worst.tol[k], passed=within(error, worst.tol[k])))
        info.inertial_results = results
        findings = body_findings(moving, info) if info.file_mode else []
        section = Section(
            self.title,
            f"{len(results)} rigid bodies; total mass {info.u.total_mass:.6g} kg (URDF), "
            f"{info.m.total_mass:.6g} kg (MJCF); {sum(c.passed for c in checks)} of {len(checks)} checks pass.",
        )
        section.table(
            "Rigid bodies (common frame, zero configuration)",
            [
                "body (URDF / MJCF)",
                "URDF links",
                "MJCF bodies",
                "mass URDF [kg]",
                "mass MJCF [kg]",
                "Δ CoM [m]",
                "principal moments URDF [kg·m²]",
                "principal moments MJCF [kg·m²]",
                "ΔI [kg·m²]",
                "status",
            ],
            [
                [
                    r.label,
                    ", ".join(p.name for p in r.group.urdf),
                    ", ".join(p.name for p in r.group.mjcf),
                    r.urdf.mass,
                    r.mjcf.mass,
                    r.diff.com,
                    r.tensors["urdf_principal"],
                    r.tensors["mjcf_principal"],
                    r.diff.tensor,
                    r.status + (" (welded to the world)" if r.group.fixed_base_root else ""),
                ]
                for r in results
            ],
        )
        section.data["total_mass"] = {"urdf": info.u.total_mass, "mjcf": info.m.total_mass}
        return SuiteResult(checks, section, findings)


def _kind(r) -> str:
    mass_tol, com_tol, _ = r.tol
    if r.diff.mass > mass_tol:
        return "mass_difference"
    if r.diff.com > com_tol:
        return "com_difference"
    return "inertia_rotated" if r.tensors["same_moments"] else "inertia_difference"


def _describe(r) -> str:
    t = r.tensors
    parts = [
        f"mass {r.urdf.mass:.6g} kg (URDF) vs {r.mjcf.mass:.6g} kg (MJCF)" if r.diff.mass > r.tol[0] else "",
        f"centres of mass {r.diff.com:.3g} m apart" if r.diff.com > r.tol[1] else "",
        (
            f"same principal moments {_vec(t['mjcf_principal'])} kg·m² with axes turned {t['largest_axis_angle_deg']:.3g}° "
            f"({'; '.join(t['turned'])})"
            if t["same_moments"]
            else f"principal moments {_vec(t['urdf_principal'])} (URDF) vs {_vec(t['mjcf_principal'])} (MJCF) kg·m²"
            + (f", axes up to {t['largest_axis_angle_deg']:.3g}° apart" if t["largest_axis_angle_deg"] > 1e-3 else "")
        )
        + f": ΔI {r.diff.tensor:.3g} kg·m²"
        if r.diff.tensor > r.tol[2]
        else "",
    ]
    lumped = [p.name for p in r.group.urdf + r.group.mjcf if p.twin is None and not any(p is x for x in r.moved)]
    text = "; ".join(p for p in parts if p)
    if not math.isfinite(r.tol[1]):
        text += " (its centre of mass and inertia are not compared: they depend on a mesh file that is absent)"
    return text + (f" (including {', '.join(lumped)}, fixed to it in one file only)" if lumped else "")


def _alike(x: float) -> float:
    """A value to 4 significant digits, as the messages print it: bodies whose values agree so far
    (the fingers of a hand, mirrored legs) differ the same way and are one finding."""
    return float(f"{x:.4g}")


def _vec(v) -> str:
    return "[" + ", ".join(f"{x:.4g}" for x in v) + "]"


def body_findings(results, info) -> list[Finding]:
    """One finding per rigid body that differs (the same difference on several bodies is one
    finding); one ``rounding`` finding when bodies agree only to the written precision."""
    out: list[Finding] = []
    if info.inertials_explained_by:
        return out
    units = _mass_units(results, info)
    if units is not None:
        return [units]
    signature: dict[tuple, list] = {}
    for r in results:
        if r.status != "differs":
            continue
        key = (_kind(r),) + tuple(
            _alike(x)
            for x in (
                r.urdf.mass,
                r.mjcf.mass,
                r.diff.com,
                r.diff.tensor,
                *r.tensors["urdf_principal"],
                *r.tensors["mjcf_principal"],
            )
        )
        signature.setdefault(key, []).append(r)
    for (kind, *_), group in signature.items():
        r = group[0]
        names: dict[str, Any] = {"link": [x.group.urdf_link for x in group], "mjcf_link": [x.group.mjcf_link for x in group]}
        where = ", ".join(x.label for x in group)
        values = {
            "urdf": {
                "mass": r.urdf.mass,
                "com": r.urdf.com.tolist(),
                "inertia": r.urdf.inertia.tolist(),
                "principal": r.tensors["urdf_principal"],
                "links": [p.name for p in r.group.urdf],
            },
            "mjcf": {
                "mass": r.mjcf.mass,
                "com": r.mjcf.com.tolist(),
                "inertia": r.mjcf.inertia.tolist(),
                "principal": r.tensors["mjcf_principal"],
                "links": [p.name for p in r.group.mjcf],
            },
            "mass_difference_kg": r.mjcf.mass - r.urdf.mass,
            "com_distance_m": r.diff.com,
            "inertia_difference_kgm2": r.diff.tensor,
            "axes": r.tensors["axes"],
            "groups": [x.group.key for x in group],
            "checks": [[p, "rigid bodies"] for p in PROPS],
        }
        magnitude, unit = {"mass_difference": (r.diff.mass, "kg"), "com_difference": (r.diff.com, "m")}.get(
            kind, (r.diff.tensor, "kg·m²")
        )
        prefix = f"{len(group)} bodies alike: " if len(group) > 1 else ""
        out.append(
            finding(
                kind,
                f"{prefix}{where}: {_describe(r)}",
                values,
                magnitude=magnitude,
                unit=unit,
                prop={"mass_difference": "inertia.mass", "com_difference": "inertia.com"}.get(kind, "inertia.tensor"),
                **names,
            )
        )
    rounded = [r for r in results if r.status == "rounding"]
    if rounded:
        sides = [rounded_side(r.urdf.mass, r.mjcf.mass) for r in rounded if r.urdf.mass != r.mjcf.mass]
        side = max(set(sides), key=sides.count) if sides else "both files"
        coarse = next((p for p in info.precision if p.file == side), max(info.precision, key=lambda p: p.relative))
        out.append(
            finding(
                "rounding",
                f"{len(rounded)} rigid bodies agree only to the written precision ({coarse.describe(['relative', 'com', 'inertial_angle'])}): "
                f"largest |Δm| {max(r.diff.mass for r in rounded):.2g} kg, |Δcom| {max(r.diff.com for r in rounded):.2g} m, "
                f"ΔI {max(r.diff.tensor for r in rounded):.2g} kg·m²",
                {
                    "file": side,
                    "bodies": [r.label for r in rounded],
                    "mass_kg": max(r.diff.mass for r in rounded),
                    "com_m": max(r.diff.com for r in rounded),
                    "inertia_kgm2": max(r.diff.tensor for r in rounded),
                },
                magnitude=max(r.diff.mass for r in rounded),
                unit="kg",
                prop="inertia.mass",
            )
        )
    return out


def _mass_units(results, info) -> Finding | None:
    """Every body's mass a constant multiple of the other file's (grams as kilograms): one finding."""
    ratio = uniform_mass_ratio(info.inertial_results or results)
    name = unit_factor(ratio, "mass") if ratio is not None else None
    if name is None:
        return None
    massive = [r for r in results if r.urdf.mass > 0 and r.mjcf.mass > 0 and not r.group.fixed_base_root]
    return finding(
        "mass_units",
        f"the MJCF's masses are the URDF's {name} on all {len(massive)} rigid bodies",
        {
            "ratio": ratio,
            "urdf": [r.urdf.mass for r in massive],
            "mjcf": [r.mjcf.mass for r in massive],
            "checks": [[p, "rigid bodies"] for p in PROPS],
        },
        magnitude=ratio,
        unit="",
        prop="inertia.mass",
        link=[r.group.urdf_link for r in massive],
        mjcf_link=[r.group.mjcf_link for r in massive],
    )
