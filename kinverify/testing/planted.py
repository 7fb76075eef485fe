"""Planted changes: a URDF's MJCF as MuJoCo writes it, and hypothesis strategies that change one or
two things in it as a person editing it by hand would, each change recorded with its size.

    urdf = mesh_free_urdf(Path("robot.urdf").read_text())
    mjcf = mujoco_mjcf(urdf)                       # MuJoCo's own conversion: the two files agree
    @given(planted_changes(mjcf))
    def test_one_finding_per_change(change):
        text, planted = change                     # the MJCF with the changes, what was planted

A :class:`Planted` names the joint or body it was planted on (MuJoCo keeps the URDF's names) and
its size in SI units, as file mode reports it: a turn or tilt in rad (the angle), an offset in m
(the vector's length), a mass in kg, a centre of mass in m (how far the rigid body's moved: a
body and those welded to it are one), a principal moment in kg·m², a range
end in rad (m for a slide), damping in N·m·s/rad (N·s/m). :func:`equivalent_rewrites` draws
rewrites of the same robot that must give no error.
"""

from __future__ import annotations

import dataclasses
import math
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np
from hypothesis import strategies as st

from kinverify.model.transforms import axis_angle_to_matrix, matrix_to_quat, quat_to_matrix

KINDS = ("axis_flip", "axis_tilt", "frame_offset_along", "frame_offset_across", "frame_turn", "frame_turn_twist",
         "mass", "com", "inertia", "range", "damping")
FRAME_KINDS = ("axis_flip", "axis_tilt", "frame_offset_along", "frame_offset_across", "frame_turn", "frame_turn_twist")
JOINT_KINDS = FRAME_KINDS + ("range", "damping")  # planted on a joint (and the body holding it); the rest on a body
DEG = math.pi / 180


@dataclasses.dataclass(frozen=True)
class Planted:
    """One planted change: its ``kind`` (one of :data:`KINDS`), the ``joint`` or ``body`` it is on
    (MJCF names; a frame change names both), its ``size`` in ``unit``."""

    kind: str
    joint: str | None
    body: str | None
    size: float
    unit: str

    @property
    def names(self) -> tuple[str, ...]:
        """The names a finding of this change may go by."""
        return tuple(n for n in (self.joint, self.body) if n)

    def __str__(self) -> str:
        return f"{self.kind} on {' / '.join(self.names)}: {self.size:.6g} {self.unit}"


# --- the pair: a mesh-free URDF and the MJCF MuJoCo writes from it ---------------------------------

def mesh_free_urdf(urdf_text: str) -> str:
    """The URDF without its mesh visuals and collisions (their files are not needed to compare
    kinematics and dynamics), and with any inertia MuJoCo refuses (the triangle inequality broken)
    made what MuJoCo's ``balanceinertia`` makes of it: the mean of its principal moments, about
    every axis."""
    root = ET.fromstring(urdf_text)
    for link in root.iter("link"):
        for tag in ("visual", "collision"):
            for el in link.findall(tag):
                if el.find("geometry/mesh") is not None:
                    link.remove(el)
        inertia = link.find("inertial/inertia")
        if inertia is not None:
            names = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
            xx, yy, zz, xy, xz, yz = (float(inertia.get(n, "0")) for n in names)
            moments = np.linalg.eigvalsh(np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]))
            if moments[0] + moments[1] < moments[2] * (1 - 1e-9):
                mean = float(np.mean(moments))
                inertia.attrib.update({n: repr(mean) if n in ("ixx", "iyy", "izz") else "0" for n in names})
    return ET.tostring(root, encoding="unicode")


