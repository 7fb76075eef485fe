"""Names and paths are text wherever kinverify shows or writes them (kinverify/text.py): rich markup
(``[/]``) in a robot name or an output path, matplotlib math text (``$\\undefinedsym$``) in a
frame the report draws, control characters and newlines in names and paths, a terminal whose
encoding cannot show a name, an output path that is not UTF-8, a joint name with newlines written
by ``--write-accepted`` and read back by ``--accept``, a loop of symbolic links as an input or an
output. Each was an exit 3 (or a wrong accepted file); each is now an ordinary run or one line."""

from __future__ import annotations

import io
import json
import os
import sys
import tomllib
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st
from matplotlib import cbook
from rich.text import Text

from kinverify.cli import main
from kinverify.text import literal, markup, shown, toml_comment, toml_string
from tests.fuzz.conftest import FAST, FILES
from tests.fuzz.harness import fuzz_settings, refused, run_checked

HOSTILE = ["[/]", "[bold red]x", "a\\", "$\\undefinedsym$", ":robot:", "a\nb", "\x1b[31m", "\u202e", "é✓", "\\[/]"]
NAMES = st.lists(st.sampled_from(HOSTILE) | st.text(max_size=6), max_size=4).map("".join)


def _rename(work: Path, old: str, new: str, out: str) -> None:
    """u.urdf and r.xml with the name ``old`` (an XML attribute value) replaced by ``new``, as ``out``.urdf/.xml."""
    (work / f"{out}.urdf").write_text((work / "u.urdf").read_text().replace(f'"{old}"', f'"{new}"'))
    (work / f"{out}.xml").write_text((work / "r.xml").read_text().replace(f'"{old}"', f'"{new}"'))


@given(NAMES)
@fuzz_settings(200)
def test_names_are_shown_as_they_are_never_interpreted(name):
    assert Text.from_markup(f"[b]{markup(name)}[/b]", emoji=False).plain == shown(name)  # no MarkupError, no lost tag
    assert not any(c in shown(name) for c in "\n\r\x1b\u202e")
    assert not cbook.is_math_text(literal(name))
    assert tomllib.loads(f"a = {toml_string(name)}\n{toml_comment(name)}\n") == {"a": name}


def test_markup_and_control_characters_in_a_robot_name_and_an_output_path_are_printed_as_written(capfd, work):
    text = (work / "u.urdf").read_text()
    (work / "n.urdf").write_text(text.replace('<robot name="arm3">', '<robot name="[/]:robot:[bold]">', 1))
    capfd.readouterr()
    code = main(
        [
            "verify",
            "--urdf",
            "n.urdf",
            "--mjcf",
            "r.xml",
            *FILES[:-1],
            "--json",
            "out[red]\x1b\t.json",
            "--report",
            "out/a[/]b.html",
        ]
    )
    out, err = capfd.readouterr()
    assert code == 0 and err == "", err
    assert "[/]:robot:[bold]-vs-arm3: 15 configurations" in out and "json: out[red]\\x1b\\t.json" in out
    assert "\x1b" not in out and "\t" not in out
    assert json.loads((work / "out[red]\x1b\t.json").read_text())["model"] == "[/]:robot:[bold]-vs-arm3"
    assert (work / "out" / "a[" / "]b.html").is_file()


def test_math_text_in_a_frame_the_report_draws_is_drawn_as_text(capfd, work):
    _rename(work, "end_effector", "$\\undefinedsym$", "m")  # the last frame: always labelled in the skeleton
    code, _ = run_checked(
        capfd,
        ["verify", "--urdf", "m.urdf", "--mjcf", "m.xml", "--samples", "0", "--quiet", "--report", "out/r.html"],
        [work / "m.urdf", work / "m.xml"],
        work,
    )
    assert code == 0
    assert "pictures" in json.loads((work / "reports" / "arm3.json").read_text())["sections"]


