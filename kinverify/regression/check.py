"""Compare a model with a saved baseline: what moved, by how much, and why.

The current spec is evaluated at the baseline's stored configurations (not at a fresh sample
set, so a changed joint limit does not move the samples). Each record is compared with the
property's metric; per (property, frame) the worst sample is kept. Explanations come from the
spec stored in the baseline (:mod:`kinverify.specdiff`), the fingerprints of the generated
files, and the library versions.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from kinverify.errors import InputError
from kinverify.regression.baseline import (
    BASELINE_TOLERANCES,
    QUANTITIES,
    Tolerance,
    compute_records,
    fingerprints,
    read_baseline,
    record_delta,
)
from kinverify.model.canonical import spec_from_canonical, spec_to_canonical
from kinverify.model.spec import ArmSpec
from kinverify.regression.specdiff import ParamChange, diff_specs
from kinverify.versions import library_versions

FALLBACK_TOLERANCE = Tolerance(1e-9, "")


@dataclass(frozen=True)
class Moved:
    """One (property, frame) whose value moved beyond tolerance; ``old``/``new`` at the worst
    configuration ``q`` (sample index ``sample``); ``count`` samples moved in all."""

    property: str
    frame: str
    sample: int
    q: tuple[float, ...]
    old: Any
    new: Any
    delta: float
    tolerance: float
    unit: str
    count: int
    of: int

    def to_dict(self) -> dict[str, Any]:
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in self.__dict__.items()}


@dataclass
class BaselineCheck:
    model: str
    source: str
    samples: int
    moved: list[Moved]
    frames_added: list[str] = field(default_factory=list)
    frames_removed: list[str] = field(default_factory=list)
    spec_changed: bool = False
    spec_changes: list[ParamChange] = field(default_factory=list)
    files_changed: list[str] = field(default_factory=list)  # "urdf", "mjcf"
    version_changes: dict[str, tuple[str, str]] = field(default_factory=dict)
    comparable: bool = True  # False when the joint count changed: samples cannot be re-evaluated
    compared: int = 0  # records compared
    missing_quantities: list[str] = field(default_factory=list)  # computed now, absent from the baseline

    @property
    def passed(self) -> bool:
        return self.comparable and not self.moved and not self.frames_added and not self.frames_removed

    @property
    def explanations(self) -> list[str]:
        """Why things moved (or did not): spec changes, generated files, library versions."""
        out = []
        versions = ", ".join(f"{k} {a} -> {b}" for k, (a, b) in self.version_changes.items())
        if self.spec_changed:
            out.append(
                "the spec changed: "
                + ("; ".join(c.describe() for c in self.spec_changes) or "no parameter differs by more than 1e-12")
            )
        elif self.files_changed:
            out.append(
                f"the spec is unchanged but the generated {' and '.join(self.files_changed).upper()} changed "
                "(a different kinverify generator)"
            )
        if self.version_changes:
            if self.spec_changed:
                out.append(f"library versions also changed: {versions}")
            elif self.passed:
                out.append(f"only library versions changed ({versions}); nothing moved")
            else:
                out.append(f"the spec is unchanged; library versions changed ({versions}): they explain the movement")
        elif not self.spec_changed and not self.passed:
            out.append("neither the spec nor the library versions changed")
        if self.missing_quantities:
            out.append(
                f"the baseline has no {', '.join(self.missing_quantities)} records (an older format or "
                "kinverify); they were not compared: save a new baseline to include them"
            )
        if not self.comparable:
            out.append("the joint count changed, so the baseline's configurations cannot be re-evaluated; save a new baseline")
        return out

    def to_dict(self) -> dict[str, Any]:
        return {
            "model": self.model,
            "source": self.source,
            "passed": self.passed,
            "samples": self.samples,
            "compared": self.compared,
            "moved": [m.to_dict() for m in self.moved],
            "frames_added": self.frames_added,
            "frames_removed": self.frames_removed,
            "spec_changed": self.spec_changed,
            "spec_changes": [c.to_dict() for c in self.spec_changes],
            "files_changed": self.files_changed,
            "comparable": self.comparable,
            "missing_quantities": self.missing_quantities,
            "version_changes": {k: list(v) for k, v in self.version_changes.items()},
            "explanations": self.explanations,
        }


def _key(rec: dict) -> tuple:
    return rec["property"], rec["frame"], rec["sample"]


def compare_records(
    old: list[dict], new: list[dict], q: np.ndarray, order: list[str], tolerances: dict[str, Tolerance]
) -> tuple[list[Moved], int]:
    """Moved quantities (worst sample per property and frame) and the number compared."""
    new_by_key = {_key(r): r for r in new}
    worst: dict[tuple[str, str], Moved] = {}
    counts: dict[tuple[str, str], list[int]] = {}
    compared = 0
    for rec in old:
        other = new_by_key.get(_key(rec))
        if other is None:
            continue
        compared += 1
        prop, frame = rec["property"], rec["frame"]
        tol = tolerances.get(prop, FALLBACK_TOLERANCE)
        delta = record_delta(prop, rec["value"], other["value"])
        count = counts.setdefault((prop, frame), [0, 0])
        count[1] += 1
        if not delta <= tol.value:  # also catches NaN
            count[0] += 1
            best = worst.get((prop, frame))
            if best is None or delta > best.delta:
                s = rec["sample"]
                worst[(prop, frame)] = Moved(
                    prop, frame, s, tuple(q[s].tolist()), rec["value"], other["value"], delta, tol.value, tol.unit, 0, 0
                )
    props = list(tolerances)
    rank = {f: i for i, f in enumerate(order)}
    moved = [Moved(**{**m.__dict__, "count": counts[k][0], "of": counts[k][1]}) for k, m in worst.items()]
    moved.sort(
        key=lambda m: (props.index(m.property) if m.property in props else len(props), rank.get(m.frame, len(rank)), m.property)
    )
    return moved, compared


def check_baseline(
    spec: ArmSpec, data: dict[str, Any], tolerances: dict[str, Tolerance] | None = None, source: str = ""
) -> BaselineCheck:
    """Compare ``spec`` with validated baseline ``data`` (see :func:`kinverify.baseline.read_baseline`)."""
    tolerances = dict(tolerances or BASELINE_TOLERANCES)
    q = np.asarray(data["q"], dtype=float)
    old_frames, new_frames = list(data["frames"]), list(spec.frame_names)
    result = BaselineCheck(spec.name, source, len(q), [])
    result.frames_removed = [f for f in old_frames if f not in new_frames]
    result.frames_added = [f for f in new_frames if f not in old_frames]
    prints = fingerprints(spec)
    stored = data.get("fingerprints") or {}
    result.spec_changed = stored.get("spec") != prints["spec"] and data["spec"] != spec_to_canonical(spec)
    if not result.spec_changed and (result.frames_removed or result.frames_added):  # the same model, other frames
        raise InputError(
            f"{source}: frames: the baseline records this very spec, yet its frames differ from the model's "
            f"(only in the baseline: {', '.join(result.frames_removed) or 'none'}; only in the model: "
            f"{', '.join(result.frames_added) or 'none'}): the file does not match the model; save the baseline again"
        )
    if result.spec_changed:
        result.spec_changes = diff_specs(spec_from_canonical(data["spec"], where=f"{source}: spec"), spec)
    result.files_changed = [k for k in ("urdf", "mjcf") if stored.get(k) != prints[k]]
    now = library_versions()
    old_versions = data.get("versions") or {}
    result.version_changes = {
        k: (str(old_versions.get(k)), str(now.get(k)))
        for k in sorted(set(old_versions) | set(now))
        if old_versions.get(k) != now.get(k)
    }
    stored_quantities = data.get("quantities") or ["kinematics"]
    result.missing_quantities = [qt.name for qt in QUANTITIES if qt.name not in stored_quantities]
    if q.shape[1] != spec.nq:
        result.comparable = False
        return result
    records = compute_records(spec, q, data.get("fixed") or {})
    order = new_frames + [j for j in spec.coordinate_names if j not in new_frames]
    result.moved, result.compared = compare_records(data["records"], records, q, order, tolerances)
    if not result.compared and not result.frames_added and not result.frames_removed:
        raise InputError(
            f"{source}: no record of the baseline matches what the model computes: nothing was compared (save the baseline again)"
        )
    return result


def check(spec: ArmSpec, path, tolerances: dict[str, Tolerance] | None = None) -> "BaselineCheck":
    """Re-evaluate ``spec`` at the baseline's configurations and compare: a :class:`BaselineCheck`
    (``.passed``, ``.moved``, ``.explanations``)."""
    return check_baseline(spec, read_baseline(path, model=spec.name), tolerances, source=str(path))
