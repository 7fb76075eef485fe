"""File mode: cross-validate an existing URDF against an existing MJCF, and say what differs.

``verify_files`` reads both files safely (meshes dropped), describes each through its library
(URDF: Pinocchio, MJCF: MuJoCo), matches joints and frames, aligns the two (world transform, joint
zero offsets and signs, frame conventions: :mod:`kinverify.filemode.align`), then runs every
suite that applies on the aligned files (kinematics with every library that reads each file,
limits, inertia, dynamics) and reports each difference once, as a finding with its size.
Findings decide the verdict: a failing check whose cause a finding reports is marked explained;
accepted findings (``kinverify-accepted.toml``) pass. See docs/file-mode.md.
"""

from __future__ import annotations

import dataclasses
import time

__all__ = ["verify_files", "diagnose_files", "FILE_SUITES"]

FILE_SUITES = ("kinematics", "limits", "inertia", "dynamics", "pictures")  # pictures: both files drawn, aligned
PITCH_MARGIN = 1e-3  # rad: base pitch sampled inside ±(π/2 − this) in file mode
ALIGN_SAMPLES = 24  # configurations (besides q = 0) the alignment fits over


def diagnose_files(urdf: str, mjcf: str, options=None, frames=(), joints=()) -> dict:
    """Everything file mode knows before the suites run: both files read and described, matched,
    aligned, with each library's reading built; the findings so far."""
    from kinverify.filemode import build, parts
    from kinverify.filemode.context import FileModeInfo
    from kinverify.filemode.crosscheck import cross_check, top_level_pose
    import numpy as np

    from kinverify.filemode.diagnose import alignment_findings, convention_findings, finding, length_units
    from kinverify.filemode.floating import base_findings, base_samples
    from kinverify.model.floating import BASE_REVOLUTE, base_limits
    from kinverify.filemode.geometry import reach
    from kinverify.filemode.match import match
    from kinverify.filemode.precision import floors, mjcf_precision, urdf_precision
    from kinverify.pipeline.sampling import sample_configurations
    from kinverify.run import VerifyOptions

    options = options or VerifyOptions()
    wanted = build.side_names(options)
    findings, internal = [], []
    M, mjcf_text, m, free = build.read_mjcf(mjcf, findings)
    U, urdf_text, u, library, base = build.read_urdf(urdf, findings, free)
    matching = match(u, m, joints, frames)
    if base.floating:  # the URDF's link above its floating root stays in the world: not the robot's
        matching.frames = [p for p in matching.frames if not (base.urdf.kind == "floating" and p[0] == base.urdf.root)]
    precision = (urdf_precision(U.text), mjcf_precision(M.original))
    fl = floors(*precision, matching.frames, reach(u), len(matching.independent))
    lower, upper, revolute = build.sample_ranges(u, matching.independent)
    q = sample_configurations(lower, upper, revolute, ALIGN_SAMPLES, seed=options.seed, edges=False)
    al, poses = build.run_alignment(u, m, matching, urdf_text, mjcf_text, library, fl, q, internal)
    poses_u, poses_m = build.zero_poses(poses, al)
    info = FileModeInfo(u, m, matching, al, fl, precision, bool(free), poses_u, poses_m,
                        frozenset(options.tolerances), mjcf_angle=mjcf_angle_unit(M.original), base_coordinates=base.floating)

    tol = info.tol
    twins, new_pairs = _guarded(internal, "frames with no same-named twin", lambda: parts.frame_twins(info, tol), ([], []))
    matching.frames += new_pairs
    build.add_frames(al, new_pairs)
    compared = [a for a, _, _ in matching.frames]
    if base.kind:
        findings.append(finding(base.kind, base.message, {"urdf": base.urdf.kind, "urdf_root": base.urdf.root,
                                                          "mjcf_free_bodies": free}))
    kinds = {a: m.frame_kind.get(b, "link") for a, b, _ in matching.frames}
    units = _guarded(internal, "length units", lambda: length_units(u, m, matching, compared), [])
    info.inertials_explained_by = units[0].kind if units else ""
    findings += units or _guarded(internal, "alignment findings", lambda: base_findings(
        alignment_findings(u, m, matching, al, compared, tol), base) + convention_findings(al, kinds, tol), [])
    findings += twins
    from kinverify.filemode.validate import validate_inertials

    findings += _guarded(internal, "inertial validation", lambda: validate_inertials(U, M), [])
    texts = (base.urdf_text, M.text) if base.floating else (urdf_text, mjcf_text)
    backends = build.build_backends(info, *texts, wanted, tol, findings)
    worst = max([tol(f) for f in compared] or [(1e-9, 1e-9)])
    if base.floating:  # the libraries' readings cross-checked at random base poses too
        q = np.concatenate([base_samples(len(q), options.seed), q], axis=1)
    backends, parser, parser_rows = _guarded(
        internal, "parser cross-check",
        lambda: cross_check(backends, q, worst, al.T, top_level_pose(mjcf_text), build.rebuild_mjcf), (backends, [], []))
    findings += parser
    findings += _guarded(internal, "couplings", lambda: _couplings(u, m, matching), [])
    ref = next((n for n in ("pinocchio-urdf", "mujoco-urdf", "yourdfpy") if n in backends), None)
    other = next((n for n in ("mujoco", "pinocchio-mjcf") if n in backends), None)
    if ref is None or other is None:
        from kinverify.errors import InputError

        raise InputError(f"no library could read the {'URDF' if ref is None else 'MJCF'}: "
                         + "; ".join(f.message for f in findings if f.kind == "parser_refused"))
    notes = list(U.warnings + M.warnings) + [f"URDF: {s}" for s in u.skipped] + [f"MJCF: {s}" for s in m.skipped] + info.notes
    notes.append(f"written precision: {precision[0].describe()}; {precision[1].describe()}")
    if base.floating:
        urdf_text, mjcf_text = texts
        base_lo, base_up = base_limits(np.zeros(3))
        # pitch kept 1e-3 rad off ±π/2: there roll and yaw merge, and a base frame offset between the
        # files (the coordinates conjugated) has no derivative, so the Jacobians would differ by a choice
        base_lo[4], base_up[4] = base_lo[4] + PITCH_MARGIN, base_up[4] - PITCH_MARGIN
        lower, upper = [*base_lo, *lower], [*base_up, *upper]
        revolute = [*BASE_REVOLUTE, *revolute]
    return dict(urdf=U, mjcf=M, urdf_text=urdf_text, mjcf_text=mjcf_text, info=info, matching=matching, alignment=al,
                backends=backends, reference=ref, findings=findings, notes=notes, parser_rows=parser_rows,
                internal=internal, lower=lower, upper=upper, revolute=revolute)


