"""Workspace sampling and reach statistics on random specs; the plot re-drawn from a section."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings

from kinverify.testing import strategies as kst
from kinverify.model.kinematics import frame_poses, link_poses
from kinverify.report.plots import workspace_svg
from kinverify.suites.workspace import reach_statistics, sample_workspace, workspace_section


def _chain_bound(spec) -> float:
    """Longest possible distance from the first joint's origin to any tool: every later joint
    offset, the longest tool offset and every prismatic joint's full travel."""
    offsets = sum(np.linalg.norm(j.origin.xyz) for j in spec.joints[1:])
    tools = max((np.linalg.norm(t.origin.xyz) for t in spec.tools), default=0.0)
    travel = sum(max(abs(j.limits.lower), abs(j.limits.upper)) for j in spec.joints if j.type == "prismatic")
    return offsets + tools + travel


@settings(max_examples=30, deadline=None)
@given(kst.arm_specs(max_joints=6))
def test_reach_is_bounded_by_the_chain_and_the_ranges_hold_every_point(spec):
    points = sample_workspace(lambda q: frame_poses(spec, q), spec.lower, spec.upper, 200, seed=3)
    base = (link_poses(spec, np.zeros(spec.dof))[0, 0] @ spec.joints[0].origin.transform)[:3, 3]
    stats = reach_statistics(points, base)
    assert points.shape == (200, 3)
    slack = 1e-12 * max(1.0, stats["max_reach"])  # a mean of equal values can round above them
    assert stats["min_reach"] - slack <= stats["mean_reach"] <= stats["max_reach"] + slack
    assert stats["max_reach"] <= _chain_bound(spec) + 1e-9
    assert stats["max_horizontal_reach"] <= stats["max_reach"] + 1e-12
    for i, axis in enumerate("xyz"):
        assert stats[f"{axis}_min"] <= points[:, i].min() + 1e-15 and points[:, i].max() <= stats[f"{axis}_max"] + 1e-15
    # the same seed draws the same cloud
    np.testing.assert_array_equal(points, sample_workspace(lambda q: frame_poses(spec, q), spec.lower, spec.upper, 200, seed=3))


def test_section_keeps_the_points_and_redraws_as_svg():
    points = np.random.default_rng(0).normal(size=(300, 3))
    section = workspace_section(points, np.zeros(3), "tool", "test")
    assert np.allclose(section.data["points"], points, atol=5e-5)
    assert section.tables[0].rows[0][1] == f"{np.linalg.norm(points, axis=1).max():.4f}"
    svg = workspace_svg(section.data)
    assert svg.startswith("<svg") and "data:image/png;base64," in svg  # rasterised cloud: small file
    assert workspace_svg({"points": []}) is None
