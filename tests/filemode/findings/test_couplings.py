"""Couplings compared joint by joint after each file's are resolved: a chain of couplings, or one
stated the other way round, ties the same joints."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

import tests.filemode.pairs as P
from kinverify.filemode.findings.couplings import coupling_findings
from kinverify.filemode.pipeline import verify_files
from kinverify.filemode.read.model import Coupling
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import spec_from_dict
from kinverify.run import VerifyOptions
from tests.filemode.align.test_match import hand

FAST = VerifyOptions(samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], suites=["kinematics"])


def coupled(urdf: str, mjcf: str, mimics: dict, equalities: list) -> tuple[str, str]:
    """``mimics``: URDF follower -> (leader, multiplier, offset); ``equalities``: MJCF (joint1,
    joint2, multiplier, offset) meaning joint1 = offset + multiplier·joint2."""
    for follower, (leader, k, c) in mimics.items():
        urdf = P.sub_once(
            rf'(<joint name="{follower}" type="revolute">)',
            lambda m, leader=leader, k=k, c=c: m[1] + f'<mimic joint="{leader}" multiplier="{k}" offset="{c}"/>',
            urdf,
        )
    eq = "".join(f'<joint joint1="{a}" joint2="{b}" polycoef="{c} {k} 0 0 0"/>' for a, b, k, c in equalities)
    return urdf, P.sub_once(r"</mujoco>", f"<equality>{eq}</equality></mujoco>", mjcf)


def test_a_chain_of_couplings_is_the_coupling_it_makes(tmp_path):
    """URDF: ring_base = −1·index_tip, index_tip = 1·index_base (a chain); MJCF: ring_base =
    −1·index_base and index_base = 1·index_tip (stated the other way round). One coupling, no finding."""
    spec = spec_from_dict(hand())
    urdf, mjcf = coupled(
        generate_urdf(spec),
        generate_mjcf(spec),
        {"index_tip": ("index_base", 1.0, 0.0), "ring_base": ("index_tip", -1.0, 0.0)},
        [("ring_base", "index_base", -1.0, 0.0), ("index_base", "index_tip", 1.0, 0.0)],
    )
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), FAST)
    assert not [f for f in result.findings if f.kind.startswith("coupling")], [f.message for f in result.findings]
    assert result.passed


def test_a_coupling_with_another_offset_is_a_difference(tmp_path):
    spec = spec_from_dict(hand())
    urdf, mjcf = coupled(
        generate_urdf(spec), generate_mjcf(spec), {"index_tip": ("index_base", 1.0, 0.1)}, [("index_tip", "index_base", 1.0, 0.2)]
    )
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), FAST)
    (f,) = [f for f in result.findings if f.kind.startswith("coupling")]
    assert f.kind == "coupling_difference" and f.values == {"urdf": [1.0, 0.1], "mjcf": [1.0, 0.2]}


def test_a_coupling_on_a_reversed_leader_is_compared_in_the_urdfs_joint_coordinates(tmp_path):
    """The MJCF reverses index_base's axis (q_mjcf = −q_urdf) and states index_tip's coupling in its
    own coordinates, index_tip = −1·index_base: the URDF's index_tip = 1·index_base, the same motion.
    The reversed axis is the one finding; no coupling differs."""
    spec = spec_from_dict(hand())
    urdf, mjcf = P.flipped_axis(generate_urdf(spec), generate_mjcf(spec), "index_base")
    urdf, mjcf = coupled(urdf, mjcf, {"index_tip": ("index_base", 1.0, 0.0)}, [("index_tip", "index_base", -1.0, 0.0)])
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), FAST)
    assert not [f for f in result.findings if f.kind.startswith("coupling")], [f.message for f in result.findings]
    assert [f.subject for f in result.findings if f.kind == "axis_sign_flip"] == ["index_base"]


def test_the_same_written_coupling_on_a_reversed_leader_is_a_difference(tmp_path):
    """Both files write index_tip = 1·index_base, but the MJCF's index_base turns the other way: for
    the same pose of index_base the tips turn opposite ways. In the URDF's coordinates the MJCF's
    coupling reads index_tip = −1·index_base."""
    spec = spec_from_dict(hand())
    urdf, mjcf = P.flipped_axis(generate_urdf(spec), generate_mjcf(spec), "index_base")
    urdf, mjcf = coupled(urdf, mjcf, {"index_tip": ("index_base", 1.0, 0.0)}, [("index_tip", "index_base", 1.0, 0.0)])
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), FAST)
    (f,) = [f for f in result.findings if f.kind.startswith("coupling")]
    assert f.kind == "coupling_difference" and f.subject == "index_tip"
    assert f.values == {"urdf": [1.0, 0.0], "mjcf": [-1.0, 0.0]}


def test_a_followers_fitted_zero_offset_is_taken_off_its_coupling():
    """The MJCF's index_tip zero sits 0.3 rad further (q_mjcf = q_urdf + 0.3, fitted): its coupling
    index_tip = index_base + 0.4 in its own coordinates is the URDF's index_tip = index_base + 0.1
    (0.4 − 0.3); the same 0.1 written in the MJCF is 0.3 away. The leader has no offset."""
    order = ["index_base", "index_tip"]
    u = SimpleNamespace(
        couplings=[Coupling("index_tip", "index_base", 1.0, 0.1, "<mimic>")], joint=lambda name: SimpleNamespace(type="revolute")
    )
    matching = SimpleNamespace(joints=[(n, n, "name") for n in order])
    alignment = SimpleNamespace(
        joints=[SimpleNamespace(urdf="index_base", sign=1, offset=0.0), SimpleNamespace(urdf="index_tip", sign=1, offset=0.3)]
    )

    def findings(c: float) -> list:
        m = SimpleNamespace(couplings=[Coupling("index_tip", "index_base", 1.0, c, "<equality joint>")])
        return [(f.kind, f.subject, f.values["mjcf"]) for f in coupling_findings(u, m, matching, alignment)]

    assert findings(0.4) == []
    ((kind, subject, (k, c)),) = findings(0.1)
    assert (kind, subject, k) == ("coupling_difference", "index_tip", 1.0) and c == pytest.approx(-0.2, abs=1e-12)
