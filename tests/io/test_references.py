"""Files a model makes a library open: an SDFormat file's ``<include>`` models (a model folder's
``model.config``, includes inside includes, any declared encoding) handed to Drake as checked
snapshots, and the files MuJoCo would open for an MJCF (meshes and textures in their folders, a
``<model file>`` followed into its own includes), each pinned on a small tree of files."""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from kinverify.errors import InputError
from kinverify.io.references import Budget, mjcf_files, sdf_for_drake

SDF = "<sdf version='1.9'><model name='{}'><link name='{}'/>{}</model></sdf>"


def include(uri: str) -> str:
    return f"<include><uri>{uri}</uri></include>"


def test_an_sdf_that_includes_nothing_is_handed_over_as_it_is(tmp_path):
    text = SDF.format("m", "a", "")
    assert sdf_for_drake(text, ET.fromstring(text), tmp_path / "m.sdf") is text


def test_included_models_are_snapshots_with_their_own_includes_rewritten(tmp_path):
    part = tmp_path / "part"
    part.mkdir()
    (part / "model.config").write_text("<model><sdf> part.sdf </sdf></model>")
    (part / "part.sdf").write_text(SDF.format("part", "p", include("leaf")))
    (part / "leaf").mkdir()
    # a model folder without model.config: model.sdf; Latin-1 declared, not UTF-8
    leaf = '<?xml version="1.0" encoding="latin-1"?>\n' + SDF.format("leaf", "l", "<!-- caf\xe9 -->")
    (part / "leaf" / "model.sdf").write_bytes(leaf.encode("latin-1"))
    text = SDF.format("m", "a", include("part"))
    out = sdf_for_drake(text, ET.fromstring(text), tmp_path / "m.sdf")
    snapshot = Path(ET.fromstring(out).findtext(".//include/uri"))
    assert snapshot.name.endswith("-part.sdf") and snapshot.parent != part
    inner = ET.fromstring(snapshot.read_text(encoding="utf-8"))
    assert inner.find(".//link").get("name") == "p"
    leaf_snapshot = Path(inner.findtext(".//include/uri"))
    assert leaf_snapshot.name.endswith("-model.sdf") and "<link name='l'/>" in leaf_snapshot.read_text(encoding="utf-8")


def test_a_model_including_itself_is_refused(tmp_path):
    (tmp_path / "m.sdf").write_text(SDF.format("m", "a", include("m.sdf")))
    text = (tmp_path / "m.sdf").read_text()
    with pytest.raises(InputError, match=r"the file includes itself \(m.sdf -> m.sdf\)"):
        sdf_for_drake(text, ET.fromstring(text), tmp_path / "m.sdf")


def test_mjcf_files_in_their_folders_and_a_model_file_followed(tmp_path):
    for folder in ("meshes", "tex", "parts"):
        (tmp_path / folder).mkdir()
    (tmp_path / "meshes" / "m.stl").write_bytes(b"solid")
    (tmp_path / "tex" / "h.png").write_bytes(b"png")
    (tmp_path / "tex" / "t.png").write_bytes(b"png")
    os.mkfifo(tmp_path / "meshes" / "t.png")  # MuJoCo looks for a texture in texturedir only: never opened
    (tmp_path / "parts" / "sub.xml").write_text('<mujoco><asset><mesh file="s.stl"/></asset></mujoco>')
    (tmp_path / "parts" / "s.stl").write_bytes(b"solid")
    root = ET.fromstring(
        '<mujoco><compiler meshdir="meshes" texturedir="tex"/><asset><mesh file="m.stl"/><mesh file="absent.stl"/>'
        '<hfield file="h.png"/><texture file="t.png"/><model file="parts/sub.xml"/></asset></mujoco>'
    )
    found = mjcf_files(root, tmp_path / "m.xml")
    mesh, _, hfield, texture, model = root.find("asset")
    assert found == {
        (mesh, "file"): (tmp_path / "meshes" / "m.stl").resolve(),
        (hfield, "file"): (tmp_path / "tex" / "h.png").resolve(),
        (texture, "file"): (tmp_path / "tex" / "t.png").resolve(),
        (model, "file"): (tmp_path / "parts" / "sub.xml").resolve(),
    }


def test_a_model_files_include_errors_name_the_model_file(tmp_path):
    (tmp_path / "sub.xml").write_text("<mujoco><include/></mujoco>")
    main = tmp_path / "m.xml"
    with pytest.raises(InputError) as err:
        mjcf_files(ET.fromstring('<mujoco><asset><model file="sub.xml"/></asset></mujoco>'), main)
    assert str(err.value) == f"{main}: <model file='sub.xml'>: {tmp_path / 'sub.xml'}: an <include> has no file"


def test_a_file_over_what_the_models_data_files_left_names_the_shared_budget(tmp_path):
    (tmp_path / "a.stl").write_bytes(b"x" * 200)
    (tmp_path / "b.png").write_bytes(b"x" * 100)
    text = '<mujoco><asset><mesh file="a.stl"/><texture name="t" type="2d" file="b.png"/></asset></mujoco>'
    budget = Budget()
    budget.data = 250  # 256 MB less 250 bytes already read: a.stl fits, b.png then does not
    with pytest.raises(InputError) as err:
        mjcf_files(ET.fromstring(text), tmp_path / "m.xml", budget)
    assert str(err.value) == (
        f"{tmp_path / 'm.xml'}: <texture file='b.png'>: {tmp_path / 'b.png'} is 100 bytes, which would exceed the "
        "256 MB all meshes, textures and other data files of the model share: 256.0 MB already read "
        "(see docs/robustness.md)"
    )
