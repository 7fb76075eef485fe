"""One-file audit: does every library read this one file the same way?

``kinverify verify --urdf R.urdf`` alone reads the URDF with every library that reads URDF
(Pinocchio, yourdfpy, MuJoCo's URDF import, Drake); ``--mjcf R.xml`` alone reads the MJCF with MuJoCo,
Pinocchio's MJCF parser and Drake's; ``--sdf R.sdf`` alone is Drake's reading of an SDFormat
file, which no other library here reads (said so plainly: its kinematics are checked against
finite differences of its own FK, nothing else). The primary reader of the file is the reference; each other
library's reading is compared with it configuration by configuration (FK of every link or body,
Jacobians: the kinematics suite), and where a library reads the file differently, one finding
names the library and the first element (link or body, with the joint it moves with) it places
elsewhere. A library refusing the file is a ``parser_refused`` warning; Pinocchio's MJCF parser
dropping the top-level body's pose (pinocchio#2782) is a ``parser_quirk`` info, compared after
putting the pose back. Where Pinocchio and MuJoCo both read the file, their dynamics are compared
too (:mod:`kinverify.filemode.compare.audit_dynamics`). Only libraries that genuinely disagree fail the
verdict.
"""

from __future__ import annotations

import dataclasses
import time
from types import SimpleNamespace
from typing import Any

import numpy as np

from kinverify.backends import ModelSources, available_backends, names_reading
from kinverify.backends.mujoco_ import urdf_for_mujoco
from kinverify.errors import InputError, KinverifyError, library_reason
from kinverify.filemode.align.geometry import reach
from kinverify.filemode.align.match import match
from kinverify.filemode.align.run import identity_alignment, sample_ranges
from kinverify.filemode.compare.audit_dynamics import PAIRS, AuditDynamicsSuite, inertial_findings
from kinverify.filemode.compare.crosscheck import cross_check, floored_tol, pose_errors, top_level_pose
from kinverify.filemode.compare.libraries import build_backends, rebuild_mjcf
from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.describe_mjcf import describe_mjcf
from kinverify.filemode.read.describe_sdf import describe_sdf
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.filemode.read.describe_usd import describe_usd
from kinverify.filemode.read.files import load_usd, sdf_free_bodies
from kinverify.filemode.read.loading import load_mjcf, load_sdf, load_urdf
from kinverify.filemode.read.prepare import fix_free_bases, prepare_urdf
from kinverify.filemode.usd_audit import ONLY_READER as USD_ONLY, statements
from kinverify.pipeline.sampling import Samples, sample_configurations
from kinverify.run import VerifyOptions, internal_error, verify
from kinverify.suites.base import Section, VerifyContext, tolerance
from kinverify.suites.registry import get_property

__all__ = ["audit_file", "AUDIT_SUITES"]

AUDIT_SUITES = ("kinematics", "dynamics")  # dynamics: Pinocchio against MuJoCo on the file (audit_dynamics)
CHECK_SAMPLES = 64  # configurations (after the edges) each library is first compared on, to name elements
SIDE = {"urdf": "URDF", "mjcf": "MJCF", "sdf": "SDF", "usd": "USD"}
ELEMENT = {"urdf": "link", "mjcf": "body", "sdf": "link", "usd": "body"}
SLOTS = {
    "urdf": ("urdf", "mjcf"),
    "mjcf": ("urdf", "mjcf"),
    "sdf": ("sdf", "mjcf"),
    "usd": ("usd", "mjcf"),
}  # build_backends' sides
ONLY_READER = (
    "Drake is the only library here that reads SDFormat: this audit is Drake's reading alone, its FK and "
    "Jacobians checked against finite differences of its own FK; no other library's reading to compare it with"
)


def _describe(kind: str, loaded):
    """(the text the libraries load, the primary reader's description, the free bodies held fixed).
    A URDF Pinocchio refuses is described through MuJoCo's URDF import (the refusal is one finding,
    made where the libraries are built)."""
    if kind == "usd":
        desc = describe_usd(loaded.robot)
        return loaded.text, desc, [loaded.robot.names[loaded.robot.root]] if loaded.robot.floating else []
    if kind == "sdf":
        try:
            return loaded.text, describe_sdf(loaded.text), sdf_free_bodies(loaded.text)
        except (RuntimeError, ValueError) as err:
            raise InputError(
                f"--sdf: Drake, the only reader of SDFormat, cannot load {loaded.path}: {library_reason(err)}"
            ) from None
    if kind == "mjcf":
        text, free = fix_free_bases(loaded.text)
        try:
            return text, describe_mjcf(text), free
        except ValueError as err:
            raise InputError(
                f"--mjcf: MuJoCo, the reference reader of MJCF, cannot load {loaded.path}: {library_reason(err)}"
            ) from None
    text = prepare_urdf(loaded.text)
    try:
        return text, describe_urdf(loaded.text), []
    except (ValueError, RuntimeError):  # described through MuJoCo's URDF import instead
        pass
    try:
        desc = describe_mjcf(urdf_for_mujoco(text))
    except ValueError as err:
        raise InputError(f"--urdf: neither Pinocchio nor MuJoCo can load {loaded.path}: {library_reason(err)}") from None
    return text, dataclasses.replace(desc, kind="urdf", library="mujoco (URDF import)"), []


