"""Rewrites of an MJCF that change nothing in the robot (hypothesis strategies): file mode must
find no error between the rewritten file and its URDF."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np
from hypothesis import strategies as st

from kinverify.model.transforms import matrix_to_quat
from kinverify.testing.planted import DEG, _body_rotation, _inertial, _put, _rotation, _Site, _sites, _vec


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
    if (
        site.joint is None
        or site.joint.get("type", "hinge") != "hinge"
        or site.body.get("quat") is None
        and any(site.body.get(a) is not None for a in ("euler", "axisangle", "xyaxes", "zaxis"))
    ):
        return False
    return not any(c.get(a) is not None for c in site.body if c.tag in HELD for a in ("euler", "axisangle", "xyaxes", "zaxis"))


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
        assert inertial is not None, "drawn from the sites with an inertial"
        rot = _body_rotation(inertial)
        full = rot @ np.diag(_vec(inertial, "diaginertia", [0, 0, 0])) @ rot.T
        for attr in ("diaginertia", "quat"):
            inertial.attrib.pop(attr, None)
        _put(inertial, "fullinertia", [full[0, 0], full[1, 1], full[2, 2], full[0, 1], full[0, 2], full[1, 2]])
        what = f"body {site.body.get('name')}'s inertia written as fullinertia"
    return ET.tostring(root, encoding="unicode"), what
