"""The README stays true to the code: its marked Python examples run, and its command table
lists every CLI subcommand."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from kinverify.cli import COMMANDS
from tests.paths import ROOT

README = ROOT / "README.md"
MARK = "<!-- checked: tests/test_readme.py runs this block -->"
BLOCKS = re.findall(re.escape(MARK) + r"\n```python\n(.*?)```", README.read_text(), re.S)


def test_there_are_checked_examples():
    assert BLOCKS


@pytest.mark.parametrize("code", BLOCKS)
def test_readme_example_runs(code, capsys, monkeypatch):
    monkeypatch.chdir(README.parent)
    exec(compile(code, str(README), "exec"), {"__name__": "readme_example"})
    assert "pass" in capsys.readouterr().out


def test_every_command_is_documented():
    text = README.read_text()
    for name in COMMANDS:
        assert f"`kinverify {name}" in text, f"README does not document `kinverify {name}`"
