"""Parsing with bounded nesting: exactly the limit is read, one level more is a one-line error
naming the file (and how the user named it); NaN refused where asked; .npy arrays only; unsafe or
broken XML refused with the reason."""

from __future__ import annotations

import io
import json
import math

import numpy as np
import pytest

from kinverify.io.formats import check_depth, json_loads, npy_load, toml_loads, xml_parse
from kinverify.io.read import InputFileError
from kinverify.pipeline.limits import MAX_JSON_DEPTH, MAX_XML_DEPTH


def nested(depth: int):
    value: object = 1
    for k in range(depth):
        value = [value] if k % 2 else {"k": value}
    return value


def message(call, *args, **kwargs) -> str:
    with pytest.raises(InputFileError) as err:
        call(*args, **kwargs)
    return str(err.value)


def test_check_depth_counts_dicts_and_lists_up_to_the_limit():
    value = nested(3)  # {"k": [{"k": 1}]}
    assert check_depth(value, "f.json", limit=3) is value
    assert (
        message(check_depth, value, "f.json", limit=2) == "f.json nests values more than 2 levels deep (see docs/robustness.md)"
    )
    assert (
        message(check_depth, [[], [[[]]]], "f.json", "--spec", limit=3)
        == "--spec: f.json nests values more than 3 levels deep (see docs/robustness.md)"
    )
    assert check_depth(nested(MAX_JSON_DEPTH), "f.json") == nested(MAX_JSON_DEPTH)
    assert "more than 64 levels" in message(check_depth, nested(MAX_JSON_DEPTH + 1), "f.json")


def test_json_loads_bounded_and_nan_where_allowed():
    assert json_loads("3", "f.json") == 3
    assert json_loads(b'{"a": [1, 2]}', "f.json") == {"a": [1, 2]}
    assert math.isnan(json_loads("NaN", "f.json")) and json_loads("[Infinity]", "f.json") == [math.inf]
    assert json_loads(json.dumps(nested(MAX_JSON_DEPTH)), "f.json") == nested(MAX_JSON_DEPTH)
    deep = "more than 64 levels deep (see docs/robustness.md)"
    assert message(json_loads, json.dumps(nested(MAX_JSON_DEPTH + 1)), "f.json") == f"f.json nests values {deep}"
    assert message(json_loads, "[" * 100_000 + "]" * 100_000, "f.json", "L") == f"L: f.json nests values {deep}"
    assert message(json_loads, json.dumps(nested(MAX_JSON_DEPTH + 1)), "f.json", "L") == f"L: f.json nests values {deep}"
    assert message(json_loads, "[NaN]", "f.json", allow_nan=False) == "f.json holds NaN, which is not a number this file may hold"
    assert (
        message(json_loads, '{"a": -Infinity}', "f.json", "L", allow_nan=False)
        == "L: f.json holds -Infinity, which is not a number this file may hold"
    )
    assert json_loads("[1.5]", "f.json", allow_nan=False) == [1.5]
    with pytest.raises(json.JSONDecodeError):  # the caller knows what the file was meant to be
        json_loads("[1,", "f.json")


def test_toml_loads_bounded():
    assert toml_loads('a = [[1]]\n[b]\nc = "d"\n', "f.toml") == {"a": [[1]], "b": {"c": "d"}}
    deep = "f.toml nests values more than 64 levels deep (see docs/robustness.md)"
    assert message(toml_loads, "a = " + "[" * 5000 + "]" * 5000, "f.toml") == deep
    assert message(toml_loads, "a = " + "[" * MAX_JSON_DEPTH + "]" * MAX_JSON_DEPTH, "f.toml") == deep
    assert message(toml_loads, "a = " + "[" * 5000 + "]" * 5000, "f.toml", "--spec") == f"--spec: {deep}"
    assert message(toml_loads, "a = " + "[" * MAX_JSON_DEPTH + "]" * MAX_JSON_DEPTH, "f.toml", "--spec") == f"--spec: {deep}"
    assert toml_loads("a = " + "[" * (MAX_JSON_DEPTH - 1) + "]" * (MAX_JSON_DEPTH - 1), "f.toml")["a"] is not None


def saved(array, **kwargs) -> bytes:
    buffer = io.BytesIO()
    np.save(buffer, array, **kwargs)
    return buffer.getvalue()


def test_npy_load_arrays_only():
    np.testing.assert_array_equal(npy_load(saved(np.arange(3.0)), "q.npy"), [0.0, 1.0, 2.0])
    not_npy = "q.npy is not an .npy file (an array written by numpy.save)"
    assert message(npy_load, b"", "q.npy") == not_npy
    assert message(npy_load, b"1 2 3", "q.npy") == not_npy
    assert (
        message(npy_load, saved(np.array([{}], dtype=object), allow_pickle=True), "q.npy", "--initial") == f"--initial: {not_npy}"
    )  # a pickle is never loaded
    npz = io.BytesIO()
    np.savez(npz, a=np.zeros(2))
    assert (
        message(npy_load, npz.getvalue(), "q.npy")
        == "q.npy must hold a real-valued array (an .npz archive or object array is not one)"
    )
    assert (
        message(npy_load, npz.getvalue(), "q.npy", "--targets")
        == "--targets: q.npy must hold a real-valued array (an .npz archive or object array is not one)"
    )


def xml_nested(depth: int) -> bytes:
    return ("<a>" * depth + "</a>" * depth).encode()


def test_xml_parse_root_and_depth():
    root = xml_parse(b'<!DOCTYPE robot><robot name="r"><link/></robot>', "r.urdf")  # a DTD without entities
    assert (root.tag, root.get("name"), [c.tag for c in root]) == ("robot", "r", ["link"])
    assert xml_parse(xml_nested(3), "r.urdf", limit=3).tag == "a"
    assert (
        message(xml_parse, xml_nested(4), "r.urdf", limit=3)
        == "r.urdf nests elements more than 3 levels deep (see docs/robustness.md)"
    )
    assert (
        message(xml_parse, b"<r>" + xml_nested(3) + b"<b/></r>", "r.urdf", "--urdf", limit=3)
        == "--urdf: r.urdf nests elements more than 3 levels deep (see docs/robustness.md)"
    )
    assert xml_parse(b"<r>" + xml_nested(2) * 3 + b"</r>", "r.urdf", limit=3).tag == "r"  # siblings: depth goes back down
    assert "more than 4 levels" in message(xml_parse, b"<r><a><x/><y><z><w/></z></y></a></r>", "r.urdf", limit=4)
    assert xml_parse(xml_nested(MAX_XML_DEPTH), "r.urdf").tag == "a"
    assert "more than 300 levels" in message(xml_parse, xml_nested(MAX_XML_DEPTH + 1), "r.urdf")


@pytest.mark.parametrize(
    "data, reason",
    [
        (
            b'<!DOCTYPE r [<!ENTITY e "x">]><r>&e;</r>',
            "declares XML entities (external entities and entity expansion are refused for safety; remove the DTD)",
        ),
        (
            b'<!DOCTYPE r [<!ENTITY e SYSTEM "file:///etc/passwd">]><r>&e;</r>',
            "declares XML entities (external entities and entity expansion are refused for safety; remove the DTD)",
        ),
        (b"<a>", "is not XML: no element found: line 1, column 3"),
        (b"", "is not XML: no element found: line 1, column 0"),
    ],
)
def test_xml_parse_refuses_unsafe_or_broken_xml(data, reason):
    assert message(xml_parse, data, "r.urdf") == f"r.urdf {reason}"
    assert message(xml_parse, data, "r.urdf", "--urdf") == f"--urdf: r.urdf {reason}"