def mujoco_mjcf(urdf_text: str, *, free: bool = False) -> str:
    """The MJCF MuJoCo writes from a mesh-free URDF (``MjModel.from_xml_string`` then
    ``mj_saveLastXML``), every link kept as a body (``fusestatic="false"``); with ``free``, the
    robot's root body gets a free joint (``root``), as a floating robot's MJCF has."""
    root = ET.fromstring(urdf_text)
    hints = ET.SubElement(root, "mujoco")
    ET.SubElement(hints, "compiler", fusestatic="false", discardvisual="false")
    model = mujoco.MjModel.from_xml_string(ET.tostring(root, encoding="unicode"))
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "robot.xml"
        mujoco.mj_saveLastXML(str(path), model)
        text = path.read_text()
    if not free:
        return text
    tree = ET.fromstring(text)
    body = tree.find("worldbody/body")
    body.insert(0, ET.Element("freejoint", name="root"))
    return ET.tostring(tree, encoding="unicode")


# --- reading and writing numbers ------------------------------------------------------------------

def _vec(el: ET.Element, attr: str, default) -> np.ndarray:
    text = el.get(attr)
    return np.array([float(v) for v in text.split()] if text else default, dtype=float)


def _put(el: ET.Element, attr: str, values) -> None:
    el.set(attr, " ".join(repr(float(v)) for v in np.ravel(values)))


def _rotation(axis, angle: float) -> np.ndarray:
    return axis_angle_to_matrix(np.asarray(axis, float) / np.linalg.norm(axis), np.array([angle]))[0]


def _body_rotation(body: ET.Element) -> np.ndarray:
    return quat_to_matrix(_vec(body, "quat", [1, 0, 0, 0]))


def _perpendicular(axis: np.ndarray, angle: float) -> np.ndarray:
    """The unit vector perpendicular to ``axis`` at ``angle`` about it from a fixed reference."""
    a = axis / np.linalg.norm(axis)
    ref = np.eye(3)[int(np.argmin(np.abs(a)))]
    u = np.cross(a, ref)
    u /= np.linalg.norm(u)
    return _rotation(a, angle) @ u


# --- what can be planted where ---------------------------------------------------------------------

@dataclasses.dataclass
class _Site:
    body: ET.Element
    joint: ET.Element | None
    parent: "_Site | None"
    rigid: ET.Element | None = None  # the moving body this one is welded to, when it has no joint


def _bodies(parent: ET.Element) -> list[ET.Element]:
    """The bodies ``parent`` holds, through any ``<frame>`` (MuJoCo writes a fused link as one)."""
    out = []
    for child in parent:
        if child.tag == "body":
            out.append(child)
        elif child.tag == "frame":
            out += _bodies(child)
    return out


def _sites(root: ET.Element) -> list[_Site]:
    """Every moving body (under a hinge, slide or free joint), with its own hinge or slide joint
    (None when it has none or several) and the nearest moving body above that has one."""
    out: list[_Site] = []

    def walk(body: ET.Element, moving: bool, above: _Site | None, rigid: ET.Element | None) -> None:
        joints = [j for j in body.findall("joint") if j.get("type", "hinge") in ("hinge", "slide")]
        free = body.find("freejoint") is not None or any(j.get("type") == "free" for j in body.findall("joint"))
        moving = moving or free or bool(joints)
        own = free or bool(joints)
        site = _Site(body, joints[0] if len(joints) == 1 else None, above, None if own else rigid)
        if moving:
            out.append(site)
        for child in _bodies(body):
            walk(child, moving, site if site.joint is not None else above, body if own else rigid)

    for body in _bodies(root.find("worldbody")):
        walk(body, False, None, None)
    return out


def _inertial(body: ET.Element) -> ET.Element | None:
    inertial = body.find("inertial")
    if inertial is None or float(inertial.get("mass", "0")) <= 0 or inertial.get("diaginertia") is None:
        return None
    return inertial


