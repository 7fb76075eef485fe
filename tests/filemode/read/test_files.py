"""Each file read once, on tiny files written here: the two sides of a pair, a URDF read by
Pinocchio, else MuJoCo's URDF import, else Drake (each refusal a finding, all three an input
error), its floating base decided against the other file's free bodies, an MJCF's free bases
fixed (a mesh MuJoCo cannot read dropped), what each file states, an SDFormat or USD file shaped
as either side, and a USD's bodies authored elsewhere than their joint frames."""

from __future__ import annotations

import pytest

from kinverify.errors import InputError
from kinverify.filemode.read.describe_mjcf import describe_mjcf
from kinverify.filemode.read.files import (
    load_usd,
    mjcf_angle_unit,
    read_mjcf,
    read_sdf,
    read_urdf,
    read_usd,
    sdf_free_bodies,
    sides,
    with_statements,
)
from kinverify.filemode.read.loading import LoadedFile

INERTIAL = '<inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>'
ZERO = '<inertial><mass value="0"/><inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial>'


def write(folder, name: str, text: str) -> str:
    path = folder / name
    path.write_text(text)
    return str(path)


# --- the two sides --------------------------------------------------------------------------------


def test_the_sides_of_a_pair_in_order():
    assert sides("u", "m", None) == (("urdf", "u"), ("mjcf", "m"))
    assert sides(None, "m", "s") == (("sdf", "s"), ("mjcf", "m"))
    assert sides("u", None, "s") == (("urdf", "u"), ("sdf", "s"))
    assert sides("u", None, None, "x") == (("urdf", "u"), ("usd", "x"))
    assert sides(None, None, "s", "x") == (("sdf", "s"), ("usd", "x"))
    assert sides(None, "m", None, "x") == (("usd", "x"), ("mjcf", "m"))
    assert sides("", "m", None, "x") == (("usd", "x"), ("mjcf", "m"))


@pytest.mark.parametrize("given", [("u", None, None), ("u", "m", "s"), (None, None, None), ("u", "m", "s", "x")])
def test_anything_but_two_files_is_refused(given):
    with pytest.raises(InputError, match="^file mode compares two files: give two of --urdf, --mjcf, --sdf and --usd$"):
        sides(*given)


# --- URDF -----------------------------------------------------------------------------------------

FLOATING = f"""<robot name="r">
  <link name="world"/>
  <link name="base">{INERTIAL}</link>
  <link name="arm">{INERTIAL}</link>
  <joint name="float" type="floating"><parent link="world"/><child link="base"/><origin xyz="1 2 3"/></joint>
  <joint name="spin" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <dynamics damping="0.5"/></joint>
</robot>"""


def test_a_floating_urdf_before_an_mjcf_with_one_free_body_is_compared_as_coordinates(tmp_path):
    findings: list = []
    loaded, text, desc, library, decision = read_urdf(write(tmp_path, "f.urdf", FLOATING), findings, free=("body",))
    assert findings == [] and library == "pinocchio" and loaded.kind == "urdf" and loaded.name == "r"
    assert (decision.floating, decision.kind, decision.free) == (True, "floating_base", ["body"])
    assert decision.urdf.kind == "floating" and decision.urdf.joint == "float"
    assert decision.message.startswith("both files float (the URDF's root joint float is floating; the MJCF's body body")
    assert 'type="floating"' in decision.urdf_text and 'upper="1e308"' in decision.urdf_text  # prepared for the libraries
    assert 'type="floating"' not in text and 'upper="1e308"' in text
    assert desc.frames["base"][:3, 3] == pytest.approx([0, 0, 0])  # both bases at the identity
    assert desc.joint("spin").stated == {"damping", "range"} and desc.no_inertial == {"world"}


def test_a_floating_urdf_against_a_fixed_mjcf_is_held_at_its_origin(tmp_path):
    _, text, desc, _, decision = read_urdf(write(tmp_path, "f.urdf", FLOATING), [], free=())
    assert (decision.floating, decision.kind, decision.urdf_text) == (False, "floating_one_file", "")
    assert desc.frames["base"][:3, 3] == pytest.approx([1, 2, 3])


