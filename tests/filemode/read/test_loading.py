"""Reading a user's URDF, MJCF and SDFormat safely and cleaning them: every decision of
:mod:`kinverify.filemode.read.loading` on tiny files written in ``tmp_path`` (what is refused, what
is counted, which meshes are dropped, kept or resolved, what a body whose mass came from a dropped
mesh becomes, and the warnings that say so)."""

from __future__ import annotations

import struct
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np
import pytest

from kinverify.errors import InputError
from kinverify.filemode.read import loading
from kinverify.filemode.read.loading import (
    PLACEHOLDER_INERTIA,
    PLACEHOLDER_MASS,
    _drop_meshes,
    _mujoco_warning,
    _product,
    _resolve_mesh_assets,
    _route_mujoco_warnings,
    check_supported,
    given_packages,
    load_mjcf,
    load_sdf,
    load_urdf,
    read_xml,
    resolve_asset,
)
from kinverify.io.references import Budget, mjcf_files
from kinverify.pipeline.limits import MAX_DATA_BYTES, MAX_JOINTS, MAX_LINKS, MAX_MODEL_BYTES

JOINT = '<joint name="{name}" type="{type}"><parent link="{parent}"/><child link="{child}"/>{extra}</joint>'
LIMIT = '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'


def urdf(links: str = "", name: str = "r", joint_type: str = "revolute", extra: str = "") -> str:
    """A two-link URDF: ``base`` (holding ``links``' elements) and ``arm`` on joint ``j``."""
    joint = JOINT.format(name="j", type=joint_type, parent="base", child="arm", extra=LIMIT)
    return f'<robot name="{name}"><link name="base">{links}</link><link name="arm"/>{joint}{extra}</robot>'


def write(folder: Path, name: str, text: str | bytes) -> str:
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(text if isinstance(text, bytes) else text.encode())
    return str(path)


