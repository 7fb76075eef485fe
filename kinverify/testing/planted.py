"""Planted changes: hypothesis strategies that change one or two things in an MJCF (the one MuJoCo
writes from a URDF, :mod:`kinverify.testing.mjcf_pair`) as a person editing it by hand would, each
change recorded with its size.

    urdf = mesh_free_urdf(Path("robot.urdf").read_text())   # kinverify.testing.mjcf_pair
    mjcf = mujoco_mjcf(urdf)                       # MuJoCo's own conversion: the two files agree
    @given(planted_changes(mjcf))
    def test_one_finding_per_change(change):
        text, planted = change                     # the MJCF with the changes, what was planted

A :class:`Planted` names the joint or body it was planted on (MuJoCo keeps the URDF's names) and
its size in SI units, as file mode reports it: a turn or tilt in rad (the angle), an offset in m
(the vector's length), a mass in kg, a centre of mass in m (how far the rigid body's moved: a
body and those welded to it are one), a principal moment in kg·m², a range end in rad (m for a
slide), damping in N·m·s/rad (N·s/m). An axis flip reverses the range with it (the same physical
limits), and its size is the flip itself (π). ``frame_twist`` turns a hinge's body about the
joint's own axis (where a jointed body hangs below it: on a last link the turn may change nothing)
and ``slide_offset_along`` moves a slide's body along its axis, the range and any coupling left as
written: each is the joint's zero offset, of that size. :mod:`kinverify.testing.rewrites`
draws rewrites of the same robot that must give no error.
"""

from __future__ import annotations

import dataclasses
import math
import xml.etree.ElementTree as ET

import numpy as np
from hypothesis import strategies as st

from kinverify.model.transforms import axis_angle_to_matrix, matrix_to_quat, quat_to_matrix

FRAME_KINDS = (
    "axis_flip",
    "axis_tilt",
    "frame_offset_along",
    "frame_offset_across",
    "frame_turn",
    "frame_turn_twist",
    "frame_twist",
    "slide_offset_along",
)
KINDS = FRAME_KINDS + ("mass", "com", "inertia", "range", "damping")
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
    holds_joint: bool = False  # a body with a hinge or slide hangs below it


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

    worldbody = root.find("worldbody")
    assert worldbody is not None, "an MJCF MuJoCo wrote has a <worldbody>"
    for body in _bodies(worldbody):
        walk(body, False, None, None)
    for site in out:
        if site.parent is not None and site.joint is not None:
            site.parent.holds_joint = True
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
        slide = joint.get("type") == "slide"
        if kind == "slide_offset_along":
            return slide
        if kind == "frame_twist":  # on a last link, a turn about its axis may change nothing (an inertial symmetric about it)
            return not slide and site.holds_joint
        return not ((kind.startswith("frame_turn") or kind == "frame_twist") and slide)
    inertial = _inertial(site.body)
    if inertial is None or site.rigid is not None:  # a body welded to another is one rigid body with it: its own
        return False  # centre of mass and mass are not what is compared
    share = float(inertial.get("mass", "0")) / _group_mass(site.body)
    if kind == "inertia":  # alone in its rigid body: the moment planted is one of the rigid body's
        return share == 1.0 and bool(np.all(_vec(inertial, "diaginertia", [0, 0, 0]) > 0))
    # its centre of mass moves the rigid body's by its share of the mass; and its mass changes the
    # rigid body's, written to a few digits (1.03 kg is 1.03 ± 0.005): a body of a small share
    # (a 1 g drive link welded to its 1 kg thigh) changes it by less than the files can tell
    return share >= 0.25


def _welded(body: ET.Element) -> list[ET.Element]:
    """``body`` and the bodies welded to it (no joint between): one rigid body, as file mode compares it."""
    out = [body]
    for child in _bodies(body):
        if not any(j.tag == "freejoint" or j.tag == "joint" for j in child):
            out += _welded(child)
    return out


def _group_mass(body: ET.Element) -> float:
    return sum(float(i.get("mass", "0")) for b in _welded(body) if (i := b.find("inertial")) is not None)


# --- the changes --------------------------------------------------------------------------------


def _plant(draw, kind: str, site: _Site) -> Planted:
    body, joint = site.body, site.joint
    bname = body.get("name")
    if kind in JOINT_KINDS:
        assert joint is not None, "a joint kind is planted only where the site has a joint (_applicable)"
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
        if kind.startswith("frame_offset") or kind == "slide_offset_along":
            length = draw(st.floats(0.5, 20.0)) * 1e-3 * draw(st.sampled_from([1, -1]))
            local = axis * length if kind.endswith("along") else _perpendicular(axis, draw(st.floats(0, 2 * math.pi))) * length
            _put(body, "pos", _vec(body, "pos", [0, 0, 0]) + _body_rotation(body) @ local)
            return Planted(kind, jname, bname, abs(length), "m")
        if kind == "frame_twist":  # about the joint's own axis, its range and couplings left as written: a zero offset
            angle = draw(st.floats(1.0, 10.0)) * DEG * draw(st.sampled_from([1, -1]))
            _put(body, "quat", matrix_to_quat(_body_rotation(body) @ _rotation(axis, angle)))
            return Planted(kind, jname, bname, abs(angle), "rad")
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
        damping = float(joint.get("damping", "0"))
        change = damping * draw(st.floats(0.1, 1.0)) * draw(st.sampled_from([1, -0.5]))
        joint.set("damping", repr(damping + change))
        return Planted(kind, jname, None, abs(change), "N·s/m" if slide else "N·m·s/rad")
    inertial = _inertial(body)
    assert inertial is not None, "an inertial kind is planted only where the body has one (_applicable)"
    if kind == "mass":
        mass = float(inertial.get("mass", "0"))
        factor = 1 + draw(st.floats(0.05, 0.3)) * draw(st.sampled_from([1, -1]))
        inertial.set("mass", repr(mass * factor))
        return Planted(kind, None, bname, abs(mass * factor - mass), "kg")
    if kind == "com":  # the rigid body's centre of mass moves by the body's share of that
        length = draw(st.floats(1.0, 20.0)) * 1e-3
        direction = np.array([draw(st.floats(-1, 1)) for _ in range(3)]) + np.array([0, 0, 1e-3])
        _put(inertial, "pos", _vec(inertial, "pos", [0, 0, 0]) + direction / np.linalg.norm(direction) * length)
        return Planted(kind, None, bname, length * float(inertial.get("mass", "0")) / _group_mass(body), "m")
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
def planted_changes(
    draw, mjcf_text: str, kinds=KINDS, max_changes: int = 2, min_changes: int = 1, stacked: bool | None = None
) -> tuple[str, tuple[Planted, ...]]:
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
        pool = (
            above(kind, site)
            if on_parent
            else [(k, s) for k, s in options if (_slot(k), id(s.body)) != (_slot(kind), id(site.body))]
        )
        if pool:
            planted.append(_plant(draw, *draw(st.sampled_from(pool))))
    return ET.tostring(root, encoding="unicode"), tuple(planted)