def _applicable(kind: str, site: _Site) -> bool:
    if kind in JOINT_KINDS:
        joint = site.joint
        if joint is None:
            return False
        if kind == "range":
            return joint.get("range") is not None and joint.get("limited", "auto") != "false"
        if kind == "damping":
            return float(joint.get("damping", "0")) > 0  # the URDF states it (else the change is a value one file leaves unset)
        return not (kind.startswith("frame_turn") and joint.get("type") == "slide")
    inertial = _inertial(site.body)
    if inertial is None or site.rigid is not None:  # a body welded to another is one rigid body with it: its own
        return False                                 # centre of mass and mass are not what is compared
    share = float(inertial.get("mass")) / _group_mass(site.body)
    if kind == "inertia":  # alone in its rigid body: the moment planted is one of the rigid body's
        return share == 1.0 and bool(np.all(_vec(inertial, "diaginertia", [0, 0, 0]) > 0))
    return kind == "mass" or share >= 0.25  # its centre of mass moves the rigid body's by its share of the mass


def _welded(body: ET.Element) -> list[ET.Element]:
    """``body`` and the bodies welded to it (no joint between): one rigid body, as file mode compares it."""
    out = [body]
    for child in _bodies(body):
        if not any(j.tag == "freejoint" or j.tag == "joint" for j in child):
            out += _welded(child)
    return out


def _group_mass(body: ET.Element) -> float:
    return sum(float(b.find("inertial").get("mass", "0")) for b in _welded(body) if b.find("inertial") is not None)


# --- the changes --------------------------------------------------------------------------------

def _plant(draw, kind: str, site: _Site) -> Planted:
    body, joint = site.body, site.joint
    bname = body.get("name")
    if kind in JOINT_KINDS:
        jname = joint.get("name")
        axis = _vec(joint, "axis", [0, 0, 1])
        axis = axis / np.linalg.norm(axis)
        slide = joint.get("type") == "slide"
        if kind == "axis_flip":  # its range reversed with it: the same physical limits, only the sign differs
            _put(joint, "axis", -axis)
            if joint.get("range") is not None:
                lo, hi = _vec(joint, "range", [0, 0])
                _put(joint, "range", [-hi, -lo])
            return Planted(kind, jname, None, math.pi, "rad")
        if kind == "axis_tilt":
            angle = draw(st.floats(1.0, 5.0)) * DEG
            _put(joint, "axis", _rotation(_perpendicular(axis, draw(st.floats(0, 2 * math.pi))), angle) @ axis)
            return Planted(kind, jname, None, angle, "rad")
        if kind.startswith("frame_offset"):
            length = draw(st.floats(0.5, 20.0)) * 1e-3 * draw(st.sampled_from([1, -1]))
            local = axis * length if kind.endswith("along") else _perpendicular(axis, draw(st.floats(0, 2 * math.pi))) * length
            _put(body, "pos", _vec(body, "pos", [0, 0, 0]) + _body_rotation(body) @ local)
            return Planted(kind, jname, bname, abs(length), "m")
        if kind.startswith("frame_turn"):
            angle = draw(st.floats(1.0, 10.0)) * DEG * draw(st.sampled_from([1, -1]))
            about = _perpendicular(axis, draw(st.floats(0, 2 * math.pi)))
            if kind.endswith("twist"):  # about an axis with a part along the joint's: tilt and twist together
                slant = draw(st.floats(25.0, 65.0)) * DEG
                about = math.cos(slant) * axis + math.sin(slant) * about
            _put(body, "quat", matrix_to_quat(_body_rotation(body) @ _rotation(about, angle)))
            return Planted(kind, jname, bname, abs(angle), "rad")
        if kind == "range":
            lo, hi = _vec(joint, "range", [0, 0])
            step = draw(st.floats(0.005, 0.05) if slide else st.floats(0.02, 0.3)) * draw(st.sampled_from([1, -1]))
            end = draw(st.sampled_from([0, 1]))
            new = [lo + step, hi] if end == 0 else [lo, hi + step]
            if new[0] >= new[1] - abs(step):
                new = [lo - abs(step), hi] if end == 0 else [lo, hi + abs(step)]
            _put(joint, "range", new)
            return Planted(kind, jname, None, abs(step), "m" if slide else "rad")
        damping = float(joint.get("damping"))
        change = damping * draw(st.floats(0.1, 1.0)) * draw(st.sampled_from([1, -0.5]))
        joint.set("damping", repr(damping + change))
        return Planted(kind, jname, None, abs(change), "N·s/m" if slide else "N·m·s/rad")
    inertial = _inertial(body)
    if kind == "mass":
        mass = float(inertial.get("mass"))
        factor = 1 + draw(st.floats(0.05, 0.3)) * draw(st.sampled_from([1, -1]))
        inertial.set("mass", repr(mass * factor))
        return Planted(kind, None, bname, abs(mass * factor - mass), "kg")
    if kind == "com":  # the rigid body's centre of mass moves by the body's share of that
        length = draw(st.floats(1.0, 20.0)) * 1e-3
        direction = np.array([draw(st.floats(-1, 1)) for _ in range(3)]) + np.array([0, 0, 1e-3])
        _put(inertial, "pos", _vec(inertial, "pos", [0, 0, 0]) + direction / np.linalg.norm(direction) * length)
        return Planted(kind, None, bname, length * float(inertial.get("mass")) / _group_mass(body), "m")
    moments = _vec(inertial, "diaginertia", [0, 0, 0])
    which = draw(st.sampled_from([0, 1, 2]))
    others = np.delete(moments, which)
    low, high = abs(others[0] - others[1]), others.sum()  # the triangle inequality holds for the new moment
    new = moments[which] * (1 + draw(st.floats(0.1, 0.4)) * draw(st.sampled_from([1, -1])))
    new = min(max(new, low + 0.05 * (moments[which] - low)), high - 0.05 * (high - moments[which]))
    if abs(new - moments[which]) < 0.02 * moments[which]:
        new = moments[which] + 0.5 * ((high if high - moments[which] > moments[which] - low else low) - moments[which])
    moments[which] = new
    old = _vec(inertial, "diaginertia", [0, 0, 0])[which]
    _put(inertial, "diaginertia", moments)
    return Planted(kind, None, bname, abs(new - old), "kg·m²")


