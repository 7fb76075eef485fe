"""docs/ci.md's YAML stays true: the GitHub Actions workflow parses, every kinverify line in it is a
valid command line of this CLI and runs to exit 0 in a folder set up by the page's own blocks
(baseline saved, accepted differences written), its JUnit files parse; the pre-commit config
snippet passes pre-commit's own schema and names the hook kinverify ships. (The page's bash blocks
themselves run in tests/test_docs.py.)"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import yaml

from kinverify.cli import COMMANDS, build_parser
from tests.paths import ROOT
from tests.test_docs import commands, run_line

PAGE = (ROOT / "docs" / "ci.md").read_text()
CHEAP = " --skip ik --skip tracking --skip pictures"  # the agreement suites stay; run_line adds --samples 20
YAML = re.findall(r"<!-- (the \w+): .*? -->\n```yaml\n(.*?)```", PAGE, re.S)


def snippet(name: str) -> str:
    (text,) = [code for label, code in YAML if label == name]
    return text


def workflow_lines() -> list[str]:
    steps = yaml.safe_load(snippet("the workflow"))["jobs"]["kinverify"]["steps"]
    return [line for step in steps if "run" in step for line in commands(step["run"])]


def test_the_workflow_parses_and_names_real_commands():
    flow = yaml.safe_load(snippet("the workflow"))
    assert set(flow) == {"name", True, "permissions", "jobs"}  # YAML 1.1 reads the key `on` as True
    steps = flow["jobs"]["kinverify"]["steps"]
    uses = [s["uses"].split("@")[0] for s in steps if "uses" in s]
    assert uses == ["actions/checkout", "actions/setup-python", "actions/upload-artifact", "mikepenz/action-junit-report"]
    junit = next(s for s in steps if s.get("uses", "").startswith("mikepenz/"))
    assert junit["with"]["report_paths"] == "reports/junit-*.xml" and flow["permissions"]["checks"] == "write"
    lines = workflow_lines()
    kinverify = [shlex.split(line) for line in lines if line.startswith("kinverify ")]
    assert {argv[1] for argv in kinverify} == {"verify", "baseline"} and {a[1] for a in kinverify} <= set(COMMANDS)
    for argv in kinverify:
        build_parser().parse_args(argv[1:])  # argparse exits 2 on an unknown option
        if argv[1] == "verify":
            assert re.fullmatch(r"reports/junit-[\w-]+\.xml", argv[argv.index("--junit") + 1])
    others = [line for line in lines if not line.startswith("kinverify ")]
    assert others == ["pip install kinverify", "python -m pytest tests --junitxml reports/junit-pytest.xml"]


def test_the_workflow_runs_where_the_page_set_it_up(tmp_path, monkeypatch, capsys):
    from junitparser import JUnitXml

    (tmp_path / "models").symlink_to(ROOT / "models")
    monkeypatch.chdir(tmp_path)
    blocks = re.findall(r"<!-- checked: (.*?) -->\n```bash\n(.*?)```", PAGE, re.S)
    baselines = next(code for how, code in blocks if "baseline save" in code)
    accepted = next(code for how, code in blocks if "--write-accepted" in code)
    assert run_line(commands(baselines)[0], tmp_path, capsys) == 0  # the saved baseline, committed
    *setup, write = commands(accepted)
    assert [run_line(line, tmp_path, capsys) for line in setup] == [0, 0]
    assert run_line(write + CHEAP, tmp_path, capsys) == 1  # the difference found, written for review
    for line in (line for line in workflow_lines() if line.startswith("kinverify ")):
        assert run_line(line + (CHEAP if line.startswith("kinverify verify") else ""), tmp_path, capsys) == 0, line
    files = sorted(Path("reports").glob("junit-*.xml"))
    assert [f.name for f in files] == ["junit-arm3.xml", "junit-ur5e-files.xml"]
    cases = [case for f in files for suite in JUnitXml.fromfile(str(f)) for case in suite]
    assert len(cases) > 50 and not any(type(r).__name__ in ("Failure", "Error") for case in cases for r in case.result)
    assert any(case.name == "base_transform [model]" and case.is_skipped for case in cases)  # the accepted difference


def test_the_pre_commit_config_uses_the_shipped_hook():
    from pre_commit.clientlib import CONFIG_SCHEMA, load_manifest
    from pre_commit.yaml import yaml_load
    import cfgv

    config = cfgv.validate(yaml_load(snippet("the config")), CONFIG_SCHEMA)  # pre-commit's own schema
    (repo,) = config["repos"]
    (hook,) = repo["hooks"]
    (shipped,) = load_manifest(str(ROOT / ".pre-commit-hooks.yaml"))
    assert hook["id"] == shipped["id"] == "kinverify"
    assert f"`{shipped['files']}`" in PAGE  # the page quotes the hook's default
    files = re.compile(hook["files"])
    assert files.search("description/robot.urdf") and files.search("models/arm3.toml") and not files.search("docs/x.toml")
    build_parser().parse_args(["check", *hook["args"], "models/arm3.toml"])