def mjcf_angle_unit(mjcf_text: str) -> str:
    """The MJCF's ``<compiler angle>``: "degree" (MuJoCo's default) or "radian"."""
    import xml.etree.ElementTree as ET

    compiler = ET.fromstring(mjcf_text).find("compiler")
    return "degree" if compiler is None else compiler.get("angle", "degree")


def _guarded(internal: list, what: str, fn, default):
    """``fn()``, or ``default`` with an internal error recorded when it fails (kinverify's bug)."""
    from kinverify.errors import KinverifyError

    try:
        return fn()
    except (KinverifyError, KeyboardInterrupt):
        raise
    except Exception as err:
        internal.append(f"file mode, {what}: {type(err).__name__}: {err}")
        return default


def _couplings(u, m, matching) -> list:
    """Couplings (URDF <mimic>, MJCF <equality joint>) that differ, or that one file lacks."""
    from kinverify.filemode.diagnose import finding

    out = []
    to_u = {b: a for a, b, _ in matching.joints}
    mine = {c.follower: c for c in u.couplings}
    theirs = {}
    for c in m.couplings:
        f, lead = to_u.get(c.follower), to_u.get(c.leader)
        if f is None or lead is None:
            continue
        if f in mine and mine[f].leader == lead or lead not in mine:
            theirs[f] = (lead, c.multiplier, c.offset, c)
        else:  # the MJCF states it the other way round: leader = (follower − offset) / multiplier
            theirs[lead] = (f, 1 / c.multiplier, -c.offset / c.multiplier, c) if c.multiplier else (f, 0.0, 0.0, c)
    for f in sorted(set(mine) | set(theirs)):
        a, b = mine.get(f), theirs.get(f)
        if a is None or b is None:
            side = "URDF" if a is not None else "MJCF"
            lead = a.leader if a is not None else b[0]
            out.append(finding("coupling_one_file", f"joint {f} follows {lead} in the {side} only ({(a or b[3]).source}); the "
                               "other file leaves it free: compared as coupled", {"file": side, "leader": lead}, joint=f))
        elif a.leader != b[0] or abs(a.multiplier - b[1]) > 1e-9 or abs(a.offset - b[2]) > 1e-9:
            out.append(finding("coupling_difference", f"joint {f}: {f} = {a.multiplier:g}·{a.leader} + {a.offset:g} in the URDF, "
                               f"{b[1]:g}·{b[0]} + {b[2]:g} in the MJCF", {"urdf": [a.multiplier, a.offset],
                                                                          "mjcf": [b[1], b[2]]}, joint=f))
    return out