def cube_stl(path: Path, half: float = 0.05) -> Path:
    """A closed binary STL cube of side ``2 * half``: a mesh MuJoCo reads."""
    v = [(x, y, z) for x in (-half, half) for y in (-half, half) for z in (-half, half)]
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1)]
    faces += [(2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    data = bytearray(b"cube".ljust(80) + struct.pack("<I", len(faces)))
    for a, b, c in faces:
        p = np.array([v[a], v[b], v[c]])
        n = np.cross(p[1] - p[0], p[2] - p[0])
        if np.dot(n, p.sum(axis=0)) < 0:
            p, n = p[[0, 2, 1]], -n
        data += struct.pack("<12fH", *(n / np.linalg.norm(n)), *p.ravel(), 0)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(bytes(data))
    return path


# --- read_xml ------------------------------------------------------------------------------------


def test_a_file_that_is_not_utf8_is_refused_naming_the_byte(tmp_path):
    path = write(tmp_path, "r.urdf", b'<robot name="r">\xff</robot>')
    with pytest.raises(InputError) as err:
        read_xml(path, "urdf")
    assert str(err.value) == f"--urdf: cannot read {path}: not UTF-8 text (byte 16)"


def test_a_byte_order_mark_is_not_part_of_the_text(tmp_path):
    path = write(tmp_path, "r.urdf", b"\xef\xbb\xbf" + urdf().encode())
    text, root = read_xml(path, "urdf")
    assert text == urdf() and root.get("name") == "r"


def test_compiled_text_above_the_model_limit_is_refused_and_at_the_limit_read():
    head = '<robot name="r"><link name="a"/></robot>'
    at_limit = head + " " * (MAX_MODEL_BYTES - len(head))  # trailing blanks: parsed in no time
    text, root = read_xml("r.urdf.xacro", "urdf", at_limit)
    assert text is at_limit and [link.get("name") for link in root] == ["a"]
    over = at_limit[:-1] + "é"  # two bytes: one byte above
    with pytest.raises(InputError) as err:
        read_xml("r.urdf.xacro", "urdf", over)
    assert str(err.value) == "--urdf: r.urdf.xacro is 8.0 MB, above the 8 MB kinverify reads (see docs/robustness.md)"


@pytest.mark.parametrize(
    "kind, text, words",
    [
        ("urdf", "<mujoco/>", "is an MJCF, not a URDF (root element <mujoco>, expected <robot>)"),
        ("mjcf", '<robot name="r"/>', "is a URDF, not an MJCF (root element <robot>, expected <mujoco>)"),
        ("sdf", "<mujoco/>", "is an MJCF, not an SDFormat file (root element <mujoco>, expected <sdf>)"),
        ("urdf", "<sdf/>", "is an SDFormat file, not a URDF (root element <sdf>, expected <robot>)"),
        ("mjcf", "<foo/>", "is a <foo> document, not an MJCF (root element <foo>, expected <mujoco>)"),
    ],
)
def test_a_file_of_another_kind_is_refused_naming_both(tmp_path, kind, text, words):
    path = write(tmp_path, "m.xml", text)
    with pytest.raises(InputError) as err:
        read_xml(path, kind)
    assert str(err.value) == f"--{kind}: {path} {words}"


TWO_ROOTS = '<robot name="r"><link name="a"/><link name="b"/></robot>'
XACRO_TWO_ROOTS = TWO_ROOTS.replace("<robot ", '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" ')
XACRO_TWO_ROOTS = XACRO_TWO_ROOTS.replace("</robot>", '<xacro:property name="p" value="1"/></robot>')


def test_a_urdf_is_checked_as_a_tree_unless_it_is_a_xacro_source(tmp_path):
    with pytest.raises(InputError, match="--urdf: .*r.urdf"):
        read_xml(write(tmp_path, "r.urdf", TWO_ROOTS), "urdf")
    for name, text in (("r.urdf.xacro", TWO_ROOTS), ("x.urdf", XACRO_TWO_ROOTS)):  # checked once compiled
        assert read_xml(write(tmp_path, name, text), "urdf")[0] == text
    with pytest.raises(InputError, match="r.urdf.xacro"):  # compiled: checked under the source's name
        read_xml("r.urdf.xacro", "urdf", TWO_ROOTS)


def test_a_urdf_and_an_mjcf_with_a_non_finite_pose_are_refused(tmp_path):
    bad = urdf().replace("<axis ", '<origin xyz="nan 0 0"/><axis ', 1)
    with pytest.raises(InputError, match="--urdf: .*r.urdf"):
        read_xml(write(tmp_path, "r.urdf", bad), "urdf")
    mjcf = '<mujoco><worldbody><body name="b" pos="inf 0 0"/></worldbody></mujoco>'
    with pytest.raises(InputError, match="--mjcf: .*m.xml"):
        read_xml(write(tmp_path, "m.xml", mjcf), "mjcf")


def test_an_mjcf_with_includes_is_returned_expanded_and_without_as_written(tmp_path):
    write(tmp_path, "part.xml", '<mujoco><body name="included"/></mujoco>')
    main = '<mujoco model="m"><!-- kept --><worldbody><include file="part.xml"/></worldbody></mujoco>'
    text, root = read_xml(write(tmp_path, "m.xml", main), "mjcf")
    assert [b.get("name") for b in ET.fromstring(text).iter("body")] == ["included"] == [b.get("name") for b in root.iter("body")]
    plain = main.replace('<include file="part.xml"/>', '<body name="own"/>')
    assert read_xml(write(tmp_path, "plain.xml", plain), "mjcf")[0] == plain  # the comment is still there


def test_read_xml_refuses_what_kinverify_does_not_compare(tmp_path):
    with pytest.raises(InputError, match="planar base"):
        read_xml(write(tmp_path, "p.urdf", urdf(joint_type="planar")), "urdf")


# --- check_supported -----------------------------------------------------------------------------


def chain(links: int, types: list[str]) -> ET.Element:
    """A URDF chain of ``links`` links, joint i of type ``types[i]`` (fixed past the list)."""
    joints = "".join(
        JOINT.format(name=f"j{i}", type=(types[i] if i < len(types) else "fixed"), parent=f"l{i}", child=f"l{i + 1}", extra="")
        for i in range(links - 1)
    )
    return ET.fromstring('<robot name="c">' + "".join(f'<link name="l{i}"/>' for i in range(links)) + joints + "</robot>")


def refusal(root: ET.Element, kind: str) -> str | None:
    try:
        check_supported(root, kind, "f")
    except InputError as err:
        return str(err)
    return None


def test_a_planar_root_joint_is_refused_a_planar_joint_further_down_is_not():
    assert refusal(chain(3, ["planar"]), "urdf") == (
        "--urdf: f: joint 'j0' is planar: unsupported: planar base "
        "(kinverify compares fixed and floating bases; make the root joint fixed or floating)"
    )
    assert refusal(chain(3, ["fixed", "planar"]), "urdf") is None
    assert refusal(chain(3, ["floating"]), "urdf") is None
    orphan = chain(2, ["planar"])
    orphan.find("joint").remove(orphan.find("joint/parent"))  # no parent: not a root joint
    assert refusal(orphan, "urdf") is None


def test_urdf_links_and_movable_joints_are_bounded():
    assert refusal(chain(MAX_LINKS, []), "urdf") is None
    assert refusal(chain(MAX_LINKS + 1, []), "urdf") == (
        f"--urdf: f has {MAX_LINKS + 1} links, above the {MAX_LINKS} kinverify compares (see docs/robustness.md)"
    )
    movable = ["revolute"] * (MAX_JOINTS - 2) + ["continuous", "prismatic"]
    assert refusal(chain(MAX_JOINTS + 5, movable + ["planar", "floating"]), "urdf") is None
    assert refusal(chain(MAX_JOINTS + 2, movable + ["revolute"]), "urdf") == (
        f"--urdf: f has {MAX_JOINTS + 1} movable joints, above the {MAX_JOINTS} kinverify compares (see docs/robustness.md)"
    )
    for kind in ("continuous", "prismatic"):
        assert f"{MAX_JOINTS + 1} movable joints" in refusal(chain(MAX_JOINTS + 2, movable + [kind]), "urdf")
    both = refusal(chain(MAX_LINKS + 1, ["revolute"] * (MAX_JOINTS + 1)), "urdf")
    assert f"has {MAX_LINKS + 1} links" in both  # the links first


def sdf(links: int, joints: list[str]) -> ET.Element:
    inner = "".join(f'<link name="l{i}"/>' for i in range(links - 1))
    kinds = "".join(f'<joint name="j{i}" type="{t}"/>' for i, t in enumerate(joints))
    return ET.fromstring(f'<sdf><model name="m"><link name="top"/><model name="inner">{inner}</model>{kinds}</model></sdf>')


def test_sdformat_links_nested_models_included_and_movable_joints_are_bounded():
    assert refusal(sdf(MAX_LINKS, []), "sdf") is None
    assert refusal(sdf(MAX_LINKS + 1, []), "sdf") == (
        f"--sdf: f has {MAX_LINKS + 1} links, above the {MAX_LINKS} kinverify compares (see docs/robustness.md)"
    )
    joints = ["revolute"] * (MAX_JOINTS - 2) + ["prismatic", "continuous"]
    assert refusal(sdf(2, joints + ["ball", "fixed", "universal"]), "sdf") is None
    for kind in ("revolute", "prismatic", "continuous"):
        assert refusal(sdf(2, joints + [kind]), "sdf") == (
            f"--sdf: f has {MAX_JOINTS + 1} movable joints, above the {MAX_JOINTS} kinverify compares (see docs/robustness.md)"
        )


def mjcf_root(bodies: int, joints: list[str | None] = (), more: str = "") -> ET.Element:
    kinds = "".join("<joint/>" if t is None else f'<joint type="{t}"/>' for t in joints)
    nested = "".join(f'<body name="b{i}">' for i in range(bodies)) + "</body>" * bodies
    return ET.fromstring(f'<mujoco><worldbody><body name="j">{kinds}</body>{nested}{more}</worldbody></mujoco>')


def test_mjcf_bodies_generated_and_replicated_and_movable_joints_are_bounded():
    assert refusal(mjcf_root(MAX_LINKS - 1), "mjcf") is None
    assert refusal(mjcf_root(MAX_LINKS), "mjcf") == (
        f"--mjcf: f has {MAX_LINKS + 1} bodies, above the {MAX_LINKS} kinverify compares (see docs/robustness.md)"
    )
    for tag in ("composite", "flexcomp"):  # bodies they generate: the product of count
        assert refusal(mjcf_root(MAX_LINKS - 13, more=f'<{tag} count="3 4 1"/>'), "mjcf") is None
        assert f"has {MAX_LINKS + 1} bodies" in refusal(mjcf_root(MAX_LINKS - 12, more=f'<{tag} count="3 4 1"/>'), "mjcf")
    half = MAX_LINKS // 2
    assert refusal(mjcf_root(half - 1, more='<replicate count="2"><site/></replicate>'), "mjcf") is None
    assert f"has {2 * half + 2} bodies" in refusal(mjcf_root(half, more='<replicate count="2"><site/></replicate>'), "mjcf")
    joints = [None] * (MAX_JOINTS - 2) + ["hinge", "slide"]
    assert refusal(mjcf_root(1, joints + ["ball", "free"]), "mjcf") is None
    for kind in (None, "hinge", "slide"):
        assert refusal(mjcf_root(1, joints + [kind]), "mjcf") == (
            f"--mjcf: f has {MAX_JOINTS + 1} movable joints, above the {MAX_JOINTS} kinverify compares (see docs/robustness.md)"
        )


@pytest.mark.parametrize(
    "counts, product", [(None, 1), ("", 1), ("7", 7), ("2 3 4", 24), ("0 5", 5), ("-3 2", 2), ("2 x", 1), ("x 2", 1)]
)
def test_a_count_is_the_product_of_its_whole_numbers(counts, product):
    assert _product(counts) == product


# --- resolve_asset -------------------------------------------------------------------------------


@pytest.fixture
def package(tmp_path):
    """tmp/pkg/meshes/a.stl (the mesh) and tmp/pkg/urdf (the model's folder)."""
    mesh = cube_stl(tmp_path / "pkg" / "meshes" / "a.stl")
    (tmp_path / "pkg" / "urdf").mkdir()
    return mesh.resolve(), tmp_path / "pkg" / "urdf"


def test_a_mesh_reference_resolves_in_every_form(tmp_path, package):
    mesh, base = package
    for name in (
        "package://pkg/meshes/a.stl",
        "../meshes/a.stl",
        "file://../meshes/a.stl",
        str(mesh),
        f"file://{mesh}",
    ):
        assert resolve_asset(name, base) == mesh, name
    elsewhere = tmp_path / "elsewhere"
    assert resolve_asset("package://other/meshes/a.stl", elsewhere, {"other": str(tmp_path / "pkg")}) == mesh
    assert resolve_asset("package://other/meshes/a.stl", elsewhere) is None


def test_a_reference_to_nothing_or_to_a_folder_is_absent(package):
    _, base = package
    for name in ("package://pkg/meshes/b.stl", "package://pkg/meshes", "../meshes/b.stl", "../meshes", "file://../meshes", ""):
        assert resolve_asset(name, base) is None, name


def test_the_meshes_of_a_model_share_one_budget(package):
    mesh, base = package
    size = mesh.stat().st_size
    budget = Budget()
    assert resolve_asset("../meshes/a.stl", base, budget=budget) == mesh and budget.data == MAX_DATA_BYTES - size
    assert resolve_asset("package://pkg/meshes/a.stl", base, budget=budget) == mesh and budget.data == MAX_DATA_BYTES - 2 * size
    budget.data = size
    assert resolve_asset("../meshes/a.stl", base, budget=budget) == mesh and budget.data == 0
    for left in (0, size - 1, -size):  # spent: nothing more, not even what a negative budget would wrap to
        budget.data = left
        with pytest.raises(InputError) as err:
            resolve_asset("../meshes/a.stl", base, budget=budget)
        assert str(err.value).startswith(f"a mesh the model references: {mesh} is ")  # the file named once
    one_byte = base / "one.bin"
    one_byte.write_bytes(b"x")
    budget.data = 0
    with pytest.raises(InputError) as err:
        resolve_asset("one.bin", base, budget=budget)
    # what is left of the budget all meshes share, in a unit that shows each size
    assert str(err.value) == (
        f"a mesh the model references: {one_byte.resolve()} is 1 byte, which would exceed the 256 MB all meshes, "
        "textures and other data files of the model share: 256.0 MB already read (see docs/robustness.md)"
    )


# --- given_packages and load_urdf ------------------------------------------------------------------


def test_a_block_gives_packages_and_xacro_arguments_and_puts_back_what_was_there(package):
    assert loading._GIVEN == {"packages": {}, "xacro_args": {}}
    with given_packages({"p": "/a"}, {"x": "1"}):
        assert loading._GIVEN == {"packages": {"p": "/a"}, "xacro_args": {"x": "1"}}
        with pytest.raises(KeyError), given_packages({"q": "/b"}):
            assert loading._GIVEN == {"packages": {"q": "/b"}, "xacro_args": {}}
            raise KeyError("x")
        assert loading._GIVEN == {"packages": {"p": "/a"}, "xacro_args": {"x": "1"}}
    assert loading._GIVEN == {"packages": {}, "xacro_args": {}}


MESH = '<{tag}><geometry><mesh filename="{file}"/></geometry></{tag}>'


def mesh_urdf(*elements: tuple[str, str]) -> str:
    return urdf(
        "".join(MESH.format(tag=tag, file=file) for tag, file in elements)
        + '<visual><geometry><box size="1 1 1"/></geometry></visual>'
    )


def geometry(loaded) -> list[tuple[str, str]]:
    out = []
    for el in ET.fromstring(loaded.text).find("link"):
        if el.tag in ("visual", "collision"):
            shape = el.find("geometry")[0]
            out.append((el.tag, shape.get("filename") or shape.tag))
    return out


SKIPPED = "mesh visual/collision elements skipped, their files are absent (meshes are not needed for kinematics and dynamics)"
NOT_LOADED = "mesh visual/collision elements not loaded, their files present (meshes are not needed for kinematics and dynamics)"


def test_urdf_meshes_present_are_kept_as_absolute_paths_absent_ones_dropped(tmp_path, package):
    mesh, base = package
    text = mesh_urdf(("visual", "package://pkg/meshes/a.stl"), ("collision", "../meshes/gone.stl"), ("visual", "gone.stl"))
    text = text.replace('<link name="arm"/>', '<link name="arm"><collision><geometry><mesh/></geometry></collision></link>')
    path = write(base, "r.urdf", text)
    loaded = load_urdf(path)
    assert (loaded.path, loaded.kind, loaded.original, loaded.name) == (path, "urdf", text, "r")
    assert geometry(loaded) == [("visual", str(mesh)), ("visual", "box")]
    assert ET.fromstring(loaded.text).find("link[@name='arm']/collision") is None  # a <mesh> without file: absent
    assert loaded.warnings == (f"URDF: 3 {SKIPPED}", "URDF: 1 mesh references resolved to existing files and kept")
    assert loaded.tree.tag == "robot" and loaded.tree is loaded.tree


def test_urdf_meshes_present_are_not_loaded_without_keep_meshes(package):
    _, base = package
    path = write(base, "r.urdf", mesh_urdf(("visual", "../meshes/a.stl"), ("collision", "../meshes/a.stl")))
    loaded = load_urdf(path, keep_meshes=False)
    assert geometry(loaded) == [("visual", "box")]
    assert loaded.warnings == (f"URDF: 2 {NOT_LOADED}",)
    plain = load_urdf(write(base, "plain.urdf", urdf(name="")))
    assert (
        plain.warnings == ()
        and plain.name == "plain"
        and plain.text == ET.tostring(ET.fromstring(urdf(name="")), encoding="unicode")
    )


def test_urdf_packages_come_from_the_call_else_from_the_block(tmp_path, package):
    mesh, _ = package
    path = write(tmp_path / "elsewhere", "r.urdf", mesh_urdf(("visual", "package://other/meshes/a.stl")))
    assert geometry(load_urdf(path, packages={"other": str(tmp_path / "pkg")}))[0] == ("visual", str(mesh))
    with given_packages({"other": str(tmp_path / "pkg")}):
        assert geometry(load_urdf(path))[0] == ("visual", str(mesh))
        assert geometry(load_urdf(path, packages={}))[0] == ("visual", "box")
    assert geometry(load_urdf(path))[0] == ("visual", "box")


XACRO = """<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="x">
  <xacro:arg name="lower" default="-1"/>
  <link name="base"/><link name="arm"/>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="$(arg lower)" upper="1" effort="1" velocity="1"/></joint>
</robot>"""


def lower(loaded) -> str:
    return ET.fromstring(loaded.text).find("joint/limit").get("lower")


def test_a_xacro_file_is_compiled_with_the_arguments_of_the_call_else_of_the_block(tmp_path):
    path = write(tmp_path, "x.urdf.xacro", XACRO)
    loaded = load_urdf(path)
    assert loaded.warnings == ("URDF compiled from xacro (x.urdf.xacro)",)
    assert lower(loaded) == "-1" and "xacro" not in loaded.original and loaded.name == "x"
    assert lower(load_urdf(path, xacro_args={"lower": "-2"})) == "-2"
    with given_packages(xacro_args={"lower": "-3"}):
        assert lower(load_urdf(path)) == "-3"
        assert lower(load_urdf(path, xacro_args={})) == "-1"
        assert load_urdf(write(tmp_path, "plain.urdf", urdf())).warnings == ()  # the block's arguments are for xacro files
    with pytest.raises(InputError) as err:
        load_urdf(str(tmp_path / "plain.urdf"), xacro_args={"lower": "-2"})
    assert str(err.value) == f"--xacro-arg: {tmp_path / 'plain.urdf'} is not a xacro file (no .xacro suffix, no xacro namespace)"


def test_an_sdformat_file_is_named_after_its_model_else_its_file(tmp_path):
    text = '<sdf version="1.9"><model name="m"><link name="a"/></model></sdf>'
    loaded = load_sdf(write(tmp_path, "s.sdf", text))
    assert (loaded.kind, loaded.name, loaded.original, loaded.path) == ("sdf", "m", text, str(tmp_path / "s.sdf"))
    assert ET.fromstring(loaded.text).find("model/link").get("name") == "a"
    assert load_sdf(write(tmp_path, "t.sdf", text.replace(' name="m"', ""))).name == "t"
    assert load_sdf(write(tmp_path, "w.sdf", '<sdf version="1.9"><world name="w"/></sdf>')).name == "w"


def test_sdformat_packages_come_from_the_call_else_from_the_block(tmp_path):
    write(tmp_path, "pkg/inner.sdf", '<sdf version="1.9"><model name="inner"><link name="x"/></model></sdf>')
    path = write(
        tmp_path,
        "main/m.sdf",
        '<sdf version="1.9"><model name="m"><include><uri>package://p/inner.sdf</uri></include></model></sdf>',
    )
    with pytest.raises(InputError, match="package://p/inner.sdf"):
        load_sdf(path)
    given = {"p": str(tmp_path / "pkg")}
    with given_packages(given):
        inner = ET.fromstring(load_sdf(path).text).findtext("model/include/uri")
    assert inner.endswith("-inner.sdf") and "package://" not in inner
    assert ET.fromstring(load_sdf(path, packages=given).text).findtext("model/include/uri").endswith("-inner.sdf")
    with given_packages(given), pytest.raises(InputError, match="package://p/inner.sdf"):
        load_sdf(path, packages={})


# --- MJCF: meshes resolved and dropped -------------------------------------------------------------


def drop(body: str, assets: str = "", kept=frozenset(), top: str = "", defaults: str = ""):
    root = ET.fromstring(
        f"<mujoco>{top}<default>{defaults}</default><asset>{assets}</asset><worldbody>{body}</worldbody></mujoco>"
    )
    return root, _drop_meshes(root, set(kept))


def names(root: ET.Element, tag: str) -> list[str | None]:
    return [el.get("name") for el in root.iter(tag)]


def test_geoms_on_absent_meshes_are_dropped_kept_meshes_and_primitives_stay():
    body = (
        '<body name="b"><inertial mass="1" diaginertia="1 1 1"/><geom name="own" mesh="gone"/><geom name="kept" mesh="here"/>'
        '<geom name="box" type="box" size="1 1 1"/><geom name="cls" class="m"/><geom name="fit" type="capsule" mesh="gone"/>'
        '<geom name="fit2" type="box" class="m"/><geom name="as_mesh" type="mesh" mesh="gone"/></body>'
    )
    root, (dropped, fitted, massless, approximate) = drop(
        body, kept={"here"}, defaults='<default class="m"><geom mesh="gone"/></default>'
    )
    assert names(root.find("worldbody"), "geom") == ["kept", "box"]
    # fitted: own and cls (no type: MuJoCo's sphere), fit (capsule), fit2 (box, its mesh from its class)
    assert (dropped, fitted, massless, approximate) == (5, 4, [], [])


def test_default_classes_forget_dropped_meshes_and_the_mesh_type():
    defaults = (
        '<geom type="mesh" mesh="gone" rgba="1 0 0 1"/><default class="a"><geom type="capsule" mesh="gone"/></default>'
        '<default class="k"><geom type="mesh" mesh="here"/></default><default class="n"><geom type="mesh"/></default>'
    )
    root, _ = drop("", kept={"here"}, defaults=defaults)
    geoms = [dict(g.attrib) for g in root.find("default").iter("geom")]
    assert geoms == [{"rgba": "1 0 0 1"}, {"type": "capsule"}, {"type": "mesh", "mesh": "here"}, {"type": "mesh"}]


def test_assets_of_absent_meshes_skins_height_fields_and_file_textures_are_dropped():
    assets = (
        '<mesh name="gone" file="g.stl"/><mesh name="here" file="h.stl"/><mesh file="path/stem.stl"/><mesh file="other.stl"/>'
        '<skin file="s.skn"/><hfield name="h" nrow="2" ncol="2"/><texture name="t1" file="a.png"/>'
        '<texture name="cube" type="cube" fileright="r.png"/><texture file="dir/unnamed.png"/>'
        '<texture name="sky" builtin="gradient" width="8" height="8"/><material name="m1" texture="t1"/>'
        '<material name="m2" texture="cube"/><material name="m3" texture="unnamed"/><material name="m4" texture="sky"/>'
    )
    root, _ = drop("", assets, kept={"here", "stem"})
    asset = root.find("asset")
    assert [(el.tag, el.get("name") or el.get("file")) for el in asset] == [
        ("mesh", "here"),
        ("mesh", "path/stem.stl"),
        ("texture", "sky"),
        *[("material", f"m{i}") for i in range(1, 5)],
    ]
    assert [m.get("texture") for m in asset.iter("material")] == [None, None, None, "sky"]


def test_contact_pairs_with_a_dropped_geom_are_dropped():
    body = '<body name="b"><geom name="g" mesh="gone"/><geom name="s" type="sphere" size="1"/><geom name="t" type="sphere" size="1"/></body>'
    contact = (
        '<contact><pair geom1="g" geom2="s"/><pair geom1="s" geom2="g"/><pair geom1="s" geom2="t"/>'
        '<exclude body1="b" body2="b"/></contact>'
    )
    root, _ = drop(body + "</worldbody>" + contact + "<worldbody>")
    assert [(el.tag, el.get("geom1")) for el in root.find("contact")] == [("pair", "s"), ("exclude", None)]


def test_a_body_whose_mass_was_all_in_absent_meshes_gets_a_placeholder():
    body = '<body name="b"><geom mesh="gone"/><geom mesh="gone2"/><body name="c"><geom name="x" mesh="gone"/></body></body>'
    root, (dropped, _, massless, approximate) = drop(body)
    assert (dropped, massless, approximate) == (3, ["b", "c"], [])
    for name in ("b", "c"):
        (inertial,) = root.find(f".//body[@name='{name}']").findall("inertial")
        assert inertial.attrib == {
            "pos": "0 0 0",
            "mass": repr(PLACEHOLDER_MASS),
            "diaginertia": " ".join([repr(PLACEHOLDER_INERTIA)] * 3),
        }
    assert (PLACEHOLDER_MASS, PLACEHOLDER_INERTIA) == (1e-6, 1e-12)


def test_a_body_left_with_a_weighing_geom_needs_no_placeholder_a_weightless_one_does():
    body = (
        '<body name="w"><geom mesh="gone"/><geom type="sphere" size="0.1"/></body>'
        '<body name="z"><geom mesh="gone"/><geom type="sphere" size="0.1" mass="0"/></body>'
        '<body><geom mesh="gone"/></body>'
    )
    root, (_, _, massless, _) = drop(body)
    assert massless == ["w", "z", "?"]
    assert [len(b.findall("inertial")) for b in root.iter("body")] == [0, 1, 1]


@pytest.mark.parametrize(
    "geom, defaults, unknown",
    [
        ('mass="0"', "", False),
        ('density="0"', "", False),
        ('density="0" mass="0.5"', "", False),  # stated mass: kept as a point (below)
        ('mass="0" density="5"', "", False),
        ('density="2"', "", True),
        ('mass="heavy"', "", False),  # unreadable: MuJoCo says so; counted as weighing, stated
        ('density="heavy"', "", True),
        ('class="light"', '<default class="light"><geom density="0"/></default>', False),
        ('class="light"', '<default class="light"><geom mass="0"/></default>', False),
        ('class="light"', '<default class="light"><geom density="3"/></default>', True),
    ],
)
def test_a_geom_without_mass_leaves_its_body_mass_known(geom, defaults, unknown):
    _, (_, _, massless, _) = drop(f'<body name="b"><geom mesh="gone" {geom}/></body>', defaults=defaults)
    assert massless == (["b"] if unknown else [])


@pytest.mark.parametrize(
    "top, inertial, unknown",
    [
        ("", True, False),
        ('<compiler inertiafromgeom="true"/>', True, True),
        ('<compiler inertiafromgeom="auto"/>', False, True),
        ('<compiler inertiafromgeom="false"/>', False, False),
        ('<compiler inertiafromgeom="auto"/>', True, False),
    ],
)
def test_a_body_mass_comes_from_its_geoms_without_inertial_or_when_the_compiler_says_so(top, inertial, unknown):
    body = '<body name="b">' + ('<inertial mass="1" diaginertia="1 1 1"/>' if inertial else "") + '<geom mesh="gone"/></body>'
    root, (_, _, massless, _) = drop(body, top=top)
    assert massless == (["b"] if unknown else [])
    assert len(root.find(".//body").findall("inertial")) == (1 if (inertial or unknown) else 0)


def test_a_geom_at_the_world_gives_no_body_mass():
    root, (dropped, _, massless, _) = drop('<geom mesh="gone"/>')
    assert (dropped, massless, list(root.find("worldbody"))) == (1, [], [])


def test_a_dropped_mesh_with_stated_mass_is_kept_as_a_point():
    body = '<body name="b"><geom name="g" mesh="gone" mass="2" pos="1 2 3" quat="0 1 0 0" rgba="1 0 0 1" density="9"/></body>'
    root, (_, _, massless, approximate) = drop(body)
    assert (massless, approximate) == ([], ["b"])
    (point,) = root.iter("geom")
    assert point.attrib == {
        "pos": "1 2 3",
        "quat": "0 1 0 0",
        "name": "g",
        "mass": "2",
        "type": "sphere",
        "size": "1e-4",
        "contype": "0",
        "conaffinity": "0",
        "group": "5",
    }
    cls = '<default class="heavy"><geom mass="3"/></default>'
    root, (_, _, massless, approximate) = drop(
        '<body name="c"><geom mesh="gone" class="heavy"/><geom mesh="g2" mass="1"/></body>', defaults=cls
    )
    assert approximate == ["c"] and [g.get("mass") for g in root.find("worldbody").iter("geom")] == ["3", "1"]
    _, (_, _, massless, approximate) = drop('<body><geom mesh="gone" mass="2"/></body>')
    assert approximate == ["?"]


def test_a_body_with_stated_and_unstated_dropped_mass_is_unknown_not_approximate():
    body = (
        '<body name="b"><geom mesh="gone" mass="2"/><geom mesh="gone"/></body><body name="c"><geom mesh="gone" mass="1"/></body>'
    )
    root, (_, _, massless, approximate) = drop(body)
    assert (massless, approximate) == (["b"], ["c"])
    assert root.find(".//body[@name='b']").find("inertial") is None  # the point keeps its mass


def test_mesh_assets_found_are_rewritten_absolute_and_named(tmp_path):
    cube_stl(tmp_path / "meshes" / "cube.stl")
    (tmp_path / "tex.png").write_bytes(b"png")
    text = (
        '<mujoco><compiler meshdir="meshes"/><asset><mesh name="named" file="cube.stl"/><mesh file="cube.stl"/>'
        '<mesh name="gone" file="gone.stl"/><texture name="t" file="../tex.png"/></asset>'
        '<worldbody><flexcomp name="f" type="mesh" file="cube.stl"/></worldbody></mujoco>'
    )
    path = write(tmp_path, "m.xml", text)
    cube = str((tmp_path / "meshes" / "cube.stl").resolve())
    root = ET.fromstring(text)
    assert _resolve_mesh_assets(root, mjcf_files(root, path)) == ({"named", "cube"}, 0)
    assert [m.get("file") for m in root.iter("mesh")] + [root.find(".//flexcomp").get("file")] == [cube, cube, "gone.stl", cube]
    assert root.find(".//texture").get("file") == "../tex.png"
    root = ET.fromstring(text)
    assert _resolve_mesh_assets(root, mjcf_files(root, path), keep=False) == (set(), 2)
    assert [m.get("file") for m in root.iter("mesh")] + [root.find(".//flexcomp").get("file")] == [
        "cube.stl",
        "cube.stl",
        "gone.stl",
        cube,
    ]


def test_an_mjcf_asset_model_file_is_rewritten_absolute(tmp_path):
    write(tmp_path, "sub/inner.xml", '<mujoco><worldbody><body name="i"/></worldbody></mujoco>')
    text = '<mujoco><asset><model name="inner" file="sub/inner.xml"/></asset><worldbody/></mujoco>'
    root = ET.fromstring(text)
    assert _resolve_mesh_assets(root, mjcf_files(root, write(tmp_path, "m.xml", text))) == (set(), 0)
    assert root.find(".//model").get("file") == str((tmp_path / "sub" / "inner.xml").resolve())


# --- load_mjcf -------------------------------------------------------------------------------------


def mjcf(geoms: str, assets: str = "", model: str = ' model="m"', inertial: bool = False) -> str:
    mass = '<inertial mass="1" diaginertia="0.1 0.1 0.1"/>' if inertial else ""
    return (
        f'<mujoco{model}><compiler meshdir="meshes"/><asset>{assets}</asset><worldbody>'
        f'<body name="b">{mass}<joint name="j" axis="0 0 1"/>{geoms}</body></worldbody></mujoco>'
    )


MASSLESS = (
    "MJCF bodies without <inertial> whose mass came from their (absent) meshes, not compared (a body left with no mass "
    "at all holds 1e-06 kg so that MuJoCo loads it): "
)
APPROXIMATE = "MJCF bodies whose (absent) mesh geoms state their mass: the mass is compared, not the centre of mass and inertia: "


@pytest.fixture
def meshes(tmp_path):
    cube_stl(tmp_path / "meshes" / "cube.stl")
    return tmp_path


def test_mjcf_absent_meshes_are_dropped_present_ones_kept_and_the_body_still_loads(meshes):
    text = mjcf(
        '<geom mesh="cube"/><geom mesh="gone"/><geom type="capsule" size="0.1" mesh="gone"/>',
        '<mesh name="cube" file="cube.stl"/><mesh name="gone" file="gone.stl"/>',
    )
    loaded = load_mjcf(write(meshes, "robot.xml", text))
    assert (loaded.kind, loaded.name, loaded.original, loaded.path) == ("mjcf", "m", text, str(meshes / "robot.xml"))
    assert loaded.warnings == (
        "MJCF: 2 mesh geoms (2 of them primitives fitted to a mesh, whose size came from it) and their assets skipped, "
        "their files are absent",  # the one present is kept: not among those skipped
        "MJCF: 1 mesh assets resolved to existing files and kept",
        MASSLESS + "b",  # in part: the cube gives it some
    )
    assert (loaded.unknown_mass, loaded.unknown_com) == (("b",), ())
    model = mujoco.MjModel.from_xml_string(loaded.text)
    # the cube's geom has no type: MuJoCo's sphere fitted to the cube (radius its half side), density 1000
    assert model.ngeom == 1 and model.geom_type[0] == mujoco.mjtGeom.mjGEOM_SPHERE
    assert model.geom_size[0][0] == pytest.approx(0.05, rel=1e-6)
    assert model.body_mass[1] == pytest.approx(1000 * 4 / 3 * np.pi * 0.05**3, rel=1e-6)


def test_mjcf_meshes_present_are_not_loaded_without_keep_meshes(meshes):
    geoms = '<geom type="mesh" mesh="cube"/><geom type="mesh" mesh="gone"/>'
    text = mjcf(geoms, '<mesh name="cube" file="cube.stl"/><mesh name="gone" file="gone.stl"/>', model="")
    loaded = load_mjcf(write(meshes, "nameless.xml", text), keep_meshes=False)
    assert loaded.name == "nameless"
    assert loaded.warnings == (
        "MJCF: 2 mesh geoms and their assets skipped (1 of their files present, not loaded: meshes are not needed for "
        "kinematics and dynamics)",
        MASSLESS + "b",
    )
    assert loaded.unknown_mass == ("b",) and loaded.unknown_com == ()
    model = mujoco.MjModel.from_xml_string(loaded.text)
    assert (model.ngeom, model.body_mass[1]) == (0, pytest.approx(PLACEHOLDER_MASS, rel=1e-9))


def test_mjcf_without_meshes_is_returned_as_written_without_warnings(meshes):
    text = mjcf('<geom type="sphere" size="0.1"/>')
    loaded = load_mjcf(write(meshes, "m.xml", text))
    assert loaded.warnings == () and loaded.text == ET.tostring(ET.fromstring(text), encoding="unicode")


def test_mjcf_stated_mass_of_a_dropped_mesh_is_kept_and_an_mjcf_mujoco_refuses_is_still_returned(meshes):
    text = mjcf(
        '<geom type="mesh" mesh="gone" mass="2" pos="0.1 0 0"/><geom type="sphere" size="0.1" material="nowhere"/>',
        '<mesh name="gone" file="gone.stl"/>',
    )
    loaded = load_mjcf(write(meshes, "m.xml", text))
    skipped, refused, approximate = loaded.warnings
    assert skipped == "MJCF: 1 mesh geoms and their assets skipped, their files are absent"
    assert refused.startswith("mujoco cannot compile the MJCF (absent meshes dropped): ") and "nowhere" in refused
    assert approximate == APPROXIMATE + "b"
    assert (loaded.unknown_mass, loaded.unknown_com) == ((), ("b",))
    fixed = mujoco.MjModel.from_xml_string(loaded.text.replace(' material="nowhere"', ""))
    assert fixed.body_mass[1] == pytest.approx(2 + 1000 * 4 / 3 * np.pi * 0.1**3, rel=1e-9)


def test_mujoco_warnings_become_python_warnings_unless_a_handler_is_set():
    before = mujoco.get_mju_user_warning()
    try:
        mujoco.set_mju_user_warning(None)
        _route_mujoco_warnings(mujoco)
        assert mujoco.get_mju_user_warning() is _mujoco_warning
        own = print
        mujoco.set_mju_user_warning(own)
        _route_mujoco_warnings(mujoco)
        assert mujoco.get_mju_user_warning() is own
    finally:
        mujoco.set_mju_user_warning(before)
    with pytest.warns(UserWarning) as caught:
        _mujoco_warning("XML contains a 'NaN'")
    assert [str(w.message) for w in caught] == ["MuJoCo: XML contains a 'NaN'"]


def test_load_mjcf_routes_mujocos_warnings(meshes):
    before = mujoco.get_mju_user_warning()
    try:
        mujoco.set_mju_user_warning(None)
        load_mjcf(write(meshes, "m.xml", mjcf("")))
        assert mujoco.get_mju_user_warning() is _mujoco_warning
    finally:
        mujoco.set_mju_user_warning(before)


def test_mjcf_bodies_of_unknown_mass_or_centre_are_all_named(meshes):
    bodies = "".join(
        f'<body name="{name}"><joint axis="0 0 1"/><geom type="mesh" mesh="gone"{mass}/></body>'
        for name, mass in (("u1", ""), ("u2", ""), ("c1", ' mass="1"'), ("c2", ' mass="2"'))
    )
    text = f'<mujoco><asset><mesh name="gone" file="gone.stl"/></asset><worldbody>{bodies}</worldbody></mujoco>'
    loaded = load_mjcf(write(meshes, "four.xml", text))
    assert loaded.warnings[-2:] == (MASSLESS + "u1, u2", APPROXIMATE + "c1, c2")
    assert (loaded.unknown_mass, loaded.unknown_com) == (("u1", "u2"), ("c1", "c2"))
