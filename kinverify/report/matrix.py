"""The report's heat map: one row per property (grouped by suite, in registry order), one column
per backend under test, each cell coloured by ``log10(max error / tolerance)``.

A check compares two views ``(a, b)``; its column is the side being tested and the row says what
it was compared against:

- ``(x, x)``: a solver on its own backend (``ik.failure_rate``): column ``x``, against its goal;
- one side is not a backend (``finite-difference``, ``limits``, ``geometry``, ``plan``...): column
  is the backend, against the other side;
- both are backends: the side that is not the reference is tested (``analytic`` vs ``mujoco``:
  column ``mujoco``); with neither the reference, the first side (the IK solver's backend);
- neither is a backend (``urdf`` vs ``mjcf`` parameters, ``closed-form`` vs ``geometry``): the
  first side, against the second.

A suite whose rows each hold a single cell collapses into one column, the pair named on the row.
A cell is the worst of its checks (frames, compared backends) relative to its tolerance.
"""

from __future__ import annotations

import builtins
import math
import re
from collections import Counter
from dataclasses import dataclass, field
from typing import Any

from kinverify.report.units import display_unit, revolute
from kinverify.results import VerifyResult
from kinverify.suites.base import EXPLAINED, PERFORMANCE, Check


def reference(result: VerifyResult) -> str:
    """The backend FK is compared against: the first side of most ``fk.position`` checks."""
    sides = Counter(c.backends[0] for c in result.checks if c.property == "fk.position")
    return sides.most_common(1)[0][0] if sides else (result.backends[0] if result.backends else "")


def column_of(pair: tuple[str, str], backends, ref: str) -> tuple[str, str]:
    """``(column, against)`` of a check's backend pair (rules in the module docstring)."""
    a, b = pair
    real = set(backends)
    if a == b:
        return a, "goal"
    if (a in real) != (b in real):
        return (a, b) if a in real else (b, a)
    return (b, a) if a == ref else (a, b)


def ratio(c: Check) -> float:
    """max error ÷ tolerance: 0 for a zero error, inf for an error above a zero tolerance, NaN for NaN."""
    if c.max_error != c.max_error:
        return math.nan
    if c.max_error == 0:
        return 0.0
    return c.max_error / c.tolerance if c.tolerance > 0 else math.inf


def severity(c: Check) -> tuple[bool, float]:
    """Sort key of a check, worst last: passing by ratio, then failing."""
    r = ratio(c)
    return (not c.passed, math.inf if r != r else r)


# colour stops for log10(ratio): far below the tolerance -> dark, near it -> light, above -> red
_AGREE = [(-9.0, (27, 94, 32)), (-6.0, (67, 160, 71)), (-3.0, (165, 214, 167)), (-1.0, (205, 232, 190)), (0.0, (255, 241, 118))]
_PERF = [(-3.0, (21, 101, 192)), (-1.0, (100, 181, 246)), (0.0, (227, 242, 253))]
FAIL_COLOUR, BELOW_GOAL_COLOUR, NAN_COLOUR = (198, 40, 40), (255, 179, 0), (120, 120, 120)
EXPLAINED_COLOUR = (225, 190, 231)  # a difference a finding reports (the finding's purple, light)


def _interp(stops, x: float) -> tuple[int, int, int]:
    if x <= stops[0][0]:
        return stops[0][1]
    for (x0, c0), (x1, c1) in zip(stops, stops[1:], strict=False):
        if x <= x1:
            t = (x - x0) / (x1 - x0)
            return tuple(round(u + t * (v - u)) for u, v in zip(c0, c1, strict=True))
    return stops[-1][1]


def colour(r: float, passed: bool, performance: bool, counts: bool = True, explained: bool = False) -> tuple[str, str]:
    """(background, text colour) of a cell of ratio ``r``: greens for agreement, blues for a
    performance goal met, red for a failure that counts, amber for a goal missed (not counted),
    light purple for a difference a finding reports (``explained``)."""
    if r != r:
        rgb = NAN_COLOUR
    elif not passed and explained:
        rgb = EXPLAINED_COLOUR
    elif not passed:
        rgb = FAIL_COLOUR if counts else BELOW_GOAL_COLOUR
    else:
        rgb = _interp(_PERF if performance else _AGREE, math.log10(r) if r > 0 else -99.0)
    luminance = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
    return "#%02x%02x%02x" % rgb, "#000" if luminance > 140 else "#fff"


def short(x: float) -> str:
    """A number in at most 5 characters for a cell: ``0``, ``3e-16``, ``0.5``, ``12``."""
    if x != x:
        return "nan"
    if x == 0:
        return "0"
    if math.isinf(x):
        return "inf"
    if 0.01 <= abs(x) < 100:
        return f"{x:.2g}"
    if 100 <= abs(x) < 1000:
        return f"{x:.0f}"
    return f"{x:.0e}".replace("e-0", "e-").replace("e+0", "e").replace("e+", "e")


def slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "-", text).strip("-") or "x"


