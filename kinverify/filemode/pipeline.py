"""File mode: cross-validate an existing URDF against an existing MJCF (or an SDFormat file against
either, read by Drake), and say what differs.

``verify_files`` reads both files safely (meshes dropped), describes each through its library
(URDF: Pinocchio, MJCF: MuJoCo), matches joints and frames, aligns the two (world transform, joint
zero offsets and signs, frame conventions: :mod:`kinverify.filemode.align.fit`), then runs every
suite that applies on the aligned files (kinematics with every library that reads each file,
limits, inertia, dynamics) and reports each difference once, as a finding with its size.
Findings decide the verdict: a failing check whose cause a finding reports is marked explained;
accepted findings (``kinverify-accepted.toml``) pass. See docs/file-mode.md.

The two files are two *sides* (:mod:`kinverify.filemode.read.files`): the first read as the URDF
is, the second as the MJCF is; an SDFormat file takes the side of the format it is paired with
(``kinds``), and what is said of a side names its format. Three files at once (``verify_three``)
are two pairs, URDF against MJCF and URDF against SDFormat, in one result.
"""

from __future__ import annotations

import dataclasses
import re
import time
from pathlib import Path
from typing import Any

import numpy as np

import kinverify.filemode.findings.accepted as acc
from kinverify.backends import ModelSources, names_reading
from kinverify.errors import InputError, KinverifyError
from kinverify.filemode.align.attribution import attribute
from kinverify.filemode.align.run import unmoved_world
from kinverify.filemode.align.floating import base_findings, base_samples
from kinverify.filemode.align.geometry import reach
from kinverify.filemode.align.match import match
from kinverify.filemode.align.run import add_frames, run_alignment, sample_ranges, zero_poses
from kinverify.filemode.compare.context import FileModeInfo
from kinverify.filemode.compare.crosscheck import cross_check, top_level_pose
from kinverify.filemode.compare.libraries import build_backends, rebuild_mjcf, side_names
from kinverify.filemode.compare.parts import frame_twins
from kinverify.filemode.findings.alignment import alignment_findings, convention_findings, length_units
from kinverify.filemode.findings.couplings import coupling_findings
from kinverify.filemode.findings.finish import finish
from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.describe_usd import usd_precision
from kinverify.filemode.read.files import LABELS, mjcf_angle_unit, read_mjcf, read_sdf, read_urdf, read_usd
from kinverify.filemode.read.precision import Precision, floors, mjcf_precision, urdf_precision
from kinverify.filemode.read.validate import validate_inertials
from kinverify.map.contract import map_files
from kinverify.map.render import map_section
from kinverify.model.floating import BASE_COORDINATES, BASE_REVOLUTE, base_limits
from kinverify.pipeline.sampling import sample_configurations
from kinverify.results import VerifyResult
from kinverify.run import VerifyOptions, verify
from kinverify.suites.base import tolerance
from kinverify.suites.registry import get_property
from kinverify.versions import library_versions

FILE_SUITES = ("kinematics", "limits", "inertia", "dynamics", "pictures")  # pictures: both files drawn, aligned
URDF_MJCF = ("urdf", "mjcf")
SDF_SUITES = ("kinematics", "limits", "inertia")  # with an SDFormat side: no MuJoCo drawing, no Pinocchio/MuJoCo dynamics
PITCH_MARGIN = 1e-3  # rad: base pitch sampled inside ±(π/2 − this) in file mode
ALIGN_SAMPLES = 24  # configurations (besides q = 0) the alignment fits over


