"""File mode: cross-validate an existing URDF against an existing MJCF, and say what differs.

``verify_files`` loads both files safely (meshes dropped), describes each through its library
(URDF: Pinocchio, MJCF: MuJoCo), matches joints and frames, runs the kinematics pipeline with
every library that loads each file (URDF: Pinocchio, yourdfpy, MuJoCo's URDF import; MJCF:
MuJoCo, Pinocchio's MJCF parser) against ``pinocchio-urdf``, then diagnoses the differences.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from kinverify.backends import ModelSources, available_backends, build_backend
from kinverify.errors import InputError, KinverifyError
from kinverify.pipeline.sampling import sample_configurations
from kinverify.filemode.crosscheck import MJCF_SIDE, URDF_SIDE, frame_residuals, parser_checks, top_level_pose
from kinverify.filemode.describe import ModelDesc, describe_mjcf, describe_urdf
from kinverify.filemode.diagnose import (ANG_TOL, POS_TOL, base_transform, diagnose_base, diagnose_dynamics, diagnose_frames, diagnose_joints,
                       diagnose_limits, diagnose_links, diagnose_rounding, finding)
from kinverify.filemode.loading import load_mjcf, load_urdf
from kinverify.filemode.match import Matching, match
from kinverify.filemode.aliased import AliasedBackend
from kinverify.filemode.section import build_section
from kinverify.filemode.validate import validate_inertials

__all__ = ["verify_files", "diagnose_files"]

DIAGNOSIS_SAMPLES = 64  # configurations for the FK evidence (residuals, parser cross-checks)


def _describe(loaded, describe, kind: str, refusals: list) -> ModelDesc:
    try:
        return describe(loaded.text)
    except (ValueError, RuntimeError) as err:
        lib = "Pinocchio" if kind == "urdf" else "MuJoCo"
        refusals.append(finding("parser_refused", f"{lib} refuses the {kind.upper()}: {str(err).strip().splitlines()[-1]}",
                                {"file": kind.upper(), "library": lib}))
    if kind == "urdf":  # second opinion: MuJoCo's URDF import
        from kinverify.backends.mujoco_ import urdf_for_mujoco

        try:
            desc = describe_mjcf(urdf_for_mujoco(loaded.text))
            return dataclasses.replace(desc, kind="urdf", library="mujoco (URDF import)")
        except ValueError as err:
            raise InputError(f"--urdf: no library can load {loaded.path}: {str(err).strip().splitlines()[0]}") from None
    raise InputError(f"--mjcf: MuJoCo cannot load {loaded.path}: {refusals[-1].message}")


def _limits(u: ModelDesc, m: ModelDesc, matching: Matching):
    lower, upper, revolute = [], [], []
    for a, b, _ in matching.joints:
        ju, jm = u.joint(a), m.joint(b)
        span = math.pi if ju.type == "revolute" else 0.5
        lo, up = max(ju.lower, jm.lower), min(ju.upper, jm.upper)
        if not lo < up:  # limits do not overlap: sample the URDF's
            lo, up = ju.lower, ju.upper
        lower.append(lo if math.isfinite(lo) else -span)
        upper.append(up if math.isfinite(up) else span)
        revolute.append(ju.type == "revolute")
    return tuple(lower), tuple(upper), tuple(revolute)


def diagnose_files(urdf: str, mjcf: str, options=None, frames=(), joints=()):
    """Everything file mode knows before the kinematics pipeline runs: loaded files, descriptions,
    matching, sources, the backends that loaded, and the findings."""
    U, M = load_urdf(urdf), load_mjcf(mjcf)
    refusals: list = []
    u = _describe(U, describe_urdf, "urdf", refusals)
    m = _describe(M, describe_mjcf, "mjcf", refusals)
    matching = match(u, m, joints, frames)
    lower, upper, revolute = _limits(u, m, matching)
    sources = ModelSources(
        name=M.name if M.name == U.name else f"{U.name}-vs-{M.name}",
        joint_names=tuple(a for a, _, _ in matching.joints), frames=tuple(f[0] for f in matching.frames),
        lower=lower, upper=upper, revolute=revolute, urdf=U.text, mjcf=M.text,
        mjcf_joint_names=tuple(b for _, b, _ in matching.joints), mjcf_frames=tuple(f[1] for f in matching.frames))
    wanted = [n for n in (options.backends if options and options.backends else URDF_SIDE + MJCF_SIDE)
              if n in URDF_SIDE + MJCF_SIDE]
    if not any(n in URDF_SIDE for n in wanted) or not any(n in MJCF_SIDE for n in wanted):
        raise InputError(f"--backends: file mode needs a URDF backend ({', '.join(URDF_SIDE)}) and an MJCF backend "
                         f"({', '.join(MJCF_SIDE)}); got {', '.join(options.backends or [])}")
    backends = {}
    for name in wanted:
        info = available_backends().get(name)
        if info is None or not info.available:
            continue
        try:
            backends[name] = build_backend(name, sources)
        except Exception as err:  # a library that fails on the user's file refuses it (e.g. yourdfpy on a planar joint)
            side = "URDF" if name in URDF_SIDE else "MJCF"
            why = _mimic_hint(U.text, str(err)) if name == "yourdfpy" else ""
            text = str(err) if isinstance(err, KinverifyError) else f"{type(err).__name__}: {_first_line(err)}"
            refusals.append(finding("parser_refused", f"{name} refuses the {side}: {text}{why}", {"file": side, "backend": name}))
    ref = next((n for n in URDF_SIDE if n in backends), None)
    other = next((n for n in MJCF_SIDE if n in backends), None)
    if ref is None or other is None:
        side = "URDF" if ref is None else "MJCF"
        raise InputError(f"no backend could load the {side}: " + "; ".join(f.message for f in refusals))

    q = sample_configurations(lower, upper, revolute, DIAGNOSIS_SAMPLES, seed=options.seed if options else 0)
    internal: list[str] = []  # kinverify's own failures in a diagnosis step: reported, the other steps still run

    def step(name, fn, *args, default=None):
        try:
            return fn(*args)
        except (KinverifyError, KeyboardInterrupt):
            raise
        except Exception as err:
            internal.append(internal_error(f"file-mode diagnosis {name}", err))
            return [] if default is None else default

    t_base = step("base transform", base_transform, u, m, matching, default=np.eye(4))
    residual_rows, starts, residual = step("frame residuals", frame_residuals, backends[ref], backends[other], q, t_base,
                                           matching.frames, default=([], None, None))
    findings = list(refusals)
    findings += step("inertial validation", validate_inertials, U, M)
    findings += step("base", diagnose_base, t_base, residual)
    parser, parser_rows = step("parser cross-check", lambda: parser_checks(backends, q, m, top_level_pose(M.text)),
                                default=([], []))
    findings += parser
    for side, names in (("URDF", matching.unmatched_urdf), ("MJCF", matching.unmatched_mjcf)):
        for n in names:
            findings.append(finding("unmatched_joint", f"joint {n} is only in the {side}: not compared, held at zero",
                                    {"file": side}, joint=n))
    if starts:
        findings.append(starts)
    differing = {f[0] for f, row in zip(matching.frames, residual_rows) if row[3] > POS_TOL or row[4] > ANG_TOL}
    kin = step("joints", diagnose_joints, u, m, matching, t_base, differing) + step("frames", diagnose_frames, u, m, matching)
    findings += kin
    findings += step("rounding", diagnose_rounding, kin, U.text, M.original, u, m, matching)
    findings += step("limits", diagnose_limits, u, m, matching)
    links, link_rows = step("links", diagnose_links, u, m, matching, default=([], []))
    findings += links
    dyn, dyn_notes = step("dynamics", diagnose_dynamics, u, m, matching, default=([], []))
    findings += dyn
    notes = list(U.warnings + M.warnings) + [f"URDF: {s}" for s in u.skipped] + [f"MJCF: {s}" for s in m.skipped]
    notes += [f"joint dynamics in one file only: {n}" for n in dyn_notes]
    section = build_section(U, M, matching, findings, notes, residual_rows, parser_rows, link_rows, ref, other)
    return dict(sources=sources, backends=backends, reference=ref, findings=findings, notes=notes, section=section,
                urdf=U, mjcf=M, matching=matching, base=t_base, internal_errors=internal)


def internal_error(where: str, err: Exception) -> str:
    from kinverify.run import internal_error as describe

    return describe(where, err)


def _first_line(err: Exception) -> str:
    lines = str(err).strip().splitlines()
    return lines[0] if lines else type(err).__name__


def _mimic_hint(urdf_text: str, message: str) -> str:
    import xml.etree.ElementTree as ET

    mimic = [j.get("name") for j in ET.fromstring(urdf_text).iter("joint") if j.find("mimic") is not None]
    hits = [n for n in mimic if repr(n) in message]
    return f" ({', '.join(hits)}: <mimic> joint, which yourdfpy drives from its leader and does not expose)" if hits else ""


def verify_files(urdf: str, mjcf: str, options, frames=(), joints=(), command: str = ""):
    """File mode of ``kinverify verify``: the kinematics checks plus the diagnosis, as a VerifyResult."""
    from kinverify.run import VerifyOptions, verify

    options = options or VerifyOptions()
    diag = diagnose_files(urdf, mjcf, options, frames, joints)
    # MJCF-side backends are seen under the URDF's frame names so the checks pair frames by name.
    sources = diag["sources"]
    extra = [b if n in URDF_SIDE else AliasedBackend(b, sources.frames) for n, b in diag["backends"].items()]
    suites = [s for s in ("kinematics", "pictures") if options.suites is None or s in options.suites]  # pictures: the overlay
    opts = dataclasses.replace(options, reference=diag["reference"], backends=[diag["reference"]], suites=suites)
    result = verify(sources, opts, extra_backends=extra, source=f"{urdf} + {mjcf}", command=command)
    result.sections["filemode"] = diag["section"]
    result.findings = diag["findings"] + result.findings
    result.notes += diag["notes"]
    result.internal_errors = diag["internal_errors"] + result.internal_errors
    result.model_info["files"] = {"urdf": urdf, "mjcf": mjcf}
    result.model_info["joint_pairs"] = [list(p) for p in diag["matching"].joints]
    result.model_info["frame_pairs"] = [list(p) for p in diag["matching"].frames]
    return result
