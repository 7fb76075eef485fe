"""Test pairs for file mode: a generated URDF/MJCF pair (models/*.toml) and deliberate edits of one
file, each standing for what real pairs differ by. Generated in the test (nothing large is
committed); each edit is a text edit of the XML, as a maintainer would make it."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from kinverify.filemode.pipeline import FILE_SUITES
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import load_spec
from tests.paths import MODELS
import mujoco

# File mode's suites but the drawing of both files: the pictures suite renders in a child process
# (a fresh interpreter, about 0.9 s of CPU per run) and makes no check and no finding; tests whose
# assertions are about what file mode compares and finds leave it out (the drawing is tested in
# tests/suites/test_pictures.py and tests/report/test_filemode_report.py).
NO_PICTURES = [s for s in FILE_SUITES if s != "pictures"]


def ignored_by_drake(finding) -> bool:
    """Drake's MJCF (or URDF) parser saying which elements it ignores: an info for what nothing
    compared depends on (timestep, lights, sensors, frictionloss...), a warning for what is compared
    through it (sites), tested in their own right."""
    return finding.kind in ("parser_refused", "parser_ignores") and "elements" in finding.values


def generated_pair(model: str = "panda") -> tuple[str, str]:
    spec = load_spec(MODELS / f"{model}.toml")
    return generate_urdf(spec), generate_mjcf(spec)


def sub_once(pattern: str, repl, text: str) -> str:
    new, n = re.subn(pattern, repl, text, count=1, flags=re.S)
    assert n == 1, f"pattern not found: {pattern}"
    return new


def body_attr(mjcf: str, body: str, attr: str, fn) -> str:
    return sub_once(rf'(<body name="{body}"[^>]*? {attr}=")([^"]*)(")', lambda m: m[1] + fn(m[2]) + m[3], mjcf)


def joint_attr(text: str, joint: str, attr: str, fn) -> str:
    return sub_once(rf'(<joint name="{joint}"[^>]*? {attr}=")([^"]*)(")', lambda m: m[1] + fn(m[2]) + m[3], text)


def nums(fn):
    return lambda s: " ".join(repr(float(v)) for v in fn([float(x) for x in s.split()]))


def quat_z(angle: float) -> str:
    return f"{math.cos(angle / 2)!r} 0 0 {math.sin(angle / 2)!r}"


# --- the world and the joints' conventions ---------------------------------------------------


def turned_world(urdf, mjcf, angle=math.pi / 4, xyz=None):
    """The MJCF mounts the robot turned about z (and moved by ``xyz``) in its world."""
    pose = f'quat="{quat_z(angle)}"' + (f' pos="{" ".join(repr(float(v)) for v in xyz)}"' if xyz is not None else "")
    return urdf, mjcf.replace('<body name="world_mount">', f'<body name="world_mount" {pose}>', 1)


def turned_half(urdf, mjcf):
    """The world turned by π about z, as two public industrial-arm pairs do."""
    return turned_world(urdf, mjcf, math.pi)


def offset_zero(urdf, mjcf, joint="panda_joint4", offset=0.1):
    """The MJCF's joint zero sits ``offset`` further (``ref``), its range in its own coordinates."""
    mjcf = joint_attr(mjcf, joint, "range", nums(lambda v: [x + offset for x in v]))
    return urdf, sub_once(rf'(<joint name="{joint}" )', lambda m: m[1] + f'ref="{offset!r}" ', mjcf)


def flipped_axis(urdf, mjcf, joint="panda_joint3"):
    """The MJCF's axis reversed (its range reversed with it: the same physical limits)."""
    mjcf = joint_attr(mjcf, joint, "range", nums(lambda v: [-v[1], -v[0]]))
    return urdf, joint_attr(mjcf, joint, "axis", nums(lambda v: [-x for x in v]))


def renamed_joints(urdf, mjcf):
    """The MJCF names its joints J1...J7 (and its actuators and sensors refer to them so)."""
    return urdf, re.sub(r'"panda_joint(\d)"', r'"J\1"', mjcf)


# --- links and frames -------------------------------------------------------------------------

TOOL = dict(mass=0.4, com=np.array([0.01, 0.0, 0.03]), inertia=np.diag([2e-4, 3e-4, 1e-4]))