def robot(inertial: str = INERTIAL, axis: str = "0 0 1") -> str:
    return f"""<robot name="r"><link name="a">{INERTIAL}</link><link name="b">{inertial}</link><link name="tip"/>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="{axis}"/></joint>
  <joint name="t" type="fixed"><parent link="b"/><child link="tip"/></joint></robot>"""


def test_a_urdf_pinocchio_refuses_is_read_by_mujoco(tmp_path):
    findings: list = []
    _, _, desc, library, decision = read_urdf(write(tmp_path, "r.urdf", robot()), findings)
    assert library == "mujoco" and (desc.kind, desc.library) == ("urdf", "mujoco (URDF import)")
    (refused,) = findings
    assert refused.kind == "parser_refused" and refused.values == {"file": "URDF", "library": "pinocchio"}
    assert refused.message.startswith("Pinocchio refuses the URDF: Joint [j] is of type REVOLUTE but it does not specify limits")
    assert refused.message.endswith("; read with MuJoCo's URDF import instead")
    assert desc.no_inertial == {"tip"} and desc.joint("j").stated == frozenset()  # the URDF's statements
    assert decision.kind == "" and not decision.floating


def test_a_urdf_mujoco_refuses_too_is_read_by_drake(tmp_path):
    findings: list = []
    _, _, desc, library, _ = read_urdf(write(tmp_path, "r.urdf", robot(ZERO)), findings)
    assert library == "drake" and desc.no_inertial == {"tip"}
    assert [f.values for f in findings] == [{"file": "URDF", "library": "pinocchio"}, {"file": "URDF", "library": "mujoco"}]
    assert findings[1].message.startswith("MuJoCo's URDF import refuses the URDF too: mass and inertia of moving bodies")
    assert findings[1].message.endswith("; read with Drake's URDF parser instead") and findings[1].kind == "parser_refused"


def test_a_urdf_no_library_reads_is_an_input_error_naming_each_reason(tmp_path):
    path = write(tmp_path, "r.urdf", robot(axis="0 0 0"))
    findings: list = []
    with pytest.raises(InputError) as err:
        read_urdf(path, findings)
    message = str(err.value)
    assert message.startswith(f"--urdf: no library can load {path}: axis too small in joint")
    assert "; Drake: " in message and "axis is zero" in message and len(findings) == 2


# --- MJCF -----------------------------------------------------------------------------------------

MJCF = """<mujoco model="m">
  <worldbody>
    <body name="base" pos="1 2 3"><joint name="free" type="free" damping="0.5" armature="0.25"/>
      <geom type="sphere" size="0.1" mass="1"/>
      <body name="arm" pos="0 0 1"><joint name="h1" axis="0 0 1" damping="0.1"/><geom type="sphere" size="0.1" mass="1"/>
        <body name="hand"><joint name="h2" axis="0 1 0"/><geom type="sphere" size="0.1" mass="1"/></body>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="h1" forcerange="-3 3" forcelimited="true"/><motor joint="h2"/></actuator>
  <keyframe><key qpos="1 2 3 1 0 0 0 0 0"/></keyframe>
</mujoco>"""


def test_an_mjcf_free_base_is_fixed_and_its_free_joint_values_kept(tmp_path):
    findings: list = []
    loaded, text, desc, free = read_mjcf(write(tmp_path, "m.xml", MJCF), findings)
    assert findings == [] and free == ["base"] and loaded.name == "m"
    assert 'type="free"' not in text and "keyframe" not in text
    assert desc.free_joint == {"armature": 0.25, "damping": 0.5}
    assert desc.frames["base"][:3, 3] == pytest.approx([0, 0, 0])
    # stated: h1's damping and its finite force bound; h2's actuator has no force bound
    assert desc.joint("h1").stated == {"damping", "effort"} and desc.joint("h2").stated == frozenset()