def plantable_kinds(mjcf_text: str) -> tuple[str, ...]:
    """The kinds of :data:`KINDS` that can be planted in this MJCF (``damping`` only where a joint
    states it, ``range`` where one is limited...)."""
    sites = _sites(ET.fromstring(mjcf_text))
    return tuple(k for k in KINDS if any(_applicable(k, s) for s in sites))


def _slot(kind: str) -> str:
    """Changes of one slot on one element would merge into one: never two of them there."""
    return "frame" if kind in FRAME_KINDS else kind


@st.composite
def planted_changes(draw, mjcf_text: str, kinds=KINDS, max_changes: int = 2, min_changes: int = 1,
                    stacked: bool | None = None) -> tuple[str, tuple[Planted, ...]]:
    """The MJCF with ``min_changes`` to ``max_changes`` (at most 2) random changes of ``kinds``
    planted, and what was planted. Of two, the second is sometimes on the joint above the first's
    (a change stacked on its parent's); ``stacked=True``: always (``False``: never)."""
    root = ET.fromstring(mjcf_text)
    options = [(k, s) for k in kinds for s in _sites(root) if _applicable(k, s)]
    if not options:
        raise ValueError(f"none of {kinds} can be planted in this MJCF")
    count = draw(st.integers(min(min_changes, 2), max(1, min(max_changes, 2))))

    def above(kind, site) -> list:  # what can be planted on the joint above, of another slot
        return [(k, s) for k, s in options if s is site.parent and (_slot(k), id(s.body)) != (_slot(kind), id(site.body))]

    first = [o for o in options if above(*o)] if count == 2 and stacked else options
    if not first:
        raise ValueError(f"no joint in this MJCF has one above it where one of {kinds} can be planted")
    kind, site = draw(st.sampled_from(first))
    planted = [_plant(draw, kind, site)]
    if count == 2:
        on_parent = bool(above(kind, site)) and (stacked if stacked is not None else draw(st.booleans()))
        pool = above(kind, site) if on_parent else [(k, s) for k, s in options if (_slot(k), id(s.body)) != (_slot(kind), id(site.body))]
        if pool:
            planted.append(_plant(draw, *draw(st.sampled_from(pool))))
    return ET.tostring(root, encoding="unicode"), tuple(planted)


