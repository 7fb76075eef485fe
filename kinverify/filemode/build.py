"""Reading the two files and building what compares them: descriptions (with the libraries'
refusals as findings), the alignment, and every library's reading of each file seen through it."""

from __future__ import annotations

import dataclasses
import importlib
import math

import numpy as np

from kinverify.backends import available_backends
from kinverify.errors import InputError, KinverifyError, library_reason
from kinverify.filemode.align import align
from kinverify.filemode.alignment import Alignment, FrameFit, JointMap, PairPoses
from kinverify.filemode.aligned import AlignedBackend
from kinverify.filemode.crosscheck import MJCF_SIDE, URDF_SIDE
from kinverify.filemode.describe import ModelDesc, describe_mjcf, describe_urdf
from kinverify.filemode.diagnose import finding
from kinverify.filemode.floating import UrdfBase, decide, fixed_urdf, floating_urdf, urdf_base
from kinverify.filemode.loading import load_mjcf, load_urdf
from kinverify.model.floating import BASE_COORDINATES
from kinverify.filemode.match import Matching

OPEN_RANGE = {"revolute": math.pi, "prismatic": 0.5}  # sampled range of a joint without limits


def read_urdf(path: str, findings: list, free=()):
    """The loaded URDF, its prepared text, its description, the library that read it and the
    floating-base decision (:class:`BaseDecision`) against the MJCF's ``free`` top-level bodies.
    The text and description have a floating root fixed (at the identity when both files float:
    the base coordinates at zero; else at its origin)."""
    from kinverify.backends.mujoco_ import urdf_for_mujoco
    from kinverify.filemode.prepare import prepare_urdf

    loaded = load_urdf(path)
    base = urdf_base(loaded.text)
    floating, kind, message = decide(base, list(free))
    fixed = fixed_urdf(loaded.text, keep_origin=not floating)
    decision = BaseDecision(floating, kind, message, base, list(free),
                            prepare_urdf(floating_urdf(loaded.text)) if floating else "")
    text = prepare_urdf(fixed)
    try:
        return loaded, text, describe_urdf(fixed), "pinocchio", decision
    except (ValueError, RuntimeError) as err:
        findings.append(finding("parser_refused", f"Pinocchio refuses the URDF: {library_reason(err)}; read with MuJoCo's URDF "
                                "import instead", {"file": "URDF", "library": "pinocchio"}))
    try:
        desc = dataclasses.replace(describe_mjcf(urdf_for_mujoco(text)), kind="urdf", library="mujoco (URDF import)")
        return loaded, text, desc, "mujoco", decision
    except ValueError as err:
        raise InputError(f"--urdf: no library can load {path}: {library_reason(err)}") from None


@dataclasses.dataclass
class BaseDecision:
    """Whether the base pose is compared as coordinates, and the finding that says why (see
    :func:`kinverify.filemode.floating.decide`); ``urdf_text``: the URDF with its floating root
    (one added above the root link when the URDF left it unstated), for the libraries."""

    floating: bool
    kind: str
    message: str
    urdf: UrdfBase
    free: list
    urdf_text: str = ""


def read_mjcf(path: str, findings: list):
    """The loaded MJCF, its prepared text (free base fixed), its description and the fixed bodies.
    A mesh file MuJoCo cannot read is dropped like an absent one (a warning says which)."""
    from kinverify.filemode.prepare import fix_free_bases

    loaded = load_mjcf(path)
    for attempt in (0, 1):
        text, free = fix_free_bases(loaded.text)
        try:
            return loaded, text, describe_mjcf(text), free
        except ValueError as err:
            if attempt == 0 and "mesh assets resolved" in " ".join(loaded.warnings):
                findings.append(finding("parser_refused", f"MuJoCo cannot read a mesh of the MJCF ({library_reason(err)}): meshes "
                                        "dropped (they do not change kinematics or dynamics)", {"file": "MJCF", "library": "mujoco"}))
                loaded = load_mjcf(path, keep_meshes=False)
                continue
            raise InputError(f"--mjcf: MuJoCo cannot load {path}: {library_reason(err)}") from None


def sample_ranges(u: ModelDesc, joints) -> tuple[list, list, list]:
    lower, upper, revolute = [], [], []
    for name in joints:
        j = u.joint(name)
        span = OPEN_RANGE[j.type]
        lo, up = (j.lower, j.upper) if math.isfinite(j.lower) and math.isfinite(j.upper) and j.lower < j.upper else (-span, span)
        lower.append(lo)
        upper.append(up)
        revolute.append(j.type == "revolute")
    return lower, upper, revolute


def identity_alignment(u: ModelDesc, matching: Matching) -> Alignment:
    return Alignment(np.eye(4), [JointMap(a, b, u.joint(a).type) for a, b, _ in matching.joints], matching.couplings,
                     matching.independent)


