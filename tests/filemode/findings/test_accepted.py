"""Accepted differences: an entry accepts the one finding it names (kind and subject) at its
magnitude, and nothing else; each rule pinned by the smallest pair where it and its nearest wrong
variant disagree."""

from __future__ import annotations

import math

import pytest

from kinverify.errors import InputError
from kinverify.filemode.findings.accepted import DEFAULT_NAME, Entry, apply, default_path, load, write
from kinverify.filemode.findings.table import finding


def damping(joint: str, size: float = 0.2):
    return finding(
        "damping_difference",
        f"damping 0.1 in the URDF, {0.1 + size:g} in the MJCF on 1 joint: {joint}",
        {"urdf": 0.1, "mjcf": 0.1 + size},
        magnitude=size,
        unit="N·m·s/rad",
        prop="dynamics.damping",
        joint=[joint],
        mjcf_joint=[joint],
    )


def states(findings) -> list[tuple[str, bool, bool]]:
    return [(f.subject, f.accepted, f.fails) for f in findings]


ENTRY = Entry("damping_difference", "joint1", 0.2, "N·m·s/rad", "simulation damping")


def test_an_entry_accepts_its_own_joint_and_not_another_of_the_same_kind_and_size():
    out = apply([damping("joint1"), damping("joint2")], [ENTRY], lambda f: 1e-9)
    assert states(out) == [("joint1", True, False), ("joint2", False, True)]
    assert out[0].values["accepted_reason"] == "simulation damping" and "accepted_reason" not in out[1].values


def test_an_entry_accepts_no_finding_of_another_kind_on_its_joint():
    friction = finding(
        "friction_difference",
        "friction 0 in the URDF, 0.2 in the MJCF on 1 joint: joint1",
        {"urdf": 0.0, "mjcf": 0.2},
        magnitude=0.2,
        unit="N·m",
        joint=["joint1"],
    )
    (out,) = apply([friction], [ENTRY], lambda f: 1e-9)
    assert (out.accepted, out.fails) == (False, True)


def test_a_magnitude_that_moved_beyond_the_tolerance_fails_saying_what_it_was_accepted_at():
    inside, outside = (
        apply([damping("joint1", 0.2 + 5e-10)], [ENTRY], lambda f: 1e-9),
        apply([damping("joint1", 0.25)], [ENTRY], lambda f: 1e-9),
    )
    assert (inside[0].accepted, outside[0].accepted, outside[0].fails) == (True, False, True)
    assert outside[0].message.endswith("(changed: accepted at 0.2 N·m·s/rad, now 0.25 N·m·s/rad)")
    assert outside[0].values["accepted_magnitude"] == 0.2


@pytest.mark.parametrize(
    "recorded, now, accepted",
    [
        (None, None, True),
        (None, 0.2, False),
        (0.2, None, False),  # a size appears or disappears: changed
        (math.inf, math.inf, True),
        (math.inf, 1.0, False),
        (1.0, math.inf, False),
        (1.0, 1.5, True),
        (1.0, 1.5 + 2**-20, False),  # within the tolerance 0.5, its edge included
        (1000.0, 1000.0005, True),
        (1000.0, 1000.002, False),  # within RELATIVE (1e-6) of the recorded size
    ],
)
def test_a_recorded_magnitude_matches_within_the_tolerance_or_the_relative_window(recorded, now, accepted):
    f = (
        finding("damping_difference", "m", magnitude=now, unit="N·m·s/rad", joint=["joint1"])
        if now is not None
        else finding("damping_difference", "m", joint=["joint1"])
    )
    tolerance = {"damping_difference": 0.5}  # the finding's own tolerance, asked of it
    (out,) = apply(
        [f], [Entry("damping_difference", "joint1", recorded)], lambda g: tolerance[g.kind] if recorded == 1.0 else 0.0
    )
    assert out.accepted is accepted


def test_written_entries_load_back_and_accept_the_same_findings(tmp_path):
    findings = [
        damping("joint1"),
        damping("joint2", math.inf),
        finding("frame_offset", 'site "tcp" \\ moved\nfar', {}, magnitude=0.01, unit="m", frame=["tcp"]),
        finding("rounding", "info only", {}, magnitude=1e-6, unit="m", frame=["link3"]),
        finding("axis_direction", "no size", {}, joint=["joint3"]),
    ]
    path = write(tmp_path / "kinverify-accepted.toml", findings, "robot.urdf + robot.xml")
    text = path.read_text()
    assert text.startswith("# kinverify accepted differences for robot.urdf + robot.xml\n") and "rounding" not in text
    assert 'reason = ""' in text and "magnitude = inf" in text and "# damping 0.1 in the URDF" in text
    entries = load(path)
    assert entries == [
        Entry("damping_difference", "joint1", 0.2, "N·m·s/rad"),
        Entry("damping_difference", "joint2", math.inf, "N·m·s/rad"),
        Entry("frame_offset", "tcp", 0.01, "m"),
        Entry("axis_direction", "joint3", None),
    ]
    out = apply(findings, entries, lambda f: 0.0)
    assert [f.accepted for f in out] == [True, True, True, False, True]