def _first_element(kind: str, desc, ref, other, q: np.ndarray, tol: tuple[float, float]) -> dict | None:
    """Where ``other`` starts to read the file differently from ``ref``: the first frame in chain
    order whose pose differs, at q = 0 (placed elsewhere) or only as the joints move."""
    common = [f for f in other.frames if f in ref.frames]
    if not common:
        return None
    cols_r, cols_o = [ref.frames.index(f) for f in common], [other.frames.index(f) for f in common]
    zero = np.zeros((1, q.shape[1]))
    both = np.concatenate([zero, q])
    pos, rot = pose_errors(ref.poses(both)[:, cols_r], other.poses(both)[:, cols_o])
    pos0, rot0 = pose_errors(ref.poses(zero)[:, cols_r], other.poses(zero)[:, cols_o])
    tol = floored_tol(tol, ref, other)  # a float32 library (Newton) at its agreement floor
    bad = [k for k in range(len(common)) if pos[k] > tol[0] or rot[k] > tol[1]]
    if not bad:
        return None
    k = min(bad, key=lambda i: (desc.frame_depth.get(common[i], 0), i))
    frame = common[k]
    return dict(
        frame=frame,
        joint=desc.frame_owner.get(frame),
        position_m=float(pos[k]),
        rotation_rad=float(rot[k]),
        at_zero=bool(pos0[k] > tol[0] or rot0[k] > tol[1]),
        frames=[common[i] for i in bad],
        element="site" if desc.frame_kind.get(frame) == "site" else ELEMENT[kind],
    )


def _disagreement(kind: str, ref: str, name: str, where: dict, agree=()):
    """One error finding per library that reads the file differently, naming its first element and,
    with three readings or more, the libraries that agree with each other (``agree``)."""
    how = (
        "placed elsewhere at q = 0"
        if where["at_zero"]
        else f"placed alike at q = 0, apart once {where['joint'] or 'the joints'} moves"
    )
    more = len(where["frames"]) - 1
    message = (
        f"{name} reads the {SIDE[kind]}'s {where['element']} {where['frame']} differently from {ref}: {how}, up to "
        f"{where['position_m']:.3g} m, {where['rotation_rad']:.3g} rad"
        + (f" ({more} frame{'s' if more > 1 else ''} below it differ with it)" if more > 0 else "")
        + (
            f"; {' and '.join([', '.join(agree[:-1]), agree[-1]] if len(agree) > 2 else agree)} agree with each other, "
            f"{name} stands apart"
            if len(agree) > 1
            else ""
        )
    )
    values = {
        "file": SIDE[kind],
        "backends": [ref, name],
        "backend": name,
        "agree": list(agree),
        **{k: where[k] for k in ("joint", "position_m", "rotation_rad", "at_zero", "frames")},
    }
    names = {"frame": where["frame"]} if where["element"] == "site" else {"link": where["frame"]}
    return finding(
        "parser_disagreement",
        message,
        values,
        magnitude=max(where["position_m"], where["rotation_rad"]),
        unit="m|rad",
        prop="fk.position",
        severity="error",
        **names,
    )