def run_alignment(u, m, matching, urdf_text, mjcf_text, library, floors, samples, internal: list) -> tuple[Alignment, PairPoses]:
    poses = PairPoses(u, m, matching, urdf_text, mjcf_text, library)
    try:
        return align(poses, matching, floors, samples), poses
    except (KinverifyError, KeyboardInterrupt):
        raise
    except Exception as err:  # our bug: compare unaligned, say so
        internal.append(f"alignment: {type(err).__name__}: {err}")
        return identity_alignment(u, matching), poses


def zero_poses(poses: PairPoses, al: Alignment) -> tuple[dict, dict]:
    """Every frame of each file at the aligned zero (the MJCF's in its own world)."""
    zero = al.expand(np.zeros((1, len(al.independent))))
    pu, pm = poses.urdf(zero)[0], poses.mjcf(al.to_mjcf(zero))[0]
    return {f: pu[i] for f, i in poses.ui.items()}, {f: pm[i] for f, i in poses.mi.items()}


def add_frames(al: Alignment, pairs) -> None:
    """Frames matched after the alignment (same place, no same-named twin): they coincide."""
    for fu, fm, why in pairs:
        al.frames.append(FrameFit(fu, fm, why, 0.0, 0.0, np.eye(4), 0.0, 0.0, False))


def build_backends(info, urdf_text: str, mjcf_text: str, wanted, tol, findings: list) -> dict:
    """Every library that reads each file, through the alignment (URDF side: couplings only); with
    the base coordinates first when both files float (``info.base_coordinates``)."""
    al, matching = info.alignment, info.matching
    base = list(BASE_COORDINATES) if info.base_coordinates else []
    frames_u = [a for a, _, _ in matching.frames]
    frames_m = [b for _, b, _ in matching.frames]
    all_u = [j.urdf for j in al.joints]
    all_m = [j.mjcf for j in al.joints]
    tinv = np.linalg.inv(al.T)
    constants = []
    for f in frames_u:
        fit = next((x for x in al.frames if x.urdf == f), None)
        ptol, rtol = tol(f)
        convention = (fit is not None and (fit.position > ptol or fit.rotation > rtol)
                      and fit.residual_position <= ptol and fit.residual_rotation <= rtol)
        constants.append(fit.constant if convention else np.eye(4))
    out = {}
    for name in wanted:
        info_b = available_backends().get(name)
        if info_b is None or not info_b.available:
            continue
        try:
            klass = getattr(importlib.import_module(info_b.module, "kinverify.backends"), info_b.cls)
            if name in URDF_SIDE:
                independent = name == "yourdfpy"  # yourdfpy drives <mimic> joints from their leaders itself
                inner = klass.from_urdf(urdf_text, base + (al.independent if independent else all_u), frames_u, name=name)
                out[name] = AlignedBackend(inner, al, frames_u, "independent" if independent else "urdf")
            else:
                keep = _readable_frames(klass, mjcf_text, base + all_m, frames_m, name)
                inner = klass.from_mjcf(mjcf_text, base + all_m, [frames_m[i] for i in keep], name=name)
                out[name] = AlignedBackend(inner, al, [frames_u[i] for i in keep], "mjcf", tinv, [constants[i] for i in keep])
                if len(keep) < len(frames_m):
                    missing = [frames_m[i] for i in range(len(frames_m)) if i not in keep]
                    info.notes.append(f"{name} has no frame for {', '.join(missing)} (compared on the other frames)")
        except Exception as err:  # a library refusing a real file is a finding, whatever it raises
            if isinstance(err, KeyboardInterrupt):
                raise
            side = "URDF" if name in URDF_SIDE else "MJCF"
            text = str(err) if isinstance(err, KinverifyError) else f"{type(err).__name__}: {library_reason(err)}"
            findings.append(finding("parser_refused", f"{name} refuses the {side}: {text}",
                                    {"file": side, "backend": name}))
    return out


def _readable_frames(klass, mjcf_text: str, joints, frames, name: str) -> list[int]:
    """Indices of the frames a library reads (Pinocchio's MJCF parser makes no frame for a site)."""
    from kinverify.errors import UnknownNameError

    try:
        klass.from_mjcf(mjcf_text, joints, frames, name=name)
        return list(range(len(frames)))
    except UnknownNameError as err:
        known = set(err.available)
        return [i for i, f in enumerate(frames) if f in known]


def rebuild_mjcf(backend: AlignedBackend, left: np.ndarray) -> AlignedBackend:
    return AlignedBackend(backend.inner, backend.alignment, backend.frames, "mjcf", left, backend.constants)


def side_names(options) -> list[str]:
    wanted = [n for n in (options.backends or URDF_SIDE + MJCF_SIDE) if n in URDF_SIDE + MJCF_SIDE]
    if not any(n in URDF_SIDE for n in wanted) or not any(n in MJCF_SIDE for n in wanted):
        raise InputError(f"--backends: file mode needs a URDF backend ({', '.join(URDF_SIDE)}) and an MJCF backend "
                         f"({', '.join(MJCF_SIDE)}); got {', '.join(options.backends or [])}")
    return wanted
