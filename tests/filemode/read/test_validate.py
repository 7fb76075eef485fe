"""Physically impossible inertials in a user's URDF or MJCF are error findings naming the file and
the link or body; the physical limits (a point mass, a thin rod) and what the libraries report
themselves (unreadable numbers) are not."""

from __future__ import annotations

import numpy as np
import pytest

from kinverify.filemode.read.loading import LoadedFile
from kinverify.filemode.read.validate import KIND, TOL, inertial_problem, mjcf_problems, urdf_problems, validate_inertials


def moments_text(matrix) -> str:
    return ", ".join(f"{v:.6g}" for v in np.linalg.eigvalsh(np.asarray(matrix, float)))


@pytest.mark.parametrize(
    "mass, problem",
    [
        (float("nan"), "mass nan is not finite"),
        (float("inf"), "mass inf is not finite"),
        (float("-inf"), "mass -inf is not finite"),
        (-0.5, "mass -0.5 kg is negative"),
        (-1e-9, "mass -1e-09 kg is negative"),
        (0.0, None),
        (2.0, None),
    ],
)
def test_a_mass_is_finite_and_not_negative_whether_or_not_an_inertia_is_given(mass, problem):
    assert inertial_problem(mass, None) == problem
    assert inertial_problem(mass, np.zeros((3, 3))) == problem


def test_an_inertia_with_a_non_finite_entry_is_refused():
    for value in (float("nan"), float("inf"), -float("inf")):
        inertia = np.eye(3)
        inertia[0, 1] = inertia[1, 0] = value
        assert inertial_problem(1.0, inertia) == "inertia has non-finite entries"


def test_zero_mass_with_any_non_zero_inertia_is_refused_with_zero_inertia_accepted():
    assert inertial_problem(0.0, np.zeros((3, 3))) is None
    for i, j in ((0, 0), (2, 2), (0, 2)):
        inertia = np.zeros((3, 3))
        inertia[i, j] = inertia[j, i] = 1e-9
        assert inertial_problem(0.0, inertia) == "mass is zero but the inertia is not"
    assert inertial_problem(1e-12, np.diag([1.0, 1.0, 1.0])) is None


def test_the_physical_limits_are_accepted():
    assert inertial_problem(1.0, np.zeros((3, 3))) is None  # a point mass
    assert inertial_problem(1.0, np.diag([0.0, 1.0, 1.0])) is None  # a thin rod
    assert inertial_problem(1.0, np.diag([1.0, 1.0, 2.0])) is None  # a thin plate: A + B = C
    assert inertial_problem(1.0, np.diag([1.0, 2.0, 3.0])) is None


def test_a_negative_principal_moment_is_refused_beyond_the_relative_tolerance():
    assert TOL == 1e-6
    assert inertial_problem(1.0, np.diag([-1e-6, 1.0, 1.0])) is None  # at the tolerance
    assert inertial_problem(1.0, np.diag([-4e-6, 4.0, 4.0])) is None  # relative to the largest moment
    assert inertial_problem(1.0, np.diag([-2e-6, 1.0, 1.0])) == (
        "inertia is not positive semi-definite (principal moments -2e-06, 1, 1 kg·m²)"
    )
    assert inertial_problem(1.0, np.diag([-3e-6, 4.0, 4.0])) is None
    tilted = np.array([[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 3.0]])  # moments -1, 3, 3: only visible rotated
    assert inertial_problem(1.0, tilted) == "inertia is not positive semi-definite (principal moments -1, 3, 3 kg·m²)"


def test_the_triangle_inequality_is_refused_beyond_the_relative_tolerance():
    assert inertial_problem(1.0, np.diag([1.0, 1.0, 2.0 + 1e-7])) is None
    assert inertial_problem(1.0, np.diag([1.0, 1.0, 2.0 + 1e-5])) == (
        "principal moments 1, 1, 2.00001 kg·m² break the triangle inequality A + B >= C (no rigid body has them)"
    )
    assert inertial_problem(1.0, np.diag([3.0, 1.0, 1.0])) == (
        "principal moments 1, 1, 3 kg·m² break the triangle inequality A + B >= C (no rigid body has them)"
    )
    assert inertial_problem(1.0, np.diag([0.0, 0.0, 1.0])) is not None  # not a rod: two zero moments


