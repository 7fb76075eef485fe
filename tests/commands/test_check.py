"""``kinverify check`` and the pre-commit hook that runs it: shipped models pass, a model that
moved from its baseline or a URDF/MJCF pair that disagrees fails with one line naming it, bad input
exits 2, and pre-commit itself accepts the hook manifest and runs the command on the changed files."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from kinverify.cli import COMMANDS, main
from kinverify.commands import check
from tests.paths import MODELS, ROOT

FAST = ["--samples", "20"]


def lines(capsys) -> tuple[list[str], list[str]]:
    captured = capsys.readouterr()
    return captured.out.splitlines(), captured.err.splitlines()


def test_shipped_models_pass_one_line_each(capsys):
    assert main(["check", str(MODELS / "arm3.toml"), str(MODELS / "gripper.toml")]) == 0
    out, err = lines(capsys)
    assert [line.split(":")[0] for line in out] == [str(MODELS / "arm3.toml"), str(MODELS / "gripper.toml")] and not err
    for line in out:
        checks = int(re.search(r"ok: 0 of (\d+) checks failed, 0 error findings$", line)[1])
        assert checks > 100  # kinematics, limits, inertia and dynamics on every backend


def test_a_model_that_moved_from_its_baseline_fails(tmp_path, monkeypatch, capsys):
    from kinverify.model.specfile import load_spec
    from kinverify.regression.baseline import save_baseline

    monkeypatch.chdir(tmp_path)
    spec_path = tmp_path / "models" / "arm3.toml"
    spec_path.parent.mkdir()
    shutil.copy(MODELS / "arm3.toml", spec_path)
    save_baseline(load_spec(spec_path), "baselines/arm3.json", samples=10)  # the README's place: baselines/ at the root
    assert main(["check", "models/arm3.toml", *FAST]) == 0
    (out,), _ = lines(capsys)
    assert out.endswith("; baseline baselines/arm3.json: nothing moved")

    text = spec_path.read_text()
    spec_path.write_text(text.replace("xyz = [0.0, 0.0, 0.25]", "xyz = [0.0, 0.0, 0.251]", 1))  # link2 1 mm longer
    assert main(["check", "models/arm3.toml", *FAST]) == 1
    (out,), _ = lines(capsys)
    assert out.startswith("models/arm3.toml: FAIL: 0 of ")  # the models still agree with each other...
    assert (
        "baseline baselines/arm3.json: 10 quantities moved, first fk.position at link3 by 0.001 m" in out
    )  # ...not with the baseline
    assert out.endswith("(details: kinverify baseline check models/arm3.toml --baseline baselines/arm3.json)")

    # baselines/ beside the spec comes first; --baselines names another folder
    (tmp_path / "models" / "baselines").mkdir()
    save_baseline(load_spec(spec_path), "models/baselines/arm3.json", samples=10)
    assert main(["check", "models/arm3.toml", *FAST]) == 0
    assert check.baseline_for(Path("models/arm3.toml"), None) == Path("models/baselines/arm3.json")
    assert main(["check", "models/arm3.toml", "--baselines", "baselines", *FAST]) == 1
    assert check.baseline_for(Path("models/arm3.toml"), "elsewhere") is None


def test_a_pair_that_disagrees_fails_and_an_accepted_file_rechecks_it(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["generate", str(MODELS / "ur5e.toml"), "--out", "pair"]) == 0
    mjcf = Path("pair/ur5e.xml")
    mjcf.write_text(mjcf.read_text().replace('<body name="world_mount">', '<body name="world_mount" quat="0 0 0 1">'))
    capsys.readouterr()
    # the MJCF alone finds its URDF; both given run once
    assert main(["check", "pair/ur5e.xml", "pair/ur5e.urdf", *FAST, "--suites", "kinematics"]) == 1
    (out,), _ = lines(capsys)
    assert out.startswith("pair/ur5e.urdf + ur5e.xml: FAIL: 0 of ") and "1 error finding; first: base_transform (model)" in out
    assert out.endswith("details: kinverify verify --urdf pair/ur5e.urdf --mjcf pair/ur5e.xml")

    skip = [
        f"--skip={suite}" for suite in ("limits", "inertia", "ik", "dynamics", "tracking", "diagnosis", "workspace", "pictures")
    ]
    assert (
        main(
            [
                "verify",
                "--urdf",
                "pair/ur5e.urdf",
                "--mjcf",
                "pair/ur5e.xml",
                "--quiet",
                *FAST,
                *skip,
                "--json",
                "r.json",
                "--report",
                "r.html",
                "--write-accepted",
                "pair/kinverify-accepted.toml",
            ]
        )
        == 1
    )
    capsys.readouterr()
    assert (
        main(["check", "pair/kinverify-accepted.toml", *FAST, "--suites", "kinematics"]) == 0
    )  # the reviewed difference is accepted
    (out,), _ = lines(capsys)
    assert out.startswith("pair/ur5e.urdf + ur5e.xml: ok: 0 of ") and out.endswith("0 error findings")


def test_bad_input_and_other_files(tmp_path, capsys):
    from kinverify.generate import generate_urdf
    from kinverify.model.specfile import load_spec

    (tmp_path / "broken.toml").write_text("x = [\n")
    (tmp_path / "alone.urdf").write_text(generate_urdf(load_spec(MODELS / "arm3.toml")))
    (tmp_path / "launch.xml").write_text("<launch><node pkg='x'/></launch>")
    (tmp_path / "notes.md").write_text("# notes\n")
    files = [str(tmp_path / n) for n in ("broken.toml", "missing.toml", "alone.urdf", "launch.xml", "notes.md")]
    assert main(["check", *files, str(MODELS / "scara.toml"), *FAST]) == 2  # the worst code; the good model still runs
    out, err = lines(capsys)
    assert err == [
        f"error: {files[0]}: malformed TOML: Invalid value (at end of document)",
        f"error: {files[1]}: cannot read spec file: No such file or directory",
    ]
    # a URDF with no MJCF beside it: the one-file audit (every library that reads URDF)
    assert out[0].startswith(f"{files[2]}: ok: every library reads it alike; ")
    assert out[1:3] == [
        f"{files[3]}: skipped (not a spec .toml, a URDF or an MJCF)",
        f"{files[4]}: skipped (not a spec .toml, a URDF or an MJCF)",
    ]
    assert out[3].startswith(f"{MODELS / 'scara.toml'}: ok: ")
    assert main(["check", str(MODELS / "arm3.toml"), "--suites", "kinematics,speed"]) == 2
    assert capsys.readouterr().err.startswith("kinverify: error: --suites: unknown suite 'speed'; suites: kinematics,")


def test_a_kinverify_bug_in_one_model_is_one_line_and_the_others_still_run(capsys, monkeypatch):
    import kinverify.run

    real = kinverify.run.verify_spec

    def broken_for_scara(spec, options=None, **kwargs):  # a real exception from the real call path
        return {}["missing key"] if spec.name == "scara" else real(spec, options, **kwargs)

    monkeypatch.setattr(kinverify.run, "verify_spec", broken_for_scara)
    assert main(["check", str(MODELS / "scara.toml"), str(MODELS / "arm3.toml"), *FAST]) == 3
    out, _ = lines(capsys)
    assert out[0] == f"{MODELS / 'scara.toml'}: ERROR (internal): KeyError: 'missing key' (a kinverify bug)"
    assert out[1].startswith(f"{MODELS / 'arm3.toml'}: ok: ")


def manifest() -> dict:
    from pre_commit.clientlib import load_manifest  # pre-commit's own validation of .pre-commit-hooks.yaml

    (hook,) = load_manifest(str(ROOT / ".pre-commit-hooks.yaml"))
    return hook


def test_the_hook_manifest_is_valid_and_runs_kinverify_check():
    hook = manifest()
    assert hook["id"] == "kinverify" and hook["language"] == "python" and hook["pass_filenames"] and hook["require_serial"]
    program, command = hook["entry"].split()
    assert program == "kinverify" and command in COMMANDS and command == "check"
    files = re.compile(hook["files"])
    assert all(files.search(p) for p in ("models/arm3.toml", "models/robot.urdf", "models/robot/robot.xml"))
    assert not any(files.search(p) for p in ("pyproject.toml", "docs/models/x.toml", "models/README.md"))
    assert check.ACCEPTED == __import__("kinverify.filemode.findings.accepted", fromlist=["DEFAULT_NAME"]).DEFAULT_NAME


@pytest.mark.skipif(shutil.which("git") is None, reason="pre-commit needs git")
def test_pre_commit_runs_the_hook_on_the_changed_models(tmp_path):
    """A repository using the hook, run by pre-commit itself: the manifest's entry and files with
    ``language: system`` (the installed kinverify), so pre-commit builds no environment."""
    import yaml

    hook = manifest()
    repo = tmp_path / "robot"
    (repo / "models").mkdir(parents=True)
    shutil.copy(MODELS / "arm3.toml", repo / "models" / "arm3.toml")
    (repo / "README.md").write_text("# robot\n")
    local = {k: hook[k] for k in ("id", "name", "entry", "files", "require_serial")}
    config = {"repos": [{"repo": "local", "hooks": [{**local, "language": "system", "args": FAST, "verbose": True}]}]}
    (repo / ".pre-commit-config.yaml").write_text(yaml.safe_dump(config))
    env = {
        **os.environ,
        "PRE_COMMIT_HOME": str(tmp_path / "cache"),
        "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}",
        "GIT_AUTHOR_NAME": "t",
        "GIT_AUTHOR_EMAIL": "t@t",
        "GIT_COMMITTER_NAME": "t",
        "GIT_COMMITTER_EMAIL": "t@t",
    }

    def run(*argv):
        return subprocess.run(argv, cwd=repo, env=env, capture_output=True, text=True, timeout=300)

    assert run("git", "init", "-q").returncode == 0 and run("git", "add", ".").returncode == 0
    pre_commit = [sys.executable, "-m", "pre_commit", "run", "--color", "never"]
    proc = run(*pre_commit)  # the staged files: pre-commit passes models/arm3.toml, not README.md
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "models/arm3.toml: ok: 0 of " in proc.stdout and "README.md" not in proc.stdout
    (repo / "models" / "arm3.toml").write_text("[arm\n")
    assert run("git", "add", ".").returncode == 0
    proc = run(*pre_commit)
    assert proc.returncode == 1 and "error: models/arm3.toml: malformed TOML" in proc.stdout
