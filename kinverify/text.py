"""Names, paths and messages from files and arguments as kinverify shows them: always as text.

A robot named ``[/]``, an output path ``out[/].json``, a frame named ``$\\undefinedsym$`` or a
joint whose name holds a newline or an escape sequence is data, never markup, math text or a
terminal command. What reaches the terminal goes through :func:`shown` (control characters,
bidirectional overrides and undecodable bytes written as escapes: ``\\n``, ``\\x1b``,
``\\u202e``, ``\\udcff``), what reaches rich markup through :func:`markup` (also rich's tags
escaped), what reaches a matplotlib label through :func:`literal` (dollar signs escaped), and
what reaches a TOML file through :func:`toml_string` (a basic string that reads back exactly).
The files kinverify writes (JSON, HTML) keep the names exactly.
"""

from __future__ import annotations

import re
import sys
from typing import Any

# C0 and C1 controls, DEL, bidirectional embeddings/overrides/isolates, lone surrogates (bytes
# that were not UTF-8, as Python decodes file names and arguments)
_UNSAFE = re.compile("[\x00-\x1f\x7f-\x9f\u202a-\u202e\u2066-\u2069\ud800-\udfff]")
_TRAILING_BACKSLASHES = re.compile(r"\\*$")
_BACKSLASH_BEFORE_TEXT_BRACKET = re.compile(r"\\(?=\[(?![a-z#/@][^[]*?\]))")  # before a "[" rich would not take for a tag
_TOML_ESCAPES = {'"': '\\"', "\\": "\\\\", "\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f", "\r": "\\r"}


def _escaped(char: str) -> str:
    code = ord(char)
    return {"\n": "\\n", "\t": "\\t", "\r": "\\r"}.get(char) or (f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}")


def shown(text: Any) -> str:
    """``str(text)`` safe to print: control characters, bidirectional overrides and lone
    surrogates written as backslash escapes (``a\\nb`` for a newline), everything else as is."""
    return _UNSAFE.sub(lambda m: _escaped(m.group()), str(text))


def markup(text: Any) -> str:
    """``text`` inside a rich markup string: :func:`shown`, with rich's tags escaped (``\\[/]``).

    rich reads a backslash before a ``[`` in plain text as escaping it, and halves the backslashes
    before a tag (ours may follow the text): a backslash before a ``[`` that is no tag is doubled,
    and a run of backslashes at the end is doubled, so the name is shown with every backslash."""
    from rich.markup import escape  # rich is imported by the commands that print with it, not by the CLI's start

    plain = shown(text)
    run = _TRAILING_BACKSLASHES.search(plain).group()  # type: ignore[union-attr]  # matches the empty run too
    body = plain[: len(plain) - len(run)]
    return escape(_BACKSLASH_BEFORE_TEXT_BRACKET.sub(r"\\\\", body)) + run * 2


def literal(text: Any) -> str:
    """``text`` as a matplotlib label: :func:`shown`, dollar signs escaped so no math text is parsed."""
    return shown(text).replace("$", "\\$")


def toml_string(text: str) -> str:
    """A TOML basic string (``"..."``) that reads back as exactly ``text``: quotes, backslashes and
    every control character escaped (a newline cannot end the string or start a table)."""
    out = []
    for char in text:
        code = ord(char)
        if char in _TOML_ESCAPES:
            out.append(_TOML_ESCAPES[char])
        elif code < 0x20 or code == 0x7F or 0xD800 <= code <= 0xDFFF:  # surrogates: not TOML, kept visible
            out.append(f"\\u{code:04x}" if code < 0xD800 else f"\\\\u{code:04x}")
        else:
            out.append(char)
    return '"' + "".join(out) + '"'


def toml_comment(text: str) -> str:
    """One TOML comment line: ``# `` and :func:`shown` (a newline in ``text`` cannot end it)."""
    return "# " + shown(text)


def tolerant_streams() -> list:
    """Make ``sys.stdout`` and ``sys.stderr`` replace what their encoding cannot write (``LC_ALL=C``
    with an ASCII terminal, ``PYTHONIOENCODING=latin-1``) instead of raising; returns what
    :func:`restore_streams` needs to undo it."""
    changed = []
    for stream in (sys.stdout, sys.stderr):
        errors = getattr(stream, "errors", None)
        if errors == "strict" and hasattr(stream, "reconfigure"):
            try:
                stream.reconfigure(errors="replace")
            except (ValueError, OSError):  # a closed or unusual stream: leave it
                continue
            changed.append((stream, errors))
    return changed


def restore_streams(changed: list) -> None:
    for stream, errors in changed:
        try:
            stream.reconfigure(errors=errors)
        except (ValueError, OSError):
            pass


def console(**kwargs):
    """A rich console that never turns a name into an emoji (``:robot:``); names still need :func:`markup`."""
    from rich.console import Console

    return Console(emoji=False, **kwargs)
