"""The same joint in every side: one row per joint, named by the first file.

Files are matched to the first file as file mode matches a URDF to an MJCF
(:func:`kinverify.filemode.align.match.match_joints`: by name, by name without the prefix a file
puts on its names, by number, by place in the kinematic tree) when both have a description, else
by name and by lower-case alphanumeric name. An actuator table's joints are named as the file its
patterns were matched against."""

from __future__ import annotations

import re
from dataclasses import dataclass

from kinverify.filemode.align.match import match_joints
from kinverify.map.side import MapJoint, Side


@dataclass
class Rows:
    """``names[r][s]``: the name of row ``r``'s joint in side ``s`` (None: the side lacks it)."""

    sides: list[Side]
    names: list[list[str | None]]

    def row_of(self, s: int, name: str) -> int | None:
        return next((r for r, row in enumerate(self.names) if row[s] == name), None)

    def name(self, r: int, s: int) -> str:
        """Row ``r``'s joint name in side ``s``, which has it (KeyError if it lacks it)."""
        name = self.names[r][s]
        if name is None:
            raise KeyError(f"side {s} lacks the joint of row {r}")
        return name

    def joint(self, r: int, s: int) -> MapJoint | None:
        name = self.names[r][s]
        return None if name is None else self.sides[s].joint(name)

    def label(self, r: int) -> str:
        return next(n for n in self.names[r] if n is not None)


def _simple(name: str) -> str:
    return re.sub(r"[^0-9a-z]", "", name.lower())


def pair_names(a: Side, b: Side) -> list[tuple[str, str]]:
    """``(name in a, name in b)`` for the joints both have."""
    if a.desc is not None and b.desc is not None:
        pairs, _, _ = match_joints(a.desc, b.desc)
        known_a, known_b = set(a.names), set(b.names)
        return [(x, y) for x, y, _ in pairs if x in known_a and y in known_b]
    out: list[tuple[str, str]] = []
    used = set()
    for key in (lambda n: n, _simple):
        keys_b: dict[str, list[str]] = {}
        for n in b.names:
            if n not in used:
                keys_b.setdefault(key(n), []).append(n)
        taken = {x for x, _ in out}
        for n in a.names:
            hits = keys_b.get(key(n), [])
            if n not in taken and len(hits) == 1:
                out.append((n, hits[0]))
                used.add(hits[0])
    return out


def match_rows(sides: list[Side], table_targets: dict[int, int]) -> Rows:
    """Rows over ``sides`` (``sides[0]`` names them); ``table_targets``: an actuator table's side
    index -> the index of the file whose joint names it uses."""
    ref = sides[0]
    names: list[list[str | None]] = [[n] + [None] * (len(sides) - 1) for n in ref.names]
    by_ref = {n: r for r, n in enumerate(ref.names)}
    for s, side in enumerate(sides[1:], start=1):
        if s in table_targets:
            continue
        paired = dict(pair_names(ref, side))
        for a, b in paired.items():
            names[by_ref[a]][s] = b
        names += [[None] * s + [n] + [None] * (len(sides) - s - 1) for n in side.names if n not in paired.values()]
    for s, target in table_targets.items():
        for row in names:
            if row[target] is not None:
                row[s] = row[target]
    return Rows(sides, names)
