"""``map_files``: files (and an actuator table) -> sides -> rows -> maps and findings -> :class:`MapResult`."""

from __future__ import annotations

import time
from pathlib import Path
from dataclasses import dataclass, field
from typing import Any

from kinverify.errors import InputError
from kinverify.map.compare import RTOL, order_findings, value_findings
from kinverify.map.drives import drive_findings
from kinverify.map.maps import all_maps
from kinverify.map.readers import read_side
from kinverify.map.rows import Rows, match_rows
from kinverify.map.side import VALUES, Side
from kinverify.map.table import read_table
from kinverify.suites.base import Finding, _plain


@dataclass
class MapOptions:
    keyframe: str | None = None  # the MJCF keyframe that is the default pose (None: qpos0)
    actuators: str | None = None  # an Isaac Lab-style actuator table (YAML or TOML)
    rtol: float = RTOL


@dataclass
class MapResult:
    sides: list[Side]
    rows: Rows
    maps: dict[str, list[dict]]
    findings: list[Finding]
    duration_s: float = 0.0
    notes: list[str] = field(default_factory=list)

    @property
    def exit_code(self) -> int:
        """1 when an error finding says the files disagree on the contract, else 0."""
        return int(any(f.fails for f in self.findings))

    def to_dict(self) -> dict[str, Any]:
        sides = []
        for side in self.sides:
            entry: dict[str, Any] = {
                "file": side.label,
                "path": side.path,
                "format": side.format,
                "order": side.order if side.ordered else None,
                "joints": side.names if side.ordered else None,
                "notes": side.notes,
            }
            if side.ordered:
                entry["qpos_index"] = [j.qpos for j in side.joints]
                entry["dof_index"] = [j.dof for j in side.joints]
            entry["actuators"] = (
                None
                if side.actuators is None
                else [{"name": a.name, "joints": list(a.joints), "kind": a.kind} for a in side.actuators]
            )
            entry["values"] = {j.name: _joint_values(side, j) for j in side.joints}
            sides.append(entry)
        rows = [{self.sides[s].label: n for s, n in enumerate(row)} for row in self.rows.names]
        return _plain(
            {
                "kind": "kinverify-map",
                "files": [s.label for s in self.sides],
                "sides": sides,
                "rows": rows,
                "maps": self.maps,
                "findings": [f.to_dict() for f in self.findings],
                "verdict": "differ" if self.exit_code else "agree",
                "notes": self.notes,
                "duration_s": self.duration_s,
            }
        )


def _joint_values(side: Side, j) -> dict[str, Any]:
    out: dict[str, Any] = {
        "type": j.type,
        "driven": j.driven,
        "mode": j.mode or None,
        "follows": None
        if j.follows is None
        else {
            "leader": j.follows.leader,
            "multiplier": j.follows.multiplier,
            "offset": j.follows.offset,
            "source": j.follows.source,
        },
    }
    for v in VALUES:
        amount = getattr(j, v.name)
        out[v.name] = (
            amount if amount is not None else (f"not compared: {j.apart[v.name]}" if v.name in j.apart else side.state(v.name))
        )
    out["units"] = {v.name: v.unit(j.type) for v in VALUES}
    out["how"] = dict(j.how)
    return out


def map_files(paths: list[str], options: MapOptions | None = None) -> MapResult:
    """The contract between ``paths`` (two or more, or one with an actuator table)."""
    t0 = time.perf_counter()
    options = options or MapOptions()
    if len(paths) + bool(options.actuators) < 2:
        raise InputError("kinverify map compares two or more files (or one file and --actuators TABLE)")
    if len(set(paths)) != len(paths):
        raise InputError(f"{next(p for p in paths if paths.count(p) > 1)} is given twice")
    sides = [read_side(p, options) for p in paths]
    if options.keyframe and not any(side.format == "mjcf" for side in sides):
        raise InputError(f"--keyframe {options.keyframe!r}: no MJCF among the files (keyframes are MJCF's)")
    targets = {}
    if options.actuators:
        table, targets[len(sides)] = read_table(options.actuators, sides)
        sides.append(table)
    names = [Path(side.path).name for side in sides]
    for side, name in zip(sides, names, strict=True):
        side.label = name if names.count(name) == 1 else side.path
    rows = match_rows(sides, targets)
    findings = order_findings(rows) + drive_findings(rows) + value_findings(rows, options.rtol)
    order = {"error": 0, "warning": 1, "info": 2}
    findings.sort(key=lambda f: order[f.severity])
    return MapResult(sides, rows, all_maps(rows), findings, time.perf_counter() - t0)