def merged_fixed_link(urdf, mjcf):
    """The URDF keeps a tool as a fixed link on link 3 of arm3; the MJCF merges its mass into link3."""
    t = TOOL
    ixx, iyy, izz = (float(x) for x in np.diag(t["inertia"]))
    link = (
        f'<link name="tool"><inertial><origin xyz="{" ".join(repr(float(x)) for x in t["com"])}" rpy="0 0 0"/>'
        f'<mass value="{t["mass"]!r}"/><inertia ixx="{ixx!r}" iyy="{iyy!r}" izz="{izz!r}" ixy="0" ixz="0" iyz="0"/>'
        "</inertial></link>"
        '<joint name="tool_mount" type="fixed"><parent link="link3"/><child link="tool"/>'
        '<origin xyz="0 0 0" rpy="0 0 0"/></joint>'
    )
    urdf = urdf.replace("</robot>", link + "</robot>")

    def merge(match):
        mass, com = float(match["mass"]), np.array([float(x) for x in match["pos"].split()])
        full = [float(x) for x in match["full"].split()]
        inertia = np.array([[full[0], full[3], full[4]], [full[3], full[1], full[5]], [full[4], full[5], full[2]]])
        total = mass + t["mass"]
        c = (mass * com + t["mass"] * t["com"]) / total
        i = sum(
            ii + mm * ((r @ r) * np.eye(3) - np.outer(r, r))
            for mm, cc, ii in ((mass, com, inertia), (t["mass"], t["com"], t["inertia"]))
            for r in [cc - c]
        )
        full = " ".join(repr(float(x)) for x in (i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]))
        return f'<inertial pos="{" ".join(repr(float(x)) for x in c)}" mass="{float(total)!r}" fullinertia="{full}"/>'

    return urdf, sub_once(
        r'(?<=<body name="link3" )(.*?)<inertial pos="(?P<pos>[^"]*)" mass="(?P<mass>[^"]*)" '
        r'fullinertia="(?P<full>[^"]*)"/>',
        lambda m: m[1] + merge(m),
        mjcf,
    )


def extra_flange(urdf, mjcf):
    """The URDF has a massless tool flange 16.5 mm beyond its flange; the MJCF has none."""
    flange = (
        '<link name="tool_flange"/><joint name="tool_flange_mount" type="fixed"><parent link="flange"/>'
        '<child link="tool_flange"/><origin xyz="0 0 0.0165" rpy="0 0 0"/></joint>'
    )
    return urdf.replace("</robot>", flange + "</robot>"), mjcf


def gripper_in_mjcf(urdf, mjcf):
    """The MJCF has a one-finger gripper on link 7 that the URDF lacks."""
    gripper = (
        '<body name="gripper_finger" pos="0 0 0.05"><joint name="gripper_joint" type="slide" axis="0 1 0" '
        'range="0 0.04"/><inertial pos="0 0 0.02" mass="0.1" diaginertia="1e-5 1e-5 1e-5"/></body>'
    )
    return urdf, sub_once(r'(<body name="panda_link7"[^>]*>)', lambda m: m[1] + gripper, mjcf)


# --- values -----------------------------------------------------------------------------------


def rounded_mjcf(urdf, mjcf):
    """The MJCF written back by MuJoCo (MjSpec.to_xml: 6 significant digits, inertias as
    principal moments and a quaternion), as machine-converted files are."""
    return urdf, mujoco.MjSpec.from_string(mjcf).to_xml()


def degrees_mjcf(urdf, mjcf):
    """The MJCF drops ``<compiler angle="radian">``: MuJoCo reads its ranges in degrees."""
    return urdf, mjcf.replace(' angle="radian"', "", 1)


def grams_mjcf(urdf, mjcf):
    """The MJCF's masses written in grams."""
    return urdf, re.sub(r'(<inertial [^>]*mass=")([^"]*)(")', lambda m: m[1] + repr(float(m[2]) * 1000) + m[3], mjcf)


def heavier_link(urdf, mjcf):
    """The URDF's panda_link4 is 20 % heavier (its inertia tensor unchanged)."""
    return sub_once(
        r'(<link name="panda_link4">.*?<mass value=")([^"]*)(")', lambda m: m[1] + repr(1.2 * float(m[2])) + m[3], urdf
    ), mjcf


def swapped_inertia(urdf, mjcf):
    """The MJCF's panda_link3 fullinertia with x and y exchanged (same moments, axes swapped)."""

    def swap(v):
        ixx, iyy, izz, ixy, ixz, iyz = v
        return [iyy, ixx, izz, ixy, iyz, ixz]

    return urdf, sub_once(r'(<body name="panda_link3".*?fullinertia=")([^"]*)(")', lambda m: m[1] + nums(swap)(m[2]) + m[3], mjcf)


def upper_limit(urdf, mjcf):
    """The URDF lets panda_joint2 go 0.2 rad further up."""
    return sub_once(
        r'(<joint name="panda_joint2".*?<limit [^>]*upper=")([^"]*)(")', lambda m: m[1] + repr(float(m[2]) + 0.2) + m[3], urdf
    ), mjcf


def friction_added(urdf, mjcf):
    """The MJCF gives panda_joint5 0.3 N·m of Coulomb friction (frictionloss) the URDF lacks."""
    return urdf, joint_attr(mjcf, "panda_joint5", "frictionloss", lambda v: "0.3")


def moved_axis(urdf, mjcf):
    """The MJCF's panda_link3 (and joint 3's axis with it) 1 mm further along x."""
    return urdf, body_attr(mjcf, "panda_link3", "pos", nums(lambda v: [v[0] + 1e-3, v[1], v[2]]))