@dataclass
class Cell:
    column: str
    checks: list[Check]
    against: list[str]
    revolute: tuple[bool, ...] = ()  # the model's joint types, for joint-space units

    @property
    def worst(self) -> Check:
        return max(self.checks, key=severity)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks)

    @property
    def anchor(self) -> str:
        return "d-" + slug(f"{self.worst.property}-{self.column}")

    def style(self) -> str:
        w = self.worst
        bg, fg = colour(ratio(w), self.passed, w.kind == PERFORMANCE, w.counts, w.kind == EXPLAINED)
        return f"background:{bg};color:{fg}"

    @property
    def text(self) -> str:
        return short(self.worst.max_error)

    @property
    def title(self) -> str:
        w = self.worst
        n_fail = sum(not c.passed for c in self.checks)
        limit = "goal" if w.kind == PERFORMANCE else "tolerance"
        verdict = (
            "all pass"
            if not n_fail
            else f"{n_fail} of {len(self.checks)} "
            + (
                "below goal"
                if w.kind == PERFORMANCE and not w.counts
                else "differ as a finding says"
                if w.kind == EXPLAINED
                else "fail"
            )
        )
        return (
            f"{w.property}: {' vs '.join(w.backends)} at {w.frame}: {w.max_error:.3g} {display_unit(w.unit, self.revolute)} "
            f"({limit} {w.tolerance:.3g}); {len(self.checks)} check{'s' if len(self.checks) != 1 else ''}, {verdict}"
        )


@dataclass
class Row:
    property: str
    kind: str
    cells: dict[str, Cell] = field(default_factory=dict)

    @builtins.property  # the field above shadows the builtin in this class body
    def against(self) -> str:
        sides = list(dict.fromkeys(a for cell in self.cells.values() for a in cell.against))
        if sides == ["goal"]:
            return "goal"
        sides = [s for s in sides if s != "goal"]
        return f"vs {sides[0]}" if len(sides) == 1 else (f"vs {len(sides)} others" if sides else "")

    @builtins.property
    def failed(self) -> bool:
        return any(not c.passed for c in self.cells.values())


@dataclass
class Group:
    suite: str
    title: str
    columns: list[str]
    rows: list[Row]
    single: bool = False  # one cell per row: the pair is named on the row

    @property
    def failed(self) -> bool:
        return any(r.failed for r in self.rows)


def groups(result: VerifyResult) -> list[Group]:
    """The matrix: suites in registry order (unknown properties last), properties in the order
    the suite declares them, columns in the order of ``result.backends`` then first seen."""
    from kinverify.suites.registry import SUITES

    ref, rev = reference(result), tuple(revolute(result))
    suite_of = {p.name: (s.name, s.title) for s in SUITES for p in s.properties}
    declared = [p.name for s in SUITES for p in s.properties]
    by_suite: dict[str, Group] = {}
    for c in result.checks:
        name, title = suite_of.get(c.property, ("other", "Other properties"))
        g = by_suite.setdefault(name, Group(name, title, [], []))
        row = next((r for r in g.rows if r.property == c.property), None)
        if row is None:
            row = Row(c.property, c.kind)
            g.rows.append(row)
        col, against = column_of(c.backends, result.backends, ref)
        cell = row.cells.setdefault(col, Cell(col, [], [], rev))
        cell.checks.append(c)
        if against not in cell.against:
            cell.against.append(against)
    order = {n: i for i, n in enumerate(s.name for s in SUITES)}
    rank = {b: i for i, b in enumerate(result.backends)}
    out = []
    for name in sorted(by_suite, key=lambda n: order.get(n, len(order))):
        g = by_suite[name]
        g.rows.sort(key=lambda r: declared.index(r.property) if r.property in declared else len(declared))
        seen = list(dict.fromkeys(col for r in g.rows for col in r.cells))
        g.columns = sorted(seen, key=lambda col: (rank.get(col, len(rank)), seen.index(col)))
        g.single = len(g.columns) > 1 and all(len(r.cells) == 1 for r in g.rows)
        out.append(g)
    return out


def layout(groups: list[Group]) -> list[list[list[Group]]]:
    """Stacks of columns of groups. The first stack holds the suites with a column per backend,
    one above the other; the second the suites collapsed to one column (narrow), packed into
    columns no taller than the tallest of them, so that they sit beside the wide stack on a wide
    screen and in one row under it on a narrower one."""
    wide = [g for g in groups if not g.single and len(g.columns) > 1]
    narrow = [g for g in groups if g.single or len(g.columns) <= 1]
    stacks = [[wide]] if wide else []
    if narrow:
        height = max(len(g.rows) for g in narrow)
        columns: list[list[Group]] = []
        for g in narrow:
            if columns and sum(len(h.rows) + 1 for h in columns[-1]) + len(g.rows) <= height:
                columns[-1].append(g)
            else:
                columns.append([g])
        stacks.append(columns)
    return stacks


def legend(explained: bool = False) -> list[dict[str, Any]]:
    """Swatches for the legend: agreement ratios, performance, failures (and, when the run has
    them, differences a finding reports)."""
    items = [
        (1e-9, True, False, "≤ 1e-9 of tolerance"),
        (1e-6, True, False, "1e-6"),
        (1e-3, True, False, "1e-3"),
        (0.5, True, False, "near tolerance"),
        (10, False, False, "fails"),
        (1e-3, True, True, "performance: goal met"),
        (10, False, True, "below goal (not counted)"),
    ]
    out = []
    for r, passed, perf, label in items:
        bg, fg = colour(r, passed, perf, counts=not perf)
        out.append({"style": f"background:{bg};color:{fg}", "label": label, "performance": perf})
    if explained:
        bg, fg = colour(10, False, False, counts=False, explained=True)
        out.append({"style": f"background:{bg};color:{fg}", "label": "differs as a finding says", "performance": False})
    return out
