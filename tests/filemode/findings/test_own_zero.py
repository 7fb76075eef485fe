"""A joint's range read two ways: through the fitted sign and zero offset (physically), and in each
file's own zero (the sign carried, the offset not). The offset explains a range written alike in
each file's own zero; what differs beyond it is measured in the reading where fewer ends differ."""

from __future__ import annotations

import math

import pytest

import tests.filemode.findings.descs as D
from kinverify.filemode.align.result import JointMap
from kinverify.filemode.findings.own_zero import bound_error, bounds, mapped_bounds, sign_flip_finding, zero_offset_finding

INF = math.inf

TOL = 1e-9


def test_a_range_written_alike_in_each_files_own_zero_is_the_offsets():
    """[−1, 2] in both files, a zero offset of 0.1: physically 0.1 apart at each end, explained."""
    b = bounds(-1.0, 2.0, -1.0, 2.0, 1, 0.1, revolute=True)
    assert b.error == pytest.approx(0.1) and b.offset_explains(TOL)


def test_a_range_carried_through_the_offset_differs_in_no_reading():
    """The MJCF writes the range shifted by the offset ([−0.9, 2.1]): the same physical range; not
    'explained' (nothing to explain)."""
    b = bounds(-1.0, 2.0, -0.9, 2.1, 1, 0.1, revolute=True)
    assert b.error == pytest.approx(0.0, abs=1e-12) and not b.offset_explains(TOL)


def test_without_an_offset_there_is_nothing_to_explain():
    b = bounds(-1.0, 2.0, -1.0, 2.1, 1, 0.0, revolute=True)
    assert b.written is None and not b.offset_explains(TOL) and b.beyond_offset(TOL) == pytest.approx(0.1)


def test_an_end_changed_besides_the_offset_is_its_own_size():
    """The twist of 0.1 rad and the upper end moved from 2 to 2.3 as written: 0.3 beyond the offset
    (the lower end agrees as written), not the 0.2 left physically at the upper end (2.1 against
    2.3) nor the 0.1 at the lower."""
    b = bounds(-1.0, 2.0, -1.0, 2.3, 1, 0.1, revolute=True)
    assert not b.offset_explains(TOL)
    assert b.error == pytest.approx(0.2) and b.beyond_offset(TOL) == pytest.approx(0.3)


def test_an_end_changed_on_a_range_carried_through_the_offset_is_its_own_size():
    """The range carried through the offset ([−0.9, 2.1]) with the upper end then moved to 2.4:
    0.3 physically (the lower end agrees there), not the 0.4 of the reading in each file's own zero."""
    b = bounds(-1.0, 2.0, -0.9, 2.4, 1, 0.1, revolute=True)
    assert b.beyond_offset(TOL) == pytest.approx(0.3)


def test_a_reversed_axis_reads_the_range_as_written_with_or_without_the_sign():
    """A reversed axis and an offset of 0.1: the range reversed with it ([−2, 1] for the URDF's
    [−1, 2]) or left exactly as the URDF writes it is explained by the joint map; a range that is
    neither is not, and the reversed axis alone (no offset) explains the range left as written."""
    assert bounds(-1.0, 2.0, -2.0, 1.0, -1, 0.1, revolute=True).offset_explains(TOL)
    assert bounds(-1.0, 2.0, -1.0, 2.0, -1, 0.1, revolute=True).offset_explains(TOL)
    assert not bounds(-1.0, 2.0, -1.0, 2.5, -1, 0.1, revolute=True).offset_explains(TOL)
    assert bounds(-1.0, 2.0, -1.0, 2.0, -1, 0.0, revolute=True).offset_explains(TOL)
    assert bounds(-1.0, 2.0, -1.0, 2.0, 1, 0.0, revolute=True).written is None


def test_a_whole_turn_is_taken_where_it_fits():
    """An offset of 3 rad with the range shifted by 3 − 2π: the same range a whole turn apart."""
    b = bounds(-1.0, 1.0, -1.0 + 3 - 2 * math.pi, 1.0 + 3 - 2 * math.pi, 1, 3.0, revolute=True)
    assert b.error == pytest.approx(0.0, abs=1e-12)


def test_a_slides_range_written_alike_is_its_offsets_and_unlimited_ends_stay_unlimited():
    b = bounds(0.0, 0.04, 0.0, 0.04, 1, -0.0127, revolute=False)
    assert b.offset_explains(TOL) and b.error == pytest.approx(0.0127)
    inf = bounds(-math.inf, math.inf, -math.inf, math.inf, 1, 0.2, revolute=True)
    assert inf.error == 0.0 and not inf.offset_explains(TOL)