def test_an_mjcf_without_free_base_keeps_its_pose(tmp_path):
    text = MJCF.replace('<joint name="free" type="free" damping="0.5" armature="0.25"/>', "").replace(
        '<keyframe><key qpos="1 2 3 1 0 0 0 0 0"/></keyframe>', ""
    )
    _, _, desc, free = read_mjcf(write(tmp_path, "m.xml", text), [])
    assert free == [] and desc.free_joint == {} and desc.frames["base"][:3, 3] == pytest.approx([1, 2, 3])


MESHED = """<mujoco model="m">
  <asset><mesh name="bad" file="bad.stl"/></asset>
  <worldbody>
    <body name="a"><joint name="h" axis="0 0 1"/><geom type="sphere" size="0.1" mass="MASS"/>
      <geom type="mesh" mesh="bad" mass="0"/></body>
  </worldbody>
</mujoco>"""


def test_a_mesh_mujoco_cannot_read_is_dropped_with_a_finding(tmp_path):
    (tmp_path / "bad.stl").write_bytes(b"not a mesh at all" * 10)
    findings: list = []
    loaded, text, desc, free = read_mjcf(write(tmp_path, "m.xml", MESHED.replace("MASS", "1")), findings)
    (refused,) = findings
    assert refused.kind == "parser_refused" and refused.values == {"file": "MJCF", "library": "mujoco"}
    assert refused.message.startswith("MuJoCo cannot read a mesh of the MJCF (")
    assert "meshes dropped (they do not change kinematics or dynamics)" in refused.message
    assert "bad.stl" not in text and "bad.stl" not in loaded.text and [j.name for j in desc.joints] == ["h"] and free == []


def test_an_mjcf_mujoco_refuses_is_an_input_error(tmp_path):
    (tmp_path / "bad.stl").write_bytes(b"not a mesh at all" * 10)
    path = write(tmp_path, "m.xml", MESHED.replace("MASS", "0"))  # no mass on a moving body: refused with or without meshes
    findings: list = []
    with pytest.raises(InputError, match=f"^--mjcf: MuJoCo cannot load {path}: "):
        read_mjcf(path, findings)
    assert len(findings) == 1  # the meshes were dropped once, then the refusal stands
    plain = write(
        tmp_path,
        "p.xml",
        MESHED.replace("MASS", "0")
        .replace('<geom type="mesh" mesh="bad" mass="0"/>', "")
        .replace('<mesh name="bad" file="bad.stl"/>', ""),
    )
    findings = []
    with pytest.raises(InputError, match="mass and inertia of moving bodies"):
        read_mjcf(plain, findings)
    assert findings == []


def test_statements_say_which_bodies_have_an_unknown_mass_or_centre_of_mass(tmp_path):
    text = MJCF.replace('<joint name="free" type="free" damping="0.5" armature="0.25"/>', "").replace(
        '<keyframe><key qpos="1 2 3 1 0 0 0 0 0"/></keyframe>', ""
    )
    loaded = LoadedFile("m.xml", "mjcf", text, text, "m", (), ("arm",), ("hand",))
    desc = with_statements(describe_mjcf(text), loaded)
    known = {b.name: (b.mass_known, b.com_known) for b in desc.bodies}
    assert known["arm"] == (False, True) and known["hand"] == (True, False) and known["base"] == (True, True)


# --- SDFormat ---------------------------------------------------------------------------------

LINK = "<link name='{}'><inertial><mass>1</mass><inertia><ixx>1</ixx><iyy>1</iyy><izz>1</izz></inertia></inertial></link>"
SDF = (
    "<sdf version='1.9'><model name='s'>"
    + LINK.format("base")
    + LINK.format("arm")
    + "<joint name='j' type='revolute'><parent>base</parent><child>arm</child>"
    "<axis><xyz>0 0 1</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis></joint>WORLD</model></sdf>"
)
WELDED = "<joint name='w' type='fixed'><parent>world</parent><child>base</child></joint>"


def test_links_no_joint_holds_are_free_bodies():
    assert sdf_free_bodies(SDF.replace("WORLD", "")) == ["base"]
    assert sdf_free_bodies(SDF.replace("WORLD", WELDED)) == []
    assert sdf_free_bodies(SDF.replace("WORLD", WELDED).replace("<child>base</child>", "<child> base\n</child>")) == []
    assert sdf_free_bodies("<sdf version='1.9'><world name='w'/></sdf>") == []