def slide_joint(urdf, mjcf):
    """The MJCF makes panda_joint7 prismatic."""
    return urdf, joint_attr(mjcf, "panda_joint7", "type", lambda t: "slide")


def write_pair(folder: Path, urdf: str, mjcf: str) -> tuple[str, str]:
    (folder / "robot.urdf").write_text(urdf)
    (folder / "robot.xml").write_text(mjcf)
    return str(folder / "robot.urdf"), str(folder / "robot.xml")


def _quat_mul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ]
    )


def reframed_body(mjcf: str, body: str, angle: float) -> str:
    """The MJCF with ``body``'s frame turned by ``angle`` about its own z axis (the joint axis in a
    generated file) and everything written in that frame turned back: the same robot, another
    choice of link frame, as a maintainer writing the file by hand might make."""
    root = ET.fromstring(mjcf)
    el = next(b for b in root.iter("body") if b.get("name") == body)
    q = np.array([math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)])
    c, s = math.cos(angle), math.sin(angle)
    back = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])  # R⁻¹: body coordinates in the new frame
    old = np.array([float(x) for x in el.get("quat", "1 0 0 0").split()])
    el.set("quat", " ".join(repr(float(x)) for x in _quat_mul(old, q)))
    fmt = lambda v: " ".join(repr(float(x)) for x in v)  # noqa: E731
    for child in el:
        for attr in ("pos", "axis"):
            if child.get(attr):
                child.set(attr, fmt(back @ np.array([float(x) for x in child.get(attr).split()])))
        if child.get("fromto"):
            v = np.array([float(x) for x in child.get("fromto").split()])
            child.set("fromto", fmt(np.concatenate([back @ v[:3], back @ v[3:]])))
        if child.tag in ("body", "site") or (child.tag == "inertial" and child.get("quat")):
            qc = np.array([float(x) for x in child.get("quat", "1 0 0 0").split()])
            child.set("quat", fmt(_quat_mul(q * [1, -1, -1, -1], qc)))
        if child.tag == "inertial" and child.get("fullinertia"):
            xx, yy, zz, xy, xz, yz = (float(x) for x in child.get("fullinertia").split())
            i = back @ np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]) @ back.T
            child.set("fullinertia", fmt([i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]))
    return ET.tostring(root, encoding="unicode")


def suspended(mjcf: str, body: str, mass: float) -> str:
    """``body`` hung in the MJCF from a new body ``suspension`` (``mass`` kg) on a slide joint the
    URDF lacks, at the same place: as a mobile base's MJCF hangs its wheels from suspensions."""
    root = ET.fromstring(mjcf)
    parent = next(p for p in root.iter() for c in p if c.tag == "body" and c.get("name") == body)
    child = next(c for c in parent if c.tag == "body" and c.get("name") == body)
    holder = ET.Element("body", {"name": "suspension", "pos": child.get("pos", "0 0 0")})
    ET.SubElement(holder, "inertial", {"pos": "0 0 -0.02", "mass": repr(mass), "diaginertia": "1 1 1"})
    ET.SubElement(holder, "joint", {"name": "suspension_joint", "type": "slide", "axis": "0 0 1", "range": "-0.005 0.005"})
    child.set("pos", "0 0 0")
    parent.insert(list(parent).index(child), holder)
    parent.remove(child)
    holder.append(child)
    return ET.tostring(root, encoding="unicode")


def small_usda(
    tmp_path, name: str, header: str = "", body1: str = "/r/b1", pos0: str = "(0, 0, 0.1)", art: bool = True, extra: str = ""
) -> str:
    """A two-body USD robot (a fixed root body, a revolute joint ``j1`` to the second) written as
    ``NAME.usda`` in ``tmp_path``: its path. ``header``, ``body1``, ``pos0``, ``art``, ``extra``: the
    pieces tests change."""
    api = '"PhysicsRigidBodyAPI", "PhysicsMassAPI"' + (', "PhysicsArticulationRootAPI"' if art else "")
    text = f'''#usda 1.0
(
    upAxis = "Z"{header}
)
def Xform "r"
{{
    def Xform "b0" (apiSchemas = [{api}])
    {{
        float physics:mass = 1
    }}
    def Xform "b1" (apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsMassAPI"])
    {{
        float physics:mass = 2
    }}
    def PhysicsFixedJoint "root"
    {{
        rel physics:body1 = </r/b0>
    }}
    def PhysicsRevoluteJoint "j1"
    {{
        uniform token physics:axis = "Z"
        rel physics:body0 = </r/b0>
        rel physics:body1 = <{body1}>
        point3f physics:localPos0 = {pos0}
    }}
    {extra}
}}
'''
    path = tmp_path / f"{name}.usda"
    path.write_text(text)
    return str(path)
