"""Every library that reads each file, seen through the alignment (:mod:`~kinverify.filemode.align.view`),
so the kinematics suite compares the two files after what the alignment explains. A library that
refuses a file is a finding."""

from __future__ import annotations

import importlib

import numpy as np

from kinverify.backends import available_backends, names_reading
from kinverify.errors import BackendError, InputError, KinverifyError, UnknownNameError, library_reason
from kinverify.filemode.align.view import AlignedBackend
from kinverify.filemode.compare.crosscheck import refusal_findings
from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.files import LABELS
from kinverify.model.floating import BASE_COORDINATES


def build_backends(info, urdf_text: str, mjcf_text: str, wanted, tol, findings: list, kinds=("urdf", "mjcf")) -> dict:
    """Every library that reads each file, through the alignment (first side, the URDF's: couplings
    only); with the base coordinates first when both files float (``info.base_coordinates``).
    ``kinds``: the format of each side (an SDFormat file may take either, read by Drake)."""
    first, second = names_reading(kinds[0]), names_reading(kinds[1])
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
        convention = (
            fit is not None
            and (fit.position > ptol or fit.rotation > rtol)
            and fit.residual_position <= ptol
            and fit.residual_rotation <= rtol
        )
        constants.append(fit.constant if convention and fit is not None else np.eye(4))
    out = {}
    for name in wanted:
        info_b = available_backends().get(name)
        if info_b is None or not info_b.available:
            continue
        try:
            klass = getattr(importlib.import_module(info_b.module, "kinverify.backends"), info_b.cls)
            if name in first:
                load = getattr(klass, f"from_{kinds[0]}")
                # yourdfpy drives the URDF's own <mimic> followers from their leaders itself; a
                # coupling only the other file states is given to it like to every other library
                pick = (
                    [j for j in all_u if j not in al.couplings or al.couplings[j].source != "<mimic>"]
                    if name == "yourdfpy"
                    else None
                )
                inner = load(urdf_text, base + (all_u if pick is None else pick), frames_u, name=name)
                out[name] = AlignedBackend(inner, al, frames_u, "urdf", pick=pick)
            elif name in second:
                load = getattr(klass, f"from_{kinds[1]}")
                keep = _readable_frames(load, mjcf_text, base + all_m, frames_m, name)
                inner = load(mjcf_text, base + all_m, [frames_m[i] for i in keep], name=name)
                out[name] = AlignedBackend(inner, al, [frames_u[i] for i in keep], "mjcf", tinv, [constants[i] for i in keep])
                if len(keep) < len(frames_m):
                    missing = [frames_m[i] for i in range(len(frames_m)) if i not in keep]
                    info.notes.append(f"{name} has no frame for {', '.join(missing)} (compared on the other frames)")
        except Exception as err:  # a library refusing a real file is a finding, whatever it raises
            if isinstance(err, KeyboardInterrupt):
                raise
            side = LABELS[kinds[0] if name in first else kinds[1]]
            if isinstance(err, BackendError) and err.backend == name:  # its name is said once, below
                text = err.reason
            else:
                text = str(err) if isinstance(err, KinverifyError) else f"{type(err).__name__}: {library_reason(err)}"
            findings.append(finding("parser_refused", f"{name} refuses the {side}: {text}", {"file": side, "backend": name}))
    findings += refusal_findings(out, kinds)
    return out


def _readable_frames(load, mjcf_text: str, joints, frames, name: str) -> list[int]:
    """Indices of the frames a library reads (Pinocchio's MJCF parser makes no frame for a site)."""
    try:
        load(mjcf_text, joints, frames, name=name)
        return list(range(len(frames)))
    except UnknownNameError as err:
        known = set(err.available)
        return [i for i, f in enumerate(frames) if f in known]


def rebuild_mjcf(backend: AlignedBackend, left: np.ndarray) -> AlignedBackend:
    return AlignedBackend(backend.inner, backend.alignment, backend.frames, "mjcf", left, backend.constants)


def side_names(options, kinds=("urdf", "mjcf")) -> list[str]:
    first, second = names_reading(kinds[0]), names_reading(kinds[1])
    wanted = [n for n in (options.backends or first + second) if n in first + second]
    if not any(n in first for n in wanted) or not any(n in second for n in wanted):
        article = {"URDF": "a", "USD": "a"}  # "an MJCF", "an SDF": as they are spoken
        a, b = (f"{article.get(LABELS[k], 'an')} {LABELS[k]}" for k in kinds)
        raise InputError(
            f"--backends: file mode needs {a} backend ({', '.join(first)}) and {b} backend "
            f"({', '.join(second)}); got {', '.join(options.backends or [])}"
        )
    return wanted
