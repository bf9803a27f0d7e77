"""The progress bar of every command: the library's steps (:mod:`solverplan.progress`) drawn with rich on stderr.

Nothing is drawn for a job shorter than :data:`DELAY` seconds (rich is not even imported), when stderr is not a
terminal, or with ``--quiet``. Reports arrive from the library's loops, often thousands a second: they only store
the latest state, and rich's own refresh thread draws it a few times a second.
"""

from __future__ import annotations

import contextlib
import sys
import threading
import time
from typing import Any, Iterator

from solverplan.progress import watching

DELAY = 2.0
"""Seconds a command runs before its progress bar appears."""


class _Bar:
    """Starts a rich progress display at the first report after :data:`DELAY` seconds; one line per task."""

    def __init__(self) -> None:
        self.started = time.monotonic()
        self.display: Any = None
        self.tasks: dict[str, Any] = {}
        self.last: dict[str, float] = {}
        self.lock = threading.Lock()

    def report(self, task: str, done: float, total: float | None) -> None:
        if self.display is None:
            if time.monotonic() - self.started < DELAY:
                return
            self._start()
        now = time.monotonic()
        if total is None and task in self.tasks and now - self.last.get(task, 0.0) < 0.1:
            return  # a search ticks at every expansion: a few updates a second are enough
        self.last[task] = now
        with self.lock:
            key = self.tasks.get(task)
            if key is None:
                for other in self.tasks.values():  # an earlier stage is over once the next reports
                    self.display.update(other, visible=False)
                key = self.tasks[task] = self.display.add_task(task, total=total)
            if total is None:
                self.display.update(key, total=None, advance=0)
            else:
                self.display.update(key, completed=done, total=total)

    def _start(self) -> None:
        from rich.console import Console
        from rich.progress import (BarColumn, MofNCompleteColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn,
                                   TimeRemainingColumn)

        self.display = Progress(SpinnerColumn(), TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                                TimeElapsedColumn(), TimeRemainingColumn(), console=Console(stderr=True), transient=True)
        self.display.start()

    def close(self) -> None:
        if self.display is not None:
            self.display.stop()


@contextlib.contextmanager
def command_progress(quiet: bool) -> Iterator[None]:
    """Draw the steps the library reports inside this block on stderr (see the module docstring)."""
    if quiet or not sys.stderr.isatty():
        yield
        return
    bar = _Bar()
    try:
        with watching(report=bar.report):
            yield
    finally:
        bar.close()