# --- rewrites that change nothing -------------------------------------------------------------------

HELD = ("inertial", "geom", "site", "body", "joint", "camera", "light", "frame")


def _turn_back(el: ET.Element, back: np.ndarray) -> None:
    """``el`` (held by a body whose frame turned by ``backᵀ``) put back where it was."""
    if el.get("pos") is not None:
        _put(el, "pos", back @ _vec(el, "pos", [0, 0, 0]))
    if el.get("fromto") is not None:
        ends = _vec(el, "fromto", [0] * 6).reshape(2, 3)
        _put(el, "fromto", (back @ ends.T).T)
    if el.tag == "joint":
        if el.get("axis") is not None or el.get("type", "hinge") in ("hinge", "slide"):
            _put(el, "axis", back @ _vec(el, "axis", [0, 0, 1]))
        return
    if el.get("fullinertia") is not None:
        xx, yy, zz, xy, xz, yz = _vec(el, "fullinertia", [0] * 6)
        full = back @ np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]) @ back.T
        _put(el, "fullinertia", [full[0, 0], full[1, 1], full[2, 2], full[0, 1], full[0, 2], full[1, 2]])
    elif el.tag in ("inertial", "geom", "site", "body", "camera", "frame"):
        _put(el, "quat", matrix_to_quat(back @ _body_rotation(el)))


def _turnable(site: _Site) -> bool:
    """A body whose frame can be turned about its hinge with all it holds turned back: every
    orientation it holds is a ``quat`` (or none)."""
    if site.joint is None or site.joint.get("type", "hinge") != "hinge" or site.body.get("quat") is None and \
            any(site.body.get(a) is not None for a in ("euler", "axisangle", "xyaxes", "zaxis")):
        return False
    return not any(c.get(a) is not None for c in site.body if c.tag in HELD
                   for a in ("euler", "axisangle", "xyaxes", "zaxis"))


@st.composite
def equivalent_rewrites(draw, mjcf_text: str) -> tuple[str, str]:
    """The MJCF rewritten without changing the robot, and what was done: a body's frame turned
    about its own hinge's axis with everything it holds turned back, or an inertial's
    ``diaginertia`` + ``quat`` written as the same ``fullinertia``."""
    root = ET.fromstring(mjcf_text)
    sites = _sites(root)
    turnable = [s for s in sites if _turnable(s)]
    inertials = [s for s in sites if _inertial(s.body) is not None]
    choices = (["turn"] if turnable else []) + (["fullinertia"] if inertials else [])
    if not choices:
        raise ValueError("nothing in this MJCF can be rewritten")
    if draw(st.sampled_from(choices)) == "turn":
        site = draw(st.sampled_from(turnable))
        axis = _vec(site.joint, "axis", [0, 0, 1])
        angle = draw(st.floats(5.0, 175.0)) * DEG * draw(st.sampled_from([1, -1]))
        turn = _rotation(axis, angle)
        _put(site.body, "quat", matrix_to_quat(_body_rotation(site.body) @ turn))
        for child in site.body:
            if child.tag in HELD:
                _turn_back(child, turn.T)
        what = f"body {site.body.get('name')} turned {math.degrees(angle):.4g}° about joint {site.joint.get('name')}'s axis, all it holds turned back"
    else:
        site = draw(st.sampled_from(inertials))
        inertial = _inertial(site.body)
        rot = _body_rotation(inertial)
        full = rot @ np.diag(_vec(inertial, "diaginertia", [0, 0, 0])) @ rot.T
        for attr in ("diaginertia", "quat"):
            inertial.attrib.pop(attr, None)
        _put(inertial, "fullinertia", [full[0, 0], full[1, 1], full[2, 2], full[0, 1], full[0, 2], full[1, 2]])
        what = f"body {site.body.get('name')}'s inertia written as fullinertia"
    return ET.tostring(root, encoding="unicode"), what
