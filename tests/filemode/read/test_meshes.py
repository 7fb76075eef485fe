"""File mode keeps mesh references whose files exist (package://, relative, meshdir) and drops
the ones that are absent, with a warning either way."""

from __future__ import annotations

import re
import struct
from pathlib import Path

import mujoco
import numpy as np

from kinverify import load_spec
from kinverify.filemode.pipeline import verify_files
from kinverify.filemode.read.loading import load_mjcf, load_urdf, resolve_asset
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.run import VerifyOptions
from tests.filemode.pairs import NO_PICTURES, generated_pair, sub_once, write_pair

FAST = VerifyOptions(samples=20, fd_samples=5, suites=NO_PICTURES)


def cube_stl(path: Path, half: float = 0.02) -> None:
    """A binary STL cube (12 triangles, outward normals): the format MuJoCo reads."""
    v = np.array([[x, y, z] for x in (-half, half) for y in (-half, half) for z in (-half, half)])
    faces = [
        (0, 1, 3),
        (0, 3, 2),
        (4, 6, 7),
        (4, 7, 5),
        (0, 4, 5),
        (0, 5, 1),
        (2, 3, 7),
        (2, 7, 6),
        (0, 2, 6),
        (0, 6, 4),
        (1, 5, 7),
        (1, 7, 3),
    ]
    data = bytearray(b"kinverify test cube".ljust(80, b" ") + struct.pack("<I", len(faces)))
    for a, b, c in faces:
        n = np.cross(v[b] - v[a], v[c] - v[a])
        if np.dot(n, v[a] + v[b] + v[c]) < 0:
            b, c = c, b
            n = -n
        data += struct.pack("<12fH", *(n / np.linalg.norm(n)), *v[a], *v[b], *v[c], 0)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(bytes(data))


def ros_style_pair(tmp: Path) -> tuple[Path, Path]:
    """arm3 as mypkg/urdf/arm3.urdf (meshes by package://) and mypkg/mjcf/arm3.xml (meshdir), with
    one mesh present on link1 and one absent on link2 in each file."""
    spec = load_spec("models/arm3.toml")
    cube_stl(tmp / "mypkg" / "meshes" / "cube.stl")
    urdf = generate_urdf(spec)
    for link, name in (("link1", "cube.stl"), ("link2", "missing.stl")):
        visual = f'<visual><geometry><mesh filename="package://mypkg/meshes/{name}"/></geometry></visual>'
        urdf = re.sub(rf'(<link name="{link}">)', rf"\1{visual}", urdf, count=1)
    mjcf = generate_mjcf(spec).replace('<compiler angle="radian"', '<compiler meshdir="../meshes" angle="radian"')
    mjcf = mjcf.replace(
        "  <worldbody>",
        '  <asset><mesh name="cube" file="cube.stl"/><mesh name="gone" file="missing.stl"/></asset>\n  <worldbody>',
        1,
    )
    mjcf = re.sub(r'(<body name="link1"[^>]*>\n\s*<joint[^>]*/>)', r'\1<geom name="c1" type="mesh" mesh="cube"/>', mjcf, count=1)
    mjcf = re.sub(r'(<body name="link2"[^>]*>\n\s*<joint[^>]*/>)', r'\1<geom name="c2" type="mesh" mesh="gone"/>', mjcf, count=1)
    (tmp / "mypkg" / "urdf").mkdir(parents=True)
    (tmp / "mypkg" / "mjcf").mkdir(parents=True)
    paths = tmp / "mypkg" / "urdf" / "arm3.urdf", tmp / "mypkg" / "mjcf" / "arm3.xml"
    paths[0].write_text(urdf)
    paths[1].write_text(mjcf)
    return paths


def test_resolve_asset_forms(tmp_path):
    cube_stl(tmp_path / "pkg" / "meshes" / "a.stl")
    model_dir = tmp_path / "pkg" / "urdf"
    model_dir.mkdir()
    found = (tmp_path / "pkg" / "meshes" / "a.stl").resolve()
    assert resolve_asset("package://pkg/meshes/a.stl", model_dir) == found
    assert resolve_asset("../meshes/a.stl", model_dir) == found
    assert resolve_asset(f"file://{found}", model_dir) == found
    assert resolve_asset(str(found), model_dir) == found
    assert resolve_asset("package://pkg/meshes/b.stl", model_dir) is None
    assert resolve_asset("package://other/meshes/a.stl", model_dir) is None


def test_existing_meshes_are_kept_and_absent_ones_dropped(tmp_path):
    urdf_path, mjcf_path = ros_style_pair(tmp_path)
    urdf, mjcf = load_urdf(str(urdf_path)), load_mjcf(str(mjcf_path))
    cube = str((tmp_path / "mypkg" / "meshes" / "cube.stl").resolve())
    assert f'filename="{cube}"' in urdf.text and "missing.stl" not in urdf.text
    assert any("1 mesh visual/collision elements skipped" in w for w in urdf.warnings)
    assert any("1 mesh references resolved" in w for w in urdf.warnings)
    assert f'file="{cube}"' in mjcf.text and "missing.stl" not in mjcf.text and 'name="c2"' not in mjcf.text
    assert any("1 mesh assets resolved" in w for w in mjcf.warnings)
    model = mujoco.MjModel.from_xml_string(mjcf.text)  # loads from any folder: absolute path
    assert model.nmesh == 1 and model.mesh_vertnum[0] == 8


