"""A URDF and the MJCF MuJoCo writes from it: the pair the planted-change strategies
(:mod:`kinverify.testing.planted`) change, whose two files agree before anything is planted."""

from __future__ import annotations

import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np


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
    assert body is not None, "the generated MJCF has a body under <worldbody>"
    body.insert(0, ET.Element("freejoint", name="root"))
    return ET.tostring(tree, encoding="unicode")