def verify_files(urdf: str, mjcf: str, options=None, frames=(), joints=(), command: str = "", accept=None,
                 write_accepted=None):
    """File mode of ``kinverify verify``: the suites on the aligned files and the findings, as a
    VerifyResult. ``accept``: an accepted-differences TOML file (default: ``kinverify-accepted.toml``
    beside the URDF, when present); ``write_accepted``: write this run's error findings there."""
    from kinverify.backends import ModelSources
    import kinverify.filemode.accepted as acc
    from kinverify.model.floating import BASE_COORDINATES
    from kinverify.run import VerifyOptions, verify

    t0 = time.perf_counter()
    options = options or VerifyOptions()
    entries = acc.load(accept) if accept else (acc.load(p, "the accepted differences") if (p := acc.default_path(urdf)) else [])
    internal: list[str] = []
    diag = _guarded(internal, "reading the files", lambda: diagnose_files(urdf, mjcf, options, frames, joints), None)
    if diag is None:
        return _failed(urdf, mjcf, options, internal, command)
    info, U, M = diag["info"], diag["urdf"], diag["mjcf"]
    al, matching = info.alignment, info.matching
    name = M.name if M.name == U.name else f"{U.name}-vs-{M.name}"
    base = BASE_COORDINATES if info.base_coordinates else ()
    sources = ModelSources(name, base + tuple(al.independent), tuple(a for a, _, _ in matching.frames), tuple(diag["lower"]),
                           tuple(diag["upper"]), tuple(diag["revolute"]), urdf=diag["urdf_text"], mjcf=diag["mjcf_text"],
                           mjcf_joint_names=base + tuple(matching.mjcf_name(a) for a in al.independent),
                           mjcf_frames=tuple(b for _, b, _ in matching.frames))
    selected = [s for s in FILE_SUITES if options.suites is None or s in options.suites]
    opts = dataclasses.replace(options, reference=diag["reference"], backends=[diag["reference"]],
                               suites=[s for s in selected if s != "dynamics"], extra={**options.extra, "filemode": info})
    result = verify(sources, opts, extra_backends=list(diag["backends"].values()), source=f"{urdf} + {mjcf}", command=command)
    result.internal_errors = diag["internal"] + result.internal_errors
    from kinverify.filemode.finish import finish

    _guarded(result.internal_errors, "findings",
             lambda: finish(result, diag, sources, opts, "dynamics" in selected, entries, write_accepted, urdf), None)
    result.duration_s = time.perf_counter() - t0
    return result


def _failed(urdf: str, mjcf: str, options, internal: list[str], command: str):
    """The result of a run kinverify itself could not complete (verdict ``error``, exit 3)."""
    from pathlib import Path

    from kinverify.results import VerifyResult
    from kinverify.versions import library_versions

    return VerifyResult(model=f"{Path(urdf).stem}-vs-{Path(mjcf).stem}", source=f"{urdf} + {mjcf}", seed=options.seed,
                        samples=0, joint_names=[], frames=[], backends=[], checks=[], versions=library_versions(),
                        command=command, internal_errors=internal, model_info={"files": {"urdf": urdf, "mjcf": mjcf}})
