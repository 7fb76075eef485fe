"""Fuzz the spec-file input: mangled TOML through ``generate`` (the spec loader and both
generators) and, for a few examples, through ``verify`` (every backend loads what was generated)."""

from __future__ import annotations

import tempfile
import tomllib
from pathlib import Path

from hypothesis import given, note
from hypothesis import strategies as st

from tests.fuzz.harness import fuzz_settings, run_checked
from tests.fuzz.mangle import mangled_spec
from tests.paths import MODELS

SPECS = [tomllib.loads((MODELS / f"{name}.toml").read_text()) for name in ("arm3", "ur5e", "scara")]


def specs():
    return st.sampled_from(SPECS).flatmap(mangled_spec)


@fuzz_settings(60)
@given(specs())
def test_mangled_spec_through_generate(capfd, case):
    text, ops = case
    note(f"mutations: {ops}\n{text}")
    with tempfile.TemporaryDirectory() as tmp:
        spec, out = Path(tmp) / "spec.toml", Path(tmp) / "out"
        spec.write_text(text)
        code, err = run_checked(capfd, ["generate", str(spec), "--out", str(out)], [spec], Path(tmp))
        if code == 2:
            assert str(spec) in err  # the message names the file
        else:
            assert len(list(out.glob("*.urdf"))) == 1 and len(list(out.glob("*.xml"))) == 1


@fuzz_settings(3)
@given(specs())
def test_mangled_spec_through_verify(capfd, case):
    text, ops = case
    note(f"mutations: {ops}\n{text}")
    with tempfile.TemporaryDirectory() as tmp:
        spec = Path(tmp) / "spec.toml"
        spec.write_text(text)
        argv = [
            "verify",
            str(spec),
            "--samples",
            "0",
            "--skip",
            "ik",
            "--skip",
            "tracking",
            "--skip",
            "pictures",
            "--quiet",
            "--json",
            f"{tmp}/r.json",
            "--report",
            f"{tmp}/r.html",
        ]
        code, _ = run_checked(capfd, argv, [spec], Path(tmp))
        assert (code == 2) == (not Path(tmp, "r.json").exists())