@pytest.mark.parametrize(
    "content, words",
    [
        ("accepted = [", "is not TOML"),
        ('accepted = "all"', "'accepted' must be an array of tables"),
        ('[[accepted]]\nsubject = "joint1"', 'accepted[0] needs kind = "..." and subject = "..."'),
        ('[[accepted]]\nkind = "damping_difference"\nsubject = 3', "accepted[0] needs kind"),
        ('[[accepted]]\nkind = "damping_difference"\nmagnitude = "0.2"', "accepted[0].magnitude must be a number"),
        ('[[accepted]]\nkind = "damping_difference"\nmagnitude = true', "accepted[0].magnitude must be a number"),
        ('[[accepted]]\nkind = "damping_difference"\nmagnitude = nan', "accepted[0].magnitude must be a number"),
    ],
)
def test_a_malformed_accepted_file_is_one_error_naming_the_file_and_the_entry(tmp_path, content, words):
    path = tmp_path / "acc.toml"
    path.write_text(content)
    with pytest.raises(InputError) as err:
        load(path, "--accept")
    assert str(err.value).startswith(f"--accept: {path}") and words in str(err.value), str(err.value)


def test_an_entry_may_leave_out_subject_unit_reason_and_magnitude(tmp_path):
    path = tmp_path / "acc.toml"
    path.write_text(
        '[[accepted]]\nkind = "length_units"\n[[accepted]]\nkind = "k"\nsubject = "s"\nmagnitude = 2\n'
        'unit = "m"\nreason = "why"\n'
    )
    assert load(path) == [Entry("length_units", "", None, "", ""), Entry("k", "s", 2.0, "m", "why")]
    assert isinstance(load(path)[1].magnitude, float) and load(tmp_path / "acc.toml", "x") == load(path)
    (tmp_path / "empty.toml").write_text("")
    assert load(tmp_path / "empty.toml") == []


def test_the_accepted_file_beside_the_urdf_is_found_by_its_name(tmp_path):
    urdf = tmp_path / "robot.urdf"
    assert default_path(str(urdf)) is None
    (tmp_path / DEFAULT_NAME).write_text("")
    assert default_path(str(urdf)) == (tmp_path / DEFAULT_NAME).resolve()


def test_a_changed_size_says_what_it_was_accepted_at_and_what_it_is_now():
    def changed(recorded, now, unit):
        f = (
            finding("length_units", "lengths differ", magnitude=now, unit=unit)
            if now is not None
            else finding("length_units", "lengths differ")
        )
        (out,) = apply([f], [Entry("length_units", "", recorded, unit)], lambda g: 0.0)
        return out.message

    assert changed(None, 2.0, "") == "lengths differ (changed: accepted at no size, now 2)"
    assert changed(1.5, None, "m") == "lengths differ (changed: accepted at 1.5 m, now no size)"


def test_written_names_and_messages_with_quotes_backslashes_and_newlines_stay_one_entry(tmp_path):
    odd = finding("frame_offset", 'tcp moved\nby "1 cm" \\ there', {}, magnitude=0.01, unit='m "SI"', frame=['tcp "a" \\ b\nc'])
    text = write(tmp_path / "a.toml", [odd], "u + m").read_text()
    assert text.splitlines()[:2] == [
        "# kinverify accepted differences for u + m",
        "# Each entry accepts one finding (kind + subject) at its magnitude; review every one and say why.",
    ]
    assert '# tcp moved\\nby "1 cm" \\ there' in text.splitlines()  # the newline shown as an escape: one comment line
    assert load(tmp_path / "a.toml") == [Entry("frame_offset", 'tcp "a" \\ b\nc', 0.01, 'm "SI"')]  # the name exactly


def test_an_unreadable_or_too_deep_accepted_file_is_named_with_its_flag(tmp_path):
    missing = tmp_path / "none.toml"
    with pytest.raises(InputError, match=f"^--accept: {missing} is not a file$"):
        load(missing)
    deep = tmp_path / "deep.toml"
    deep.write_text("x = " + "[" * 100 + "]" * 100)
    with pytest.raises(InputError, match=f"^--write-accepted: {deep} nests values more than 64 levels deep"):
        load(deep, "--write-accepted")
