"""After the suites: the dynamics on the aligned files with the reported differences substituted,
the findings of one file's extra parts, tolerance floors, one finding per cause, accepted
differences, and the report section."""

from __future__ import annotations

import time
import traceback

import kinverify.filemode.findings.accepted as acc
from kinverify.errors import KinverifyError
from kinverify.filemode.compare.dynamics import FileDynamicsSuite, parameter_findings
from kinverify.filemode.compare.inertials import analyse
from kinverify.filemode.compare.parts import part_findings, total_mass_finding
from kinverify.filemode.findings.explain import apply_floors, dynamics_floors, explain, rounding_finding
from kinverify.filemode.findings.rounding import rounded_constants
from kinverify.filemode.findings.section import build_section
from kinverify.pipeline.sampling import Samples
from kinverify.suites.base import Section, VerifyContext, tolerance
from kinverify.suites.registry import get_property


def _tol(opts, name: str) -> float:
    return tolerance(opts, get_property(name))


def _snap_note(parts) -> str:
    """What MuJoCo's compiler did to the stated inertial of a rigid body's parts at run time."""
    did = [
        what
        for what, done in (
            ("aligned its principal axes with the body frame", any(p.snapped for p in parts)),
            ("put its centre of mass at the body origin", any(p.snapped_com for p in parts)),
        )
        if done
    ]
    return f" (MuJoCo {' and '.join(did)})" if did else ""


def run_dynamics(result, info, sources, opts, results, damping_joints) -> None:
    unknown = [r.label for r in results if r.status == "unknown"]
    if unknown:  # a placeholder mass makes the mass matrix near singular: nothing to measure there
        result.sections["dynamics"] = Section(
            FileDynamicsSuite.title,
            "not compared: the masses of " + ", ".join(unknown) + " come from mesh files that are absent (see mass_unknown)",
        )
        return
    snapped = {r.group.key for r in results if any(p.snapped or p.snapped_com for p in r.group.mjcf)}
    # the MJCF's whole rigid body, with what a joint in one file only moves (held at zero, as the
    # locked models hold it)
    groups = {
        r.group.key: r.group.total("mjcf")
        for r in results
        if (r.status in ("differs", "explained", "unset", "unknown") or r.moved or r.group.key in snapped)
        and not r.group.fixed_base_root
    }
    subs = [f"the MJCF's inertial of {r.label}" + _snap_note(r.group.mjcf) for r in results if r.group.key in groups]
    subs += [f"the MJCF's damping of {', '.join(sorted(damping_joints))}"] if damping_joints else []
    suite = FileDynamicsSuite(info, groups, damping_joints, subs)
    q = Samples(sources.lower, sources.upper, sources.revolute, max(opts.samples, 1), opts.seed)
    t0 = time.perf_counter()
    try:
        out = suite.run(VerifyContext(sources, {}, q, opts))
    except KinverifyError as err:
        result.sections["dynamics"] = Section(suite.title, f"skipped: {err}")
        return
    except Exception as err:  # our bug: say so, keep the rest
        where = traceback.extract_tb(err.__traceback__)[-1]
        result.internal_errors.append(
            f"suite dynamics: {type(err).__name__}: {err} ({where.filename.rsplit('/', 1)[-1]}:{where.lineno})"
        )
        return
    finally:
        result.timings["dynamics"] = time.perf_counter() - t0
    if out.section is not None:
        if subs:
            out.section.notes.insert(
                0, "Substituted on the Pinocchio side before comparing (each reported as a finding): " + "; ".join(subs) + "."
            )
        result.sections["dynamics"] = out.section
    result.checks += out.checks
    result.findings += out.findings


def finish(result, diag, sources, opts, dynamics: bool, entries, write_accepted, urdf_path: str) -> None:
    info = diag["info"]
    defaults = tuple(_tol(opts, p) for p in ("inertia.mass", "inertia.com", "inertia.tensor"))
    results = analyse(info, defaults)
    params = parameter_findings(info, {p: _tol(opts, p) for p in ("dynamics.damping", "dynamics.friction")})
    damping = {j for f in params if f.kind in ("damping_difference", "damping_unset") for j in f.subject.split(", ")}
    if dynamics:
        run_dynamics(result, info, sources, opts, results, damping)
    findings = diag["findings"] + part_findings(info, results, defaults[0]) + result.findings + params
    total = total_mass_finding(info, findings, defaults[0])
    findings += [total] if total else []
    checks, raised = apply_floors(result.checks, info)
    checks = dynamics_floors(
        checks,
        info,
        {
            p: _tol(opts, p)
            for p in ("dynamics.mass_matrix", "dynamics.gravity", "dynamics.bias", "dynamics.inverse", "dynamics.forward")
        },
    )
    xml = {"usd": "<robot/>"}  # a USD side is no XML: no rounded constant written as text to find
    culprits = [
        c
        for c in rounded_constants(
            xml.get(diag["urdf"].kind, diag["urdf"].text), xml.get(diag["mjcf"].kind, diag["mjcf"].original)
        )
    ]
    culprits = [(side, where, written, exact[1], decimals) for side, where, written, exact, decimals in culprits]
    rounding = rounding_finding(raised, info, culprits)
    findings += [rounding] if rounding else []
    checks, findings = explain(checks, findings, info)
    starts = {fr for f in findings if f.kind == "disagreement_starts" for fr in f.values.get("frames", [])}
    findings = [f for f in findings if not (f.kind == "frame_convention" and f.subject in starts)]  # no "motion agrees" there
    if entries:
        findings = acc.apply(findings, entries, lambda f: _tol(opts, f.property) if f.property else 1e-9)
    if write_accepted:
        path = acc.write(write_accepted, findings, f"{urdf_path} + {info and diag['mjcf'].path}")
        result.notes.append(f"accepted differences written to {path}: review each entry and give its reason")
    result.checks = checks
    result.findings = findings
    result.notes += diag["notes"]
    section = build_section(diag["urdf"], diag["mjcf"], info, findings, diag["notes"], diag["parser_rows"])
    result.sections = {"filemode": section, **{k: v for k, v in result.sections.items() if k != "filemode"}}
    result.model_info["files"] = {"urdf": diag["urdf"].path, "mjcf": diag["mjcf"].path}
    result.model_info["joint_pairs"] = [list(p) for p in info.matching.joints]
    result.model_info["frame_pairs"] = [list(p) for p in info.matching.frames]