def diagnose_files(urdf: str, mjcf: str, options=None, frames=(), joints=(), kinds=URDF_MJCF) -> dict:
    """Everything file mode knows before the suites run: both files read and described, matched,
    aligned, with each library's reading built; the findings so far. ``urdf`` and ``mjcf`` are the
    first and second sides, of formats ``kinds``."""

    options = options or VerifyOptions()
    wanted = side_names(options, kinds)
    findings: list
    internal: list
    findings, internal = [], []
    readers = {"sdf": read_sdf, "usd": read_usd}
    M, mjcf_text, m, free = readers.get(kinds[1], read_mjcf)(mjcf, findings)
    U, urdf_text, u, library, base = readers.get(kinds[0], read_urdf)(urdf, findings, free)
    matching = match(u, m, joints, frames)
    if base.floating:  # the URDF's link above its floating root stays in the world: not the robot's
        matching.frames = [p for p in matching.frames if not (base.urdf.kind == "floating" and p[0] == base.urdf.root)]
    precision = (_precision(kinds[0], U, u), _precision(kinds[1], M, m))
    fl = floors(*precision, matching.frames, reach(u), len(matching.independent))
    lower, upper, revolute = sample_ranges(u, matching.independent)
    q = sample_configurations(lower, upper, revolute, ALIGN_SAMPLES, seed=options.seed, edges=False)
    al, poses = run_alignment(u, m, matching, urdf_text, mjcf_text, library, fl, q, internal, base_fixes_frame=base.floating)
    info = FileModeInfo(
        u,
        m,
        matching,
        al,
        fl,
        precision,
        bool(free),
        *zero_poses(poses, al),
        frozenset(options.tolerances),
        mjcf_angle=mjcf_angle_unit(M.original) if kinds[1] == "mjcf" else "radian",
        base_coordinates=base.floating,
    )
    if not base.floating:  # a world transform that only stands for the first joints' own change: not taken
        info = _guarded(internal, "attribution", lambda: unmoved_world(info, poses, q), info)
    al = info.alignment

    tol = info.tol
    limits = get_property("limits.position")  # the limits suite's tolerance: a range the zero offset explains
    limit_tol = max(tolerance(options, limits), info.floor(limits.name, info.floors.limit))
    twins, new_pairs = _guarded(internal, "frames with no same-named twin", lambda: frame_twins(info, tol), ([], []))
    matching.frames += new_pairs
    add_frames(al, new_pairs)
    al.attribution = _guarded(internal, "attribution", lambda: attribute(info), {})
    compared = [a for a, _, _ in matching.frames]
    if base.kind:
        findings.append(
            finding(base.kind, base.message, {"urdf": base.urdf.kind, "urdf_root": base.urdf.root, "mjcf_free_bodies": free})
        )
    frame_kinds = {a: m.frame_kind.get(b, "link") for a, b, _ in matching.frames}
    units = _guarded(internal, "length units", lambda: length_units(u, m, matching, compared), [])
    info.inertials_explained_by = units[0].kind if units else ""
    aligned = units or _guarded(
        internal, "alignment findings", lambda: alignment_findings(u, m, matching, al, compared, tol, limit_tol), []
    )
    moved = {fr for f in aligned if f.severity == "error" for fr in f.values.get("frames", [])}  # said there already
    findings += units or base_findings(aligned, base) + _guarded(
        internal, "frame conventions", lambda: convention_findings(al, frame_kinds, tol, moved), []
    )
    findings += twins
    if kinds == URDF_MJCF:  # an SDFormat file's inertials are Drake's to validate (it refuses a non-physical one)
        findings += _guarded(internal, "inertial validation", lambda: validate_inertials(U, M), [])
    texts = (base.urdf_text, M.text) if base.floating else (urdf_text, mjcf_text)
    backends = build_backends(info, *texts, wanted, tol, findings, kinds)
    worst = max([tol(f) for f in compared] or [(1e-9, 1e-9)])
    if base.floating:  # the libraries' readings cross-checked at random base poses too
        q = np.concatenate([base_samples(len(q), options.seed), q], axis=1)
    backends, parser, parser_rows = _guarded(
        internal,
        "parser cross-check",
        lambda: cross_check(backends, q, worst, al.T, top_level_pose(mjcf_text) if kinds[1] == "mjcf" else None, rebuild_mjcf),
        (backends, [], []),
    )
    findings += parser
    findings += _guarded(internal, "couplings", lambda: coupling_findings(u, m, matching, al), [])
    ref = next((n for n in _readers(kinds[0]) if n in backends), None)
    other = next((n for n in _readers(kinds[1]) if n in backends), None)
    if ref is None or other is None:
        raise InputError(
            f"no library could read the {LABELS[kinds[0]] if ref is None else LABELS[kinds[1]]}: "
            + "; ".join(f.message for f in findings if f.kind == "parser_refused")
        )
    notes = (
        list(U.warnings + M.warnings)
        + [f"{LABELS[kinds[0]]}: {s}" for s in u.skipped]
        + [f"{LABELS[kinds[1]]}: {s}" for s in m.skipped]
        + info.notes
    )
    notes.append(f"written precision: {precision[0].describe()}; {precision[1].describe()}")
    if base.floating:
        urdf_text, mjcf_text = texts
        base_lo, base_up = base_limits(np.zeros(3))
        # pitch kept 1e-3 rad off ±π/2: there roll and yaw merge, and a base frame offset between the
        # files (the coordinates conjugated) has no derivative, so the Jacobians would differ by a choice
        base_lo[4], base_up[4] = base_lo[4] + PITCH_MARGIN, base_up[4] - PITCH_MARGIN
        lower, upper = [*base_lo, *lower], [*base_up, *upper]
        revolute = [*BASE_REVOLUTE, *revolute]
    return dict(
        urdf=U,
        mjcf=M,
        urdf_text=urdf_text,
        mjcf_text=mjcf_text,
        info=info,
        matching=matching,
        alignment=al,
        backends=backends,
        reference=ref,
        findings=findings,
        notes=notes,
        parser_rows=parser_rows,
        internal=internal,
        lower=lower,
        upper=upper,
        revolute=revolute,
    )


