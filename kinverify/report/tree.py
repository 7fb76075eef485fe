"""The kinematic tree as inline SVG: links as boxes from the root (left) to the tips (right),
joints on the edges with their type, and the links and joints that have findings or failing checks
marked (error red, warning amber, failing downstream of where a failure starts light red).

Built by hand (no graphviz): every name from the model is escaped; hovering a box or an edge
shows the full name and why it is marked.
"""

from __future__ import annotations

from markupsafe import Markup, escape

CHAR_W, ROW_H, BOX_H, FONT = 7.0, 34, 22, 12
MAX_CHARS = 24
GLYPH = {"revolute": "↻", "continuous": "↻", "prismatic": "↔", "fixed": "■", "floating": "✥", "planar": "▭"}
STYLE = {  # mark -> (fill, stroke, text)
    None: ("#f5f7f9", "#90a4ae", "#263238"),
    "error": ("#ffebee", "#c62828", "#b71c1c"),
    "warning": ("#fff8e1", "#f9a825", "#7a5a00"),
    "downstream": ("#fff5f5", "#ef9a9a", "#8e2a2a"),
}
WHY = {
    "error": "a finding or a failure starts here",
    "warning": "a warning finding",
    "downstream": "a failing check (downstream of where the failure starts)",
}


def _short(name: str) -> str:
    return name if len(name) <= MAX_CHARS else name[: MAX_CHARS - 1] + "…"


def layout(tree: dict) -> tuple[dict[str, tuple[int, float]], list[dict]]:
    """Depth and row of every link (leaves on consecutive rows, a parent centred on its
    children) and the joints drawn (those joining two known links)."""
    links = list(dict.fromkeys(tree.get("links") or []))
    joints = [j for j in tree.get("joints") or [] if j.get("parent") in links and j.get("child") in links]
    children: dict[str, list[str]] = {}
    has_parent = set()
    for j in joints:
        if j["child"] not in has_parent:
            children.setdefault(j["parent"], []).append(j["child"])
            has_parent.add(j["child"])
    place: dict[str, tuple[int, float]] = {}
    next_row = [0]

    def visit(link: str, depth: int) -> float:
        if link in place:  # a loop in a malformed tree: draw it once
            return place[link][1]
        place[link] = (depth, 0.0)
        kids = [k for k in children.get(link, []) if k not in place]
        if kids:
            rows = [visit(k, depth + 1) for k in kids]
            row = (rows[0] + rows[-1]) / 2
        else:
            row = float(next_row[0])
            next_row[0] += 1
        place[link] = (depth, row)
        return row

    for link in links:
        if link not in has_parent:
            visit(link, 0)
    for link in links:  # anything left (cycles) starts its own row
        if link not in place:
            visit(link, 0)
    return place, joints


def tree_svg(tree: dict, marks: dict[str, str] | None = None) -> Markup | None:
    marks = marks or {}
    place, joints = layout(tree)
    if not place:
        return None
    depth_max = max(d for d, _ in place.values())
    box_w = [0.0] * (depth_max + 1)
    gap = [60.0] * (depth_max + 1)
    for link, (d, _) in place.items():
        box_w[d] = max(box_w[d], CHAR_W * len(_short(link)) + 14)
    for j in joints:
        d = place[j["parent"]][0]
        gap[d] = max(gap[d], CHAR_W * 0.85 * (len(_short(j["name"])) + 2) + 16)
    x0 = [8.0]
    for d in range(depth_max):
        x0.append(x0[-1] + box_w[d] + gap[d])
    rows = max(r for _, r in place.values()) + 1
    width, height = x0[-1] + box_w[-1] + 8, rows * ROW_H + 10

    def centre(link):
        return (x0[place[link][0]], 8 + place[link][1] * ROW_H + BOX_H / 2)

    parts = []
    for j in joints:
        (xa, ya), (xb, yb) = centre(j["parent"]), centre(j["child"])
        xa += box_w[place[j["parent"]][0]]
        mark = marks.get(j["name"])
        fill, stroke, text = STYLE[mark if mark in STYLE else None]
        colour = stroke if mark else "#78909c"
        label = f"{GLYPH.get(j.get('type', ''), '')} {_short(j['name'])}".strip()
        why = f" — {WHY[mark]}" if mark in WHY else ""
        bold = ' font-weight="700"' if mark == "error" else ""
        label_fill = text if mark else "#546e7a"
        parts.append(
            f"<g><title>joint {escape(j['name'])} ({escape(j.get('type', '') or '?')}){escape(why)}</title>"
            f'<path d="M{xa:.1f},{ya:.1f} C{xa + 20:.1f},{ya:.1f} {xb - 20:.1f},{yb:.1f} {xb:.1f},{yb:.1f}" '
            f'fill="none" stroke="{colour}" stroke-width="{2.2 if mark else 1.3}"/>'
            f'<text x="{(xa + xb) / 2:.1f}" y="{yb - 5:.1f}" text-anchor="middle" font-size="{FONT - 2}" '
            f'fill="{label_fill}"{bold}>{escape(label)}</text></g>'
        )
    for link, (d, r) in place.items():
        mark = marks.get(link)
        fill, stroke, text = STYLE[mark if mark in STYLE else None]
        x, y = x0[d], 8 + r * ROW_H
        why = f" — {WHY[mark]}" if mark in WHY else ""
        dash = ' stroke-dasharray="4 2"' if mark == "downstream" else ""
        parts.append(
            f"<g><title>link {escape(link)}{escape(why)}</title>"
            f'<rect x="{x:.1f}" y="{y:.1f}" width="{box_w[d]:.1f}" height="{BOX_H}" rx="5" fill="{fill}" '
            f'stroke="{stroke}" stroke-width="{2 if mark else 1}"{dash}/>'
            f'<text x="{x + box_w[d] / 2:.1f}" y="{y + BOX_H / 2 + 4:.1f}" text-anchor="middle" font-size="{FONT}" '
            f'fill="{text}">{escape(_short(link))}</text></g>'
        )
    return Markup(
        f'<svg class="tree" xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
        f'viewBox="0 0 {width:.0f} {height:.0f}" font-family="ui-monospace, Menlo, Consolas, monospace" '
        f'role="img" aria-label="kinematic tree">' + "".join(parts) + "</svg>"
    )
