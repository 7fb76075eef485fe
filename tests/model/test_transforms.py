"""Rotation helpers: round trips and the small-angle accuracy the comparisons rely on."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify.model.transforms import (
    axis_angle_to_matrix,
    geodesic_distance,
    matrix_to_quat,
    matrix_to_rpy,
    quat_to_matrix,
    rotation_angle,
    rotation_log,
    rpy_to_matrix,
)

angles = st.floats(-np.pi, np.pi, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(st.lists(angles, min_size=3, max_size=3))
def test_rpy_and_quaternion_round_trips(rpy):
    m = rpy_to_matrix(rpy)
    np.testing.assert_allclose(rpy_to_matrix(matrix_to_rpy(m)), m, atol=1e-12)
    q = matrix_to_quat(m)
    assert q[0] >= 0 and abs(np.linalg.norm(q) - 1) < 1e-15
    np.testing.assert_allclose(quat_to_matrix(q), m, atol=1e-14)


@settings(max_examples=200, deadline=None)
@given(
    st.floats(1e-14, np.pi - 1e-6), st.lists(st.floats(-1, 1), min_size=3, max_size=3).filter(lambda v: np.linalg.norm(v) > 0.1)
)
def test_geodesic_angle_is_accurate_down_to_tiny_angles(angle, axis):
    axis = np.array(axis) / np.linalg.norm(axis)
    r = axis_angle_to_matrix(axis, np.array(angle))
    assert abs(rotation_angle(r) - angle) <= 1e-15 + 1e-12 * angle
    np.testing.assert_allclose(rotation_log(r), axis * angle, atol=1e-12)
    assert abs(geodesic_distance(np.eye(3), r) - angle) <= 1e-15 + 1e-12 * angle


def test_rpy_is_fixed_axis_xyz():
    r = rpy_to_matrix([0.1, 0.2, 0.3])
    rz, ry, rx = (axis_angle_to_matrix(a, np.array(v)) for a, v in (([0, 0, 1], 0.3), ([0, 1, 0], 0.2), ([1, 0, 0], 0.1)))
    np.testing.assert_allclose(r, rz @ ry @ rx, atol=1e-15)


def _half_turn_about_x_plus_z() -> np.ndarray:
    return axis_angle_to_matrix(np.array([1.0, 0.0, 1.0]) / np.sqrt(2.0), np.pi)


def test_rpy_at_gimbal_lock_makes_the_matrix_back():
    """Pitch ±π/2 leaves only roll ∓ yaw defined: the rpy still makes the matrix, and a half turn
    about (1, 0, 1)/√2 is not read as a bare 90° pitch (its roll was dropped)."""
    half = _half_turn_about_x_plus_z()
    np.testing.assert_allclose(half, [[0, 0, 1], [0, -1, 0], [1, 0, 0]], atol=1e-15)
    rpy = matrix_to_rpy(half)
    np.testing.assert_allclose(rpy_to_matrix(rpy), half, atol=1e-12)
    assert abs(abs(rpy[0]) - np.pi) < 1e-12 and abs(rpy[1] + np.pi / 2) < 1e-12  # roll π, pitch −90°
    for pitch in (np.pi / 2, -np.pi / 2):
        for roll, yaw in ((0.0, 0.0), (0.3, 0.0), (0.0, -1.1), (0.7, 2.0), (-2.5, 3.0)):
            m = rpy_to_matrix([roll, pitch, yaw])
            got = matrix_to_rpy(m)
            assert got[1] == pitch  # exactly ±π/2: the lock itself, not a neighbour
            np.testing.assert_allclose(rpy_to_matrix(got), m, atol=1e-12)
    batch = np.stack([half, rpy_to_matrix([0.7, np.pi / 2, 2.0]), rpy_to_matrix([0.1, 0.2, 0.3])])
    np.testing.assert_allclose(rpy_to_matrix(matrix_to_rpy(batch)), batch, atol=1e-12)