# --- the bounds read through the joint map, end by end ----------------------------------------


def test_bounds_are_mapped_through_the_sign_then_moved_by_the_offset():
    assert mapped_bounds(-1.0, 2.0, 1, 0.5) == (-0.5, 2.5)
    assert mapped_bounds(-1.0, 2.0, -1, 0.5) == (-1.5, 1.5)  # [−2, 1] reversed, then moved


def test_a_bound_error_is_zero_for_equal_bounds_inf_for_one_unbounded_end_and_none_for_a_missing_one():
    assert bound_error(None, 1.0) is None and bound_error(1.0, None) is None
    assert bound_error(INF, INF) == 0.0 and bound_error(-INF, -INF) == 0.0
    assert bound_error(INF, 1.0) == INF and bound_error(1.0, -INF) == INF
    assert bound_error(1.0, 3.5) == 2.5 and bound_error(3.5, 1.0) == 2.5


def test_an_error_equal_to_the_tolerance_is_within_it_and_the_written_reading_too():
    """[−1, 2] against [−1, 2.25] with an offset of 0.5: physically 0.5 and 0.25 apart at the ends,
    as written 0 and 0.25. At a tolerance of 0.25 the written reading is within it (an end at the
    tolerance passes), the physical one not: the offset explains the range; at 0.5 nothing differs."""
    b = bounds(-1.0, 2.0, -1.0, 2.25, 1, 0.5, revolute=False)
    assert (b.lower, b.upper) == (-0.5, 2.5) and b.ends == (0.5, 0.25) and b.written == (0.0, 0.25)
    assert b.error == 0.5
    assert b.offset_explains(0.25) and not b.offset_explains(0.5) and not b.offset_explains(0.2)
    assert b.beyond_offset(0.25) == 0.25 and b.beyond_offset(0.0) == 0.25
    # an end equal to the tolerance does not differ: physically (0.25, 0.25) no end differs at 0.25,
    # as written (0, 0.5) one does; the reading where fewer ends differ gives the size
    c = bounds(-1.0, 2.0, -1.0, 2.5, 1, 0.25, revolute=False)
    assert c.ends == (0.25, 0.25) and c.written == (0.0, 0.5)
    assert c.beyond_offset(0.25) == 0.25 and c.beyond_offset(0.3) == 0.25 and c.beyond_offset(0.1) == 0.5


def test_a_whole_turn_the_other_way_is_taken_where_it_fits_but_never_on_a_slide():
    shift = -3.0 + 2 * math.pi
    b = bounds(-1.0, 1.0, -1.0 + shift, 1.0 + shift, 1, -3.0, revolute=True)
    assert b.error == pytest.approx(0.0, abs=1e-12) and b.lower == pytest.approx(-1.0 + shift)
    slide = bounds(-1.0, 1.0, -1.0 + shift, 1.0 + shift, 1, -3.0, revolute=False)
    assert slide.error == pytest.approx(2 * math.pi) and (slide.lower, slide.upper) == (-4.0, -2.0)


def test_the_whole_turn_is_not_taken_without_an_offset():
    """No zero offset: a range a whole turn apart is a whole turn apart."""
    b = bounds(-1.0, 1.0, -1.0 + 2 * math.pi, 1.0 + 2 * math.pi, 1, 0.0, revolute=True)
    assert b.error == pytest.approx(2 * math.pi) and b.written is None


def test_a_reversed_axis_without_offset_reads_as_written_with_the_sign_not_carried():
    """Reversed, no offset: [−1, 2] against [−1, 2] reads physically [−2, 1] (1 apart each end), as
    written (the sign not carried) 0 apart: the reversed axis explains it."""
    b = bounds(-1.0, 2.0, -1.0, 2.0, -1, 0.0, revolute=True)
    assert b.ends == (1.0, 1.0) and b.written == (0.0, 0.0) and b.offset_explains(TOL)


# --- the zero offset and reversed axis findings -------------------------------------------------


def pair(utype="revolute", lo=-1.0, up=2.0, mlo=-1.0, mup=2.0):
    u = D.desc("urdf", [D.joint("a", type=utype, lower=lo, upper=up)])
    m = D.desc("mjcf", [D.joint("b", type=utype, lower=mlo, upper=mup)])
    return u, m


NAMES = {"joint": "a", "mjcf_joint": "b"}


