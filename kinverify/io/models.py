"""Checks on a URDF or MJCF tree before any library sees it, and MJCF ``<include>`` expansion.

- A URDF's links form one tree (:func:`check_urdf_tree`): links and joints have unique names, every joint names a parent and a child
  link of the file, a link has at most one parent joint, exactly one link is no joint's child,
  and every link is reached from it (a joint from a link back to an ancestor is a cycle, on which
  Pinocchio's URDF parser crashes the process and a chain walk never ends). Joint types are
  URDF's.
- Poses and axes are finite numbers (:func:`check_urdf_numbers`, :func:`check_mjcf_numbers`):
  NaN in a joint origin or axis otherwise reaches the libraries, which print to the terminal and
  compute NaN.
- :func:`expand_includes`: an MJCF's ``<include file>`` elements replaced by the included files'
  content, each read by :func:`kinverify.io.read.read_bytes` (so it is an input of the run, and
  refused if it is a FIFO or a device), the whole within ``MAX_MODEL_BYTES``; MuJoCo then never
  reads a file itself, and the text loads from anywhere.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

from kinverify.errors import InputError
from kinverify.io.formats import xml_parse
from kinverify.io.read import InputFileError, read_bytes
from kinverify.pipeline.limits import MAX_INCLUDE_DEPTH, MAX_MODEL_BYTES, MAX_XML_DEPTH

URDF_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")


def _where(path, label: str) -> str:
    return f"{label}: {path}" if label else str(path)


def check_urdf_tree(root: ET.Element, path, label: str = "") -> None:
    """:class:`InputError` unless the URDF's links and joints form one tree (see the module doc)."""
    where = _where(path, label)
    links: dict[str, ET.Element] = {}
    for link_element in root.findall("link"):
        name = link_element.get("name")
        if name is None:
            raise InputError(f"{where}: a <link> has no name")
        if name in links:
            raise InputError(f"{where}: link {name!r} is defined twice")
        links[name] = link_element
    if (
        links
        and "world" not in links
        and any((p := j.find("parent")) is not None and p.get("link") == "world" for j in root.findall("joint"))
    ):
        links["world"] = ET.Element("link", name="world")  # the world itself, as Drake and Gazebo read an undeclared one
    parent_of: dict[str, tuple[str, str]] = {}  # child link -> (parent link, joint)
    joint_names: set[str] = set()
    for joint in root.findall("joint"):
        name = joint.get("name")
        if name is None or name in joint_names:
            raise InputError(f"{where}: joint {name!r} is defined twice" if name else f"{where}: a <joint> has no name")
        joint_names.add(name)
        kind = joint.get("type")
        if kind not in URDF_JOINT_TYPES:
            raise InputError(
                f"{where}: joint {name!r} has type {kind!r}: unsupported (URDF joint types: {', '.join(URDF_JOINT_TYPES)})"
            )
        ends = []
        for tag in ("parent", "child"):
            element = joint.find(tag)
            link = element.get("link") if element is not None else None
            if link is None:
                raise InputError(f'{where}: joint {name!r} has no <{tag} link="..."/>')
            if link not in links:
                raise InputError(f"{where}: joint {name!r}: its {tag} link {link!r} is not a link of the file")
            ends.append(link)
        parent, child = ends
        if child in parent_of:
            raise InputError(
                f"{where}: link {child!r} is the child of two joints ({parent_of[child][1]!r} and {name!r}): a URDF is a tree"
            )
        parent_of[child] = (parent, name)
    roots = [n for n in links if n not in parent_of]
    if len(roots) > 1:
        raise InputError(
            f"{where}: links {', '.join(map(repr, roots[:5]))} are all roots (no joint has them as child): a URDF is one tree"
        )
    if not links:
        raise InputError(f"{where}: no <link>")
    if not roots:
        raise InputError(
            f"{where}: every link is a joint's child: the joints form a cycle ({_cycle(parent_of, next(iter(links)))})"
        )
    children: dict[str, list[str]] = {}
    for child, (parent, _) in parent_of.items():
        children.setdefault(parent, []).append(child)
    reached, todo = set(), [roots[0]]
    while todo:
        link = todo.pop()
        reached.add(link)
        todo.extend(children.get(link, ()))
    unreached = [n for n in links if n not in reached]
    if unreached:
        raise InputError(f"{where}: the joints form a cycle ({_cycle(parent_of, unreached[0])}): a URDF is a tree")


