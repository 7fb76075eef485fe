"""What file mode hands the suites: kinverify.filemode.compare.context's defaults, tolerances,
floors and spec mode's view of the generated files, pinned."""

from __future__ import annotations

import math

import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.backends.sources import ModelSources
from kinverify.filemode.align.match import Matching
from kinverify.filemode.align.result import Alignment
from kinverify.filemode.compare.context import FileModeInfo, aligned_poses, file_view
from kinverify.filemode.read.precision import Floors
from kinverify.run import VerifyOptions
from kinverify.suites.base import VerifyContext


def pose(xyz, angle=0.0) -> np.ndarray:
    t = np.eye(4)
    c, s = math.cos(angle), math.sin(angle)
    t[:3, :3] = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
    t[:3, 3] = xyz
    return t


def bare(**kw) -> FileModeInfo:
    matching = Matching([("a", "x", "name"), ("b", "y", "axis")], [], [], [("l1", "b1", "name"), ("l2", "b2", "position")])
    return FileModeInfo(None, None, matching, Alignment(np.eye(4), [], {}, []), **kw)


def test_a_view_of_two_files_starts_in_file_mode_with_nothing_set():
    info = bare()
    assert (info.floating, info.file_mode, info.base_coordinates) == (False, True, False)
    assert (info.mjcf_angle, info.inertials_explained_by) == ("radian", "")
    assert [p.file for p in info.precision] == ["URDF", "MJCF"]
    assert info.notes == [] and info.inertial_results == [] and info.user_tolerances == frozenset()
    assert info.poses_u == {} and info.poses_m == {} and info.floors == Floors()
    assert bare().notes is not info.notes  # each view its own notes


def test_pairs_read_from_the_matching():
    info = bare()
    assert info.joint_pairs == [("a", "x"), ("b", "y")]
    assert info.frame_pairs == [("l1", "b1"), ("l2", "b2")]


def test_a_frames_tolerance_is_double_precision_at_its_distance_plus_twice_its_floor():
    info = bare(
        floors=Floors(frames={"far": (1e-4, 2e-4)}), poses_u={"far": pose((0.5, -3.0, 2.0)), "near": pose((0.2, 0.1, 0.0))}
    )
    assert info.tol("far") == pytest.approx((3e-9 + 2e-4, 1e-9 + 4e-4), rel=1e-12)
    assert info.tol("near") == pytest.approx((1e-9, 1e-9), rel=1e-12)  # within 1 m: 1e-9
    assert info.tol("nowhere") == pytest.approx((1e-9, 1e-9), rel=1e-12)
    info = bare(floors=Floors(frames={"x": (1e-4, 2e-4)}))
    assert info.tol("x") == pytest.approx((1e-9 + 2e-4, 1e-9 + 4e-4), rel=1e-12)


def test_a_floor_applies_unless_the_user_set_that_property():
    info = bare(user_tolerances=frozenset({"inertia.mass"}))
    assert info.floor("inertia.mass", 0.5) == 0.0
    assert info.floor("inertia.com", 0.5) == 0.5


def test_mjcf_poses_are_brought_into_the_urdfs_world():
    t = pose((1.0, 2.0, 0.0), 0.5)
    al = Alignment(t, [], {}, [])
    out = aligned_poses(al, {"a": t @ pose((0.1, 0.0, 0.3), 0.2), "b": t})
    np.testing.assert_allclose(out["a"], pose((0.1, 0.0, 0.3), 0.2), atol=1e-15)
    np.testing.assert_allclose(out["b"], np.eye(4), atol=1e-15)
    assert list(out) == ["a", "b"]


@pytest.fixture(scope="module")
def arm3() -> ModelSources:
    urdf, mjcf = P.generated_pair("arm3")
    mjcf = mjcf.replace('"joint3"', '"joint3_mj"')  # a joint the MJCF names otherwise: no pair by name
    names = ("joint1", "joint2", "joint3", "nowhere")
    return ModelSources("arm3", names, ("end_effector",), (-1.0,) * 4, (1.0,) * 4, (True,) * 4, urdf=urdf, mjcf=mjcf)


def test_spec_mode_pairs_the_generated_files_by_name(arm3):
    info = FileModeInfo.from_sources(arm3)
    assert info.file_mode is False and info.floating is False
    assert info.joint_pairs == [("joint1", "joint1"), ("joint2", "joint2")]  # in both files only
    assert info.matching.joints[0] == ("joint1", "joint1", "name")
    assert (info.matching.unmatched_urdf, info.matching.unmatched_mjcf) == ([], [])
    assert info.frame_pairs == [(f, f) for f in ("base", "link1", "link2", "link3", "end_effector")]  # "world" is the URDF's only
    al = info.alignment
    np.testing.assert_array_equal(al.T, np.eye(4))
    assert [(j.urdf, j.mjcf, j.type, j.sign, j.offset) for j in al.joints] == [
        (n, n, "revolute", 1, 0.0) for n in ("joint1", "joint2")
    ]
    assert al.couplings == {} and al.independent == ["joint1", "joint2"]
    assert set(info.poses_u) == set(info.u.frames) and set(info.poses_m) == set(info.m.frames)
    np.testing.assert_array_equal(info.poses_m["end_effector"], info.m.frames["end_effector"])
    assert (info.u.kind, info.m.kind) == ("urdf", "mjcf")


def test_a_suite_sees_file_modes_view_or_spec_modes(arm3):
    handed = bare()
    ctx = VerifyContext(arm3, {}, [], VerifyOptions(extra={"filemode": handed}))
    assert file_view(ctx) is handed
    view = file_view(VerifyContext(arm3, {}, [], VerifyOptions()))
    assert view is not None and view.file_mode is False and len(view.joint_pairs) == 2
    for missing in ({"urdf": None}, {"mjcf": None}):
        lacking = ModelSources(**{**arm3.__dict__, **missing})
        assert file_view(VerifyContext(lacking, {}, [], VerifyOptions())) is None
