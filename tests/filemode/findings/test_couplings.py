"""Couplings compared joint by joint after each file's are resolved: a chain of couplings, or one
stated the other way round, ties the same joints."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.filemode.findings.couplings import coupling_findings, written_alike
from kinverify.filemode.pipeline import verify_files
from kinverify.filemode.read.model import Coupling
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import spec_from_dict
from kinverify.run import VerifyOptions
from tests.filemode.align.test_match import hand

FAST = VerifyOptions(samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], suites=["kinematics"])
LIMITS = VerifyOptions(samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], suites=["kinematics", "limits"])


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


def coupling_table(offsets: dict, urdf_coupling: Coupling, lower=-1.0, upper=1.0):
    """``coupling_findings`` on the bare tables: index_tip follows index_base in both files; the
    alignment's fitted zero ``offsets`` (joint -> offset, signs +1); ``urdf_coupling`` the URDF's.
    Returns a function of the MJCF's coupling giving (kind, subject, mjcf values, magnitude, unit)."""
    order = ["index_base", "index_tip"]
    u = SimpleNamespace(couplings=[urdf_coupling], joint=lambda name: SimpleNamespace(type="revolute", lower=lower, upper=upper))
    matching = SimpleNamespace(joints=[(n, n, "name") for n in order])
    alignment = SimpleNamespace(joints=[SimpleNamespace(urdf=n, sign=1, offset=offsets.get(n, 0.0)) for n in order])

    def findings(k: float, c: float) -> list:
        m = SimpleNamespace(couplings=[Coupling("index_tip", "index_base", k, c, "<equality joint>")])
        return [(f.kind, f.subject, f.values["mjcf"], f.magnitude, f.unit) for f in coupling_findings(u, m, matching, alignment)]

    return findings, (u, matching, alignment)


def test_a_followers_fitted_zero_offset_is_taken_off_its_coupling():
    """The MJCF's index_tip zero sits 0.3 rad further (q_mjcf = q_urdf + 0.3, fitted): its coupling
    index_tip = index_base + 0.4 in its own coordinates is the URDF's index_tip = index_base + 0.1
    (0.4 − 0.3): no finding. The same 0.1 written in the MJCF (its own zero) is the zero offset's
    consequence, said by the zero offset finding: no coupling finding either. 0.2 written differs
    from both readings; by 0.1 beyond the offset (read in each file's own zero), not the 0.2 the
    offset-carried reading leaves (−0.1 against 0.1)."""
    findings, (u, matching, alignment) = coupling_table(
        {"index_tip": 0.3}, Coupling("index_tip", "index_base", 1.0, 0.1, "<mimic>")
    )
    assert findings(1.0, 0.4) == []
    assert findings(1.0, 0.1) == []
    m = SimpleNamespace(couplings=[Coupling("index_tip", "index_base", 1.0, 0.1, "<equality joint>")])
    assert written_alike(u, m, matching, alignment) == {"index_tip": "index_base"}
    ((kind, subject, (k, c), size, unit),) = findings(1.0, 0.2)
    assert (kind, subject, k, unit) == ("coupling_difference", "index_tip", 1.0, "rad")
    assert c == pytest.approx(-0.1, abs=1e-12) and size == pytest.approx(0.1, abs=1e-12)


def test_a_leaders_zero_offset_is_no_coupling_difference_when_each_file_writes_the_coupling_alike():
    """index_base's zero sits 0.2 rad further in the MJCF (its frame turned about its axis); both
    files write index_tip = 0.5·index_base. In the URDF's coordinates the MJCF's reads
    index_tip = 0.5·index_base + 0.1: the leader's offset carried, not a coupling that changed."""
    findings, (u, matching, alignment) = coupling_table(
        {"index_base": 0.2}, Coupling("index_tip", "index_base", 0.5, 0.0, "<mimic>")
    )
    assert findings(0.5, 0.0) == []
    m = SimpleNamespace(couplings=[Coupling("index_tip", "index_base", 0.5, 0.0, "<equality joint>")])
    assert written_alike(u, m, matching, alignment) == {"index_tip": "index_base"}
    assert findings(0.5, -0.1) == []  # the offset compensated in the MJCF's coupling: the same motion


def test_a_coupling_difference_has_the_size_the_follower_sits_apart_over_the_leaders_range():
    """No offsets: index_tip = 1·index_base in the URDF, 1.5·index_base + 0.1 in the MJCF: over the
    leader's range [−1, 1] the follower sits up to 0.5 + 0.1 = 0.6 rad apart (at q = 1). A size of
    0 or None would say nothing; the offset alone (0.1) would understate it."""
    findings, _ = coupling_table({}, Coupling("index_tip", "index_base", 1.0, 0.0, "<mimic>"))
    ((kind, subject, _, size, unit),) = findings(1.5, 0.1)
    assert (kind, subject, unit) == ("coupling_difference", "index_tip", "rad")
    assert size == pytest.approx(0.6, abs=1e-12)
    findings, _ = coupling_table({}, Coupling("index_tip", "index_base", 1.0, 0.0, "<mimic>"), -float("inf"), float("inf"))
    assert findings(1.5, 0.1)[0][3] == float("inf")  # an unlimited leader: unbounded


def twisted(mjcf: str, body: str, axis, angle: float) -> str:
    """The generated MJCF (bodies without a ``quat``) with ``body``'s frame turned by ``angle``
    about ``axis`` (its joint's axis, in its own frame), all it holds turned with it: the joint's
    zero moved, its range and couplings left as written."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    q = [math.cos(angle / 2), *(math.sin(angle / 2) * a)]
    return P.sub_once(rf'(<body name="{body}")', lambda m: m[1] + ' quat="' + " ".join(repr(float(x)) for x in q) + '"', mjcf)


def test_a_twisted_mimic_leader_is_one_zero_offset_that_says_its_follower_follows(tmp_path):
    """index_base's frame turned by 0.1 rad about its own axis in the MJCF, the range and the
    coupling index_tip = 1·index_base left as written: one error, the zero offset of 0.1 rad on
    index_base, which says the range and the coupling carry it; no coupling or limit difference."""
    spec = spec_from_dict(hand())
    urdf, mjcf = coupled(
        generate_urdf(spec), generate_mjcf(spec), {"index_tip": ("index_base", 1.0, 0.0)}, [("index_tip", "index_base", 1.0, 0.0)]
    )
    result = verify_files(*P.write_pair(tmp_path, urdf, twisted(mjcf, "index_1", [1.0, 0.0, 0.0], 0.1)), LIMITS)
    errors = [f for f in result.findings if f.severity == "error"]
    assert [(f.kind, f.subject) for f in errors] == [("zero_offset", "index_base")], [f.message for f in errors]
    (f,) = errors
    assert f.magnitude == pytest.approx(0.1, abs=1e-6) and f.unit == "rad"
    assert f.values["couplings_written_alike"] == ["index_tip"] and f.values["range_written_alike"]
    assert result.verdict == "fail"
