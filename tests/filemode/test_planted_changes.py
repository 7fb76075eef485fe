"""One planted difference, one error finding, with its size: the shared real robots' URDFs (made
mesh-free), the MJCF MuJoCo writes from each, and one or two changes planted in that MJCF as a person
editing it would (:mod:`kinverify.testing.planted`). File mode must report each planted change
once, naming its joint or body, with its size within 2 % (or the written precision), and nothing
else as an error; rewrites that change nothing give no error at all. A hinge's frame turned about
its own axis (``frame_twist``) and a slide's moved along it (``slide_offset_along``, panda's
fingers, one following the other) are each the joint's zero offset alone: the range and coupling
they leave as written are the offset's to say, not a limit or coupling difference beside it.

Fixed bases: panda, iiwa14, ur5e, z1, leap_hand; floating (a free joint on the MJCF's root body):
go2, a1, anymal_c. Each kind is planted alone on a robot drawn among all; two changes, on a joint
and the joint above it, on a robot of each group; and the changes afresh every run (file mode
takes a second or more a pair: a few pairs a run keep the suite inside CI's time).
``KINVERIFY_REAL_ROBOTS`` points elsewhere when ../shared/real-robots is not beside the project;
robots whose folder is absent are not drawn, and a group with none is skipped."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from kinverify.filemode.pipeline import verify_files
from kinverify.run import VerifyOptions
from kinverify.testing.assertions import assert_files_agree
from kinverify.testing.strategies import (
    PLANTED_KINDS,
    equivalent_rewrites,
    mesh_free_urdf,
    mujoco_mjcf,
    plantable_kinds,
    planted_changes,
)
from tests.paths import REAL_ROBOTS

REAL = Path(os.environ.get("KINVERIFY_REAL_ROBOTS", REAL_ROBOTS))
URDFS = {
    "panda": "panda/panda_erd.urdf",
    "iiwa14": "iiwa14/iiwa14_no_collision_drake.urdf",
    "ur5e": "ur5e/ur5e_ur_description.urdf",
    "z1": "z1/z1_erd.urdf",
    "leap_hand": "leap_hand/leap_hand_dexurdf.urdf",
    "go2": "go2/go2_erd.urdf",
    "a1": "a1/a1_unitree_ros.urdf",
    "anymal_c": "anymal_c/anymal_c_anybotics.urdf",
}
FLOATING = ("go2", "a1", "anymal_c")
GROUPS = {"fixed": tuple(r for r in URDFS if r not in FLOATING), "floating": FLOATING}
# Drake too: its parsers are tried in a process of their own first, so the mass="0" inertials MuJoCo
# writes for panda and go2 (on which Drake's MJCF parser ends its process) are a refusal and the run
# goes on. Measured over the module (seed 1): 27 s of CPU without Drake, 30 s with it, 37 s with
# every library (Newton's too, which this property does not need).
BACKENDS = ["pinocchio-urdf", "mujoco", "pinocchio-mjcf", "yourdfpy", "mujoco-urdf", "drake-urdf", "drake-mjcf"]
OPTIONS = VerifyOptions(
    samples=4, fd_samples=1, backends=BACKENDS, suites=["kinematics", "limits", "inertia"], extra={"dynamics_samples": 3}
)
# the written precision: MuJoCo writes 6 significant digits, so a planted size differs from the
# files' difference by up to that much of the value it was planted on (a range end of 3.14159 rad)
ABSOLUTE = {"m": 1e-6, "rad": 1e-5, "kg": 1e-5, "kg·m²": 1e-9, "N·m·s/rad": 1e-5, "N·s/m": 1e-5}


# a pair takes file mode 0.3-3 s of CPU (up to 20 s where a floating robot's frame moved): a few
# examples a test, failures replayed from the example database and not shrunk (CI: derandomized,
# tests/conftest.py)
def examples(n: int) -> settings:
    return settings(
        max_examples=n,
        deadline=None,
        phases=(Phase.explicit, Phase.reuse, Phase.generate),
        suppress_health_check=[HealthCheck.too_slow],
    )


@pytest.fixture(scope="module")
def pairs(tmp_path_factory):
    """robot -> (the mesh-free URDF's path, the MJCF MuJoCo writes from it), made once per module."""
    cache: dict[str, tuple[Path, str]] = {}

    def pair(robot: str) -> tuple[Path, str]:
        if robot not in cache:
            urdf = mesh_free_urdf((REAL / URDFS[robot]).read_text())
            path = tmp_path_factory.mktemp(robot) / f"{robot}.urdf"
            path.write_text(urdf)
            cache[robot] = path, mujoco_mjcf(urdf, free=robot in FLOATING)
        return cache[robot]

    return pair


def present(robot: str) -> bool:
    return (REAL / URDFS[robot]).is_file()


def robots(group: str) -> list[str]:
    found = [r for r in GROUPS[group] if present(r)]
    if not found:
        pytest.skip(f"none of {', '.join(GROUPS[group])} in {REAL}")
    return found


def run(urdf: Path, mjcf_text: str):
    mjcf = urdf.with_name("planted.xml")
    mjcf.write_text(mjcf_text)
    return verify_files(str(urdf), str(mjcf), OPTIONS)


def names(finding) -> set[str]:
    return {n for side in (finding.subject, finding.other) for n in side.split(", ") if n}


def size_agrees(planted, finding) -> bool:
    if planted.kind == "axis_flip":  # a sign: its size is the flip itself
        return finding.kind == "axis_sign_flip"
    if finding.magnitude is None or finding.unit != planted.unit:
        return False
    return abs(finding.magnitude - planted.size) <= max(0.02 * planted.size, ABSOLUTE[planted.unit])


def assert_one_finding_each(result, planted) -> None:
    """Each planted change is exactly one error finding naming it, of its size; no other error."""
    errors = [f for f in result.findings if f.severity == "error"]
    problems = [f"kinverify's own error: {e}" for e in result.internal_errors]
    matched = set()
    for p in planted:
        hits = [i for i, f in enumerate(errors) if names(f) & set(p.names)]
        matched.update(hits)
        if len(hits) != 1:
            problems.append(f"{p}: {len(hits)} error findings name it")
        elif not size_agrees(p, errors[hits[0]]):
            f = errors[hits[0]]
            problems.append(f"{p}: reported as {f.kind} {f.magnitude} {f.unit}")
    problems += [f"not planted: {f.kind} {f.subject} ({f.magnitude} {f.unit})" for i, f in enumerate(errors) if i not in matched]
    assert not problems, "\n".join(
        [
            "planted: " + "; ".join(map(str, planted)),
            *problems,
            "error findings:",
            *(f"  {f.kind} {f.subject}: {f.message}" for f in errors),
        ]
    )


@pytest.mark.parametrize("kind", PLANTED_KINDS)
@examples(1)
@given(data=st.data())
def test_a_planted_change_is_one_error_finding_naming_it_with_its_size(pairs, kind, data):
    """Each kind on a robot drawn among those it can be planted on (the first drawn differs from
    kind to kind, so a derandomized run still sees every robot)."""
    turn = PLANTED_KINDS.index(kind) % len(URDFS)
    able = [r for r in [*URDFS][turn:] + [*URDFS][:turn] if present(r) and kind in plantable_kinds(pairs(r)[1])]
    if not able:
        pytest.skip(f"no shared robot takes {kind}")
    urdf, mjcf = pairs(data.draw(st.sampled_from(able), label="robot"))
    text, planted = data.draw(planted_changes(mjcf, kinds=(kind,), max_changes=1), label="planted")
    assert_one_finding_each(run(urdf, text), planted)


@pytest.mark.parametrize("group", list(GROUPS))
@examples(1)
@given(data=st.data())
def test_two_changes_on_a_joint_and_the_joint_above_are_two_findings_each_of_its_size(pairs, group, data):
    urdf, mjcf = pairs(data.draw(st.sampled_from(robots(group)), label="robot"))
    text, planted = data.draw(planted_changes(mjcf, min_changes=2, stacked=True), label="planted")
    assert len(planted) == 2
    assert_one_finding_each(run(urdf, text), planted)


@pytest.mark.parametrize("group", list(GROUPS))
@examples(2)
@given(data=st.data())
def test_an_equivalent_rewrite_gives_no_error(pairs, group, data):
    urdf, mjcf = pairs(data.draw(st.sampled_from(robots(group)), label="robot"))
    text, what = data.draw(equivalent_rewrites(mjcf), label="rewrite")
    path = urdf.with_name("rewritten.xml")
    path.write_text(text)
    assert_files_agree(urdf, path, backends=BACKENDS, samples=4)
