"""Couplings compared joint by joint after each file's are resolved: a chain of couplings, or one
stated the other way round, ties the same joints."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import tests.filemode.findings.descs as D
import tests.filemode.pairs as P
from kinverify.filemode.align.result import JointMap
from kinverify.filemode.findings.couplings import coupling_findings, written_alike
from kinverify.filemode.pipeline import verify_files
from kinverify.filemode.read.model import Coupling
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import spec_from_dict
from kinverify.run import VerifyOptions
from tests.filemode.align.test_match import hand

INF = math.inf

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


# --- on hand-made descriptions: URDF joints a, b, c; the MJCF's A, B, C -------------------------


def tables(ucoup=(), mcoup=(), maps=None, type="revolute", lower=-1.0, upper=2.0):
    """``coupling_findings`` of URDF couplings ``ucoup`` against MJCF ones ``mcoup`` (MJCF names),
    ``maps``: URDF joint -> (sign, offset) of the joint map (None: no alignment)."""
    names = ["a", "b", "c"]
    u = D.desc("urdf", [D.joint(n, type=type, lower=lower, upper=upper) for n in names], ucoup)
    m = D.desc("mjcf", [D.joint(n.upper(), type=type, lower=lower, upper=upper) for n in names], mcoup)
    matching = D.matching([(n, n.upper()) for n in names])
    al = None if maps is None else D.alignment([JointMap(n, n.upper(), type, *maps.get(n, (1, 0.0))) for n in names])
    return coupling_findings(u, m, matching, al), written_alike(u, m, matching, al) if al else None


EQ = "<equality joint>"


def test_the_same_coupling_under_other_names_is_no_finding():
    assert tables([D.couple("b", "a", 2.0, 0.5)], [D.couple("B", "A", 2.0, 0.5, EQ)]) == ([], None)
    assert tables([D.couple("b", "a", 2.0, 0.5)], [D.couple("B", "A", 2.0, 0.5, EQ)], {}) == ([], {})


def test_a_coupling_in_one_file_only_is_a_warning_naming_the_file_and_the_leader():
    (f,), _ = tables([D.couple("b", "a")], [])
    assert (f.kind, f.severity, f.subject, f.values) == ("coupling_one_file", "warning", "b", {"file": "URDF", "leader": "a"})
    assert f.message == "joint b follows a in the URDF only (<mimic>); the other file leaves it free: compared as coupled"
    (g,), _ = tables([], [D.couple("C", "A", 1.0, 0.0, EQ)])
    assert (g.subject, g.values) == ("c", {"file": "MJCF", "leader": "a"})  # the URDF's names
    assert g.message.startswith("joint c follows a in the MJCF only (<equality joint>)")


def test_a_coupling_of_a_joint_the_other_file_lacks_is_left_to_the_pairing():
    """The URDF couples b to z, a joint the MJCF has no match for; the MJCF couples B to a joint
    named Z the URDF lacks: neither is compared."""
    u = D.desc("urdf", [D.joint("a"), D.joint("b"), D.joint("z")], [D.couple("b", "z")])
    m = D.desc("mjcf", [D.joint("A"), D.joint("B"), D.joint("Z")], [D.couple("A", "Z", 1.0, 0.0, EQ)])
    assert coupling_findings(u, m, D.matching([("a", "A"), ("b", "B")])) == []


def test_two_leaders_are_one_difference_saying_both_couplings():
    """c = 1·a in the URDF, C = 2·B + 0.5 in the MJCF: both couple c, to different joints."""
    (f,), _ = tables([D.couple("c", "a")], [D.couple("C", "B", 2.0, 0.5, EQ)])
    assert (f.kind, f.severity, f.subject, f.magnitude) == ("coupling_difference", "error", "c", None)
    assert f.values == {"urdf": [1.0, 0.0], "mjcf": [2.0, 0.5]}
    assert f.message == "joint c: c = 1·a + 0 in the URDF, 2·b + 0.5 in the MJCF"


def test_a_difference_without_a_joint_map_is_said_in_plain_words_with_its_size_at_the_lower_end():
    """b = 1·a against B = 2·A − 0.5 over a's range [−2, 1]: q − 0.5 apart, 2.5 at q = −2 (0.5 at q = 1)."""
    (f,), _ = tables([D.couple("b", "a")], [D.couple("B", "A", 2.0, -0.5, EQ)], lower=-2.0, upper=1.0)
    assert f.magnitude == pytest.approx(2.5) and f.unit == "rad"
    assert f.message == "joint b: b = 1·a + 0 in the URDF, 2·a + -0.5 in the MJCF"
    (g,), _ = tables([D.couple("b", "a")], [D.couple("B", "A", 2.0, -0.5, EQ)], maps={})  # the identity map: no words on it
    assert g.message == f.message


def test_a_multiplier_that_differs_on_an_unlimited_leader_is_unbounded_but_an_offset_alone_is_its_size():
    (f,), _ = tables([D.couple("b", "a")], [D.couple("B", "A", 1.0, 0.25, EQ)], lower=-INF, upper=INF)
    assert f.magnitude == 0.25
    (g,), _ = tables([D.couple("b", "a")], [D.couple("B", "A", 1.0, 0.25, EQ)], lower=-1.0, upper=INF)
    (h,), _ = tables([D.couple("b", "a")], [D.couple("B", "A", 2.0, 0.0, EQ)], lower=-1.0, upper=INF)
    assert g.magnitude == 0.25 and h.magnitude == INF