def _section(kind: str, path: str, wanted, backends: dict, kept: dict, reference: str, rows, findings, notes):

    compared = {r[1].split(" vs ")[-1]: r for r in rows}
    refused = {f.values.get("backend") for f in findings if f.kind == "parser_refused" and "elements" not in f.values}
    ignores = {
        f.values.get("backend"): f.values["elements"] for f in findings if f.kind == "parser_refused" and "elements" in f.values
    }
    quirks = {f.values.get("backends", ["", ""])[1] for f in findings if f.kind == "parser_quirk"}
    differ = {f.values.get("backend") for f in findings if f.kind == "parser_disagreement"}
    table = []
    for name in names_reading(kind):
        info = available_backends()[name]
        if not info.available:
            status = f"not installed ({info.reason})"
        elif name not in wanted:
            status = "not selected (--backends)"
        elif name in refused or name not in backends:
            status = "refuses the file"
        elif name == reference:
            status = "reference"
        elif name in differ:
            status = "reads it differently"
        elif name in quirks:
            status = "agrees once the known quirk is corrected (pinocchio#2782)"
        else:
            status = "agrees"
        if name in ignores and status != "refuses the file":
            status += f" (its parser ignores {', '.join(ignores[name])})"
        row = compared.get(name)
        table.append([name, status, "" if row is None else f"{row[2]:.3g}", "" if row is None else f"{row[3]:.3g}"])
    readers = [n for n in kept if n in backends]
    section = Section(
        f"One-file audit: every library reading the {SIDE[kind]}",
        f"{path} read by {len(readers)} librar{'y' if len(readers) == 1 else 'ies'} "
        f"({', '.join(readers)}); reference {reference}; "
        f"{sum(f.fails for f in findings)} disagreement(s).",
    )
    section.table("Libraries", ["library", "reading", f"max position vs {reference} [m]", "max rotation [rad]"], table)
    section.notes += notes
    return section


def _dynamics(result, kind: str, text: str, top, sources, al, opts, kept: dict, notes: list, desc, scale: float) -> None:
    """Pinocchio's and MuJoCo's dynamics of the file, when both read it (the suite's checks and
    section), on every 1-DOF joint (a coupling's follower at its leader's value)."""
    missing = [n for n in PAIRS[kind] if n not in kept]
    if missing:
        notes.append(f"dynamics not compared: {', '.join(missing)} did not read the file")
        return
    if kind == "urdf" and desc.library == "pinocchio":
        try:
            result.findings += inertial_findings(text, desc, scale)
        except Exception as err:  # our bug: say so, keep the rest
            result.internal_errors.append(internal_error("inertials", err))
    suite = AuditDynamicsSuite(kind, text, top)
    t0 = time.perf_counter()
    try:
        q = Samples(sources.lower, sources.upper, sources.revolute, max(opts.samples, 1), opts.seed)
        n = int(opts.extra.get("dynamics_samples", 100))
        every = dataclasses.replace(
            sources, joint_names=tuple(j.urdf for j in al.joints), revolute=tuple(j.type == "revolute" for j in al.joints)
        )
        out = suite.run(VerifyContext(every, {}, al.expand(np.asarray(q[:n])), opts))
    except KinverifyError as err:  # e.g. joints held at neutral: the models have more coordinates than compared
        notes.append(f"dynamics not compared: {err}")
        return
    except Exception as err:  # our bug: say so, keep the rest
        result.internal_errors.append(internal_error("suite dynamics", err))
        return
    finally:
        result.timings["dynamics"] = time.perf_counter() - t0
    result.checks += out.checks
    result.findings += out.findings
    if out.section is not None:
        result.sections["dynamics"] = out.section
        if out.section.summary.startswith("skipped: "):  # the suite's own skip: its reason in full, as a note
            notes.append(f"dynamics not compared: {out.section.summary.removeprefix('skipped: ')}")


