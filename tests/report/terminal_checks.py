"""What ``kinverify verify`` leaves on a screen or in a log, and the checks its layout must pass.

:func:`run_in_terminal` runs the real CLI in a pseudo-terminal of a given width (what ``script``
with ``stty cols 80`` does, without depending on either); :func:`run_to_file` runs it with stdout
to a file and no terminal anywhere (a CI log: rich falls back to 80 columns);
:func:`render` prints a saved result in-process, as a terminal or as a log. :func:`assert_fits`
then reads the tables back by their header's column positions and compares every number with the
checks it stands for, so a number split over two lines or shown as another value fails.
"""

from __future__ import annotations

import fcntl
import io
import os
import re
import struct
import subprocess
import sys
import termios

from rich.cells import cell_len
from rich.console import Console

from kinverify.report.terminal import print_result
from kinverify.results import VerifyResult
from kinverify.suites.base import PERFORMANCE

ANSI = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]")
CURSOR_SHOWN = "\x1b[?25h"  # rich's live progress display ends with this...
ERASE = "\r\x1b[1A\x1b[2K"  # ...then erases its last line
PASSING_LINES = 40


def _env() -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "LINES")}
    env["TERM"] = "xterm-256color"
    return env


def run_in_terminal(argv: list[str], cwd, columns: int = 80, rows: int = 50) -> tuple[list[str], int]:
    """``python -m kinverify argv`` with stdin, stdout and stderr on a pseudo-terminal of
    ``columns``; returns the lines left on the screen (the progress display erased) and the exit code."""
    master, slave = os.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", rows, columns, 0, 0))
    proc = subprocess.Popen(
        [sys.executable, "-m", "kinverify", *argv], stdin=slave, stdout=slave, stderr=slave, cwd=cwd, env=_env(), close_fds=True
    )
    os.close(slave)
    chunks = []
    while True:
        try:
            data = os.read(master, 1 << 16)
        except OSError:  # EIO: the child side closed
            break
        if not data:
            break
        chunks.append(data)
    code = proc.wait()
    os.close(master)
    raw = b"".join(chunks).decode("utf-8", "replace").replace("\r\n", "\n")
    assert raw.count(CURSOR_SHOWN) <= 1, "the progress display ran twice"
    after = raw.split(CURSOR_SHOWN)[-1].replace(ERASE, "", 1)  # up to the progress line, erase it, print over it
    assert "\r" not in after and "\x1b[1A" not in after, "something redraws lines after the progress display"
    return _trim([ANSI.sub("", line) for line in after.split("\n")]), code


def run_to_file(argv: list[str], cwd) -> tuple[list[str], int]:
    """``python -m kinverify argv`` with stdout and stderr to a file and no terminal on any stream."""
    log = os.path.join(cwd, "stdout.log")
    with open(log, "w", encoding="utf-8") as out:
        code = subprocess.run(
            [sys.executable, "-m", "kinverify", *argv],
            stdin=subprocess.DEVNULL,
            stdout=out,
            stderr=subprocess.STDOUT,
            cwd=cwd,
            env=_env(),
        ).returncode
    with open(log, encoding="utf-8") as f:
        text = f.read()
    assert not ANSI.search(text), "escape codes in a log"
    return _trim(text.split("\n")), code


def render(result: VerifyResult, width: int = 80, terminal: bool = False) -> list[str]:
    """``print_result`` as a terminal of ``width`` (colours, then stripped) or as a log would get it."""
    buf = io.StringIO()
    print_result(result, Console(file=buf, width=width, force_terminal=terminal, color_system="truecolor" if terminal else None))
    return _trim([ANSI.sub("", line) for line in buf.getvalue().split("\n")])


def _trim(lines: list[str]) -> list[str]:
    while lines and not lines[-1].strip():
        lines.pop()
    while lines and not lines[0].strip():
        lines.pop(0)
    return lines


def table_rows(lines: list[str], first_header: str) -> tuple[str, list[str]]:
    """The header line that starts with ``first_header`` and the rows under it (each row starts
    with its property's name; a line that starts with a space continues the row above)."""
    starts = [i for i, line in enumerate(lines) if line.startswith(first_header + " ")]
    assert len(starts) == 1, f"{len(starts)} header lines start with {first_header!r}"
    start = starts[0]
    rows = []
    for line in lines[start + 1 :]:
        if not re.match(r"[a-z_]+\.[^\s]+ ", line) and not line.startswith(" "):
            break
        rows.append(line)
    return lines[start], rows


def assert_fits(lines: list[str], result: VerifyResult, width: int = 80, wrapped_rows_allowed: bool = False) -> None:
    """No line wider than ``width``; no table row on two lines (unless ``wrapped_rows_allowed``:
    then only text wraps, between words); every number whole and equal, to its 3 significant digits,
    to the worst check of its row (largest error over tolerance), with a result word that matches;
    a passing run without findings or notes in at most :data:`PASSING_LINES` lines."""
    widest = max(lines, key=lambda line: cell_len(line.rstrip()))
    assert cell_len(widest.rstrip()) <= width, f"{cell_len(widest.rstrip())} columns: {widest!r}"
    tables = [
        ("property", "max error", "tolerance", [c for c in result.checks if c.kind != PERFORMANCE]),
        ("performance", "measured", "goal", [c for c in result.checks if c.kind == PERFORMANCE]),
    ]
    for first, value_header, limit_header, checks in tables:
        if not checks:
            continue
        header, rows = table_rows(lines, first)
        value_end = header.index(value_header) + len(value_header)  # right-aligned numbers end here
        limit_start = header.index(limit_header)  # tolerance or goal, then its unit
        wrapped = [r for r in rows if r.startswith(" ")]
        assert wrapped_rows_allowed or not wrapped, f"rows on two lines: {wrapped}"
        shown: dict[str, list[float]] = {}
        for row in (r for r in rows if not r.startswith(" ")):
            prop = row.split()[0]
            value, limit = float(row[:value_end].split()[-1]), float(row[limit_start:].split()[0])
            mine = [c for c in checks if c.property == prop]
            match = [c for c in mine if _same(c.max_error, value) and _same(c.tolerance, limit)]
            assert match, f"{row!r}: no {prop} check has {value} against {limit}"
            word = row.split()[-1]
            assert word == "ok" if all(c.passed for c in match) else word in ("FAIL", "missed", "finding"), row
            shown.setdefault(prop, []).append(value / limit if limit else value)
        for prop in {c.property for c in checks}:
            assert prop in shown, f"{prop} has no row"
            worst = max(c.max_error / c.tolerance if c.tolerance else c.max_error for c in checks if c.property == prop)
            assert _same(max(shown[prop]), worst, rel=2e-2), (prop, shown[prop], worst)
    if result.passed and not result.findings and not result.notes:
        assert len(lines) <= PASSING_LINES, f"a passing run in {len(lines)} lines"
        assert not [line for line in lines if line.startswith(" ")], "a line continues the one above"


def _same(a: float, b: float, rel: float = 6e-3) -> bool:
    """Equal to the 3 significant digits the terminal shows (0 only as 0, inf as inf)."""
    if a == b:
        return True
    return abs(a - b) <= rel * max(abs(a), abs(b))
