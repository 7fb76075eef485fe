"""Accepted differences: an entry accepts the one finding it names (kind and subject) at its
magnitude, and nothing else; each rule pinned by the smallest pair where it and its nearest wrong
variant disagree."""

from __future__ import annotations

from kinverify.filemode.findings.accepted import Entry, apply
from kinverify.filemode.findings.table import finding


def damping(joint: str, size: float = 0.2):
    return finding("damping_difference", f"damping 0.1 in the URDF, {0.1 + size:g} in the MJCF on 1 joint: {joint}",
                   {"urdf": 0.1, "mjcf": 0.1 + size}, magnitude=size, unit="N·m·s/rad", prop="dynamics.damping",
                   joint=[joint], mjcf_joint=[joint])


def states(findings) -> list[tuple[str, bool, bool]]:
    return [(f.subject, f.accepted, f.fails) for f in findings]


ENTRY = Entry("damping_difference", "joint1", 0.2, "N·m·s/rad", "simulation damping")


def test_an_entry_accepts_its_own_joint_and_not_another_of_the_same_kind_and_size():
    out = apply([damping("joint1"), damping("joint2")], [ENTRY], lambda f: 1e-9)
    assert states(out) == [("joint1", True, False), ("joint2", False, True)]
    assert out[0].values["accepted_reason"] == "simulation damping" and "accepted_reason" not in out[1].values


def test_an_entry_accepts_no_finding_of_another_kind_on_its_joint():
    friction = finding("friction_difference", "friction 0 in the URDF, 0.2 in the MJCF on 1 joint: joint1",
                       {"urdf": 0.0, "mjcf": 0.2}, magnitude=0.2, unit="N·m", joint=["joint1"])
    (out,) = apply([friction], [ENTRY], lambda f: 1e-9)
    assert (out.accepted, out.fails) == (False, True)


def test_a_magnitude_that_moved_beyond_the_tolerance_fails_saying_what_it_was_accepted_at():
    inside, outside = apply([damping("joint1", 0.2 + 5e-10)], [ENTRY], lambda f: 1e-9), \
        apply([damping("joint1", 0.25)], [ENTRY], lambda f: 1e-9)
    assert (inside[0].accepted, outside[0].accepted, outside[0].fails) == (True, False, True)
    assert outside[0].message.endswith("(changed: accepted at 0.2 N·m·s/rad, now 0.25 N·m·s/rad)")
    assert outside[0].values["accepted_magnitude"] == 0.2