def test_an_sdf_after_a_urdf_is_shaped_as_an_mjcf(tmp_path):
    loaded, text, desc, free = read_sdf(write(tmp_path, "s.sdf", SDF.replace("WORLD", "")), [])
    assert free == ["base"] and text == loaded.text and [j.name for j in desc.joints] == ["j"] and loaded.name == "s"


def test_an_sdf_before_an_mjcf_is_shaped_as_a_urdf(tmp_path):
    path = write(tmp_path, "s.sdf", SDF.replace("WORLD", ""))
    loaded, text, desc, library, decision = read_sdf(path, [], free=["body"])
    assert library == "drake" and text == loaded.text
    assert (decision.floating, decision.kind, decision.free) == (True, "floating_base", ["body"])
    assert (decision.urdf.kind, decision.urdf.root, decision.urdf.joint, decision.urdf.link) == (
        "floating",
        "base",
        "(free body)",
        "base",
    )
    assert "the SDF's link base is a free body" in decision.message and "URDF's root joint" not in decision.message
    assert decision.urdf_text == loaded.text
    welded = write(tmp_path, "w.sdf", SDF.replace("WORLD", WELDED))
    *_, decision = read_sdf(welded, [], free=["body"])
    assert (decision.floating, decision.kind, decision.urdf_text) == (False, "floating_one_file", "")
    assert (decision.urdf.kind, decision.urdf.joint, decision.urdf.root) == (
        "fixed",
        None,
        "base",
    )  # the root link, welded to the world


def test_an_sdf_drake_refuses_is_an_input_error(tmp_path):
    path = write(tmp_path, "s.sdf", SDF.replace("WORLD", "").replace("<child>arm</child>", "<child>nothere</child>"))
    with pytest.raises(InputError, match=f"^--sdf: Drake cannot load {path}: ") as err:
        read_sdf(path, [])
    assert "name[nothere]" in str(err.value) and "\n" not in str(err.value)  # Drake's reason, on one line


def test_the_mjcf_angle_unit():
    assert mjcf_angle_unit("<mujoco/>") == "degree"
    assert mjcf_angle_unit("<mujoco><compiler autolimits='true'/></mujoco>") == "degree"
    assert mjcf_angle_unit("<mujoco><compiler angle='radian'/></mujoco>") == "radian"


# --- USD ------------------------------------------------------------------------------------------

USD_HEAD = '#usda 1.0\n(\n    upAxis = "Z"\n    metersPerUnit = 1{extra}\n)\n'
USD_BODY = (
    'def Xform "{name}" (apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsMassAPI"{root}])\n{{\nfloat physics:mass = 1\n'
    'double3 xformOp:translate = {at}\nquatd xformOp:orient = {q}\nuniform token[] xformOpOrder = ["xformOp:translate", "xformOp:orient"]\n}}\n'
)
TURN = "(0.7, 0, 0, 0.7)"  # not a unit quaternion


def usd(folder, name: str, fixed: bool = True, b1: str = "(0, 0, 1)", q1: str = "(1, 0, 0, 0)", extra: str = "") -> str:
    text = (
        USD_HEAD.format(extra=extra)
        + 'def Xform "r"\n{\n'
        + USD_BODY.format(name="b0", root=', "PhysicsArticulationRootAPI"', at="(0, 0, 0)", q="(1, 0, 0, 0)")
        + USD_BODY.format(name="b1", root="", at=b1, q=q1)
        + USD_BODY.format(name="b2", root="", at="(0, 0, 2)", q="(1, 0, 0, 0)")
        + ('def PhysicsFixedJoint "root"\n{\nrel physics:body1 = </r/b0>\n}\n' if fixed else "")
        + 'def PhysicsRevoluteJoint "j1"\n{\nrel physics:body0 = </r/b0>\nrel physics:body1 = </r/b1>\n'
        "point3f physics:localPos0 = (0, 0, 1)\n}\n"
        'def PhysicsRevoluteJoint "j2"\n{\nrel physics:body0 = </r/b1>\nrel physics:body1 = </r/b2>\n'
        "point3f physics:localPos0 = (0, 0, 1)\n}\n}\n"
    )
    return write(folder, name, text)


