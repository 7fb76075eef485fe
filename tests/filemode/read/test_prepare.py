"""The texts prepared for the libraries, pinned element by element on tiny XML: continuous joints
made unlimited revolute ones, MJCF free bases fixed at the origin (keyframes gone), and joints
locked (URDF: fixed; MJCF: removed with what refers to them)."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from kinverify.filemode.read.prepare import (
    continuous_joints,
    fix_free_bases,
    lock_mjcf_joints,
    lock_urdf_joints,
    prepare_urdf,
)

URDF = """<robot name="r">
  <link name="a"/><link name="b"/><link name="c"/><link name="d"/>
  <joint name="spin" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>
  <joint name="wheel" type="continuous"><parent link="b"/><child link="c"/>
    <limit effort="5" velocity="2"/></joint>
  <joint name="elbow" type="revolute"><parent link="c"/><child link="d"/><origin xyz="0 0 1"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="3" velocity="1"/><dynamics damping="0.1"/>
    <mimic joint="spin"/></joint>
</robot>"""


def joints(text: str) -> dict[str, ET.Element]:
    return {j.get("name"): j for j in ET.fromstring(text).iter("joint")}


def test_continuous_joints_are_named():
    assert continuous_joints(URDF) == {"spin", "wheel"}
    assert continuous_joints('<robot name="r"><joint name="x" type="revolute"/></robot>') == set()
    assert continuous_joints('<robot name="r"><actuator name="m" type="continuous"/></robot>') == set()  # not a joint


def test_a_continuous_joint_becomes_an_unlimited_revolute_one():
    text = prepare_urdf(URDF)
    assert isinstance(text, str)
    out = joints(text)
    spin, wheel, elbow = out["spin"], out["wheel"], out["elbow"]
    assert spin.get("type") == wheel.get("type") == elbow.get("type") == "revolute"
    assert spin.find("limit").attrib == {"effort": "0", "velocity": "0", "lower": "-1e308", "upper": "1e308"}
    assert len(spin.findall("limit")) == 1
    assert wheel.find("limit").attrib == {"effort": "5", "velocity": "2", "lower": "-1e308", "upper": "1e308"}
    assert elbow.find("limit").attrib == {"lower": "-1", "upper": "1", "effort": "3", "velocity": "1"}


def test_a_urdf_without_continuous_joints_is_returned_as_written():
    text = '<robot name="r">\n  <joint name="x" type="revolute"/>\n</robot>'
    assert prepare_urdf(text) is text


MJCF = """<mujoco>
  <worldbody>
    <body name="base" pos="1 2 3" quat="0 1 0 0" euler="1 0 0" axisangle="0 0 1 1" xyaxes="1 0 0 0 1 0" zaxis="0 0 1">
      <freejoint/>
      <joint name="hinge" type="hinge"/>
      <body name="inner" pos="0 0 1"><freejoint/></body>
    </body>
    <body pos="4 5 6"><joint name="f2" type="free"/></body>
    <body name="arm" pos="7 8 9"><joint name="slide" type="slide"/></body>
  </worldbody>
  <keyframe><key qpos="0"/></keyframe>