def test_an_inertia_written_unsymmetric_is_read_as_its_symmetric_part():
    written = np.array([[1.0, 0.0, 0.0], [1.8, 1.0, 0.0], [0.0, 0.0, 1.0]])  # symmetric part: off-diagonal 0.9
    expected = (written + written.T) / 2
    assert inertial_problem(1.0, written) == (
        f"principal moments {moments_text(expected)} kg·m² break the triangle inequality A + B >= C (no rigid body has them)"
    )


URDF_LINK = '<link name="{name}"><inertial>{mass}{inertia}</inertial></link>'


def urdf(*links: str) -> str:
    return '<robot name="r">' + "".join(links) + "</robot>"


def link(name: str = "l", mass: str | None = "1", inertia: str | None = 'ixx="1" iyy="1" izz="1"') -> str:
    return URDF_LINK.format(
        name=name,
        mass="" if mass is None else f'<mass value="{mass}"/>',
        inertia="" if inertia is None else f"<inertia {inertia}/>",
    )


def test_urdf_inertials_are_read_with_each_entry_in_its_place():
    attrs = 'ixx="1" iyy="2" izz="4" ixy="0.1" ixz="0.2" iyz="0.3"'
    ((name, mass, inertia, problem),) = urdf_problems(urdf(link("l", "3", attrs), "<link name='bare'/>"))
    expected = np.array([[1, 0.1, 0.2], [0.1, 2, 0.3], [0.2, 0.3, 4]])
    assert (name, mass) == ("l", 3.0) and np.array_equal(inertia, expected)
    assert (
        problem
        == f"principal moments {moments_text(expected)} kg·m² break the triangle inequality A + B >= C (no rigid body has them)"
    )


def test_urdf_inertia_entries_not_written_are_zero():
    assert urdf_problems(urdf(link(inertia='ixx="1" iyy="1"'))) == []  # a thin rod along z
    ((_, _, inertia, problem),) = urdf_problems(urdf(link(inertia='izz="1"')))
    assert np.array_equal(inertia, np.diag([0.0, 0.0, 1.0])) and "break the triangle inequality" in problem


def test_urdf_a_mass_without_inertia_is_checked_alone():
    ((name, mass, inertia, problem),) = urdf_problems(urdf(link("neg", "-2", None), link("fine", "0", None)))
    assert (name, mass, inertia, problem) == ("neg", -2.0, None, "mass -2 kg is negative")


def test_urdf_inertials_the_libraries_cannot_read_are_left_to_them():
    for bad in (link("a", None), link("b", "heavy"), link("c", "-1", 'ixx="x"'), link("d", "-1", 'ixx="1" izz="x"')):
        assert urdf_problems(urdf(bad)) == []
        assert [p[0] for p in urdf_problems(urdf(bad, link("after", "-1")))] == ["after"]  # the next link still checked
    unnamed = '<link><inertial><mass value="-1"/></inertial></link>'
    assert [p[0] for p in urdf_problems(urdf(unnamed, link("e", "-1")))] == ["?", "e"]


def mjcf(*inertials: str, compiler: str = "") -> str:
    bodies = "".join(f'<body name="b{i}">{el}</body>' for i, el in enumerate(inertials))
    return f"<mujoco>{compiler}<worldbody>{bodies}<body name='none'/></worldbody></mujoco>"


