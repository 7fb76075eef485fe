"""The hypothesis strategies keep clear of the bands where a library is known to round (see
backends/quirks.py): origin rotations, each angle and the turn of all three, are 0 or at least
1e-6 rad; tool rotations 0 or at least 1e-5 rad."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings

from kinverify.model.transforms import rotation_log, rpy_to_matrix
from kinverify.testing import strategies as kst


def turn(rpy) -> float:
    return float(np.linalg.norm(rotation_log(rpy_to_matrix(rpy))))


@settings(max_examples=300, deadline=None)
@given(kst.angles_rpy())
def test_origin_rotations_are_zero_or_clear_of_the_rounding_band(rpy):
    assert all(a == 0.0 or abs(a) >= kst.TINY_ROTATION for a in rpy)
    assert rpy == [0.0, 0.0, 0.0] or turn(rpy) >= kst.TINY_ROTATION


@settings(max_examples=300, deadline=None)
@given(kst.tool_rotations())
def test_tool_rotations_are_zero_or_clear_of_mujocos_site_snap(rpy):
    assert rpy == [0.0, 0.0, 0.0] or turn(rpy) >= kst.SITE_SNAP


def test_three_half_turns_minus_a_hair_is_a_hair():
    """What the guard is for: each angle is far from 0, yet the three make a turn of 5e-9 rad
    (MuJoCo snaps such a site onto its body, trimesh drops such an edge change)."""
    rpy = [math.pi, math.pi, math.pi - 5e-9]
    assert min(abs(a) for a in rpy) > 1.0 and 4e-9 < kst._turn(rpy) < 6e-9 < kst.TINY_ROTATION