def test_a_reversed_leader_carries_its_sign_into_the_coupling():
    """A's axis reversed (q_A = −q_a): the MJCF's B = A reads b = −a; the URDF's b = −a is the same
    coupling, its b = a differs by 2·q over a's range [−1, 2]: 4 rad, said in the URDF's coordinates."""
    assert tables([D.couple("b", "a", -1.0)], [D.couple("B", "A", 1.0, 0.0, EQ)], {"a": (-1, 0.0)})[0] == []
    (f,), alike = tables([D.couple("b", "a")], [D.couple("B", "A", 1.0, 0.0, EQ)], {"a": (-1, 0.0)})
    assert f.values == {"urdf": [1.0, 0.0], "mjcf": [-1.0, 0.0]} and f.magnitude == 4.0 and alike == {}
    assert f.message.endswith("in the MJCF (its coupling carried into the URDF's joint coordinates)")


def test_a_reversed_follower_carries_its_sign_into_multiplier_and_offset():
    """B's axis reversed: the MJCF's B = A + 0.5 reads −b = a + 0.5, b = −a − 0.5."""
    assert tables([D.couple("b", "a", -1.0, -0.5)], [D.couple("B", "A", 1.0, 0.5, EQ)], {"b": (-1, 0.0)})[0] == []
    (f,), _ = tables([D.couple("b", "a", -1.0, 0.5)], [D.couple("B", "A", 1.0, 0.5, EQ)], {"b": (-1, 0.0)})
    assert f.values["mjcf"] == [-1.0, -0.5] and f.magnitude == 1.0


def test_offsets_are_carried_through_multiplier_and_sign():
    """Leader offset 0.25 and follower offset 0.5 (signs +1): the MJCF's B = 2·A + 1 reads
    b + 0.5 = 2·(a + 0.25) + 1, b = 2·a + 1; so the URDF's b = 2·a + 1 agrees, and its b = 2·a +
    1.25 differs by 0.25 (written alike in neither file's own zero)."""
    maps = {"a": (1, 0.25), "b": (1, 0.5)}
    found, alike = tables([D.couple("b", "a", 2.0, 1.25)], [D.couple("B", "A", 2.0, 1.0, EQ)], maps)
    (f,) = found
    assert f.values["mjcf"] == [2.0, 1.0] and f.magnitude == pytest.approx(0.25) and alike == {}
    assert tables([D.couple("b", "a", 2.0, 1.0)], [D.couple("B", "A", 2.0, 1.0, EQ)], maps)[0] == []


def test_a_fitted_offset_is_known_to_a_tenth_of_a_milliradian_and_ten_micrometres():
    """The follower's fitted zero offset 0.3: the MJCF's B = A + 0.40005 reads b = a + 0.10005
    against the URDF's b = a + 0.1. Within the fit's precision on a hinge (1e-4 rad), not on a
    slide (1e-5 m): there a difference of 5e-5 m, the offset carried."""
    maps = {"b": (1, 0.3)}
    hinge, _ = tables([D.couple("b", "a", 1.0, 0.1)], [D.couple("B", "A", 1.0, 0.40005, EQ)], maps)
    assert hinge == []
    (f,), alike = tables([D.couple("b", "a", 1.0, 0.1)], [D.couple("B", "A", 1.0, 0.40005, EQ)], maps, type="prismatic")
    assert f.magnitude == pytest.approx(5e-5, rel=1e-6) and f.unit == "m" and alike == {}
    assert f.message.endswith("in the MJCF (its coupling carried into the URDF's joint coordinates)")
    # without a fitted offset, the same 5e-5 is beyond the exact comparison's 1e-9 on a hinge too
    (g,), _ = tables([D.couple("b", "a", 1.0, 0.1)], [D.couple("B", "A", 1.0, 0.10005, EQ)], {})
    assert g.magnitude == pytest.approx(5e-5, rel=1e-6)


def test_a_coupling_written_alike_under_a_fitted_offset_is_the_offsets_and_beyond_it_its_own_size():
    """The follower's zero offset 0.3 (a slide): B = A + 0.1 as the URDF's b = a + 0.1 (written
    alike: the zero offset finding's to say); B = A + 0.125 differs by 0.025 read in each file's own
    zero, less than the 0.275 the offset carried leaves (b = a − 0.175): the smaller is its size;
    B = A + 0.375 the other way round (0.025 carried, 0.275 as written)."""
    maps = {"b": (1, 0.3)}
    same, alike = tables([D.couple("b", "a", 1.0, 0.1)], [D.couple("B", "A", 1.0, 0.1, EQ)], maps, type="prismatic")
    assert same == [] and alike == {"b": "a"}
    (f,), _ = tables([D.couple("b", "a", 1.0, 0.1)], [D.couple("B", "A", 1.0, 0.125, EQ)], maps, type="prismatic")
    # carried: b = a − 0.175, 0.275 apart; in each file's own zero 0.125 against 0.1: 0.025 apart
    assert f.magnitude == pytest.approx(0.025) and f.unit == "m"
    assert f.message.endswith("in the MJCF; 0.025 m apart beyond the zero offsets (read in each file's own zero: 1·a + 0.125)")
    (g,), _ = tables([D.couple("b", "a", 1.0, 0.1)], [D.couple("B", "A", 1.0, 0.375, EQ)], maps, type="prismatic")
    assert g.magnitude == pytest.approx(0.025) and "beyond the zero offsets" not in g.message  # carried is the closer


def test_offsets_that_cancel_in_a_coupling_leave_nothing_for_the_zero_offset_to_say():
    """Leader and follower both 0.25 further (signs +1): b = a + 0.1 read either way is b = a + 0.1."""
    found, alike = tables([D.couple("b", "a", 1.0, 0.1)], [D.couple("B", "A", 1.0, 0.1, EQ)], {"a": (1, 0.25), "b": (1, 0.25)})
    assert found == [] and alike == {}
