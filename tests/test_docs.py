"""The README and docs/ stay true to the code: every shell command and Python block in them runs
here (each marked with an HTML comment saying how), the property table is the one the registry
generates, the README stays a short page that documents every command and links what exists."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
import types
from pathlib import Path

import pytest

from kinverify.cli import COMMANDS, main
from tests.paths import ROOT

README = ROOT / "README.md"
DOCS = [README, *sorted((ROOT / "docs").glob("*.md"))]
CHECKED = re.compile(r"<!-- checked: (?P<how>.*?) -->\n```(?P<lang>\w+)\n(?P<code>.*?)```", re.S)
RUNNABLE = {"bash", "sh", "shell", "console", "python", "py"}
FAST = ["--samples", "20"]  # small samples for `kinverify verify`: the documented command otherwise


def blocks() -> list[tuple[str, str, str, str]]:
    """(file, lang, how, code) of every checked block."""
    return [(path.name, m["lang"], m["how"], m["code"]) for path in DOCS for m in CHECKED.finditer(path.read_text())]


BLOCKS = blocks()
SHELL = [b for b in BLOCKS if b[1] == "bash"]
PYTHON = [b for b in BLOCKS if b[1] == "python"]


def _id(block) -> str:
    return f"{block[0]}:{block[3].strip().splitlines()[0][:40]}"


def test_every_runnable_block_is_checked():
    for path in DOCS:
        text = path.read_text()
        for m in re.finditer(r"^```(\w+)\n", text, re.M):
            if m[1] in RUNNABLE:
                before = text[: m.start()].rstrip().splitlines()[-1]
                assert before.startswith("<!-- checked: "), (
                    f"{path.name}: a {m[1]} block without a checked marker: {text[m.end() :][:60]!r}"
                )
    assert SHELL and PYTHON


def commands(code: str) -> list[str]:
    lines = [re.sub(r"\s+#\s.*$", "", line).strip() for line in code.splitlines()]
    return [line for line in lines if line and not line.startswith("#")]


def run_line(line: str, scratch: Path, capsys) -> int:
    """One documented command: kinverify and ``python -m kinverify.report.docs`` in this process,
    anything else (sed, the benchmark script) as a subprocess."""
    argv = shlex.split(line)
    if argv[0] in ("kinverify", ".venv/bin/kinverify"):
        args = argv[1:]
        if args[0] == "verify" and "--samples" not in args:
            args += FAST
        code = main(args)
        capsys.readouterr()
        return code
    if argv[:3] == ["python", "-m", "kinverify.report.docs"]:
        from kinverify.report import docs

        return docs.main(argv[3:])
    if argv[0] == "python":
        argv[0] = sys.executable
    return subprocess.run(argv, cwd=scratch, capture_output=True, text=True, timeout=600).returncode


@pytest.mark.parametrize("block", SHELL, ids=_id)
def test_shell_block_runs(block, tmp_path, monkeypatch, capsys):
    name, _, how, code = block
    lines = commands(code)
    if ".ci/run" in how:  # the install and test commands: CI runs them as they are
        ci = (ROOT / ".ci" / "run").read_text()
        assert "python3 -m venv .venv" in ci and "pip install --quiet -e ." in ci and "python -m pytest -n 2" in ci
        assert "kinverify verify models/arm3.toml" in ci
        verify = [part.strip().replace(".venv/bin/", "") for line in lines for part in line.split("&&") if "kinverify " in part]
        tour = next(b for b in SHELL if b[0] == "README.md" and "scratch" in b[2])
        assert verify == ["kinverify verify models/arm3.toml"] and verify[0] in commands(tour[3])  # run here, in the tour
        return
    root = "from the project root" in how
    scratch = ROOT if root else tmp_path
    if not root:
        (tmp_path / "models").symlink_to(ROOT / "models")
    monkeypatch.chdir(scratch)
    expected = re.search(r"exits (\d)", how)
    for k, line in enumerate(lines):
        want = int(expected[1]) if expected and k == len(lines) - 1 else 0
        assert run_line(line, scratch, capsys) == want, f"{name}: {line}"


def test_readme_python_example_runs(capsys, monkeypatch):
    (block,) = [b for b in PYTHON if b[0] == "README.md" and "FunctionBackend" in b[3]]
    monkeypatch.chdir(ROOT)
    exec(compile(block[3], str(README), "exec"), {"__name__": "readme_example"})
    assert capsys.readouterr().out.strip() == "pass"


def test_readme_pytest_example_is_the_file_the_plugin_test_runs():
    from tests.testing.test_pytest_plugin import readme_example

    (block,) = [b for b in PYTHON if b[0] == "README.md" and "kinverify_baseline" in b[3]]
    assert "test_pytest_plugin.py" in block[2] and readme_example() == block[3]
    (files,) = [b for b in PYTHON if b[0] == "README.md" and "assert_files_agree" in b[3]]
    assert "test_pytest_plugin.py" in files[2] and readme_example(1) == files[3]


def test_adding_a_suite_is_one_module_and_one_registry_line(monkeypatch):
    """docs/properties.md's worked example, run: its module, the registry line, and everything
    that reads the registry picks the new property up."""
    import kinverify.run
    import kinverify.suites.registry as registry
    from kinverify.backends import ModelSources
    from kinverify.commands.verify import add_parser, options_from_args
    from kinverify.model.specfile import load_spec
    from kinverify.report import docs, matrix
    from kinverify.run import VerifyOptions, verify

    (block,) = [b for b in PYTHON if b[0] == "properties.md"]
    module = types.ModuleType("reach")
    exec(compile(block[3], "kinverify/suites/reach.py", "exec"), module.__dict__)
    suites = (*registry.SUITES, module.ReachSuite)  # the one registry line
    monkeypatch.setattr(registry, "SUITES", suites)
    monkeypatch.setattr(kinverify.run, "SUITES", suites)
    from kinverify.backends import available_backends, default_backend_names

    sources = ModelSources.from_spec(load_spec(ROOT / "models" / "arm3.toml"))
    # the example holds every backend to 1e-9: the newton extra's float32 backends (their own floor) left out
    double = [n for n in default_backend_names(sources) if available_backends()[n].extra != "newton"]
    result = verify(sources, VerifyOptions(samples=20, suites=["kinematics", "reach"], backends=double))
    reach = [c for c in result.checks if c.property == "reach.tool"]
    assert {c.backends[1] for c in reach} == set(result.backends) - {"analytic"} and all(c.passed for c in reach)
    assert max(c.max_error for c in reach) < 1e-12
    assert [g.suite for g in matrix.groups(result)] == ["kinematics", "reach"]
    assert "| `reach.tool` | `reach` | agreement | m | 1e-09 |" in docs.property_table()
    import argparse

    parser = add_parser(argparse.ArgumentParser().add_subparsers())
    opts = options_from_args(parser.parse_args(["models/arm3.toml", "--skip", "reach", "--tolerance", "reach.tool=1e-6"]))
    assert "reach" not in opts.suites and opts.tolerances == {"reach.tool": 1e-6}


def test_property_table_is_the_generated_one():
    from kinverify.report import docs

    text = (ROOT / "docs" / "properties.md").read_text()
    assert docs.replace_table(text, docs.property_table()) == text
    from kinverify.suites.registry import properties

    for name in properties():
        assert f"| `{name}` |" in text


def test_readme_is_a_short_page_that_documents_every_command_and_links_what_exists():
    text = README.read_text()
    assert len(text.splitlines()) < 250
    for name in COMMANDS:
        assert f"`kinverify {name}" in text, f"README does not document `kinverify {name}`"
    for page in ("spec-format", "properties", "file-mode", "regression", "performance", "report", "ci", "robustness"):
        assert f"docs/{page}.md" in text  # the index, with the pages to come
    for path in DOCS:
        for target in re.findall(r"\]\(([^)#]+?)(?:#[^)]*)?\)", path.read_text()):
            if not target.startswith("http"):
                assert (path.parent / target).exists(), f"{path.name}: broken link {target}"
    image = ROOT / "docs" / "img" / "report.png"
    assert image.exists() and image.stat().st_size < 300_000
