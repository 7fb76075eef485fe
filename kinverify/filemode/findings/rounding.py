"""Recognising rounded constants: 1.5708 for π/2, 2.96706 for 170°, a limit cut to fewer decimals."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from fractions import Fraction


# Angles people write in model files: multiples of 15° (π/12) and whole degrees.
def _label(k: int) -> str:

    f = Fraction(k, 12)
    num = {1: "", -1: "-"}.get(f.numerator, str(f.numerator))
    return f"{num}π" + (f"/{f.denominator}" if f.denominator > 1 else "")


_NICE = [(k * math.pi / 12, _label(k)) for k in range(-24, 25) if k]


def rounded_from(x: float, y: float) -> dict | None:
    """If one value is the other rounded to fewer decimals, say which, else None."""
    for exact, rounded in ((x, y), (y, x)):
        for n in range(1, 9):
            if abs(round(exact, n) - rounded) < 1e-12 and exact != rounded:
                return {"exact": exact, "rounded": rounded, "decimals": n}
    return None


def nice_constant(value: float, text: str) -> tuple[tuple[float, str], int] | None:
    """The constant ``text`` (as written, ``value``) rounds, with the number of decimals, or None."""
    decimals = len(text.split(".")[1]) if "." in text and "e" not in text.lower() else 0
    if decimals < 3 or decimals > 8 or value == 0:
        return None
    candidates = list(_NICE) + [(math.radians(d), f"{d}°") for d in range(-360, 361) if d]
    for exact, label in candidates:
        if abs(round(exact, decimals) - value) < 1e-12 and abs(exact - value) > 1e-12:
            return (exact, label), decimals
    return None


def rounded_constants(urdf_text: str, mjcf_text: str):
    """Yield (file, joint-or-body, written text, (exact, label), decimals) for rounded angles in
    URDF joint origins (rpy) and MJCF body orientations (euler, axisangle, in radians)."""
    for joint in ET.fromstring(urdf_text).iter("joint"):
        origin = joint.find("origin")
        for word in origin.get("rpy", "").split() if origin is not None else []:
            hit = _try(word)
            if hit:
                yield ("URDF", joint.get("name"), word, *hit)
    root = ET.fromstring(mjcf_text)
    compiler = root.find("compiler")
    if (compiler.get("angle", "degree") if compiler is not None else "degree") == "degree":
        return  # MJCF angles in degrees (MuJoCo's default, also without <compiler>): whole numbers are exact
    for body in root.iter("body"):
        hit = _quat(body.get("quat", ""))
        if hit:
            yield ("MJCF", body.get("name"), f'quat="{body.get("quat")}"', *hit)
        for attr in ("euler", "axisangle"):
            words = body.get(attr, "").split()
            for word in words[3:] if attr == "axisangle" else words:
                hit = _try(word)
                if hit:
                    yield ("MJCF", body.get("name"), word, *hit)


def _try(word: str):
    try:
        value = float(word)
    except ValueError:
        return None
    return nice_constant(value, word)


def _quat(text: str):
    """A written quaternion whose rotation angle is a rounded nice constant."""
    words = text.split()
    try:
        w, x, y, z = (float(v) for v in words)
    except ValueError:
        return None
    decimals = max((len(v.split(".")[1]) if "." in v else 0) for v in words)
    if not 3 <= decimals <= 8:
        return None
    angle = 2 * math.atan2(math.sqrt(x * x + y * y + z * z), abs(w))
    for exact, label in _NICE:
        if 1e-12 < abs(angle - abs(exact)) < 4 * 10.0**-decimals:
            return (abs(exact), label.lstrip("-")), decimals
    return None
