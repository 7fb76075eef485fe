"""The precision each file is written with, and the tolerance floors it implies.

A number written with many significant digits (5 or more: ``0.9238795``, ``2.96706``,
``1.19132``) or a rounded well-known angle (``1.571`` for π/2) was computed and then rounded
where it was written: its rounding error is at most half its last digit. Numbers written with
few digits (``0.333``, ``0.0825``, ``1``) are taken as exact: a designer's values. Two files
cannot be said to differ by less than the sum of their roundings, so file mode raises each
tolerance to this floor (never above a tolerance the user sets with ``--tolerance``): rounding is
reported as information, and a difference above the written precision still fails.

Kinematics, per frame: each rounded rotation on the frame's path from the base (a URDF joint's
``rpy`` or ``axis``, an MJCF body's ``quat``...) is off by at most 4 × its components' rounding
(quaternion components off by b each turn it by up to 4b), each rounded position by √3 × it, and
a rotation error moves a point ``r`` metres further out by ``r`` times it. Masses, inertias, centres
of mass, inertial orientations and joint limits: the coarsest rounding of each file.
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

LONG = 5  # significant digits from which a number is taken as computed, then rounded
_NUMBER = re.compile(r"^[+-]?(\d*)\.?(\d*)(?:[eE]([+-]?\d+))?$")
LABELS = {
    "relative": "masses and inertias",
    "com": "centres of mass",
    "inertial_angle": "inertial orientations",
    "limit": "joint limits",
    "angle": "frame orientations",
    "length": "frame positions",
}
POSE = ("quat", "xyaxes", "zaxis")  # unitless orientation attributes (MJCF)
DEGREE_POSE = ("euler", "axisangle")  # MJCF orientation attributes in <compiler angle> units


def quantum(text: str) -> tuple[float, int] | None:
    """(value of the last written digit, number of significant digits) of a written number."""
    hit = _NUMBER.match(text.strip())
    if not hit or not (hit[1] or hit[2]):
        return None
    whole, frac, exp = hit[1], hit[2], int(hit[3] or 0)
    return 10.0 ** (exp - len(frac)), len((whole + frac).lstrip("0"))


def rounding_of(word: str, scale: float = 1.0, angle: bool = False) -> float:
    """How far one written number may be from the value it stands for, in radians or metres
    (``scale`` converts it): half its last digit when it has many digits, the exact distance to a
    multiple of π/12 it rounds (``1.571``, ``0.785``), 0 for a number taken as exact."""
    found = quantum(word)
    if found is None:
        return 0.0
    q, digits = found
    try:
        value = float(word)
    except ValueError:
        return 0.0
    if value == 0:
        return 0.0
    if angle and scale == 1.0 and "." in word and 2 <= len(word.split(".")[1].split("e")[0]) <= 8:
        k = round(value / (math.pi / 12))
        exact = k * math.pi / 12
        if k and 1e-12 < abs(value - exact) <= q / 2:
            return abs(value - exact)
    return q / 2 * scale if digits >= LONG else 0.0


@dataclass
class Precision:
    """A file's written precision: per frame, the rotation [rad] and position [m] its path's
    rounding may account for (no lever arm); per category the largest rounding error a number
    may carry (``relative`` to the value for masses and inertias, absolute otherwise); an example
    of each."""

    file: str
    frames: dict[str, tuple[float, float]] = field(default_factory=dict)
    angle: float = 0.0  # coarsest single rotation bound (for the description)
    length: float = 0.0
    relative: float = 0.0
    com: float = 0.0
    inertial_angle: float = 0.0
    limit: float = 0.0
    examples: dict[str, str] = field(default_factory=dict)  # category -> a rounded number as written

    def note(self, category: str, q: float, word: str) -> None:
        if q > getattr(self, category):
            setattr(self, category, q)
            self.examples[category] = word

    def describe(self, categories=None) -> str:
        parts = [
            f"{LABELS[c]} to {_digits(self.examples[c], c)} ({self.examples[c]})"
            for c in categories or ("angle", "length", "relative", "com", "inertial_angle", "limit")
            if c in self.examples and getattr(self, c) > 0
        ]
        return f"the {self.file} writes " + ", ".join(parts) if parts else f"the {self.file} writes exact values"


def _digits(word: str, category: str) -> str:
    q, digits = quantum(word) or (1.0, 0)
    if category == "relative":
        return f"{digits} significant digits"
    return f"{max(0, round(-math.log10(q)))} decimals"


def _words(value: str | None) -> list[str]:
    return (value or "").split()


def _element(pose_words, position_words, scale_angle=1.0) -> tuple[float, float, str]:
    """(rotation bound, position bound, coarsest word) of one transform as written: components
    each off by up to b turn a quaternion by up to 4b; a position is off by up to √3·b."""
    rot, pos, word = 0.0, 0.0, ""
    for w in pose_words:
        b = rounding_of(w, scale_angle, angle=True)
        if 4 * b > rot:
            rot, word = 4 * b, w
    for w in position_words:
        b = rounding_of(w)
        if math.sqrt(3) * b > pos:
            pos = math.sqrt(3) * b
            word = word or w
    return rot, pos, word


def urdf_precision(urdf_text: str) -> Precision:
    root = ET.fromstring(urdf_text)
    out = Precision("URDF")
    by_child = {}
    for joint in root.findall("joint"):
        origin, axis, limit = joint.find("origin"), joint.find("axis"), joint.find("limit")
        pose = _words(origin.get("rpy")) if origin is not None else []
        rot, pos, word = _element(
            pose + _words(axis.get("xyz") if axis is not None else None), _words(origin.get("xyz")) if origin is not None else []
        )
        child, parent = joint.find("child"), joint.find("parent")
        if child is not None and parent is not None:
            by_child[child.get("link")] = (parent.get("link"), rot, pos)
            if word:
                out.note("angle" if rot >= pos else "length", max(rot, pos), word)
        if limit is not None:
            for w in _words(limit.get("lower")) + _words(limit.get("upper")):
                out.note("limit", rounding_of(w, angle=joint.get("type") != "prismatic"), w)
    for link in root.findall("link"):
        out.frames[link.get("name")] = _path(link.get("name"), by_child)  # type: ignore[index, arg-type]  # a URDF's names are checked on reading
        inertial = link.find("inertial")
        if inertial is None:
            continue
        origin = inertial.find("origin")
        if origin is not None:
            for w in _words(origin.get("xyz")):
                out.note("com", rounding_of(w), w)
            for w in _words(origin.get("rpy")):
                out.note("inertial_angle", rounding_of(w, angle=True), w)
        values = [(inertial.find("mass"), ("value",)), (inertial.find("inertia"), ("ixx", "iyy", "izz", "ixy", "ixz", "iyz"))]
        for el, attrs in values:
            for a in attrs if el is not None else ():
                _relative(out, el.get(a))  # type: ignore[union-attr]  # el is not None here
    return out


def _relative(out: Precision, word: str | None) -> None:
    if not word:
        return
    q = rounding_of(word)
    if q > 0:
        out.note("relative", q / abs(float(word)), word)


def _path(name: str, by_child: dict) -> tuple[float, float]:
    rot = pos = 0.0
    seen = set()
    while name in by_child and name not in seen:
        seen.add(name)
        name, r, p = by_child[name]
        rot, pos = rot + r, pos + p
    return rot, pos


def mjcf_precision(mjcf_text: str) -> Precision:
    root = ET.fromstring(mjcf_text)
    compiler = root.find("compiler")
    deg = math.pi / 180 if compiler is None or compiler.get("angle", "degree") == "degree" else 1.0
    out = Precision("MJCF")

    def pose_words(el) -> tuple[list[str], list[str]]:
        words = [w for a in POSE for w in _words(el.get(a))]
        euler = _words(el.get("euler")) + _words(el.get("axisangle"))[3:]
        return words, euler

    def element(el) -> tuple[float, float, str]:
        plain, euler = pose_words(el)
        r1, p1, w1 = _element(plain, _words(el.get("pos")))
        r2, _, w2 = _element(euler, [], deg)
        return r1 + r2, p1, w1 or w2

    def walk(body, rot: float, pos: float) -> None:
        r, p, word = element(body)
        for joint in body.findall("joint"):
            jr, jp, jw = _element(_words(joint.get("axis")), _words(joint.get("pos")))
            r, p, word = r + jr, p + jp, word or jw
            hinge = joint.get("type", "hinge") == "hinge"
            for w in _words(joint.get("range")):
                out.note("limit", rounding_of(w, deg if hinge else 1.0, angle=hinge), w)
        rot, pos = rot + r, pos + p
        if word:
            out.note("angle" if r >= p else "length", max(r, p), word)
        if body.get("name") and body.tag == "body":
            out.frames[body.get("name")] = (rot, pos)
        for site in body.findall("site"):
            sr, sp, _ = element(site)
            if site.get("name"):
                out.frames.setdefault(site.get("name"), (rot + sr, pos + sp))
        for inertial in body.findall("inertial"):
            for w in _words(inertial.get("pos")):
                out.note("com", rounding_of(w), w)
            plain, euler = pose_words(inertial)
            for w in plain:
                out.note("inertial_angle", rounding_of(w, angle=True), w)
            for w in euler:
                out.note("inertial_angle", rounding_of(w, deg, angle=True), w)
            for w in _words(inertial.get("mass")) + _words(inertial.get("diaginertia")) + _words(inertial.get("fullinertia")):
                _relative(out, w)
        for child in body:
            if child.tag in ("body", "frame"):  # a <frame> places what it holds (MuJoCo writes one for a fused link)
                walk(child, rot, pos)

    for world in root.findall("worldbody"):
        for body in world:
            if body.tag in ("body", "frame"):
                walk(body, 0.0, 0.0)
        for site in world.findall("site"):
            sr, sp, _ = element(site)
            if site.get("name"):
                out.frames.setdefault(site.get("name"), (sr, sp))  # type: ignore[arg-type]  # checked above
    for default in root.iter("default"):  # class defaults: joint ranges written once for many joints
        for joint in default.findall("joint"):
            hinge = joint.get("type", "hinge") == "hinge"
            for w in _words(joint.get("range")):
                out.note("limit", rounding_of(w, deg if hinge else 1.0, angle=hinge), w)
    return out


@dataclass(frozen=True)
class Floors:
    """Tolerance floors from both files' written precision (0 where both are exact): per frame
    for the kinematics (``frames``: frame -> (position m, rotation rad)), and overall."""

    frames: dict[str, tuple[float, float]] = field(default_factory=dict)
    dof: int = 1
    reach: float = 0.0
    limit: float = 0.0  # rad or m
    relative: float = 0.0  # masses and inertia tensors, relative to the value
    com: float = 0.0  # m
    inertial_angle: float = 0.0  # rad

    def frame(self, name: str) -> tuple[float, float]:
        return self.frames.get(name, (0.0, 0.0))

    def check(self, prop: str, frame: str) -> float:
        """Floor of a kinematics check of ``prop`` at ``frame``."""
        pos, rot = self.frame(frame)
        n = math.sqrt(max(self.dof, 1))
        return {
            "fk.position": pos,
            "fk.rotation": rot,
            "jacobian.linear": n * (rot * self.reach + 2 * pos),
            "jacobian.angular": n * rot,
        }.get(prop, 0.0)

    @property
    def kinematic(self) -> tuple[float, float]:
        """The largest (position, rotation) floor over the frames."""
        if not self.frames:
            return 0.0, 0.0
        return max(p for p, _ in self.frames.values()), max(r for _, r in self.frames.values())

    @property
    def dynamics(self) -> float:
        """Relative floor of the joint-space dynamics (mass matrix, forces)."""
        pos, rot = self.kinematic
        return self.relative + 2 * self.inertial_angle + 2 * rot + (pos / self.reach if self.reach > 0 else 0.0)


def floors(a: Precision, b: Precision, pairs, reach: dict[str, float], dof: int) -> Floors:
    """Floors for the frame pairs ``pairs`` ((a-file name, b-file name, ...)), a frame ``reach``
    metres out (keyed by the a-file's name), with ``dof`` compared joints."""
    frames = {}
    for pair in pairs:
        fa, fb = pair[0], pair[1]
        ra, pa = a.frames.get(fa, (0.0, 0.0))
        rb, pb = b.frames.get(fb, (0.0, 0.0))
        rot = ra + rb
        frames[fa] = (pa + pb + rot * reach.get(fa, 0.0), rot)
    return Floors(
        frames,
        dof,
        max(reach.values(), default=0.0),
        a.limit + b.limit,
        a.relative + b.relative,
        a.com + b.com,
        4 * (a.inertial_angle + b.inertial_angle),
    )