def test_a_usd_is_loaded_with_its_absent_layers_named(tmp_path):
    path = usd(tmp_path, "a.usda", extra='\n    subLayers = [@./missing.usda@]\n    defaultPrim = "r"')
    loaded, robot = load_usd(path)
    assert (loaded.path, loaded.kind, loaded.original, loaded.text, loaded.name) == (path, "usd", path, path, "r")
    (warning,) = loaded.warnings
    assert warning.startswith("USD: layer ") and "missing.usda" in warning
    assert warning.endswith(" is absent (its prims are read without it: meshes are not needed for kinematics and dynamics)")
    assert robot.names[robot.root] == "b0"
    loaded, _ = load_usd(usd(tmp_path, "b.usda"))  # no default prim: named after its root body
    assert loaded.name == "b0" and loaded.warnings == ()


def test_a_usd_after_a_urdf_is_shaped_as_an_mjcf_and_names_bodies_authored_elsewhere(tmp_path):
    findings: list = []
    loaded, text, desc, roots = read_usd(usd(tmp_path, "m.usda", b1="(0.1, 0, 1)"), findings)
    assert roots == [] and text == loaded.text == loaded.path and [j.name for j in desc.joints] == ["j1", "j2"]
    (moved,) = findings
    assert moved.kind == "usd_pose_mismatch" and moved.subject == "b1" and moved.subject_type == "link"
    assert moved.magnitude == pytest.approx(0.1, rel=1e-6) and moved.unit == "m|rad"
    assert moved.values["file"] == "USD" and moved.values["bodies"]["b1"] == pytest.approx([0.1, 0.0], abs=1e-7)
    assert moved.message.startswith("the USD places 1 bodies (their xformOps, where a simulator starts them) elsewhere")
    assert moved.message.endswith("(compared: the joint frames): b1 0.1 m, 0 rad")


def test_a_turned_body_is_named_with_the_largest_of_its_offsets(tmp_path):
    findings: list = []
    read_usd(usd(tmp_path, "t.usda", b1="(0.1, 0, 1)", q1=TURN), findings)
    (turned,) = findings
    rot = turned.values["bodies"][next(iter(turned.values["bodies"]))][1]
    assert turned.subject == "b1" and rot > 1.5 and turned.magnitude == pytest.approx(rot)
    assert "b1 (its xformOp:orient is not a unit quaternion" in turned.message


def test_a_usd_where_joints_place_the_bodies_gives_no_finding(tmp_path):
    findings: list = []
    *_, roots = read_usd(usd(tmp_path, "ok.usda", fixed=False), findings)
    assert findings == [] and roots == ["b0"]


def test_a_floating_usd_before_an_mjcf_with_one_free_body_floats_too(tmp_path):
    loaded, text, desc, library, decision = read_usd(usd(tmp_path, "f.usda", fixed=False), [], free=["body"])
    assert library == "usd" and text == loaded.path and desc.kind == "usd"
    assert (decision.floating, decision.kind, decision.free) == (True, "floating_base", ["body"])
    assert (decision.urdf.kind, decision.urdf.root, decision.urdf.joint, decision.urdf.link) == (
        "floating",
        "b0",
        "(free body)",
        "b0",
    )
    assert "the USD's root body b0 has no joint to the world" in decision.message and "URDF" not in decision.message.split(";")[0]
    assert decision.urdf_text == loaded.text


def test_a_fixed_usd_before_an_mjcf_with_one_free_body_differs(tmp_path):
    *_, decision = read_usd(usd(tmp_path, "x.usda"), [], free=["body"])
    assert (decision.floating, decision.kind, decision.urdf_text) == (False, "floating_one_file", "")
    assert (decision.urdf.kind, decision.urdf.joint) == ("fixed", None)
