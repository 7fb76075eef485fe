"""``kinverify diff`` of two URDFs (Pinocchio) or two MJCFs (MuJoCo): parameter and behaviour changes."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify import load_spec
from kinverify.testing import strategies as kst
from kinverify.cli import main
from kinverify.errors import InputError
from kinverify.regression.filediff import diff_files, file_kind
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.kinematics import frame_link_indices
from kinverify.model.spec import Origin
from tests.paths import MODELS


def moved_joint(spec, index: int, offset):
    """``spec`` with joint ``index``'s origin moved by ``offset`` [m] (in its parent link's frame)."""
    joints = list(spec.joints)
    o = joints[index].origin
    joints[index] = replace(joints[index], origin=Origin(tuple(float(a + b) for a, b in zip(o.xyz, offset, strict=True)), o.rpy))
    return replace(spec, joints=tuple(joints))


def write_pair(tmp_path: Path, old_text: str, new_text: str, suffix: str) -> tuple[str, str]:
    a, b = tmp_path / f"old{suffix}", tmp_path / f"new{suffix}"
    a.write_text(old_text)
    b.write_text(new_text)
    return str(a), str(b)


def check_one_joint_moved(diff, spec, index: int, size: float) -> None:
    """The only parameter change is joint ``index``'s origin, by ``size``; every frame riding on
    the links after that joint moves by exactly ``size``, every other frame does not move."""
    name = spec.joints[index].name
    # the generated MJCF also marks the tool's home position with a fixed site `target`
    (change,) = [c for c in diff.params if c.where != "frame target"]
    assert (change.where, change.field) == (f"joint {name}", "origin.xyz")
    assert change.delta == pytest.approx(size, rel=1e-9)
    assert all(c.field == "origin.xyz" and c.delta <= size + 1e-12 for c in diff.params if c.where == "frame target")
    riding = dict(zip(spec.frame_names, frame_link_indices(spec), strict=True))
    for f in diff.frames:
        if f.frame in riding:
            downstream = riding[f.frame] > index
            assert f.position == pytest.approx(size if downstream else 0.0, rel=1e-9, abs=1e-14), f.frame
        assert f.rotation < 1e-12
    assert {f.frame for f in diff.frames} >= set(spec.frame_names)
    for r in diff.reach:
        assert abs(r.change) <= size + 1e-12


@settings(max_examples=10, deadline=None)
@given(spec=kst.arm_specs(max_joints=6), data=st.data())
def test_a_1mm_change_in_a_generated_urdf_is_reported_at_its_joint(tmp_path_factory, spec, data):
    index = data.draw(st.integers(0, spec.dof - 1), label="joint")
    direction = np.array(data.draw(kst.axes(), label="direction"), dtype=float)
    direction /= np.linalg.norm(direction)
    new = moved_joint(spec, index, 1e-3 * direction)
    old_path, new_path = write_pair(tmp_path_factory.mktemp("u"), generate_urdf(spec), generate_urdf(new), ".urdf")
    check_one_joint_moved(diff_files(old_path, new_path, samples=10), spec, index, 1e-3)


@settings(max_examples=6, deadline=None)
@given(spec=kst.arm_specs(max_joints=6), data=st.data())
def test_a_1mm_change_in_a_generated_mjcf_is_reported_at_its_joint(tmp_path_factory, spec, data):
    index = data.draw(st.integers(0, spec.dof - 1), label="joint")
    direction = np.array(data.draw(kst.axes(), label="direction"), dtype=float)
    direction /= np.linalg.norm(direction)
    new = moved_joint(spec, index, 1e-3 * direction)
    old_path, new_path = write_pair(tmp_path_factory.mktemp("m"), generate_mjcf(spec), generate_mjcf(new), ".xml")
    check_one_joint_moved(diff_files(old_path, new_path, samples=10), spec, index, 1e-3)


@pytest.mark.parametrize("model", ["arm3", "ur5e", "panda", "scara"])
def test_identical_files_have_no_differences(tmp_path, model):
    spec = load_spec(MODELS / f"{model}.toml")
    for text, suffix in ((generate_urdf(spec), ".urdf"), (generate_mjcf(spec), ".xml")):
        old, new = write_pair(tmp_path, text, text, suffix)
        d = diff_files(old, new, samples=5)
        assert d.identical and d.params == [] and d.frames and d.samples > 5
        assert all(f.position == f.rotation == f.jacobian_linear == f.jacobian_angular == 0 for f in d.frames)
        assert all(r.change == 0 for r in d.reach) and d.reach


def test_a_heavier_link_and_a_renamed_joint(tmp_path):
    spec = load_spec(MODELS / "panda.toml")
    urdf = generate_urdf(spec)
    link = spec.joints[1].link
    heavier = urdf.replace(f'<mass value="{link.inertial.mass!r}"/>', f'<mass value="{1.2 * link.inertial.mass!r}"/>')
    assert heavier != urdf
    d = diff_files(*write_pair(tmp_path, urdf, heavier, ".urdf"), samples=5)
    (change,) = d.params
    assert (change.where, change.field) == (f"inertia moving with {spec.joints[1].name}", "mass")
    assert change.delta == pytest.approx(0.2 * link.inertial.mass, rel=1e-9)
    assert all(f.position == 0 for f in d.frames)  # kinematics untouched
    # a joint renamed: paired by chain order (same type, same angle to its parent axis)
    renamed = urdf.replace('name="panda_joint7"', 'name="wrist_roll"')
    d = diff_files(*write_pair(tmp_path, urdf, renamed, ".urdf"), samples=5)
    assert [(c.where, c.field, c.old, c.new) for c in d.params] == [("joint panda_joint7", "name", "panda_joint7", "wrist_roll")]
    assert all(f.position == 0 for f in d.frames) and len(d.frames) == len(spec.frame_names) + 1  # + world


def test_a_reexport_without_the_name_prefix_is_still_compared(tmp_path):
    spec = load_spec(MODELS / "panda.toml")
    urdf = generate_urdf(spec)
    stripped = generate_urdf(moved_joint(spec, 3, (0.0, 0.0, 1e-3))).replace("panda_", "")
    d = diff_files(*write_pair(tmp_path, urdf, stripped, ".urdf"), samples=5)
    renames = {c.old: c.new for c in d.params if c.field == "name"}
    assert renames["panda_joint4"] == "joint4" and renames["panda_link4"] == "link4" and renames["panda_link0"] == "link0"
    assert not [c for c in d.params if c.kind in ("added", "removed")]
    (moved,) = [c for c in d.params if c.field != "name"]
    assert (moved.where, moved.field) == ("joint panda_joint4", "origin.xyz") and moved.delta == pytest.approx(1e-3, rel=1e-9)
    moving = {f.frame for f in d.frames if f.position > 0}
    assert moving == {"panda_link4", "panda_link5", "panda_link6", "panda_link7", "flange"}
    assert all(f.position == pytest.approx(1e-3, rel=1e-9) for f in d.frames if f.frame in moving)
    assert not any("held at 0" in n for n in d.notes)


def test_cli_files_mixed_types_and_reports(tmp_path, capsys):
    spec = load_spec(MODELS / "arm3.toml")
    urdf, mjcf = generate_urdf(spec), generate_mjcf(spec)
    old, new = write_pair(tmp_path, urdf, generate_urdf(moved_joint(spec, 2, (0.0, 0.0, 1e-3))), ".urdf")
    report = tmp_path / "diff.html"
    assert main(["diff", old, new, "--samples", "10", "--report", str(report)]) == 1
    out = capsys.readouterr().out
    assert "joint joint3" in out and "origin.xyz" in out and "CHANGED" in out and "+0.001000" in out
    assert "joint joint3" in report.read_text() and "workspace reach" in report.read_text()
    assert main(["diff", old, old, "--samples", "5", "--report", str(tmp_path / "same.html")]) == 0
    assert "IDENTICAL" in capsys.readouterr().out
    xml = tmp_path / "arm3.xml"
    xml.write_text(mjcf)
    before = report.read_bytes()
    for args in ([old, str(xml)], [str(xml), old]):
        assert main(["diff", *args, "--report", str(report)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "Traceback" not in err
        assert re.search(r"kinverify verify --urdf \S+\.urdf --mjcf \S+arm3\.xml", err)
    assert main(["diff", str(MODELS / "arm3.toml"), old]) == 2
    assert "is a spec and" in capsys.readouterr().err
    assert report.read_bytes() == before  # nothing written on bad input


def test_bad_files_are_one_line_errors(tmp_path):
    good = tmp_path / "a.urdf"
    good.write_text(generate_urdf(load_spec(MODELS / "arm3.toml")))
    broken = tmp_path / "b.urdf"
    broken.write_text("<robot name='x'><link name='a'>")
    with pytest.raises(InputError, match="is not XML"):
        diff_files(str(good), str(broken))
    with pytest.raises(InputError, match="is not a file"):
        diff_files(str(good), str(tmp_path / "missing.urdf"))
    assert file_kind(str(good)) == "urdf" and file_kind(str(MODELS / "arm3.toml")) is None


def test_two_kinds_of_file_are_named_in_order(tmp_path):
    spec = load_spec(MODELS / "arm3.toml")
    urdf, xml = tmp_path / "a.urdf", tmp_path / "a.xml"
    urdf.write_text(generate_urdf(spec))
    xml.write_text(generate_mjcf(spec))
    with pytest.raises(InputError, match=f"^{re.escape(f'{urdf} is a URDF and {xml} an MJCF: diff compares')}"):
        diff_files(str(urdf), str(xml))
    with pytest.raises(InputError, match=f"^{re.escape(f'{xml} is an MJCF and {urdf} a URDF: diff compares')}"):
        diff_files(str(xml), str(urdf))


def test_the_sample_count_is_the_edges_and_the_uniform_draws(tmp_path):
    text = generate_urdf(load_spec(MODELS / "arm3.toml"))
    old, new = write_pair(tmp_path, text, text, ".urdf")
    assert diff_files(old, new, samples=7).samples == diff_files(old, new, samples=3).samples + 4


def test_files_with_nothing_in_common_are_not_compared_frame_by_frame(tmp_path):
    old, new = tmp_path / "arm3.urdf", tmp_path / "lift.urdf"
    old.write_text(generate_urdf(load_spec(MODELS / "arm3.toml")))
    new.write_text(generate_urdf(load_spec(MODELS / "lift.toml")))
    d = diff_files(str(old), str(new), samples=3)
    assert "no common joints or frames: FK and Jacobians not compared" in d.notes and d.frames == [] and d.samples == 0


def test_a_frame_that_moves_most_where_it_turns_least_is_reported_where_it_moves_most(tmp_path):
    # joint3's origin turned by 0.01 rad about z: link3 turns by 0.01 rad at every configuration,
    # the end effector (0.05 m along link3's z) moves by 0.05 |sin q3| 2 sin(0.005), most where
    # q3 is nearest ±90°: that configuration is reported, not the first one
    spec = load_spec(MODELS / "arm3.toml")
    joints = list(spec.joints)
    joints[2] = replace(joints[2], origin=Origin(joints[2].origin.xyz, (0.0, 0.0, 0.01)))
    old, new = write_pair(tmp_path, generate_urdf(spec), generate_urdf(replace(spec, joints=tuple(joints))), ".urdf")
    d = diff_files(old, new, samples=6)
    ee = next(f for f in d.frames if f.frame == "end_effector")
    assert ee.rotation == pytest.approx(0.01, abs=1e-9) and ee.position > 1e-4
    assert ee.position == pytest.approx(0.05 * abs(np.sin(ee.q[2])) * 2 * np.sin(0.005), rel=1e-6)
