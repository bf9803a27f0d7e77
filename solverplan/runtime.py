"""Run-time settings of the library: the safe-BVG disk cache, the memory limit and the processes, as one object.

The settings are read where they apply (the graph cache when a graph is built or looked up, the memory limit
when a job's size is checked) from :func:`settings`. Change them for a block of code with :func:`config`
— the change is undone when the block ends, and other threads and tasks keep theirs — or for the whole
process with :func:`configure`. The command line does the former for each command, from its global options
(``--graph-cache``, ``--graph-cache-min-arcs``, ``--graph-cache-size``, ``--max-memory``, ``--jobs``).

Examples
--------
>>> import solverplan as sp
>>> with sp.config(max_memory=2 * 2**30, graph_cache=None) as now:
...     now.max_memory
2147483648
>>> sp.settings().max_memory
'available'
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator, Literal, Sequence, TypeVar

from solverplan.errors import InputError
from solverplan.progress import Stopped, watching

__all__ = ["Settings", "settings", "config", "configure", "default_cache_directory", "DEFAULT_MIN_ARCS",
           "DEFAULT_MAX_BYTES"]

DEFAULT_MIN_ARCS = 100_000
"""Graphs with fewer arcs are not written to disk: they build in about 0.15 s or less (≈ 1.5 µs per arc on the
project's machine, benchmarks/README.md) and reading is not worth a file."""

DEFAULT_MAX_BYTES = 2 << 30
"""The disk cache's size cap (bytes): least recently used entries go first. Also the largest entry read."""


def default_cache_directory() -> Path:
    """``$XDG_CACHE_HOME/solverplan/graphs``, or ``~/.cache/solverplan/graphs`` when it is unset.

    The command line's graph cache lives here unless ``--graph-cache`` says otherwise; the library's is off
    until :func:`config` or :func:`configure` names a folder.
    """
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "solverplan" / "graphs"


@dataclass(frozen=True)
class Settings:
    """The library's run-time settings (immutable: change them with :func:`config` or :func:`configure`).

    Attributes
    ----------
    graph_cache
        Folder of the safe-BVG disk cache, ``None`` for none (the in-memory cache of a few graphs stays).
    graph_cache_min_arcs
        Only graphs with at least this many arcs are written to the disk cache (0: every graph).
    graph_cache_min_seconds
        Also write graphs whose build took at least this long (CPU seconds); ``None``: the size alone decides.
    graph_cache_max_bytes
        The disk cache's size cap in bytes: least recently used entries are removed after a write until it fits.
    max_memory
        Jobs estimated to need more bytes than this are refused up front; ``"available"`` (the default): the
        memory available when the job is checked (half of it is the limit, see
        :func:`solverplan.limits.memory_limit`); ``None``: no limit.
    jobs
        Processes a large job may use at once (the safe BVG of a large partition is built in batches of sources
        by forked workers); ``None`` (the default): the cores this process may use; 1: this process only. Small
        jobs always run in this process, and answers never depend on the setting.

    Examples
    --------
    >>> import solverplan as sp
    >>> current = sp.settings()
    >>> current.graph_cache_min_arcs, current.max_memory
    (100000, 'available')
    >>> with sp.config(max_memory=2 * 1024**3) as inside:      # refuse jobs estimated above 2 GiB, in this block
    ...     inside.max_memory, inside.graph_cache_min_arcs
    (2147483648, 100000)
    """

    graph_cache: Path | None = None
    graph_cache_min_arcs: int = DEFAULT_MIN_ARCS
    graph_cache_min_seconds: float | None = None
    graph_cache_max_bytes: int = DEFAULT_MAX_BYTES
    max_memory: int | None | Literal["available"] = "available"
    jobs: int | None = None

    def __post_init__(self) -> None:
        if self.graph_cache is not None and not isinstance(self.graph_cache, Path):
            object.__setattr__(self, "graph_cache", Path(self.graph_cache))
        if not _whole(self.graph_cache_min_arcs) or self.graph_cache_min_arcs < 0:
            raise InputError(f"graph_cache_min_arcs must be a whole number >= 0, got {self.graph_cache_min_arcs!r}")
        if not _whole(self.graph_cache_max_bytes) or self.graph_cache_max_bytes < 1:
            raise InputError(f"graph_cache_max_bytes must be a whole number >= 1, got {self.graph_cache_max_bytes!r}")
        seconds = self.graph_cache_min_seconds
        if seconds is not None and (isinstance(seconds, bool) or not isinstance(seconds, (int, float)) or not seconds >= 0):
            raise InputError(f"graph_cache_min_seconds must be None or a number >= 0, got {seconds!r}")
        limit = self.max_memory
        if limit not in (None, "available") and (not _whole(limit) or limit <= 0):  # type: ignore[operator]
            raise InputError(f"max_memory must be a positive number of bytes, 'available' or None, got {limit!r}")
        if self.jobs is not None and (not _whole(self.jobs) or self.jobs < 1):
            raise InputError(f"jobs must be None or a whole number >= 1, got {self.jobs!r}")


def _whole(x: Any) -> bool:
    return isinstance(x, int) and not isinstance(x, bool)


_process = Settings()  # what a new thread or a block outside any config() sees: set by configure()
_current: ContextVar[Settings | None] = ContextVar("solverplan_settings", default=None)


def settings() -> Settings:
    """The settings in force here: those of the innermost :func:`config` block, else the process's.

    Returns
    -------
    Settings
        The immutable settings object; :func:`config` and :func:`configure` make changed copies.

    Examples
    --------
    >>> import solverplan as sp
    >>> sp.settings().graph_cache_min_arcs
    100000
    """
    here = _current.get()
    return _process if here is None else here


@contextlib.contextmanager
def config(**changes: Any) -> Iterator[Settings]:
    """Change some :class:`Settings` for the duration of a ``with`` block (this thread or task only).

    Parameters
    ----------
    **changes
        Fields of :class:`Settings` and their values (``graph_cache``, ``graph_cache_min_arcs``,
        ``graph_cache_min_seconds``, ``graph_cache_max_bytes``, ``max_memory``, ``jobs``).

    Yields
    ------
    Settings
        The settings in force inside the block.

    Raises
    ------
    TypeError
        A name that is not a setting.
    InputError
        A value out of range (a ValueError too), one line naming the setting.

    Examples
    --------
    >>> import solverplan as sp
    >>> with sp.config(graph_cache_min_arcs=0):
    ...     sp.settings().graph_cache_min_arcs
    0
    >>> sp.settings().graph_cache_min_arcs
    100000
    """
    token = _current.set(dataclasses.replace(settings(), **changes))
    try:
        yield settings()
    finally:
        _current.reset(token)


def configure(**changes: Any) -> Settings:
    """Change some :class:`Settings` for the whole process (every thread and task outside a :func:`config` block).

    Parameters
    ----------
    **changes
        As for :func:`config`; ``configure()`` with no argument returns the process's settings unchanged.

    Returns
    -------
    Settings
        The process's settings after the change.

    Examples
    --------
    >>> import solverplan as sp
    >>> before = sp.configure()
    >>> sp.configure(max_memory=None).max_memory is None
    True
    >>> _ = sp.configure(max_memory=before.max_memory)
    """
    global _process
    _process = dataclasses.replace(_process, **changes)
    return _process


T = TypeVar("T")
R = TypeVar("R")


def jobs() -> int:
    """The processes a large job may use here: the setting ``jobs``, else the cores this process may use (1 inside
    a worker of :func:`parallel_map`).

    >>> import solverplan as sp
    >>> with sp.config(jobs=1):
    ...     jobs()
    1
    """
    from solverplan._arrays import cores  # numpy: not at import (the command line's start-up)

    return settings().jobs or cores()


@dataclass(frozen=True)
class _Stop:
    """A worker's :class:`~solverplan.progress.Stopped`, carried back to the parent with its fields."""

    task: str
    done: float
    total: float | None


def _silent(task: str, done: float, total: float | None) -> None:
    """A worker's progress report: none (the parent reports; a progress bar's lock must not be taken in a fork)."""


def parallel_map(fn: Callable[[T], R], items: Sequence[T], *, slot_bytes: int = 0) -> Iterator[R]:
    """Yield ``fn(x)`` for each x of ``items`` in order, computed by :func:`jobs` forked worker processes
    (:func:`solverplan._arrays.process_map`; in this process when :func:`jobs` is 1).

    In a worker the progress reports of :mod:`solverplan.progress` go nowhere (the caller reports per item as
    results come), while the stop time still applies: a worker's :class:`~solverplan.progress.Stopped` is raised
    here as it was raised there. Answers must not depend on the split: callers cut their work into items whose
    results do not depend on each other. ``slot_bytes``: as for :func:`~solverplan._arrays.process_map`.

    >>> list(parallel_map(len, ["a", "bb", "ccc"]))
    [1, 2, 3]
    """

    from solverplan._arrays import process_map  # numpy: not at import (the command line's start-up)

    def quiet(x: T) -> R | _Stop:
        with watching(report=_silent):
            try:
                return fn(x)
            except Stopped as stop:  # a Stopped pickles without its fields
                return _Stop(stop.task, stop.done, stop.total)

    n = jobs()
    for got in process_map(quiet, items, n, slot_bytes=slot_bytes) if n > 1 else map(fn, items):
        if isinstance(got, _Stop):
            raise Stopped(got.task, got.done, got.total)
        yield got