def _precision(kind: str, loaded, desc) -> Precision:
    """The written precision of one side (a USD's: single precision, :func:`usd_precision`)."""
    if kind == "urdf":
        return urdf_precision(loaded.text)
    if kind == "mjcf":
        return mjcf_precision(loaded.original)
    if kind == "usd":
        return usd_precision(desc.native)
    return Precision(LABELS[kind])


def _readers(kind: str) -> list[str]:
    """The libraries reading ``kind``, the primary first and yourdfpy (finite-difference Jacobians) last."""
    return sorted(names_reading(kind), key=lambda n: n == "yourdfpy")


def _guarded(internal: list, what: str, fn, default):
    """``fn()``, or ``default`` with an internal error recorded when it fails (kinverify's bug)."""

    try:
        return fn()
    except (KinverifyError, KeyboardInterrupt):
        raise
    except Exception as err:
        internal.append(f"file mode, {what}: {type(err).__name__}: {err}")
        return default


def verify_files(
    urdf: str, mjcf: str, options=None, frames=(), joints=(), command: str = "", accept=None, write_accepted=None, kinds=URDF_MJCF
):
    """File mode of ``kinverify verify``: the suites on the aligned files and the findings, as a
    VerifyResult. ``accept``: an accepted-differences TOML file (default: ``kinverify-accepted.toml``
    beside the URDF, when present); ``write_accepted``: write this run's error findings there.
    ``kinds``: the formats of the two sides (``("urdf", "sdf")``, ``("sdf", "mjcf")``)."""

    t0 = time.perf_counter()
    options = options or VerifyOptions()
    entries = acc.load(accept) if accept else (acc.load(p, "the accepted differences") if (p := acc.default_path(urdf)) else [])
    internal: list[str] = []
    diag = _guarded(internal, "reading the files", lambda: diagnose_files(urdf, mjcf, options, frames, joints, kinds), None)
    if diag is None:
        return _failed(urdf, mjcf, options, internal, command, kinds)
    info, U, M = diag["info"], diag["urdf"], diag["mjcf"]
    al, matching = info.alignment, info.matching
    name = M.name if M.name == U.name else f"{U.name}-vs-{M.name}"
    base = BASE_COORDINATES if info.base_coordinates else ()
    texts = {"urdf": None, "mjcf": None, "sdf": None, "usd": None, kinds[0]: diag["urdf_text"], kinds[1]: diag["mjcf_text"]}
    second: dict[str, Any] = dict(
        joint_names=base + tuple(matching.mjcf_name(a) for a in al.independent), frames=tuple(b for _, b, _ in matching.frames)
    )  # the second file's own names
    sources = ModelSources(
        name,
        base + tuple(al.independent),
        tuple(a for a, _, _ in matching.frames),
        tuple(diag["lower"]),
        tuple(diag["upper"]),
        tuple(diag["revolute"]),
        urdf=texts["urdf"],
        mjcf=texts["mjcf"],
        sdf=texts["sdf"],
        usd=texts["usd"],
        **{f"{kinds[1]}_{k}": v for k, v in second.items()},
    )
    suites = FILE_SUITES if kinds == URDF_MJCF else SDF_SUITES
    selected = [s for s in suites if options.suites is None or s in options.suites]
    opts = dataclasses.replace(
        options,
        reference=diag["reference"],
        backends=[diag["reference"]],
        suites=[s for s in selected if s != "dynamics"],
        extra={**options.extra, "filemode": info},
    )
    result = verify(sources, opts, extra_backends=list(diag["backends"].values()), source=f"{urdf} + {mjcf}", command=command)
    result.internal_errors = diag["internal"] + result.internal_errors

    _guarded(
        result.internal_errors,
        "findings",
        lambda: finish(result, diag, sources, opts, "dynamics" in selected, entries, write_accepted, urdf),
        None,
    )
    if kinds != URDF_MJCF:
        relabel(result, kinds)
        result.model_info["files"] = {kinds[0]: urdf, kinds[1]: mjcf}
        for kind in [k for k in kinds if k in ("sdf", "usd")]:
            reader = "Drake" if kind == "sdf" else "usd-core (pxr)"
            result.notes.append(
                f"{LABELS[kind]}: read by {reader}, its only reader here; compared: kinematics, limits and "
                "inertials (dynamics and the drawings need Pinocchio and MuJoCo on both files)"
            )
    add_map(result, [urdf, mjcf])  # after relabel: the map names each file's format itself
    result.duration_s = time.perf_counter() - t0
    return result


