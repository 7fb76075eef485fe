"""A rich progress display for ``kinverify verify``: one bar per suite, with the suite's own unit
of work (configurations, backends, controllers), its real total once the suite reports it, and
the time left; a spinner and the suite's name while the total is not known yet."""

from __future__ import annotations

from rich.progress import BarColumn, Progress, ProgressColumn, SpinnerColumn, TaskID, TextColumn
from rich.text import Text

# What each suite counts when it reports progress (``VerifyOptions.on_progress(done, total)``).
UNITS = {
    "kinematics": "configurations",
    "dynamics": "configurations",
    "ik": "solver backends",
    "tracking": "steps",
}  # tracking: one per controller run, then the animation


class CountColumn(ProgressColumn):
    """``120/1015 configurations``; empty until the suite has reported a total."""

    def render(self, task) -> Text:
        if task.total is None:
            return Text("")
        return Text(f"{int(task.completed)}/{int(task.total)} {task.fields.get('unit', '')}".rstrip(), style="progress.download")


class EtaColumn(ProgressColumn):
    """``1:05 left`` once the suite's speed is known; empty before."""

    max_refresh = 0.5

    def render(self, task) -> Text:
        left = task.time_remaining
        if task.total is None or left is None or task.finished:
            return Text("")
        minutes, seconds = divmod(int(round(left)), 60)
        return Text(f"{minutes}:{seconds:02d} left", style="progress.remaining")


class VerifyProgress:
    """Context manager; pass :meth:`suite` as ``verify(progress=...)`` and :meth:`advance` as
    ``VerifyOptions.on_progress``. Transient: nothing stays on screen once the run ends."""

    def __init__(self, console, label: str) -> None:
        self.label = label
        self._progress = Progress(
            SpinnerColumn(),
            TextColumn("{task.description}"),
            BarColumn(),
            CountColumn(),
            EtaColumn(),
            console=console,
            transient=True,
            disable=not console.is_terminal,
        )
        self._task: TaskID | None = None
        self.suite_name = ""

    def __enter__(self) -> "VerifyProgress":
        self._progress.__enter__()
        self._task = self._progress.add_task(f"verifying {self.label}...", total=None, unit="")
        return self

    def __exit__(self, *exc) -> None:
        self._progress.__exit__(*exc)

    def suite(self, name: str) -> None:
        """A suite starts: a new bar (its speed and time left are its own)."""
        self.suite_name = name
        assert self._task is not None  # made on entering
        self._progress.remove_task(self._task)  # a new task: no total until the suite reports one
        self._task = self._progress.add_task(f"{self.label}: {name}", total=None, unit=UNITS.get(name, "steps"))

    def advance(self, done: int, total: int) -> None:
        assert self._task is not None  # made on entering
        self._progress.update(self._task, completed=done, total=total)