def test_mjcf_diagonal_and_full_inertias_are_read_in_mujocos_order():
    full = '<inertial mass="2" fullinertia="1 2 4 0.1 0.2 0.3"/>'
    diag = '<inertial mass="1" diaginertia="1 1 3"/>'
    (b0, b1) = mjcf_problems(mjcf(full, diag))
    expected = np.array([[1, 0.1, 0.2], [0.1, 2, 0.3], [0.2, 0.3, 4]])
    assert b0[:2] == ("b0", 2.0) and np.array_equal(b0[2], expected) and moments_text(expected) in b0[3]
    assert b1[:2] == ("b1", 1.0) and np.array_equal(b1[2], np.diag([1.0, 1.0, 3.0])) and "1, 1, 3 kg·m²" in b1[3]
    both = '<inertial mass="1" diaginertia="1 1 1" fullinertia="1 1 3 0 0 0"/>'
    assert mjcf_problems(mjcf(both)) == []  # the diagonal first


def test_mjcf_inertias_of_the_wrong_length_or_unreadable_leave_the_mass_alone():
    for attrs in ('diaginertia="1 1"', 'fullinertia="1 1 3 0 0"', 'diaginertia="1 x 3"', 'fullinertia="1 1 3 0 0 x"', ""):
        assert mjcf_problems(mjcf(f'<inertial mass="1" {attrs}/>')) == []
        ((name, mass, inertia, problem),) = mjcf_problems(mjcf(f'<inertial mass="-1" {attrs}/>'))
        assert (name, mass, inertia, problem) == ("b0", -1.0, None, "mass -1 kg is negative")
    unreadable = ('<inertial diaginertia="1 1 3"/>', '<inertial mass="x" diaginertia="1 1 3"/>', '<inertial mass="-1"/>')
    assert [p[0] for p in mjcf_problems(mjcf(*unreadable))] == ["b2"]  # the next body still checked


def test_mjcf_balanceinertia_leaves_the_moments_to_mujoco_not_the_mass():
    broken = ['<inertial mass="1" diaginertia="1 1 3"/>', '<inertial mass="-1" diaginertia="1 1 3"/>']
    for flag in ('balanceinertia="true"', 'balanceinertia="TRUE"'):
        ((name, mass, inertia, problem),) = mjcf_problems(mjcf(*broken, compiler=f"<compiler {flag}/>"))
        assert (name, mass, problem) == ("b1", -1.0, "mass -1 kg is negative") and np.array_equal(inertia, np.diag([1, 1, 3]))
    for compiler in ('<compiler balanceinertia="false"/>', '<compiler angle="radian"/>', ""):
        assert [p[0] for p in mjcf_problems(mjcf(*broken, compiler=compiler))] == ["b0", "b1"]
    unnamed = "<mujoco><worldbody><body><inertial mass='-1'/></body></worldbody></mujoco>"
    assert [p[0] for p in mjcf_problems(unnamed)] == ["?"]


def test_each_problem_is_one_error_finding_naming_the_file_and_the_element():
    urdf_file = LoadedFile("r.urdf", "urdf", "", urdf(link("arm", "-1", None), link("ok")), "r")
    mjcf_file = LoadedFile("m.xml", "mjcf", "", mjcf('<inertial mass="1" diaginertia="1 1 3"/>'), "m")
    first, second = validate_inertials(urdf_file, mjcf_file)
    assert (first.kind, first.severity, first.subject, first.subject_type, first.property) == (
        KIND,
        "error",
        "arm",
        "link",
        "dynamics",
    )
    assert KIND == "nonphysical_inertia"
    assert first.message == "URDF r.urdf: link arm: non-physical inertial: mass -1 kg is negative"
    assert first.values == {"file": "URDF", "path": "r.urdf", "mass": -1.0, "inertia": None, "problem": "mass -1 kg is negative"}
    problem = "principal moments 1, 1, 3 kg·m² break the triangle inequality A + B >= C (no rigid body has them)"
    assert (second.subject, second.message) == ("b0", f"MJCF m.xml: body b0: non-physical inertial: {problem}")
    assert second.values == {
        "file": "MJCF",
        "path": "m.xml",
        "mass": 1.0,
        "inertia": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 3.0]],
        "problem": problem,
    }
    assert first.fails and second.fails
    clean = LoadedFile("c.urdf", "urdf", "", urdf(link()), "c")
    assert validate_inertials(clean, LoadedFile("c.xml", "mjcf", "", mjcf(), "c")) == []
