"""A joint's range read two ways: through the fitted sign and zero offset (physically), and in each
file's own zero (the sign carried, the offset not). The offset explains a range written alike in
each file's own zero; what differs beyond it is measured in the reading where fewer ends differ."""

from __future__ import annotations

import math

import pytest

from kinverify.filemode.findings.own_zero import bounds

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
