"""Progress on the terminal for commands that read big files (``ednc fit``, ``ednc diagnose``).

A bar (rich) on stderr while a file is read, then one spinner line per later stage, all
erased when the command ends. Shown only when a person is watching: both stdout and
stderr are terminals and the command's output is not ``--json`` (a script reading the
JSON, a pipe or a log file gets nothing extra).
"""

from __future__ import annotations

import sys
from pathlib import Path
from types import TracebackType

from rich.console import Console
from rich.progress import (
    BarColumn,
    DownloadColumn,
    Progress,
    SpinnerColumn,
    TaskID,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

from ednc.cli import UserError
from volumetric.measure.measurement import (
    MeasurementFormatError,
    Measurements,
    read_measurements,
)

__all__ = ["CommandProgress", "read_shown", "wanted"]


def wanted(as_json: bool) -> bool:
    """True when progress should be shown: a terminal on stdout and stderr, no ``--json``."""
    return not as_json and sys.stdout.isatty() and sys.stderr.isatty()


class CommandProgress:
    """Context manager for a command's stages; does nothing when ``enabled`` is False.

    ``reading(label, total)`` starts a bar over ``total`` bytes and returns the callback
    the measurement reader calls with the bytes read so far; ``stage(label)`` ends the
    current stage and shows a spinner with elapsed time for the next one.
    """

    def __init__(self, enabled: bool, console: Console | None = None) -> None:
        self._progress: Progress | None = None
        self._task: TaskID | None = None
        if enabled:
            self._progress = Progress(
                SpinnerColumn(),
                TextColumn("{task.description}"),
                BarColumn(),
                DownloadColumn(),
                TimeElapsedColumn(),
                TimeRemainingColumn(),
                console=console or Console(stderr=True),
                transient=True,
            )

    def __enter__(self) -> CommandProgress:
        if self._progress is not None:
            self._progress.start()
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        if self._progress is not None:
            self._progress.stop()

    def _finish(self) -> None:
        if self._progress is not None and self._task is not None:
            task = next(t for t in self._progress.tasks if t.id == self._task)
            if task.total is not None:
                self._progress.update(self._task, completed=task.total)
            self._progress.stop_task(self._task)
            self._progress.update(self._task, visible=False)
        self._task = None

    def reading(self, label: str, total: int) -> _Advance:
        """Start a bar of ``total`` bytes; the returned callable takes the bytes done."""
        self._finish()
        if self._progress is not None:
            self._task = self._progress.add_task(label, total=max(total, 1))
        return _Advance(self._progress, self._task)

    def stage(self, label: str) -> None:
        """End the current stage; show ``label`` with a spinner until the next one."""
        self._finish()
        if self._progress is not None:
            self._task = self._progress.add_task(label, total=None)


class _Advance:
    """The reader's progress callback: bytes read so far."""

    __slots__ = ("_progress", "_task")

    def __init__(self, progress: Progress | None, task: TaskID | None) -> None:
        self._progress = progress
        self._task = task

    def __call__(self, done: int) -> None:
        if self._progress is not None and self._task is not None:
            self._progress.update(self._task, completed=done)


def read_shown(path: Path, progress: CommandProgress) -> Measurements:
    """A measurement CSV read whole with a bar of its bytes; errors as one-line
    :class:`~ednc.cli.UserError` (as :func:`ednc.inputs.read_data`)."""
    try:
        size = path.stat().st_size
    except OSError:
        size = 0  # the read below says why
    try:
        return read_measurements(path, progress=progress.reading(f"reading {path.name}", size))
    except (MeasurementFormatError, UnicodeDecodeError) as exc:
        raise UserError(str(exc)) from exc
    except OSError as exc:
        raise UserError(f"cannot read {path}: {exc.strerror or exc}") from exc