def test_a_revolute_zero_offset_says_its_size_in_radians_and_degrees_and_the_range_it_carries():
    u, m = pair()
    f = zero_offset_finding(u, m, JointMap("a", "b", "revolute", 1, 0.25), ["a_link"], NAMES, TOL, {})
    assert (f.kind, f.subject, f.other, f.severity) == ("zero_offset", "a", "b", "error")
    assert f.magnitude == 0.25 and f.unit == "rad"
    assert f.values == {
        "offset": 0.25,
        "unit": "rad",
        "moves": ["a_link"],
        "range_written_alike": True,
        "checks": [["limits.position", "joints"]],
    }
    assert f.message.startswith(
        "joint a/b: zero offset of 0.25 rad (14.32°): at the same q the MJCF's joint sits 0.25 rad further"
    )
    assert "(q_mjcf = q_urdf + 0.25)" in f.message
    assert "; its range [-1, 2] is written alike in each file's own zero, so it too sits 0.25 rad apart physically" in f.message


def test_a_negative_slide_offset_on_a_reversed_axis_in_metres_with_the_range_carried_is_the_offset_alone():
    """A slide reversed and moved by −0.125 m, its range carried through both ([−0.125 − 2, −0.125 + 1]):
    no degrees, no range said, the map written with both minus signs."""
    u, m = pair("prismatic", mlo=-2.125, mup=0.875)
    f = zero_offset_finding(u, m, JointMap("a", "b", "prismatic", -1, -0.125), [], NAMES, TOL, {})
    assert f.unit == "m" and f.magnitude == 0.125 and f.values["unit"] == "m"
    assert "range_written_alike" not in f.values and "checks" not in f.values
    assert f.message == (
        "joint a/b: zero offset of -0.125 m: at the same q the MJCF's joint sits -0.125 m further (q_mjcf = −q_urdf − 0.125)"
    )


def test_the_couplings_of_a_joint_or_on_it_are_said_and_others_not():
    """``coupled`` ties c to a (a leads) and a to d (a follows): both said, sorted; e following f not."""
    u, m = pair(mlo=-0.75, mup=2.25)  # the range carried: only the couplings
    coupled = {"d": "a", "c": "a", "e": "f"}
    f = zero_offset_finding(u, m, JointMap("a", "b", "revolute", 1, 0.25), [], NAMES, TOL, coupled)
    assert f.values["couplings_written_alike"] == ["c", "d"]
    assert f.message.endswith(
        "; c follows a and d follows a as each file writes it in its own coordinates, so the offset carries into the coupling too"
    )
    lone = zero_offset_finding(u, m, JointMap("a", "b", "revolute", 1, 0.25), [], NAMES, TOL, {"e": "f"})
    assert "couplings_written_alike" not in lone.values and "follows" not in lone.message


def test_a_reversed_axis_alone_mirrors_an_asymmetric_range_written_alike():
    u, m = pair()
    f = sign_flip_finding(u, m, JointMap("a", "b", "revolute", -1, 0.0), ["a_link"], NAMES, TOL)
    assert (f.kind, f.subject, f.severity, f.magnitude, f.unit) == ("axis_sign_flip", "a", "error", 1.0, "")
    assert f.values == {"sign": -1, "moves": ["a_link"], "range_written_alike": True, "checks": [["limits.position", "joints"]]}
    assert f.message == (
        "joint a/b: the axis is reversed (the same q turns the other way): q_mjcf = −q_urdf; its range [-1, 2] is "
        "written alike in each file's own coordinates, so the reversed axis mirrors it: its ends sit 1 rad apart physically"
    )
    slide = sign_flip_finding(*pair("prismatic"), JointMap("a", "b", "prismatic", -1, 0.0), [], NAMES, TOL)
    assert slide.message.endswith("its ends sit 1 m apart physically")


def test_a_reversed_axis_with_its_range_reversed_too_or_beside_an_offset_says_no_range():
    mirrored = sign_flip_finding(*pair(mlo=-2.0, mup=1.0), JointMap("a", "b", "revolute", -1, 0.0), [], NAMES, TOL)
    assert mirrored.values == {"sign": -1, "moves": []} and "range" not in mirrored.message
    moved = sign_flip_finding(*pair(), JointMap("a", "b", "revolute", -1, 0.5), [], NAMES, TOL)
    assert moved.values == {"sign": -1, "moves": []}
    assert moved.message.endswith("q_mjcf = −q_urdf + 0.5")


def test_a_zero_offset_with_an_end_changed_besides_says_no_range():
    """[−1, 2] against [−1, 2.5] with an offset of 0.25: the upper end differs as written too, so the
    offset does not explain the range (the limits check reports it)."""
    u, m = pair(mlo=-1.0, mup=2.5)
    f = zero_offset_finding(u, m, JointMap("a", "b", "revolute", 1, 0.25), [], NAMES, TOL, {})
    assert "range_written_alike" not in f.values and "range" not in f.message