def _cycle(parent_of: dict[str, tuple[str, str]], start: str) -> str:
    """``a -> b -> c -> a``: the cycle above ``start`` (every link on it has a parent)."""
    seen: list[str] = []
    link = start
    while link not in seen:
        seen.append(link)
        link = parent_of[link][0]
    loop = seen[seen.index(link) :]
    return " -> ".join(repr(name) for name in reversed([*loop, loop[0]]))


def _finite(element: ET.Element, attribute: str, count: int | None, where: str, what: str, finite: bool = True) -> None:
    """``attribute`` of ``element``, when present, is ``count`` numbers (finite ones unless
    ``finite=False``); :class:`InputError` naming it otherwise."""
    text = element.get(attribute)
    if text is None:
        return
    try:
        values = [float(x) for x in text.split()]
    except ValueError:
        values = None
    if values is None or (count is not None and len(values) != count) or (finite and not all(map(math.isfinite, values))):
        kind = "finite number" if finite else "number"
        amount = f"a {kind}" if count == 1 else f"{count} {kind}s" if count else f"{kind}s"
        raise InputError(f"{where}: {what}: {attribute}={text!r} is not {amount}")


# numbers a URDF holds besides poses: they must be numbers (a non-finite mass or inertia is left
# to the inertial validation, which names it as a non-physical inertial)
URDF_NUMBERS = {
    "inertial/mass": {"value": 1},
    "inertial/inertia": dict.fromkeys(("ixx", "ixy", "ixz", "iyy", "iyz", "izz"), 1),
    "limit": {"effort": 1, "velocity": 1},
    "dynamics": {"damping": 1, "friction": 1},
    "mimic": {"multiplier": 1, "offset": 1},
    "geometry/box": {"size": 3},
    "geometry/cylinder": {"radius": 1, "length": 1},
    "geometry/sphere": {"radius": 1},
    "geometry/mesh": {"scale": 3},
}


def check_urdf_numbers(root: ET.Element, path, label: str = "") -> None:
    """Joint origins and axes, the origins of inertials, visuals and collisions, and joint limits
    are finite numbers; masses, inertias, efforts, speeds, damping, mimic factors and geometry
    sizes are numbers (Pinocchio's parser prints its complaint to the terminal and refuses the
    file; others read 0)."""
    where = _where(path, label)
    for joint in root.findall("joint"):
        what = f"joint {joint.get('name')!r}"
        for tag, attributes in (("origin", ("xyz", "rpy")), ("axis", ("xyz",))):
            for element in joint.findall(tag):
                for attribute in attributes:
                    _finite(element, attribute, 3, where, f"{what} <{tag}>")
        for limit in joint.findall("limit"):
            for attribute in ("lower", "upper"):
                _finite(limit, attribute, 1, where, f"{what} <limit>")
        for tag in ("limit", "dynamics", "mimic"):
            for element in joint.findall(tag):
                for attribute, count in URDF_NUMBERS[tag].items():
                    _finite(element, attribute, count, where, f"{what} <{tag}>", finite=False)
    for link in root.findall("link"):
        what = f"link {link.get('name')!r}"
        for part in ("inertial", "visual", "collision"):
            for origin in link.findall(f"{part}/origin"):
                for attribute in ("xyz", "rpy"):
                    _finite(origin, attribute, 3, where, f"{what} <{part}><origin>")
        for tag, counts in URDF_NUMBERS.items():
            if tag.startswith(("inertial/", "geometry/")):
                found = link.findall(tag) if tag.startswith("inertial/") else link.findall(f"*/{tag}")
                for element in found:
                    for attribute, count in counts.items():
                        _finite(element, attribute, count, where, f"{what} <{tag.split('/')[-1]}>", finite=False)