def audit_file(path: str, kind: str, options=None, command: str = "", packages=None, xacro_args=None):
    """The one-file audit of ``kind`` ("urdf", "mjcf" or "sdf") as a :class:`~kinverify.results.VerifyResult`."""
    t0 = time.perf_counter()
    options = options or VerifyOptions()
    readers = names_reading(kind)
    wanted = [n for n in (options.backends or readers) if n in readers]
    if not wanted:
        raise InputError(
            f"--backends: a one-file audit of a {SIDE[kind]} compares {', '.join(readers)}; got "
            f"{', '.join(options.backends or [])}"
        )
    findings: list = []
    loaded: Any  # a LoadedFile, or (a USD) a namespace of its fields and the articulation read
    if kind == "usd":
        loaded, robot = load_usd(path)
        loaded = SimpleNamespace(
            **{f: getattr(loaded, f) for f in ("path", "kind", "original", "text", "name", "warnings")}, robot=robot
        )
    else:
        loaded = (
            load_urdf(path, keep_meshes=False, packages=packages, xacro_args=xacro_args)
            if kind == "urdf"
            else load_sdf(path)
            if kind == "sdf"
            else load_mjcf(path, keep_meshes=False)
        )
    text, desc, free = _describe(kind, loaded)
    if not desc.joints:
        raise InputError(f"--{kind}: {path} has no movable 1-DOF joints (hinge or slide) to compare")
    matching = match(desc, desc)  # every joint and frame with itself: the readings are compared, not two files
    al = identity_alignment(desc, matching)
    notes = list(loaded.warnings) + [f"{SIDE[kind]}: {s}" for s in desc.skipped]
    # double precision at the robot's size: its reach plus how far its frames sit from the origin
    scale = max([1.0] + list(reach(desc).values())) + max([0.0] + [float(np.linalg.norm(t[:3, 3])) for t in desc.frames.values()])
    tol = (tolerance(options, get_property("fk.position")) * scale, tolerance(options, get_property("fk.rotation")))
    shim = SimpleNamespace(alignment=al, matching=matching, notes=notes, base_coordinates=False)  # a free base is held fixed here
    urdf_text, mjcf_text = ("", text) if kind == "mjcf" else (text, "")
    backends = build_backends(shim, urdf_text, mjcf_text, wanted, lambda f: tol, findings, SLOTS[kind])
    lower, upper, revolute = sample_ranges(desc, al.independent)
    q = sample_configurations(lower, upper, revolute, CHECK_SAMPLES, seed=options.seed)
    top = top_level_pose(text) if kind == "mjcf" else None
    kept, parser, rows = cross_check(backends, q, tol, np.eye(4), top, rebuild_mjcf)
    reference = next((n for n in readers if n in kept), None)
    for f in parser:
        name = f.values.get("backends", [None, None])[1] if f.kind == "parser_disagreement" else None
        where = _first_element(kind, desc, kept[reference], backends[name], q, tol) if name and reference else None
        if where is None:
            findings.append(f)
            continue
        assert reference is not None and name is not None  # where was found for them
        findings.append(_disagreement(kind, reference, name, where, f.values.get("agree", ())))
        kept[name] = backends[name]  # compared in the kinematics suite too: its checks show the size per frame
    if reference is None:
        raise InputError(
            f"--{kind}: no library can read {path}: " + "; ".join(f.message for f in findings if f.kind == "parser_refused")
        )
    if kind in ("sdf", "usd"):
        notes.insert(0, ONLY_READER if kind == "sdf" else USD_ONLY)
    if free:
        findings.append(
            finding(
                "floating_base",
                f"the {SIDE[kind]}'s free base ({', '.join(free)}) is held at the identity pose: "
                "the libraries' readings of everything below it are compared",
                {"file": SIDE[kind], "bodies": free},
            )
        )
    frames = tuple(a for a, _, _ in matching.frames)
    sources = ModelSources(
        loaded.name,
        tuple(al.independent),
        frames,
        tuple(lower),
        tuple(upper),
        tuple(revolute),
        urdf=text if kind == "urdf" else None,
        mjcf=text if kind == "mjcf" else None,
        sdf=text if kind == "sdf" else None,
        usd=text if kind == "usd" else None,
        mjcf_joint_names=tuple(al.independent) if kind == "mjcf" else None,
        mjcf_frames=frames if kind == "mjcf" else None,
    )
    suites = [s for s in AUDIT_SUITES if options.suites is None or s in options.suites]
    opts = dataclasses.replace(options, reference=reference, backends=[reference], suites=[s for s in suites if s != "dynamics"])
    result = verify(sources, opts, extra_backends=list(kept.values()), source=str(path), command=command)
    if "dynamics" in suites and kind in ("sdf", "usd"):
        notes.append(
            "dynamics not compared: Drake is the only reader of SDFormat"
            if kind == "sdf"
            else "dynamics not compared: usd-core reads the USD's kinematics and inertials, no USD dynamics library is here"
        )
    elif "dynamics" in suites:
        quirk = top if any(f.kind == "parser_quirk" for f in findings) else None
        _dynamics(result, kind, text, quirk, sources, al, opts, kept, notes, desc, scale)
    result.findings = findings + result.findings
    result.notes += notes
    section = _section(kind, str(path), wanted, backends, kept, reference, rows, findings, notes)
    result.sections = {"audit": section, **result.sections}
    if kind == "usd":
        stated, found = statements(desc, loaded)
        result.sections = {"audit": section, "usd": stated, **{k: v for k, v in result.sections.items() if k != "audit"}}
        result.findings += found
    result.model_info["files"] = {kind: str(path)}
    result.model_info["audit"] = {"file": SIDE[kind], "libraries": list(kept), "reference": reference}
    result.duration_s = time.perf_counter() - t0
    return result
