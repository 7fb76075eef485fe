"""Suite ``limits``: joint limits as the URDF (Pinocchio) and the MJCF (MuJoCo) state them.

- ``limits.position``: lower and upper bounds, in the MJCF's coordinates (file mode: the URDF's
  bounds carried through the joint's sign and zero offset); a joint limited in one file only
  differs by ``inf``;
- ``limits.effort``: URDF ``<limit effort>`` against the largest force MuJoCo's actuators can put
  on the joint (``forcerange``; ``ctrlrange × gain`` for a motor; times ``gear`` and a fixed
  tendon's coefficient); an actuator without a force bound differs by ``inf``. Several actuators
  on one joint are alternatives (a motor, a position servo, a velocity servo): the one stating
  the URDF's bound is compared when there is one (the others, if they differ, are a warning),
  else the largest. Not compared for a joint one file gives no limit;
- ``limits.velocity``: the spec's velocity limit against the URDF's (MJCF has no such field).

In file mode each difference above tolerance is also one finding, grouped by cause (limits read
in degrees, one file unlimited, actuators without a force bound, the same pair of values), and
limits rounded at the written precision are one ``rounding`` finding per file. A range that
differs only by the joint's zero offset (written alike in each file's own zero: a frame turned
about its joint's axis with the range left as written) is no limit finding: the ``zero_offset``
finding says it (:mod:`kinverify.filemode.findings.own_zero`); likewise an asymmetric range left as
written on a reversed axis (the ``axis_sign_flip`` finding says it). A range that differs beyond
them is a ``limit_difference`` of the part the joint map does not explain.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from kinverify.filemode.compare.context import file_view
from kinverify.filemode.compare.inertials import rounded_side
from kinverify.filemode.findings.own_zero import bound_error, bounds, mapped_bounds
from kinverify.filemode.findings.table import finding
from kinverify.suites.base import Finding, Property, Section, Suite, SuiteResult, VerifyContext, tolerance, within

DEGREE = 180 / math.pi
UNIT_RATIO = 2e-3  # relative closeness to 180/π for limits written in the other unit


def _unit(revolute: bool, prop: str) -> str:
    return {
        "limits.position": "rad" if revolute else "m",
        "limits.velocity": "rad/s" if revolute else "m/s",
        "limits.effort": "N·m" if revolute else "N",
    }[prop]


def _actuated(effort: float | None, joint) -> tuple[float | None, list[tuple[float, str]], int]:
    """The MJCF's force bound on ``joint`` as compared with the URDF's ``effort``: where several
    actuators drive the joint (alternatives: a motor, a position servo, a velocity servo), the
    bound of one that states the URDF's, the others that differ returned beside it, and how many
    state it; else the largest (none stating it: 0)."""
    if effort is None or not joint.effort_each:
        return joint.effort, [], 0
    same = [
        b
        for b, _ in joint.effort_each
        if b == effort or (math.isfinite(b) and math.isfinite(effort) and math.isclose(b, effort, rel_tol=1e-9, abs_tol=1e-12))
    ]
    if not same:
        return joint.effort, [], 0
    return same[0], [(b, how) for b, how in joint.effort_each if b not in same], len(same)


def _force_unit(rows: list[dict]) -> str:
    """N·m for revolute joints, N for prismatic ones, both for a mix."""
    kinds = {r["revolute"] for r in rows}
    return "N·m" if kinds == {True} else "N" if kinds == {False} else "N·m|N"


def _silent(joint, value: str) -> bool:
    """Whether the file leaves ``value`` ("range", "effort") of this joint unset."""
    return joint.stated is not None and value not in joint.stated


class LimitsSuite(Suite):
    name = "limits"
    title = "Joint limits: URDF vs MJCF"
    properties = (
        Property(
            "limits.position",
            "rad",
            1e-9,
            compares="lower and upper bounds, URDF <limit> vs MJCF range (file mode: "
            "through the joint's sign and zero offset); limited in one file only: inf",
        ),
        Property(
            "limits.effort",
            "N·m",
            1e-9,
            compares="URDF <limit effort> vs the force the MJCF's actuators can exert "
            "(forcerange, or ctrlrange × gain for a motor, × gear and tendon coefficient); no force bound: inf",
        ),
        Property("limits.velocity", "rad/s", 1e-9, compares="spec velocity limit vs URDF <limit velocity> (MJCF has none)"),
    )

    def run(self, ctx: VerifyContext) -> SuiteResult:

        info = file_view(ctx)
        if info is None:
            return SuiteResult([], Section(self.title, "skipped: needs both a URDF and an MJCF"))
        rows = self.measure(ctx, info)
        checks = []
        for prop in [p.name for p in self.properties]:
            measured = [r for r in rows if r[prop] is not None]
            if not measured:
                continue
            tol = tolerance(ctx.options, self.property(prop))
            floor = info.floor(prop, info.floors.limit) if prop == "limits.position" else 0.0
            worst = max(measured, key=lambda r: r[prop])
            revolute = {r["revolute"] for r in measured}
            unit = (
                _unit(True, prop)
                if revolute == {True}
                else _unit(False, prop)
                if revolute == {False}
                else f"{_unit(True, prop)}|{_unit(False, prop)}"
            )
            limit = max(tol, floor)
            note = f"largest at {worst['joint']}" + (
                f"; tolerance raised to the written precision ({floor:.2g})" if floor > tol else ""
            )
            check = self.value_check(
                ctx.options, prop, "joints", worst["pair"], worst[prop], note=note, unit=unit, samples=len(measured)
            )
            checks.append(dataclasses.replace(check, tolerance=limit, passed=within(worst[prop], limit)))
        findings = limit_findings(rows, info, {c.property: c.tolerance for c in checks}) if info.file_mode else []
        section = Section(self.title, f"{len(rows)} joints; {sum(c.passed for c in checks)} of {len(checks)} checks pass.")
        section.table(
            "Joint limits (MJCF coordinates)",
            [
                "joint (URDF / MJCF)",
                "lower URDF",
                "lower MJCF",
                "upper URDF",
                "upper MJCF",
                "effort URDF",
                "effort MJCF",
                "MJCF effort from",
            ],
            [
                [
                    r["label"],
                    r["lower"][0],
                    r["lower"][1],
                    r["upper"][0],
                    r["upper"][1],
                    r["effort"][0],
                    r["effort"][1],
                    r["effort_how"],
                ]
                for r in rows
            ],
        )
        if info.file_mode:
            velocity = [r for r in rows if r["velocity_urdf"] is not None]
            if velocity:
                section.notes.append(
                    "URDF velocity limits (the MJCF has no such field): "
                    + ", ".join(f"{r['joint']} {r['velocity_urdf']:g}" for r in velocity)
                )
            silent = [r["joint"] for r in rows if r["limits.effort"] is None]
            if silent:
                section.notes.append("effort not compared (one file states none): " + ", ".join(silent))
        return SuiteResult(checks, section, findings)

    @staticmethod
    def measure(ctx: VerifyContext, info) -> list[dict]:
        """One row per matched joint: bounds and efforts side by side, and each property's error."""
        spec = ctx.sources.spec
        spec_joints = {j.name: j for j in spec.joints} if spec is not None else {}
        rows = []
        for jm in info.alignment.joints:
            ju, jmj = info.u.joint(jm.urdf), info.m.joint(jm.mjcf)
            # a zero offset is a turn, known up to whole turns: the one that fits
            b = bounds(ju.lower, ju.upper, jmj.lower, jmj.upper, jm.sign, jm.offset, ju.type == "revolute")
            lo, up = b.lower, b.upper
            effort, others, alike = _actuated(ju.effort, jmj)
            row = {
                "joint": jm.urdf,
                "mjcf": jm.mjcf,
                "label": jm.urdf if jm.urdf == jm.mjcf else f"{jm.urdf} / {jm.mjcf}",
                "revolute": ju.type == "revolute",
                "pair": ("urdf", "mjcf"),
                "lower": (lo, jmj.lower),
                "upper": (up, jmj.upper),
                "effort": (ju.effort, effort),
                "effort_how": jmj.effort_how,
                "effort_others": others,
                "effort_alike": alike,
                "limits.position": b.error,
                "bounds": b,
                "offset": jm.offset,
                # the URDF's bounds in each file's own zero (the sign carried, the offset not)
                "own": list(zip(mapped_bounds(ju.lower, ju.upper, jm.sign, 0.0), (jmj.lower, jmj.upper), strict=True))
                if jm.offset
                else None,
                "limits.effort": bound_error(ju.effort, effort),
                "limits.velocity": None,
                "velocity_urdf": ju.velocity,
                "unset": {v: "URDF" if _silent(ju, v) else "MJCF" if _silent(jmj, v) else "" for v in ("range", "effort")},
            }
            if jm.urdf in spec_joints and ju.velocity is not None:
                row["limits.velocity"] = abs(spec_joints[jm.urdf].limits.velocity - ju.velocity)
            rows.append(row)
        return rows


