"""The pytest plugin as users get it: kinverify installed fresh (``pip install --target``) into a
temporary directory, a temporary project, and pytest run in a subprocess (``pytester``), so the
plugin can only arrive through the ``pytest11`` entry point declared in pyproject.toml."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from kinverify import load_spec
from kinverify.generate import generate_urdf
from tests.paths import ROOT

REPO = ROOT


@pytest.fixture(scope="module")
def fresh_install(tmp_path_factory) -> Path:
    """kinverify (no dependencies: they are in this venv already) installed into a new directory
    from a copy of the source tree, so nothing is built inside the repository."""
    src = tmp_path_factory.mktemp("src")
    shutil.copy(REPO / "pyproject.toml", src)
    shutil.copy(REPO / "README.md", src)
    shutil.copytree(REPO / "kinverify", src / "kinverify", ignore=shutil.ignore_patterns("__pycache__"))
    site = tmp_path_factory.mktemp("site")
    base = [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--target", str(site), str(src)]
    errors = []
    for extra in ([], ["--no-build-isolation"]):  # isolated build first; offline: the venv's setuptools
        done = subprocess.run(base + extra, capture_output=True, text=True)
        if done.returncode == 0:
            return site
        errors.append(done.stderr.strip().splitlines()[-1:] or ["?"])
    pytest.fail(f"pip could not install kinverify: {errors}")


@pytest.fixture
def project(pytester, fresh_install, monkeypatch):
    """An empty project whose pytest imports kinverify from the fresh install only."""
    monkeypatch.setenv("PYTHONPATH", str(fresh_install))
    monkeypatch.delenv("PYTEST_ADDOPTS", raising=False)
    return pytester


def readme_example(index: int = 0) -> str:
    """A complete test file shown in the README's pytest section: its first (a spec's) or its
    second (a URDF/MJCF pair's)."""
    text = (REPO / "README.md").read_text()
    section = text[text.index("## In your own pytest suite") :]
    return re.findall(r"```python\n(.*?)```", section, re.S)[index]


CONVERTER = '''
"""A team's own URDF -> MJCF converter: MuJoCo's reading of the URDF, written out."""
import pathlib
import tempfile

import mujoco


def urdf_to_mjcf(urdf: str, scale_mass: float = 1.0) -> str:
    model = mujoco.MjModel.from_xml_string(urdf)
    model.body_mass[2] *= scale_mass  # a converter bug, when asked for one
    with tempfile.TemporaryDirectory() as folder:
        path = pathlib.Path(folder) / "robot.xml"
        mujoco.mj_saveLastXML(str(path), model)
        return path.read_text()
'''


def test_the_plugin_loads_from_its_entry_point(project, fresh_install):
    project.makepyfile(
        test_plugin=f"""
        import pytest
        import kinverify

        @pytest.mark.kinverify
        def test_installed_copy_and_entry_point(request):
            assert kinverify.__file__.startswith({str(fresh_install)!r})
            plugin = request.config.pluginmanager.get_plugin("kinverify")  # the entry point's name
            assert plugin is not None and plugin.__name__ == "kinverify.testing.pytest_plugin"

        @pytest.mark.kinverify(model="arm.toml")
        def test_spec_from_marker_and_backends(kinverify_spec, kinverify_backends):
            spec = kinverify_spec()
            assert spec.name == "arm3"
            backends = kinverify_backends(spec)
            assert backends[0].name == "analytic" and "mujoco" in [b.name for b in backends]
            assert kinverify_backends(spec)[1] is backends[1]  # built once per session

        def test_update_flag_defaults_to_false(kinverify_update_baselines):
            assert kinverify_update_baselines is False

        def test_not_a_kinverify_test():
            pass
    """
    )
    shutil.copy(REPO / "models" / "arm3.toml", project.path / "arm.toml")
    result = project.runpytest_subprocess("-p", "no:cacheprovider", "--strict-markers", "-m", "kinverify", "-v")
    result.assert_outcomes(passed=3, deselected=1)
    result.stdout.fnmatch_lines(["kinverify 0.1.0 (python *, numpy *, pin *, mujoco *, yourdfpy *)"])


def test_the_readme_example_passes_then_reports_a_1mm_change(project):
    project.makepyfile(test_my_arm=readme_example())
    spec = (REPO / "models" / "arm3.toml").read_text()
    (project.path / "my_arm.toml").write_text(spec)
    first = project.runpytest_subprocess("-p", "no:cacheprovider", "--kinverify-update-baselines")
    first.assert_outcomes(passed=2)
    assert (project.path / "baselines" / "my_arm.json").is_file()
    # the baseline just written passes (the agreement test ran on this spec above and runs again below)
    project.runpytest_subprocess("-p", "no:cacheprovider", "-k", "nothing_moved").assert_outcomes(passed=1, deselected=1)

    old = "xyz = [0.0, 0.0, 0.25]   # link2_length"
    (project.path / "my_arm.toml").write_text(spec.replace(old, "xyz = [0.0, 0.0, 0.251]"))
    after = project.runpytest_subprocess("-p", "no:cacheprovider")
    after.assert_outcomes(passed=1, failed=1)  # the backends still agree with each other; the baseline does not
    after.stdout.fnmatch_lines(
        [
            "*kinverify: arm3 does not match baseline *my_arm.json: 10 quantities moved beyond tolerance",
            "*fk.position at frame 'link3': old * new *, delta 1.000e-03 m > tolerance 1e-09 m (*",
            "*dynamics.gravity at frame 'joint2': old * new *, delta 3.287e-04 N·m > tolerance 1e-09 N·m (*",
            "*q = [[]*[]]",
            "*why: the spec changed: joint joint3: origin.xyz [[]0, 0, 0.25[]] -> [[]0, 0, 0.251[]] (Δ 0.001)",
            "*rewrite the baseline: pytest --kinverify-update-baselines",
        ]
    )


def test_the_readme_files_example_checks_a_converter_and_finds_every_edit(project):
    """The README's second file: a converter of the project's own, its URDF and MJCF agree, and an
    edit planted in the converted MJCF is found; a converter that gets a mass wrong fails, the
    failure naming the finding. (Imports at the top: pytester drops the modules a test imports.)"""
    example = readme_example(1)
    assert "assert_files_agree" in example and "planted_changes" in example
    project.makepyfile(test_my_files=example, my_converter=CONVERTER)
    (project.path / "my_arm.urdf").write_text(generate_urdf(load_spec(REPO / "models" / "arm3.toml")))
    project.runpytest_subprocess("-p", "no:cacheprovider").assert_outcomes(passed=2)

    (project.path / "my_converter.py").write_text(CONVERTER.replace("scale_mass: float = 1.0", "scale_mass: float = 1.1"))
    wrong = project.runpytest_subprocess("-p", "no:cacheprovider", "-k", "same_robot")
    wrong.assert_outcomes(failed=1, deselected=1)
    wrong.stdout.fnmatch_lines(
        [
            "*kinverify: *my_arm.urdf and *my_arm.xml disagree (fail)",
            "*1 error finding:",
            "*mass_difference link2 (0.0763* kg): link2: mass 0.763407 kg (URDF) vs 0.839748 kg (MJCF)",
        ]
    )
