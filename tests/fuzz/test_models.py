"""Fuzz the URDF and MJCF inputs: a mangled file against the pristine one through ``diff`` (both
read by Pinocchio or MuJoCo, parameters and behaviour compared), and mangled pairs through file
mode (``verify --urdf --mjcf``: every library, matching, diagnosis, report)."""

from __future__ import annotations

import tempfile
from pathlib import Path

from hypothesis import given, note
from hypothesis import strategies as st

from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import load_spec
from tests.fuzz.harness import fuzz_settings, run_checked
from tests.fuzz.mangle import mangled_xml
from tests.paths import MODELS

PAIRS = {
    name: (generate_urdf(spec), generate_mjcf(spec))
    for name in ("arm3", "panda")
    for spec in [load_spec(MODELS / f"{name}.toml")]
}


def _files(tmp: str, **texts: str) -> dict[str, Path]:
    out = {}
    for name, text in texts.items():
        out[name] = Path(tmp) / name.replace("_", ".")
        out[name].write_text(text)
    return out


@fuzz_settings(25)
@given(st.sampled_from(sorted(PAIRS)), st.sampled_from(["urdf", "mjcf"]), st.data())
def test_mangled_model_through_diff(capfd, model, kind, data):
    pristine = PAIRS[model][0 if kind == "urdf" else 1]
    text, ops = data.draw(mangled_xml(pristine, kind))
    note(f"mutations: {ops}")
    ext = "urdf" if kind == "urdf" else "xml"
    with tempfile.TemporaryDirectory() as tmp:
        files = _files(tmp, **{f"old_{ext}": pristine, f"new_{ext}": text})
        argv = ["diff", str(files[f"old_{ext}"]), str(files[f"new_{ext}"]), "--samples", "3", "--report", f"{tmp}/d.html"]
        run_checked(capfd, argv, list(files.values()), Path(tmp))


@fuzz_settings(3)
@given(st.sampled_from(sorted(PAIRS)), st.data())
def test_mangled_pair_through_file_mode(capfd, model, data):
    urdf, mjcf = PAIRS[model]
    which = data.draw(st.sampled_from(["urdf", "mjcf", "both"]))
    if which in ("urdf", "both"):
        urdf, ops_u = data.draw(mangled_xml(urdf, "urdf"))
        note(f"URDF mutations: {ops_u}")
    if which in ("mjcf", "both"):
        mjcf, ops_m = data.draw(mangled_xml(mjcf, "mjcf"))
        note(f"MJCF mutations: {ops_m}")
    with tempfile.TemporaryDirectory() as tmp:
        files = _files(tmp, robot_urdf=urdf, robot_xml=mjcf)
        argv = [
            "verify",
            "--urdf",
            str(files["robot_urdf"]),
            "--mjcf",
            str(files["robot_xml"]),
            "--samples",
            "0",
            "--quiet",
            "--json",
            f"{tmp}/r.json",
            "--report",
            f"{tmp}/r.html",
        ]
        code, _ = run_checked(capfd, argv, list(files.values()), Path(tmp))
        assert (code == 2) == (not Path(tmp, "r.json").exists())
