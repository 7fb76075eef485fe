"""One exception hierarchy for kinverify.

Every error a user can cause derives from :class:`KinverifyError`; the CLI turns it into a
one-line message and exit code 2. Backend library exceptions are re-raised as
:class:`BackendError` so callers never need to know which library failed.
"""

from __future__ import annotations

import re


class KinverifyError(Exception):
    """Root of every kinverify error (bad input, unloadable model, ...)."""


class SpecError(KinverifyError, ValueError):
    """An arm specification is invalid.

    Attributes:
        file: path of the spec file, or None for specs built in Python.
        field: field path inside the spec, e.g. ``joints[2].axis``.
        reason: what is wrong, in a few words.
    """

    def __init__(self, field: str, reason: str, file: str | None = None) -> None:
        self.field = field
        self.reason = reason
        self.file = file
        super().__init__(self._message())

    def _message(self) -> str:
        where = f"{self.file}: " if self.file else ""
        field = f"{self.field}: " if self.field else ""
        return f"{where}{field}{self.reason}"

    def within(self, prefix: str) -> "SpecError":
        """Return the same error with ``prefix`` prepended to the field path."""
        if not prefix:
            return self
        field = f"{prefix}.{self.field}" if self.field and not self.field.startswith("[") else f"{prefix}{self.field}"
        return SpecError(field, self.reason, self.file)

    def in_file(self, file: str) -> "SpecError":
        return SpecError(self.field, self.reason, file)


class InputError(KinverifyError, ValueError):
    """A command-line argument or input file (not a spec) is invalid."""


class BackendError(KinverifyError, RuntimeError):
    """A backend library refused a model or failed during evaluation.

    Attributes:
        backend: registry name of the backend (e.g. ``pinocchio-urdf``).
        reason: what it said, without its name.
    """

    def __init__(self, backend: str, message: str) -> None:
        self.backend, self.reason = backend, message
        super().__init__(f"{backend}: {message}")


class BackendUnavailable(BackendError):
    """The library behind a backend is not installed or cannot be imported."""


class UnknownNameError(KinverifyError, KeyError):
    """A frame, joint or backend name does not exist; the message lists valid names."""

    def __init__(self, kind: str, name: str, available: list[str] | tuple[str, ...]) -> None:
        self.kind, self.name, self.available = kind, name, tuple(available)
        super().__init__(f"unknown {kind} {name!r}; available {kind}s: {', '.join(available)}")

    def __str__(self) -> str:  # KeyError would otherwise quote the whole message
        return self.args[0]


# C++ source locations libraries add to a message (Pinocchio: "From file: ...", "in function: ...",
# "at line: 962"; urdfdom: "at line 607 in /project/urdfdom/..."): where the library is, not the file.
_SOURCE_LOCATION = re.compile(r"^(from file:|in function:|at line:|at line \d+ in )", re.IGNORECASE)


def library_reason(err: BaseException | str) -> str:
    """What a library said, as one line that keeps its reason: every line of the message joined
    with ``"; "`` (MuJoCo writes the reason first and the element after it: ``size 0 must be
    positive in geom; Element name 'tip', id 25, line 199``), without the C++ source locations
    Pinocchio and urdfdom add and a bare leading ``Error:``; the exception's type when it says
    nothing. Every error relayed from MuJoCo, Pinocchio, yourdfpy or xacro goes through this."""
    lines = []
    for line in str(err).splitlines():
        line = " ".join(line.split())
        if line.lower().startswith("message:"):
            line = line[len("message:") :].strip()
        if line.startswith("Error:"):
            line = line[len("Error:") :].strip()
        if line and not _SOURCE_LOCATION.match(line):
            lines.append(line)
    if lines:
        return "; ".join(lines)
    return "" if isinstance(err, str) else type(err).__name__
