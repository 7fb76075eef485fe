"""A rich progress display for ``kinverify verify``: a status line at once, and a bar with the
configurations done and the time left once the run has lasted ``BAR_AFTER_S`` seconds."""

from __future__ import annotations

import time

from rich.progress import BarColumn, MofNCompleteColumn, Progress, SpinnerColumn, TextColumn, TimeRemainingColumn

BAR_AFTER_S = 2.0


class VerifyProgress:
    """Context manager; pass :meth:`suite` as ``verify(progress=...)`` and :meth:`advance` as
    ``VerifyOptions.on_progress``."""

    def __init__(self, console, label: str) -> None:
        self.label = label
        self._progress = Progress(SpinnerColumn(), TextColumn("{task.description}"), BarColumn(),
                                  MofNCompleteColumn(), TextColumn("configurations"), TimeRemainingColumn(),
                                  console=console, transient=True)
        self._task = None
        self._t0 = time.perf_counter()

    def __enter__(self) -> "VerifyProgress":
        self._progress.__enter__()
        self._task = self._progress.add_task(f"verifying {self.label}...", total=None)
        return self

    def __exit__(self, *exc) -> None:
        self._progress.__exit__(*exc)

    def suite(self, name: str) -> None:
        self._progress.update(self._task, description=f"verifying {self.label}: {name}", total=None, completed=0)

    def advance(self, done: int, total: int) -> None:
        if time.perf_counter() - self._t0 >= BAR_AFTER_S:
            self._progress.update(self._task, completed=done, total=total)
