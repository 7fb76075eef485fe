"""One cause, one finding, and findings decide the verdict.

After the suites ran (on the aligned files):

1. Kinematics checks get the tolerance floor of the files' written precision at their frame
   (unless the user set that property's tolerance); what passes only thanks to it is one
   ``rounding`` finding.
2. A failing check that an error (or warning) finding explains is marked ``kind = "explained"`` with a note
   naming the finding: it is shown, and no longer counts on its own (the finding does, so an
   accepted finding passes and a new one fails). Kinematics checks are explained by the finding
   of the joint upstream of their frame (axis, type, sign), the others by the finding that lists
   them (``values["checks"]``).
3. What no finding explains gets one: ``disagreement_starts`` at the first frame whose FK still
   differs (with its size), ``dynamics_difference`` for dynamics that still differ after the
   reported differences were substituted.
"""

from __future__ import annotations

import dataclasses

from kinverify.filemode.findings.table import finding
from kinverify.suites.base import EXPLAINED, Check, Finding, within

CAUSES = ("error", "warning")  # a value one file leaves unset explains the checks it fails, as a warning
KINEMATIC = ("fk.position", "fk.rotation", "jacobian.linear", "jacobian.angular")
STATE = ("dynamics.mass_matrix", "dynamics.gravity", "dynamics.bias", "dynamics.inverse", "dynamics.forward")


def apply_floors(checks: list[Check], info) -> tuple[list[Check], list[Check]]:
    """Kinematics checks with the written-precision floor; also those that pass only thanks to it."""
    out, raised = [], []
    for c in checks:
        floor = info.floor(c.property, info.floors.check(c.property, c.frame)) if c.property in KINEMATIC else 0.0
        if floor > c.tolerance:
            new = dataclasses.replace(
                c,
                tolerance=floor,
                passed=within(c.max_error, floor),
                note="; ".join(x for x in (c.note, f"tolerance raised to the written precision ({floor:.2g})") if x),
            )
            if new.passed and not c.passed:
                raised.append(new)
            c = new
        out.append(c)
    return out, raised


def dynamics_floors(checks: list[Check], info, defaults: dict) -> list[Check]:
    """Dynamics state checks with the relative floor of the written precision."""
    out = []
    for c in checks:
        base = defaults.get(c.property, 0.0)
        if c.property in STATE and base > 0 and info.floors.dynamics > 0:
            floor = info.floor(c.property, info.floors.dynamics * max(1.0, c.tolerance / base))
            if floor > c.tolerance:
                c = dataclasses.replace(
                    c,
                    tolerance=floor,
                    passed=within(c.max_error, floor),
                    note="; ".join(x for x in (c.note, f"tolerance raised to the written precision ({floor:.2g})") if x),
                )
        out.append(c)
    return out


def rounding_finding(raised: list[Check], info, culprits: list[tuple]) -> Finding | None:
    """One info finding for FK that agrees only to the written precision."""
    if not raised:
        return None
    order = {f: i for i, (f, _, _) in enumerate(info.matching.frames)}
    first = min(raised, key=lambda c: order.get(c.frame, 1 << 30))
    pos = max((c.max_error for c in raised if c.property == "fk.position"), default=0.0)
    rot = max((c.max_error for c in raised if c.property == "fk.rotation"), default=0.0)
    pa, pb = info.precision
    where = "; ".join(
        f"the {side} writes {written} for {label} at {place} (rounded to {decimals} decimals)"
        for side, place, written, label, decimals in culprits
    )
    msg = (
        f"the files agree to {pos:.2g} m and {rot:.2g} rad only, from frame {first.frame} on: within the precision they are "
        f"written with ({where or pa.describe(['angle', 'length']) + '; ' + pb.describe(['angle', 'length'])})"
    )
    mjcf = next((b for a, b, _ in info.matching.frames if a == first.frame), "")
    return finding(
        "rounding",
        msg,
        {
            "position_m": pos,
            "rotation_rad": rot,
            "frames": sorted({c.frame for c in raised}),
            "culprits": [list(c) for c in culprits],
        },
        magnitude=max(pos, rot),
        unit="m|rad",
        frame=first.frame,
        mjcf_frame=mjcf,
    )


def _explainers(c: Check, findings: list[Finding]) -> list[Finding]:
    return [
        f
        for f in findings
        if f.severity in CAUSES
        and (
            [c.property, c.frame] in [list(x) for x in f.values.get("checks", [])]
            or (c.property in KINEMATIC and c.frame in f.values.get("frames", []))
        )
    ]


def _explainer(c: Check, findings: list[Finding]) -> Finding | None:
    found = _explainers(c, findings)
    return found[0] if found else None


def explain(checks: list[Check], findings: list[Finding], info) -> tuple[list[Check], list[Finding]]:
    """Mark failing checks explained by an error finding; one new finding for what none explains."""
    new_findings = list(findings)
    order = {f: i for i, (f, _, _) in enumerate(info.matching.frames)}
    loose = [c for c in checks if c.decisive_failure and c.property in KINEMATIC and _explainer(c, findings) is None]
    if loose:
        first = min(loose, key=lambda c: order.get(c.frame, 1 << 30))
        frames = sorted({c.frame for c in loose}, key=lambda f: order.get(f, 1 << 30))
        pos = max((c.max_error for c in loose if c.property == "fk.position"), default=0.0)
        rot = max((c.max_error for c in loose if c.property == "fk.rotation"), default=0.0)
        mjcf = next((b for a, b, _ in info.matching.frames if a == first.frame), "")
        new_findings.append(
            finding(
                "disagreement_starts",
                f"forward kinematics differ from frame {first.frame} on, by up to "
                f"{pos:.3g} m and {rot:.3g} rad after alignment ({len(frames)} frames; the alignment cannot "
                "explain it: a joint origin, axis or link length differs there)",
                {"position_m": pos, "rotation_rad": rot, "frames": frames},
                magnitude=max(pos, rot),
                unit="m|rad",
                frame=first.frame,
                mjcf_frame=mjcf,
            )
        )
    state = [c for c in checks if c.decisive_failure and c.property in STATE]
    kinematic = [f for f in new_findings if f.severity == "error" and f.values.get("frames")]
    if state and not kinematic and not any(_explainer(c, new_findings) for c in state):
        worst = max(state, key=lambda c: c.max_error / c.tolerance if c.tolerance else 0.0)
        new_findings.append(
            finding(
                "dynamics_difference",
                f"the dynamics still differ after substituting every difference "
                f"reported: {', '.join(f'{c.property} {c.max_error:.3g} {c.unit}' for c in state)}",
                {"checks": [[c.property, c.frame] for c in state]},
                magnitude=worst.max_error,
                unit=worst.unit,
                prop=worst.property,
            )
        )
    out = []
    for c in checks:
        if c.decisive_failure:
            found = _explainers(c, new_findings) or (kinematic[:1] if c.property in STATE else [])
            if found:
                why = "explained by " + "; ".join(f"{f.kind} on {f.label}" for f in found)
                c = dataclasses.replace(c, kind=EXPLAINED, note="; ".join(x for x in (c.note, why) if x))
        out.append(c)
    return out, new_findings