def test_control_characters_in_a_path_are_shown_escaped_by_plain_prints_too(capfd, work):
    folder = "o\x1b[2J\nut"
    code, _ = run_checked(capfd, ["generate", "m.toml", "--out", folder], [work / "m.toml"], work)
    assert code == 0 and (work / folder / "arm3.urdf").is_file()
    main(["generate", "m.toml", "--out", folder])
    out = capfd.readouterr().out
    written = ("urdf", "xml", "sdf", "usda") if (work / folder / "arm3.usda").is_file() else ("urdf", "xml", "sdf")
    assert out.splitlines() == [f"o\\x1b[2J\\nut/arm3.{ext}" for ext in written]


def test_a_joint_name_with_newlines_round_trips_through_the_accepted_file(capfd, work):
    name = "j2&#10;[[accepted]]&#10;kind = &quot;x&quot;&#10;# \\&#9;&#13;é[/]"
    _rename(work, "joint2", name, "n")
    mjcf = (work / "n.xml").read_text()
    (work / "n.xml").write_text(mjcf.replace('1.5707963267948966" damping="0.1"', '1.5707963267948966" damping="0.5"', 1))
    pair = ["verify", "--urdf", "n.urdf", "--mjcf", "n.xml", *FILES]
    code, _ = run_checked(capfd, [*pair, "--write-accepted", "acc.toml"], [work / "n.urdf", work / "n.xml"], work)
    assert code == 1  # the damping differs: one error finding, written as one entry
    entries = tomllib.loads((work / "acc.toml").read_text())["accepted"]
    assert [(e["kind"], e["subject"]) for e in entries] == [("damping_difference", 'j2\n[[accepted]]\nkind = "x"\n# \\\t\ré[/]')]
    (work / "acc.toml").write_text((work / "acc.toml").read_text().replace('reason = ""', 'reason = "reviewed"'))
    code, _ = run_checked(capfd, [*pair, "--accept", "acc.toml"], [work / "acc.toml"], work)
    assert code == 0


@pytest.mark.parametrize("encoding", ["ascii", "latin-1"])
def test_a_name_the_terminal_cannot_encode_is_replaced_not_fatal(capfd, work, monkeypatch, encoding):
    (work / "e.urdf").write_text((work / "u.urdf").read_text().replace('<robot name="arm3">', '<robot name="bras✓é">', 1))
    stdout, stderr = io.BytesIO(), io.BytesIO()
    monkeypatch.setattr(sys, "stdout", io.TextIOWrapper(stdout, encoding=encoding, errors="strict", write_through=True))
    monkeypatch.setattr(sys, "stderr", io.TextIOWrapper(stderr, encoding=encoding, errors="strict", write_through=True))
    code = main(["verify", "--urdf", "e.urdf", *FILES[:-1], "--json", "out/é.json", "--report", "out/é.html"])
    assert code == 0, stderr.getvalue()
    text = stdout.getvalue().decode(encoding)
    assert "bras?" in text and "verdict: PASS" in text  # shown as far as the encoding goes
    assert sys.stdout.errors == "strict"  # the caller's streams are given back as they were


def test_an_output_path_that_is_not_utf8_is_written(capfd, work):
    name = os.fsdecode(b"r\xff\xfe.json")
    code, _ = run_checked(capfd, ["verify", "m.toml", *FAST, "--json", name, "--report", "out/r.html"], [], work)
    assert code == 0 and json.loads((work / name).read_text())["verdict"] == "pass"
    assert "\\udcff" in (work / "out" / "r.html").read_text(encoding="utf-8")  # the command line, shown as it can be


@pytest.mark.parametrize(
    "argv",
    [
        ["verify", "--urdf", "loop", "--mjcf", "r.xml", *FILES],
        ["verify", "--urdf", "u.urdf", "--mjcf", "r.xml", *FILES, "--json", "loop"],
        ["verify", "m.toml", *FAST, "--report", "loop"],
        ["report", "loop"],
        ["ik", "m.toml", "--targets", "loop"],
        ["baseline", "check", "m.toml", "--baseline", "loop"],
    ],
)
def test_a_loop_of_symbolic_links_is_refused_in_one_line(capfd, work, argv):
    os.symlink("loop2", work / "loop")
    os.symlink("loop", work / "loop2")
    refused(capfd, argv, work, "loop is a loop of symbolic links")