def _in_degrees(pairs) -> bool:
    """(URDF bound, MJCF bound) pairs, each alike or one the other times 180/π (the same way for all)."""
    if pairs is None:
        return False
    return all(y == x or (x != 0 and abs(abs(y / x) / DEGREE - 1) < UNIT_RATIO) for x, y in pairs) or all(
        y == x or (y != 0 and abs(abs(x / y) / DEGREE - 1) < UNIT_RATIO) for x, y in pairs
    )


def limit_findings(rows: list[dict], info, tolerances: dict) -> list[Finding]:
    """Differences above tolerance as findings, one per cause; rounding as one info per file."""
    unlimited: dict[str, list[dict]]
    out, rounded, degrees, unlimited, other = [], [], [], {}, []
    tol = tolerances.get("limits.position", 1e-9)
    for r in rows:
        err = r["limits.position"]
        if err is None or err == 0:
            continue
        if r.get("bounds") is not None and r["bounds"].offset_explains(tol):
            continue  # the range written alike in each file's own zero: the zero offset finding says so
        pairs = [r["lower"], r["upper"]]
        if math.isinf(err):
            side = "URDF" if any(math.isinf(x) and not math.isinf(y) for x, y in pairs) else "MJCF"
            unlimited.setdefault(side, []).append(r)
        elif err <= tol:
            if err > 1e-9:
                rounded.append(r)
        elif any(_in_degrees(p) for p in (pairs, r.get("own"))):  # read through the zero offset, or in each file's own zero
            degrees.append(r)
        else:
            other.append(r)
    unit = lambda r: "rad" if r["revolute"] else "m"  # noqa: E731
    for r in other:
        size, beyond = r["limits.position"], ""
        b = r.get("bounds")
        if b is not None and b.beyond_offset(tol) != size:  # read in each file's own coordinates, the joint map explains the rest
            size = b.beyond_offset(tol)
            beyond = (
                f" beyond the zero offset of {r['offset']:.6g} {unit(r)} (each file's range read in its own zero; "
                f"{r['limits.position']:.4g} {unit(r)} with the offset carried)"
                if r["offset"]
                else f" beyond the reversed axis (each file's range read as written; {r['limits.position']:.4g} "
                f"{unit(r)} with the axis carried)"
            )
        out.append(
            finding(
                "limit_difference",
                f"joint {r['label']}: limits [{r['lower'][0]:.6g}, {r['upper'][0]:.6g}] in the URDF, "
                f"[{r['lower'][1]:.6g}, {r['upper'][1]:.6g}] in the MJCF (MJCF coordinates): {size:.4g} "
                f"{unit(r)} apart" + beyond,
                {
                    "urdf": [r["lower"][0], r["upper"][0]],
                    "mjcf": [r["lower"][1], r["upper"][1]],
                    "beyond_zero_offset": bool(beyond and r["offset"]),
                    "beyond_reversed_axis": bool(beyond and not r["offset"]),
                    "checks": [["limits.position", "joints"]],
                },
                magnitude=size,
                unit=unit(r),
                prop="limits.position",
                joint=r["joint"],
                mjcf_joint=r["mjcf"],
            )
        )
    for side, group in unlimited.items():
        silent = [r for r in group if r["unset"]["range"] == side]
        if silent:
            limiting = "MJCF" if side == "URDF" else "URDF"
            out.append(
                finding(
                    "limit_unset",
                    f"the {side} leaves {len(silent)} joints without limits (no range stated: "
                    f"unlimited by default); the {limiting} limits them: "
                    + ", ".join(
                        f"{r['label']} [{r['lower'][0 if side == 'MJCF' else 1]:.6g}, "
                        f"{r['upper'][0 if side == 'MJCF' else 1]:.6g}]"
                        for r in silent
                    ),
                    {
                        "unset_in": side,
                        "urdf": [[r["lower"][0], r["upper"][0]] for r in silent],
                        "mjcf": [[r["lower"][1], r["upper"][1]] for r in silent],
                        "checks": [["limits.position", "joints"]],
                    },
                    magnitude=math.inf,
                    unit="rad",
                    prop="limits.position",
                    joint=[r["joint"] for r in silent],
                    mjcf_joint=[r["mjcf"] for r in silent],
                )
            )
            group = [r for r in group if r not in silent]
        if not group:
            continue
        out.append(
            finding(
                "limit_difference",
                f"{len(group)} joints are unlimited in the {side} and limited in the other file: "
                + ", ".join(
                    f"{r['label']} [{r['lower'][0 if side == 'MJCF' else 1]:.6g}, {r['upper'][0 if side == 'MJCF' else 1]:.6g}]"
                    for r in group
                ),
                {
                    "unlimited_in": side,
                    "urdf": [[r["lower"][0], r["upper"][0]] for r in group],
                    "mjcf": [[r["lower"][1], r["upper"][1]] for r in group],
                    "checks": [["limits.position", "joints"]],
                },
                magnitude=math.inf,
                unit="rad",
                prop="limits.position",
                joint=[r["joint"] for r in group],
                mjcf_joint=[r["mjcf"] for r in group],
            )
        )
    if degrees:
        big = (
            "MJCF"
            if max(abs(x) for r in degrees for x in (r["lower"][1], r["upper"][1]) if math.isfinite(x))
            > max(abs(x) for r in degrees for x in (r["lower"][0], r["upper"][0]) if math.isfinite(x))
            else "URDF"
        )
        how = {
            ("URDF", "degree"): 'the MJCF\'s ranges are written in radians, but without <compiler angle="radian"> '
            "MuJoCo reads them in degrees",
            ("URDF", "radian"): "the URDF's limits are written in degrees (URDF limits are radians)",
            ("MJCF", "radian"): 'the MJCF\'s ranges are written in degrees, but <compiler angle="radian"> makes '
            "MuJoCo read them in radians",
        }.get((big, info.mjcf_angle), "one file's limits are the other's in degrees")
        out.append(
            finding(
                "limit_units",
                f"{how}: {len(degrees)} joints' limits differ by the factor 180/π: " + ", ".join(r["label"] for r in degrees),
                {
                    "file": "MJCF" if "MJCF" in how.split(" ")[1] else big,
                    "urdf": [[r["lower"][0], r["upper"][0]] for r in degrees],
                    "mjcf": [[r["lower"][1], r["upper"][1]] for r in degrees],
                    "checks": [["limits.position", "joints"]],
                },
                magnitude=max(r["limits.position"] for r in degrees),
                unit="rad",
                prop="limits.position",
                joint=[r["joint"] for r in degrees],
                mjcf_joint=[r["mjcf"] for r in degrees],
            )
        )
    by_side: dict[str, list[dict]] = {}
    for r in rounded:
        x, y = max((r["lower"], r["upper"]), key=lambda p: abs(p[0] - p[1]))
        by_side.setdefault(rounded_side(x, y), []).append(r)
    for side, group in by_side.items():
        largest = max(r["limits.position"] for r in group)
        precision = next((p for p in info.precision if p.file == side), None)
        how = precision.describe(["limit"]) if precision is not None else "both files round them"
        out.append(
            finding(
                "rounding",
                f"{len(group)} joints' limits agree to {largest:.2g} only, rounded where written: {how} "
                f"(within the written precision, {tol:.2g}): " + ", ".join(r["label"] for r in group),
                {"file": side, "joints": [r["joint"] for r in group], "largest": largest},
                magnitude=largest,
                unit="rad",
                prop="limits.position",
            )
        )
    # followers: coupled in the comparison, or in either file to any joint (a finger an MJCF couples
    # to a gripper slide the URDF lacks is driven through the slide's actuator)
    coupled_m = {c.follower for c in info.m.couplings}
    coupled_u = {c.follower for c in info.u.couplings}
    followers = set(info.alignment.couplings) | {
        j.urdf for j in info.alignment.joints if j.mjcf in coupled_m or j.urdf in coupled_u
    }
    out += effort_findings(rows, tolerances.get("limits.effort", 1e-9), followers)
    return out