def test_file_mode_runs_with_a_resolved_mesh(tmp_path):
    urdf_path, mjcf_path = ros_style_pair(tmp_path)
    result = verify_files(str(urdf_path), str(mjcf_path), FAST)
    assert result.verdict == "pass", [c for c in result.checks if not c.passed][:3]
    assert any("resolved to existing files" in n for n in result.notes)


def test_collada_meshes_do_not_stop_mujocos_urdf_import(tmp_path):
    urdf_path, mjcf_path = ros_style_pair(tmp_path)
    (tmp_path / "mypkg" / "meshes" / "visual.dae").write_text("<COLLADA/>")
    text = urdf_path.read_text().replace("missing.stl", "visual.dae")
    urdf_path.write_text(text)
    assert ".dae" in load_urdf(str(urdf_path)).text  # kept: the file exists
    result = verify_files(str(urdf_path), str(mjcf_path), FAST)
    assert "mujoco-urdf" in result.backends and result.verdict == "pass"


def test_a_mesh_geom_given_its_mesh_by_a_default_class_is_dropped_with_it(tmp_path):
    """A fingertip geom with no mesh attribute of its own takes ``mesh="tip"`` from its default
    class (as MuJoCo Menagerie's LEAP hand writes it): the absent mesh is dropped with the geom, and
    the default class no longer names it, so MuJoCo loads the file."""
    urdf, mjcf = generated_pair("arm3")
    mjcf = sub_once(r"<default>", '<default><default class="tip"><geom type="mesh" mesh="tip"/></default>', mjcf)
    mjcf = sub_once(r"<worldbody>", '<asset><mesh name="tip" file="absent/tip.stl"/></asset><worldbody>', mjcf)
    mjcf = sub_once(r'(<body name="link3"[^>]*>)', lambda m: m[1] + '<geom name="tip" class="tip"/>', mjcf)
    _, path = write_pair(tmp_path, urdf, mjcf)
    loaded = load_mjcf(path)
    assert 'name="tip"' not in loaded.text.split("<worldbody>")[1] and 'mesh="tip"' not in loaded.text
    assert not [w for w in loaded.warnings if "cannot compile" in w]


FITTED_URDF = """<robot name="two">
  <link name="base_link"><inertial><mass value="2"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="link1"><inertial><origin xyz="0 0 0.1"/><mass value="1"/>
    <inertia ixx="0.002" iyy="0.002" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="joint1" type="revolute"><parent link="base_link"/><child link="link1"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="10" velocity="1"/></joint>
</robot>
"""
FITTED_MJCF = """<mujoco model="two">
  <compiler angle="radian" meshdir="assets"/>
  <default><default class="collision"><geom type="capsule" group="3"/></default></default>
  <asset><mesh name="base_link" file="base_link.stl"/><mesh name="link1" file="link1.stl"/></asset>
  <worldbody>
    <body name="base_link">
      <inertial pos="0 0 0" mass="2" diaginertia="0.01 0.01 0.01"/>
      <geom class="collision" mesh="base_link"/>
      <body name="link1" pos="0 0 0.2">
        <inertial pos="0 0 0.1" mass="1" diaginertia="0.002 0.002 0.001"/>
        <joint name="joint1" axis="0 0 1" range="-2 2"/>
        <geom class="collision" mesh="link1"/>
        <geom type="box" size="0.01 0.01 0.01"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_primitives_fitted_to_absent_meshes_are_dropped_like_mesh_geoms(tmp_path):
    """Menagerie's collision capsules are fitted to a mesh (``<geom class="collision" mesh="link1"/>``
    whose class gives ``type="capsule"``): with the mesh absent their size is not known, so they go
    like mesh geoms, and the note says so; the robot is read and agrees."""
    (tmp_path / "two.urdf").write_text(FITTED_URDF)
    (tmp_path / "two.xml").write_text(FITTED_MJCF)
    loaded = load_mjcf(str(tmp_path / "two.xml"))
    assert 'mesh="' not in loaded.text and "<mesh " not in loaded.text and 'type="box"' in loaded.text
    assert loaded.warnings[0] == (
        "MJCF: 2 mesh geoms (2 of them primitives fitted to a mesh, whose size came from it) "
        "and their assets skipped, their files are absent"
    )
    mujoco.MjModel.from_xml_string(loaded.text)
    result = verify_files(
        str(tmp_path / "two.urdf"),
        str(tmp_path / "two.xml"),
        VerifyOptions(samples=8, fd_samples=2, backends=["pinocchio-urdf", "mujoco"]),
    )
    assert result.verdict == "pass", [(f.kind, f.message) for f in result.findings if f.severity == "error"]
    assert loaded.warnings[0] in result.notes
