"""Wall-clock deadlines for the searches (private): the ``timeout=`` keyword of every planner.

A :class:`Deadline` is made once per query from a timeout in seconds (``None``: no limit) and handed down to
every search loop, which asks :meth:`Deadline.expired` at its head — once per expanded belief, label, layer or
bisection step. When it has expired the search stops where it is and returns what it has: its best answer so
far (the *incumbent*, built and replayed exactly like every answer) and the bound it has proved at that moment,
and the query reports it with ``optimality.proved`` false and a limit such as ``"timeout 2 s reached after 5120
beliefs"`` in ``optimality.limits`` (``docs/contract.md``, "Timeouts"). With no incumbent the answer is
``not-found`` (nothing is proved).

The clock is :func:`time.monotonic` (immune to changes of the system time), read at every check: a read costs
tens of nanoseconds, far less than one expansion, so a search overshoots its deadline by about one expansion.
The partition and the safe BVG a query builds first are cut too: the query runs them inside
:meth:`Deadline.watching`, they check the time between blocks of their work (:mod:`solverplan.progress`), and a
query stopped there answers ``not-found`` with the timeout and the step it reached in ``optimality.limits``.

>>> Deadline(None).expired(), NEVER.remaining() is None
(False, True)
>>> d = Deadline(0.0001)
>>> import time; time.sleep(0.001)
>>> d.expired(), d.limit("12 beliefs")
(True, 'timeout 0.0001 s reached after 12 beliefs')
>>> check_timeout(float("nan"))
Traceback (most recent call last):
...
solverplan.errors.InputError: timeout nan must be a positive, finite number of seconds
"""

from __future__ import annotations

import math
import time
from typing import Callable, ContextManager

import numpy as np

from solverplan.errors import InputError
from solverplan.limits import quote
from solverplan.progress import tick, watching

__all__ = ["Deadline", "NEVER", "check_timeout", "deadline_of", "in_chunks"]

CHUNK_ROWS = 2048
"""Rows per call of :func:`in_chunks` under a deadline: small enough that one call takes a fraction of a second
on the position searches' largest layers."""


def check_timeout(timeout: object) -> float | None:
    """``timeout`` as seconds (a float), or ``None`` for no limit.

    Raises
    ------
    InputError
        Anything but ``None`` or a positive, finite real number (0, negative, NaN, infinity, booleans,
        strings): one line naming the value.
    """
    if timeout is None:
        return None
    if isinstance(timeout, bool) or not isinstance(timeout, (int, float)):
        raise InputError(f"timeout {quote(timeout)} must be a number of seconds")
    try:
        seconds = float(timeout)
    except OverflowError:  # an int beyond the float range
        raise InputError(f"timeout {quote(timeout)} must be a positive, finite number of seconds") from None
    if not (math.isfinite(seconds) and seconds > 0):
        raise InputError(f"timeout {seconds!r} must be a positive, finite number of seconds")
    return seconds


class Deadline:
    """A point in time ``seconds`` after its creation (monotonic clock), or never (``seconds`` None).

    Once :meth:`expired` has answered True it keeps answering True, so every loop of a pipeline stops at
    the same decision, and :attr:`hit` records that some search was cut by it.
    """

    __slots__ = ("seconds", "_end", "hit")

    def __init__(self, seconds: float | None) -> None:
        self.seconds = check_timeout(seconds)
        self._end = None if self.seconds is None else time.monotonic() + self.seconds
        self.hit = False

    def expired(self) -> bool:
        """Has the deadline passed? (Always False without a limit.) Every search asks at each expansion: it is
        also where a search reports that it is alive (:func:`solverplan.progress.tick`, the progress bar)."""
        tick("search")
        if self._end is None:
            return False
        if not self.hit and time.monotonic() >= self._end:
            self.hit = True
        return self.hit

    def remaining(self) -> float | None:
        """Seconds left (≥ 0), or None without a limit (for solvers that take a time limit of their own)."""
        if self._end is None:
            return None
        return max(0.0, self._end - time.monotonic())

    def watching(self) -> ContextManager[None]:
        """A :func:`solverplan.progress.watching` that stops the work inside at this deadline: the partition and the
        safe BVG a query builds check it between blocks and raise :class:`~solverplan.progress.Stopped`, so the
        timeout covers them too."""
        return watching(stop_at=self._end)

    def limit(self, progress: str) -> str:
        """The ``optimality.limits`` entry of a search cut by this deadline after ``progress`` (e.g. "12 beliefs")."""
        return f"timeout {self.seconds:g} s reached after {progress}"

    def __repr__(self) -> str:
        return "Deadline(None)" if self.seconds is None else f"Deadline({self.seconds:g} s, {self.remaining():.3g} s left)"


NEVER = Deadline(None)
"""The deadline that never expires: the default of every search."""


def deadline_of(timeout: float | Deadline | None) -> Deadline:
    """A :class:`Deadline` for a ``timeout`` keyword: seconds (validated by :func:`check_timeout`), None, or a
    deadline already running (one query handing its budget to another)."""
    if isinstance(timeout, Deadline):
        return timeout
    seconds = check_timeout(timeout)
    return NEVER if seconds is None else Deadline(seconds)


def in_chunks(deadline: Deadline, fn: Callable[..., tuple[np.ndarray, ...]], *columns: np.ndarray,
              rows: int = CHUNK_ROWS) -> tuple[np.ndarray, ...] | None:
    """``fn(*columns)`` for a row-wise vectorised ``fn`` (each output row depends on the same input row only),
    computed ``rows`` rows at a time with the deadline asked between calls; None once it has expired. Without a
    limit ``fn`` is called once on everything (the same arrays as a direct call).

    >>> double = lambda a: (2 * a, a + 1)
    >>> [x.tolist() for x in in_chunks(NEVER, double, np.arange(5), rows=2)]
    [[0, 2, 4, 6, 8], [1, 2, 3, 4, 5]]
    >>> [x.tolist() for x in in_chunks(Deadline(60), double, np.arange(5), rows=2)]
    [[0, 2, 4, 6, 8], [1, 2, 3, 4, 5]]
    """
    n = len(columns[0])
    if deadline.seconds is None or n <= rows:
        return None if deadline.expired() else fn(*columns)
    parts = []
    for lo in range(0, n, rows):
        if deadline.expired():
            return None
        parts.append(fn(*(c[lo:lo + rows] for c in columns)))
    return tuple(np.concatenate(outs) for outs in zip(*parts))