def add_map(result, paths: list[str]) -> None:
    """The sim-to-sim map of the files (:mod:`kinverify.map`) as the report's "map" section: joint
    and actuator orders, index maps, values per radian; its findings are notes there (file mode's
    own findings decide the verdict). A file the map cannot read is a note."""
    try:
        result.sections["map"] = map_section(map_files(paths))
    except KinverifyError as err:
        result.notes.append(f"sim-to-sim map not made: {err}")
    except KeyboardInterrupt:
        raise
    except Exception as err:  # kinverify's bug
        result.internal_errors.append(f"file mode, the sim-to-sim map: {type(err).__name__}: {err}")


def relabel(result, kinds) -> None:
    """Name each side by its format: what file mode says of its first side ("URDF") and its second
    ("MJCF") said of the files compared (``kinds``), in findings, checks and report sections."""
    words = {"URDF": LABELS[kinds[0]], "MJCF": LABELS[kinds[1]], "urdf": kinds[0], "mjcf": kinds[1]}
    pattern = re.compile(r"\b(URDF|MJCF)\b|(?<=q_)(urdf|mjcf)\b")  # "the MJCF", "q_mjcf = −q_urdf"

    def text(value):
        if isinstance(value, str):
            value = pattern.sub(lambda m: words[m[0]], value)
            if "usd" in kinds:  # a USD side floats with no joint to the world, not with a free joint
                value = re.sub(r"(the USD's body \S+) has a free joint", r"\1 has no joint to the world", value)
                value = value.replace("the USD's free joint says", "the USD's root body with no joint to the world says")
                value = value.replace("its free body's pos/quat", "its root body's xform")
            return value
        if isinstance(value, list):
            return [text(v) for v in value]
        if isinstance(value, dict):
            return {k: text(v) for k, v in value.items()}
        return value

    result.findings = [dataclasses.replace(f, message=text(f.message), values=text(f.values)) for f in result.findings]
    result.checks = [
        dataclasses.replace(
            c, backends=tuple(words.get(b, b) if b in ("urdf", "mjcf") else b for b in c.backends), note=text(c.note)
        )
        for c in result.checks
    ]
    for section in result.sections.values():
        section.title, section.summary, section.notes = text(section.title), text(section.summary), text(section.notes)
        section.tables = [
            dataclasses.replace(t, title=text(t.title), columns=text(t.columns), rows=text(t.rows)) for t in section.tables
        ]
    result.notes = text(result.notes)


def verify_three(
    urdf: str | None, mjcf: str | None, sdf: str | None, options=None, command: str = "", accept=None, usd: str | None = None
):
    """Three or four files at once (of ``--urdf``, ``--mjcf``, ``--sdf`` and ``--usd``): the first of
    URDF, SDFormat and USD given against each other file, one result (each further pair's findings,
    checks and sections added, its sections under ``sdf:`` / ``usd:`` keys; the MJCF's pair first).
    Joint and frame pairs are found by name and geometry (no ``--joints``)."""
    given = [(k, p) for k, p in (("urdf", urdf), ("sdf", sdf), ("usd", usd), ("mjcf", mjcf)) if p]
    anchor, others = given[0], given[1:]
    others = sorted(others, key=lambda o: o[0] != "mjcf")
    results = [
        verify_files(anchor[1], path, options, command=command, accept=accept, kinds=(anchor[0], kind)) for kind, path in others
    ]
    first = results[0]
    for (kind, _), second in zip(others[1:], results[1:], strict=True):
        first.findings += second.findings
        first.checks += second.checks
        first.backends += [b for b in second.backends if b not in first.backends]
        first.sections.update({f"{kind}:{k}": v for k, v in second.sections.items()})
        first.internal_errors += second.internal_errors
        first.notes += [n for n in second.notes if n not in first.notes]
        first.duration_s += second.duration_s
    files = {k: p for k, p in (("urdf", urdf), ("mjcf", mjcf), ("sdf", sdf), ("usd", usd)) if p}
    first.source = " + ".join(files.values())
    first.model_info["files"] = files
    return first


def _failed(urdf: str, mjcf: str, options, internal: list[str], command: str, kinds=URDF_MJCF):
    """The result of a run kinverify itself could not complete (verdict ``error``, exit 3)."""

    return VerifyResult(
        model=f"{Path(urdf).stem}-vs-{Path(mjcf).stem}",
        source=f"{urdf} + {mjcf}",
        seed=options.seed,
        samples=0,
        joint_names=[],
        frames=[],
        backends=[],
        checks=[],
        versions=library_versions(),
        command=command,
        internal_errors=internal,
        model_info={"files": {kinds[0]: urdf, kinds[1]: mjcf}},
    )