</mujoco>"""


def test_each_top_level_free_body_is_fixed_at_the_world_origin():
    text, fixed = fix_free_bases(MJCF)
    assert fixed == ["base", "(unnamed body)"] and isinstance(text, str)
    root = ET.fromstring(text)
    base, unnamed, arm = root.find("worldbody").findall("body")
    assert base.attrib == {"name": "base"} and [c.tag for c in base] == ["joint", "body"]
    assert base.find("joint").get("name") == "hinge"
    assert base.find("body").get("pos") == "0 0 1" and base.find("body/freejoint") is not None  # not top level
    assert unnamed.attrib == {} and len(unnamed) == 0
    assert arm.get("pos") == "7 8 9" and arm.find("joint").get("name") == "slide"
    assert root.find("keyframe") is None


def test_an_mjcf_without_free_base_is_returned_as_written():
    text = '<mujoco><worldbody><body name="a" pos="1 0 0"><joint name="j"/></body></worldbody><keyframe/></mujoco>'
    assert fix_free_bases(text) == (text, [])
    assert fix_free_bases(text)[0] is text


def test_locked_urdf_joints_become_fixed_without_motion_elements():
    text = lock_urdf_joints(URDF, ["elbow", "nothere"])
    assert isinstance(text, str)
    out = joints(text)
    elbow = out["elbow"]
    assert elbow.get("type") == "fixed"
    assert [c.tag for c in elbow] == ["parent", "child", "origin"]
    assert out["spin"].get("type") == "continuous" and out["spin"].find("axis") is not None
    assert out["wheel"].find("limit") is not None
    assert lock_urdf_joints(URDF, []) is URDF


LOCK = """<mujoco>
  <worldbody>
    <body name="a"><joint name="j1"/><joint name="j2"/><joint name="j3"/>
      <body name="b"><joint name="j4"/></body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="t1"><joint joint="j1" coef="1"/></fixed>
    <fixed name="t2"><joint joint="j1" coef="1"/><joint joint="j2" coef="1"/></fixed>
    <spatial name="t3"><site site="s"/><joint joint="j1"/></spatial>
  </tendon>
  <actuator>
    <motor name="m1" joint="j1"/><motor name="m2" joint="j2"/><motor name="m3" tendon="t1"/>
    <motor name="m4" tendon="t2"/><motor name="m5" site="s"/>
  </actuator>
  <sensor><jointpos name="s1" joint="j3"/><jointpos name="s2" joint="j2"/><tendonpos name="s3" tendon="t1"/></sensor>
  <equality>
    <joint name="e1" joint1="j2" joint2="j1"/><joint name="e2" joint1="j2" joint2="j4"/><joint name="e5" joint1="j3" joint2="j2"/>
    <joint name="j1"/>
    <weld name="e3" body1="a"/><connect name="e4" jointinparent="j3"/>
  </equality>
  <keyframe><key qpos="0 0 0 0"/></keyframe>
</mujoco>"""


def test_locked_mjcf_joints_go_with_what_refers_to_them():
    text = lock_mjcf_joints(LOCK, {"j1", "j3"})
    assert isinstance(text, str)  # text, as the libraries load it
    root = ET.fromstring(text)
    assert [j.get("name") for b in root.iter("body") for j in b.findall("joint")] == ["j2", "j4"]
    tendon = root.find("tendon")
    assert [t.get("name") for t in tendon] == ["t2", "t3"]  # t1 had only j1: gone; spatial t3 kept
    assert [e.get("joint") for e in tendon.find("fixed")] == ["j2"]
    assert [e.tag for e in tendon.find("spatial")] == ["site"]
    assert [a.get("name") for a in root.find("actuator")] == ["m2", "m4", "m5"]
    assert [s.get("name") for s in root.find("sensor")] == ["s2"]
    assert [e.get("name") for e in root.find("equality")] == [
        "e2",
        "j1",
        "e3",
    ]  # e1 names j1; a joint= "j1" element with no ref kept
    assert root.find("keyframe") is None


def test_locking_no_mjcf_joint_returns_the_text_as_written():
    assert lock_mjcf_joints(LOCK, []) is LOCK
    kept = ET.fromstring(lock_mjcf_joints(LOCK, ["absent"]))
    assert kept.find("keyframe") is None and len(kept.find("actuator")) == 5 and len(kept.find("tendon")) == 3


def test_every_continuous_joint_is_prepared_wherever_it_stands():
    text = URDF.replace('name="spin" type="continuous"', 'name="spin" type="revolute"')
    out = joints(prepare_urdf(text))  # a revolute joint first, then a continuous one
    assert out["wheel"].get("type") == "revolute" and out["wheel"].find("limit").get("upper") == "1e308"
    assert out["spin"].find("limit") is None
