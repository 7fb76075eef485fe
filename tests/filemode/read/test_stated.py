"""What each file states: MJCF attributes resolved through default classes as MuJoCo does
(own, else class, else nearest childclass, else "main", each class inheriting its enclosing ones),
URDF ``<dynamics>``/``<limit>`` and a continuous joint stating "no limits". Each rule pinned by
the smallest XML where it and its nearest wrong variant disagree."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from kinverify.filemode.read.stated import (
    attribute,
    class_defaults,
    default_chain,
    mjcf_joint_values,
    unset,
    urdf_joint_values,
    urdf_links_without_inertial,
)

MJCF = """<mujoco>
  <default>
    <joint damping="1"/>
    <default class="arm">
      <joint armature="2"/>
      <default class="wrist"><geom size="1"/></default>
    </default>
    <default class="hand"><joint frictionloss="3"/></default>
  </default>
  <worldbody>
    <body name="b0" childclass="arm">
      <joint name="j0"/>
      <body name="b1">
        <joint name="j1" class="hand"/>
        <body name="b2" childclass="wrist"><joint name="j2" damping="5"/></body>
      </body>
    </body>
    <body name="b3"><joint name="j3" limited="true"/><joint/></body>
    <body name="b4" childclass="nowhere"><joint name="j4" range="0 1"/></body>
  </worldbody>
</mujoco>"""


def parsed(text: str = MJCF):
    root = ET.fromstring(text)
    parents = {child: parent for parent in root.iter() for child in parent}
    joints = {j.get("name"): j for j in root.iter("joint") if j.get("name")}
    return root, parents, joints


def test_class_defaults_chain_nearest_first_and_named_main_at_the_top():
    root, _, _ = parsed()
    assert class_defaults(root, "joint") == {
        "main": [{"damping": "1"}],
        "arm": [{"armature": "2"}, {"damping": "1"}],
        "wrist": [{"armature": "2"}, {"damping": "1"}],  # states no joint itself: inherits arm's chain
        "hand": [{"frictionloss": "3"}, {"damping": "1"}],
    }
    assert class_defaults(root, "geom") == {"main": [], "arm": [], "wrist": [{"size": "1"}], "hand": []}
    assert class_defaults(ET.fromstring("<mujoco/>"), "joint") == {}


def test_default_chain_class_else_nearest_childclass_else_main():
    root, parents, j = parsed()
    defaults = class_defaults(root, "joint")
    assert default_chain(j["j0"], parents, defaults) == defaults["arm"]  # the body's childclass
    assert default_chain(j["j1"], parents, defaults) == defaults["hand"]  # its own class first
    assert default_chain(j["j2"], parents, defaults) == defaults["wrist"]  # nearest childclass, not arm
    assert default_chain(j["j3"], parents, defaults) == [{"damping": "1"}]  # no class anywhere: main
    assert default_chain(j["j4"], parents, defaults) == []  # an unknown class: nothing inherited
    assert default_chain(ET.fromstring("<joint/>"), {}, {}) == []


def test_attribute_own_else_nearest_class():
    root, parents, j = parsed()
    defaults = class_defaults(root, "joint")
    assert attribute(j["j2"], "damping", parents, defaults) == "5"  # own beats the default's 1
    assert attribute(j["j0"], "damping", parents, defaults) == "1"  # from main, through arm
    assert attribute(j["j0"], "armature", parents, defaults) == "2"
    assert attribute(j["j1"], "armature", parents, defaults) is None  # hand does not inherit arm
    assert attribute(j["j1"], "frictionloss", parents, defaults) == "3"
    root = ET.fromstring(
        '<mujoco><default><joint damping="1"/><default class="a"><joint damping="2"/>'
        '</default></default><worldbody><body><joint name="x" class="a"/></body></worldbody></mujoco>'
    )
    _, parents, j = parsed(ET.tostring(root, encoding="unicode"))
    assert attribute(j["x"], "damping", parents, class_defaults(root, "joint")) == "2"  # nearest class first


def test_mjcf_joint_values_named_joints_outside_defaults():
    root, _, _ = parsed()
    assert mjcf_joint_values(root) == {
        "j0": frozenset({"damping", "armature"}),
        "j1": frozenset({"damping", "friction"}),
        "j2": frozenset({"damping", "armature"}),
        "j3": frozenset({"damping", "range"}),  # limited states the range
        "j4": frozenset({"range"}),
    }
    bare = ET.fromstring('<mujoco><worldbody><body><joint name="free"/></body></worldbody></mujoco>')
    assert mjcf_joint_values(bare) == {"free": frozenset()}
    assert mjcf_joint_values(ET.fromstring('<joint name="root" damping="1"/>')) == {}  # no parent: not a model's
    named_default = ET.fromstring('<mujoco><default><joint name="d" damping="1"/></default></mujoco>')
    assert mjcf_joint_values(named_default) == {}  # a default class's joint is no joint of the model


def test_urdf_joint_values_dynamics_limits_and_continuous():
    root = ET.fromstring("""<robot>
      <joint name="a" type="revolute"><dynamics damping="0.1"/><limit lower="-1" effort="5"/></joint>
      <joint name="b" type="revolute"><dynamics friction="0.2"/><limit upper="1"/></joint>
      <joint name="c" type="continuous"/>
      <joint name="d" type="revolute"><dynamics/><limit effort="0"/></joint>
      <joint name="e" type="prismatic"><limit lower="" upper=""/></joint>
      <transmission name="t"><joint name="a"/></transmission>
    </robot>""")
    assert urdf_joint_values(root) == {
        "a": frozenset({"damping", "range", "effort"}),
        "b": frozenset({"friction", "range"}),
        "c": frozenset({"range"}),  # continuous states "no position limits"
        "d": frozenset({"effort"}),
        "e": frozenset(),
    }


def test_urdf_links_without_inertial():
    root = ET.fromstring('<robot><link name="a"/><link name="b"><inertial/></link><link name="c"><visual/></link></robot>')
    assert urdf_links_without_inertial(root) == {"a", "c"}


def test_unset_only_when_known_and_missing():
    assert unset(frozenset({"range"}), "damping") is True
    assert unset(frozenset({"damping"}), "damping") is False
    assert unset(None, "damping") is False  # not known: taken as stated