def effort_findings(rows: list[dict], tol: float, followers=frozenset()) -> list[Finding]:
    """Force bounds that differ, or that one file leaves unset; ``followers``: coupled joints, driven
    through their leader (a follower with no actuator of its own is not unbounded)."""

    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        err = r["limits.effort"]
        if err is None or err <= tol:
            continue
        u, m = r["effort"]
        key = ("unbounded", math.isinf(m)) if math.isinf(err) else ("values", round(u, 9), round(m, 9))
        groups.setdefault(key, []).append(r)
    out = []
    for side, other in (("URDF", "MJCF"), ("MJCF", "URDF")):  # no bound stated at all in one file
        k = 0 if side == "URDF" else 1
        silent = [r for r in rows if r["effort"][k] is None and r["effort"][1 - k] is not None and r["joint"] not in followers]
        if silent:
            unit = _force_unit(silent)
            how = "no <limit effort>" if side == "URDF" else "no actuator on them"
            custom = [r["effort_how"] for r in silent if r["effort_how"].startswith("no drive: urdf:limit:effort")]
            if side == "MJCF" and len(custom) == len(silent):  # a USD side: the converter kept the effort as a custom attribute
                how = (
                    "no drive; the effort survives only as the custom attribute urdf:limit:effort ("
                    + ", ".join(c.split(" = ")[1].split(" ")[0] for c in custom)
                    + "), which no simulator reads"
                )
            elif side == "MJCF" and all(r["effort_how"].startswith("no drive") for r in silent):  # a USD side
                how = "no drive and no mjc:actuatorfrcrange"
            out.append(
                finding(
                    "effort_unset",
                    f"the {side} states no force bound on {len(silent)} joints ({how}); the "
                    f"{other} bounds them: " + ", ".join(f"{r['label']} {r['effort'][1 - k]:g}" for r in silent) + f" {unit}",
                    {"unset_in": side, "urdf": [r["effort"][0] for r in silent], "mjcf": [r["effort"][1] for r in silent]},
                    magnitude=max(r["effort"][1 - k] for r in silent),
                    unit=unit,
                    prop="limits.effort",
                    joint=[r["joint"] for r in silent],
                    mjcf_joint=[r["mjcf"] for r in silent],
                )
            )
    alike = [r for r in rows if r.get("effort_alike", 0) > 1 and not r.get("effort_others")]
    if alike:  # every actuator of the joint states the URDF's bound
        out.append(
            finding(
                "several_actuators",
                f"the MJCF drives {len(alike)} joints by several actuators, each bounded as the URDF "
                "bounds the joint (compared as alternatives; acting together in MuJoCo their forces add up): "
                + ", ".join(f"{r['label']} {r['effort_alike']} × {r['effort'][0]:g}" for r in alike),
                {"urdf": [r["effort"][0] for r in alike], "actuators": [r["effort_alike"] for r in alike]},
                prop="limits.effort",
                joint=[r["joint"] for r in alike],
                mjcf_joint=[r["mjcf"] for r in alike],
            )
        )
    several = [r for r in rows if r.get("effort_others")]
    if several:  # one actuator of a joint states the URDF's bound, another on it a different one
        unit = _force_unit(several)
        out.append(
            finding(
                "actuator_alternatives",
                f"the MJCF drives {len(several)} joints by several actuators, one of which bounds the "
                "force as the URDF does while another allows a different force: "
                + "; ".join(
                    f"{r['label']} {r['effort'][0]:g} {unit} in the URDF, " + ", ".join(how for _, how in r["effort_others"])
                    for r in several
                ),
                {"urdf": [r["effort"][0] for r in several], "mjcf_others": [[b for b, _ in r["effort_others"]] for r in several]},
                magnitude=max(abs(b - r["effort"][0]) for r in several for b, _ in r["effort_others"]),
                unit=unit,
                prop="limits.effort",
                joint=[r["joint"] for r in several],
                mjcf_joint=[r["mjcf"] for r in several],
            )
        )
    for key, group in groups.items():
        unit = _force_unit(group)
        names: dict[str, Any] = {"joint": [r["joint"] for r in group], "mjcf_joint": [r["mjcf"] for r in group]}
        values = {
            "urdf": [r["effort"][0] for r in group],
            "mjcf": [r["effort"][1] for r in group],
            "mjcf_from": [r["effort_how"] for r in group],
            "checks": [["limits.effort", "joints"]],
        }
        if key[0] == "unbounded":
            side = "MJCF" if key[1] else "URDF"
            if all(r["unset"]["effort"] == side for r in group):
                other = "URDF" if side == "MJCF" else "MJCF"
                msg = (
                    f"the {side} leaves the force on {len(group)} joints unbounded ("
                    + "; ".join(f"{r['label']}: {r['effort_how'] if side == 'MJCF' else 'no effort'}" for r in group[:3])
                    + ("; …" if len(group) > 3 else "")
                    + f"); the {other} limits it to "
                    + ", ".join(f"{r['effort'][0 if side == 'MJCF' else 1]:g}" for r in group)
                    + f" {unit}"
                )
                out.append(
                    finding(
                        "effort_unset",
                        msg,
                        {**values, "unset_in": side},
                        magnitude=math.inf,
                        unit=unit,
                        prop="limits.effort",
                        **names,
                    )
                )
                continue
            msg = (
                f"{len(group)} joints: the {side}'s actuators put no bound on the joint force ("
                + "; ".join(f"{r['label']}: {r['effort_how'] if side == 'MJCF' else 'URDF'}" for r in group[:3])
                + ("; …" if len(group) > 3 else "")
                + "), the other file limits it to "
                + ", ".join(f"{r['effort'][0 if side == 'MJCF' else 1]:g}" for r in group)
                + f" {unit}"
            )
            out.append(finding("effort_difference", msg, values, magnitude=math.inf, unit=unit, prop="limits.effort", **names))
        else:
            u, m = group[0]["effort"]
            msg = (
                f"{', '.join(r['label'] for r in group)}: effort limit {u:g} {unit} in the URDF, {m:g} {unit} in the MJCF "
                f"({group[0]['effort_how']})" + (f": ×{m / u:.4g}" if u else "")
            )
            out.append(finding("effort_difference", msg, values, magnitude=abs(u - m), unit=unit, prop="limits.effort", **names))
    return out
