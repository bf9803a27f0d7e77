"""Progress and stop points of long jobs: what the library reports, and where a timeout may cut it.

The library never draws anything. Its long loops (the partition of the boundary, the sweeps and joins of the safe
BVG, the searches, rollouts, explorations, studies) call :func:`step` with a task name and how far they are; a
caller that wants to see it, or to stop the job at a point in time, wraps the work in :func:`watching`:

- ``report(task, done, total)`` is called at each step (``total`` None when the size is unknown) — the command
  line renders it as a rich progress bar on stderr;
- ``stop_at`` (a :func:`time.monotonic` time) makes the first step after it raise :class:`Stopped`, which names
  the task and how far it got. The query that set the time catches it and answers with what it has (a timeout
  answer marked not proved), so a timeout covers the graph build too, not only the search.

Outside :func:`watching` a step costs one context-variable read. The watch is a :mod:`contextvars` variable, so
threads and nested queries each see their own (an inner :func:`watching` without a ``stop_at`` keeps the outer
one's, and a report function is inherited the same way).

>>> import time
>>> seen = []
>>> with watching(report=lambda task, done, total: seen.append((task, done, total))):
...     step("sweeps", 1, 4)
>>> seen
[('sweeps', 1, 4)]
>>> try:
...     with watching(stop_at=time.monotonic() - 1):
...         step("partition", 3, 10)
... except Stopped as exc:
...     print(exc)
stopped during partition (3 of 10)
"""

from __future__ import annotations

import contextvars
import time
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Callable, Iterator

__all__ = ["Stopped", "Report", "watching", "step", "tick", "stop_time", "remaining"]

Report = Callable[[str, float, "float | None"], None]
"""``report(task, done, total)``: a task's progress (``total`` None when unknown)."""


class Stopped(Exception):
    """The job reached the ``stop_at`` time of the :func:`watching` around it, at a step of ``task``.

    Attributes ``task`` (the step's name), ``done`` and ``total`` (how far it got; ``total`` None when unknown).
    The planners catch it themselves and answer ``not-found`` with the timeout in ``optimality.limits``; it reaches
    a caller only from work it wrapped in :func:`watching` with a ``stop_at`` of its own.

    Examples
    --------
    >>> import time, solverplan as sp
    >>> ell = sp.Environment.from_coords([[0, 0], [7, 0], [7, 3], [3, 3], [3, 7], [0, 7]])
    >>> try:
    ...     with sp.watching(stop_at=time.monotonic()):
    ...         sp.partition(ell)
    ... except sp.Stopped as stop:
    ...     print(stop.task, stop.done, stop.total)
    partition of the boundary: sides of the edges 0 6
    """

    def __init__(self, task: str, done: float = 0, total: float | None = None) -> None:
        self.task, self.done, self.total = task, done, total
        where = f" ({done:,.0f} of {total:,.0f})" if total else ""
        super().__init__(f"stopped during {task}{where}")


@dataclass(frozen=True)
class _Watch:
    stop_at: float | None
    report: Report | None


_WATCH: contextvars.ContextVar[_Watch | None] = contextvars.ContextVar("solverplan_watch", default=None)


@contextmanager
def watching(*, report: Report | None = None, stop_at: float | None = None) -> Iterator[None]:
    """Report the steps of the library's long loops inside the block to ``report``, and stop them at ``stop_at``.

    Parameters
    ----------
    report
        Called as ``report(task, done, total)`` at every step: the partition of the boundary (per reflex vertex), the
        safe BVG's sweeps and safe sets (per block), the searches (``total`` None: still running), rollouts (per
        bounce). Keep it cheap: searches report once per expansion. None: the enclosing watch's.
    stop_at
        A :func:`time.monotonic` time: the first step after it raises :class:`Stopped` (searches, which answer a
        timeout of their own, never stop here). None: the enclosing watch's (the earlier of two wins), or never.

    Yields
    ------
    None
        The block runs under the watch; it ends with the block (threads and tasks keep their own).

    Examples
    --------
    >>> import solverplan as sp
    >>> seen = set()
    >>> with sp.watching(report=lambda task, done, total: seen.add(task)):
    ...     plan = sp.find_plan(sp.load_environment("two_rooms"), "e0", "e5")
    >>> "search" in seen          # and, when the graph is not built yet, its steps ("safe BVG: sweeps", …)
    True
    """
    outer = _WATCH.get()
    if outer is not None:
        if report is None:
            report = outer.report
        if outer.stop_at is not None:
            stop_at = outer.stop_at if stop_at is None else min(stop_at, outer.stop_at)
    token = _WATCH.set(_Watch(stop_at, report))
    try:
        yield
    finally:
        _WATCH.reset(token)


def step(task: str, done: float = 0, total: float | None = None) -> None:
    """Report that ``task`` has done ``done`` of ``total`` units, and raise :class:`Stopped` past the stop time."""
    watch = _WATCH.get()
    if watch is None:
        return
    if watch.report is not None:
        watch.report(task, done, total)
    if watch.stop_at is not None and time.monotonic() >= watch.stop_at:
        raise Stopped(task, done, total)


def tick(task: str, done: float = 0, total: float | None = None) -> None:
    """Report how far ``task`` is (``total`` None: unknown size, it is still running) without ever stopping it: for
    loops that answer a timeout of their own (the searches under a :class:`~solverplan.plan._deadline.Deadline`) or
    have none (rollouts)."""
    watch = _WATCH.get()
    if watch is not None and watch.report is not None:
        watch.report(task, done, total)


def stop_time() -> float | None:
    """The stop time of the current watch (monotonic seconds), or None."""
    watch = _WATCH.get()
    return None if watch is None else watch.stop_at


def remaining() -> float | None:
    """Seconds left before the stop time of the current watch (≥ 0), or None without one."""
    end = stop_time()
    return None if end is None else max(0.0, end - time.monotonic())
