"""The findings table: each kind's severity, how :func:`finding` names its subject, how values
are printed and which ratios are named as unit mistakes. Each pinned by the value it must give."""

from __future__ import annotations

import math

import pytest

from kinverify.filemode.findings.table import SEVERITY, finding, fmt, unit_factor


@pytest.mark.parametrize(
    "kind, severity",
    [
        ("frame_offset", "error"),
        ("zero_offset", "error"),
        ("axis_sign_flip", "error"),
        ("limit_difference", "error"),
        ("damping_difference", "error"),
        ("coupling_difference", "error"),
        ("effort_difference", "error"),
        ("damping_unset", "warning"),
        ("limit_unset", "warning"),
        ("coupling_one_file", "warning"),
        ("base_frame_offset", "warning"),
        ("parser_refused", "warning"),
        ("rounding", "info"),
        ("frame_convention", "info"),
        ("joint_names", "info"),
        ("frame_twin", "info"),
    ],
)
def test_severity_of_each_class(kind, severity):
    assert SEVERITY[kind] == severity
    assert finding(kind, "m").severity == severity


def test_finding_severity_given_or_unknown_kind_is_a_warning():
    assert finding("frame_offset", "m", severity="info").severity == "info"
    assert finding("no_such_kind", "m").severity == "warning"


def test_finding_subject_first_named_of_joint_link_frame():
    f = finding(
        "zero_offset",
        "msg",
        {"a": 1},
        magnitude=2,
        unit="rad",
        prop="q",
        joint="j1",
        mjcf_joint="mj1",
        link="l1",
        mjcf_link="ml1",
    )
    assert (f.kind, f.message, f.subject, f.subject_type, f.other, f.property, f.values, f.magnitude, f.unit) == (
        "zero_offset",
        "msg",
        "j1",
        "joint",
        "mj1",
        "q",
        {"a": 1},
        2.0,
        "rad",
    )
    assert isinstance(f.magnitude, float)
    f = finding("mass_difference", "m", joint=None, link="l1", mjcf_link="ml1", frame="f")
    assert (f.subject, f.subject_type, f.other) == ("l1", "link", "ml1")
    f = finding("frame_offset", "m", frame="tool")  # no MJCF name: other is empty
    assert (f.subject, f.subject_type, f.other) == ("tool", "frame", "")


def test_finding_subject_file_else_model_and_lists_joined():
    values = {"file": "a.urdf"}
    f = finding("parser_refused", "m", values)
    assert (f.subject, f.subject_type, f.other, f.magnitude) == ("a.urdf", "file", "", None)
    assert f.values == values and f.values is not values  # a copy
    f = finding("parser_refused", "m")
    assert (f.subject, f.subject_type, f.values, f.property, f.unit) == ("", "model", {}, "", "")
    f = finding("lumped_links", "m", link=["a", "b"], mjcf_link=("c", "d"))
    assert (f.subject, f.other) == ("a, b", "c, d")


def test_fmt_six_significant_digits_tiny_and_negative_zero_as_zero():
    assert fmt(1.0) == "[1]"
    assert fmt(None) == "[nan]"  # a value one file does not give
    assert fmt([1.23456789, -2.5e-13, -0.0, 4.9e-13, 5e-13, -7e-13]) == "[1.23457, 0, 0, 0, 5e-13, -7e-13]"


@pytest.mark.parametrize(
    "ratio, quantity, name",
    [
        (1000.0, "length", "×1000 (millimetres as metres in the MJCF?)"),
        (0.001, "length", "×0.001 (millimetres as metres in the URDF?)"),
        (100.0, "length", "×100 (centimetres as metres in the MJCF?)"),
        (0.0254, "length", "×0.0254 (inches as metres in the MJCF?)"),
        (25.4, "length", "×25.4 (inches as millimetres in the MJCF?)"),
        (1 / 25.4, "length", "×0.0393701 (inches as millimetres in the URDF?)"),
        (1000.0 * 1.0009, "length", "×1000.9 (millimetres as metres in the MJCF?)"),  # within 1e-3
        (1000.0, "mass", "×1000 (grams as kilograms in the MJCF?)"),
        (1 / 0.45359237, "mass", "×2.20462 (pounds as kilograms in the URDF?)"),
    ],
)
def test_unit_factor_names_a_units_mistake(ratio, quantity, name):
    assert unit_factor(ratio, quantity) == name


@pytest.mark.parametrize(
    "ratio, quantity",
    [
        (1000.0 * 1.0011, "length"),
        (1.0, "length"),
        (100.0, "mass"),
        (1 / 1000.0 * 1.0011, "length"),
        (2.0, "mass"),
        (math.inf, "mass"),
    ],
)
def test_unit_factor_none_for_other_ratios(ratio, quantity):
    assert unit_factor(ratio, quantity) is None