MJCF_POSES = {"pos": 3, "quat": 4, "axis": 3, "euler": 3, "axisangle": 4, "xyaxes": 6, "zaxis": 3, "fromto": 6}
MJCF_POSED = ("body", "joint", "geom", "site", "inertial", "frame", "camera", "light")


def check_mjcf_numbers(root: ET.Element, path, label: str = "") -> None:
    """Positions, orientations and axes of bodies, joints, geoms, sites, inertials and frames, and
    joint ranges, are finite numbers."""
    where = _where(path, label)
    for tag in MJCF_POSED:
        for element in root.iter(tag):
            what = f"<{tag}{' name=' + repr(element.get('name')) if element.get('name') else ''}>"
            for attribute, count in MJCF_POSES.items():
                _finite(element, attribute, count, where, what)
            if tag == "joint":
                _finite(element, "range", 2, where, what)


def tree_depth(root: ET.Element) -> int:
    depth, stack = 0, [(root, 1)]
    while stack:
        element, d = stack.pop()
        depth = max(depth, d)
        stack.extend((child, d + 1) for child in element)
    return depth


def expand_includes(root: ET.Element, path, label: str = "", size: int = 0) -> tuple[ET.Element, list[str]]:
    """``root`` with every ``<include file>`` replaced by the included file's elements (paths
    relative to the main file's folder, as MuJoCo reads them), and the files read (the main file
    first; a file included twice, or including one above it, is refused).
    ``size``: bytes of the main file (the whole stays within ``MAX_MODEL_BYTES``)."""
    base = Path(path).resolve().parent
    included: list[str] = [str(Path(path).resolve())]
    budget = [MAX_MODEL_BYTES - size]

    def too_deep() -> InputError:
        return InputError(
            f"{_where(path, label)} with the files it includes nests elements more than {MAX_XML_DEPTH} "
            "levels deep (see docs/robustness.md)"
        )

    def expand(element: ET.Element, level: int, depth: int) -> None:
        """``level``: the element's nesting in the expanded tree; ``depth``: includes above it."""
        items, changed = [], False
        for child in list(element):
            if child.tag != "include":
                expand(child, level + 1, depth)
                items.append(child)
                continue
            name = child.get("file")
            if not name:
                raise InputError(f"{_where(path, label)}: an <include> has no file")
            if depth >= MAX_INCLUDE_DEPTH:
                raise InputError(f"{_where(path, label)}: <include> nested more than {MAX_INCLUDE_DEPTH} deep ({name})")
            file = base / name
            key = str(file.resolve())
            if key in included:
                raise InputError(f"{_where(path, label)}: {name} is included twice (MuJoCo includes a file once)")
            included.append(key)
            try:
                data = read_bytes(file, "the MJCF's <include>", max(budget[0], 0))
            except InputFileError as err:
                if err.too_large:
                    raise InputError(
                        f"{_where(path, label)}: <include file={name!r}>: with the files it includes the MJCF is "
                        f"above the {MAX_MODEL_BYTES // 2**20} MB kinverify reads (see docs/robustness.md)"
                    ) from None
                raise InputError(f"{_where(path, label)}: <include file={name!r}>: {file} {err.reason}") from None
            budget[0] -= len(data)
            sub = xml_parse(data, file, f"{_where(path, label)}: <include file={name!r}>")
            if sub.tag != "mujoco":
                raise InputError(
                    f"{_where(path, label)}: the included {name} is not MJCF (root element <{sub.tag}>, expected <mujoco>)"
                )
            if level + tree_depth(sub) - 1 > MAX_XML_DEPTH:
                raise too_deep()
            expand(sub, level, depth + 1)  # its children take the <include>'s place, beside this element's
            items.extend(sub)
            changed = True
        if changed:
            element[:] = items

    expand(root, 1, 0)
    return root, included
