"""Small numpy helpers shared by the vectorised kernels, the thread pool their blocks run in, and the forked
processes that large builds split their independent batches over."""

from __future__ import annotations

import collections
import contextvars
import functools
import mmap
import os
import signal
import threading
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Callable, Iterator, Sequence, TypeVar

import numpy as np

__all__ = ["ragged_arange", "sorted_unique", "sorted_intersection", "thread_map", "workers", "cores", "process_map",
           "keep_freed_memory"]

T = TypeVar("T")
R = TypeVar("R")


def ragged_arange(counts: np.ndarray) -> np.ndarray:
    """Concatenated ``arange(c)`` for each c in ``counts`` (int64).

    >>> ragged_arange(np.array([3, 0, 2])).tolist()
    [0, 1, 2, 0, 1]
    """
    counts = np.asarray(counts, dtype=np.int64)
    total = int(counts.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    ends = np.cumsum(counts)
    return np.arange(total, dtype=np.int64) - np.repeat(ends - counts, counts)


def sorted_unique(values: np.ndarray, *, overwrite: bool = False) -> np.ndarray:
    """``np.unique(values)`` of an integer array, by sorting: numpy 2.4's ``unique`` hashes, 15–20× slower on the
    millions of distinct keys of a graph build (1.2 s against 0.07 s for 10⁶). With ``overwrite``, a 1-d array is
    sorted in place (no copy of a large array of keys at the build's peak).

    >>> sorted_unique(np.array([5, 1, 5, 3, 1])).tolist()
    [1, 3, 5]
    """
    if overwrite and isinstance(values, np.ndarray) and values.ndim == 1:
        values.sort()
        out = values
    else:
        out = np.sort(np.asarray(values).ravel())
    if len(out) < 2:
        return out
    return out[np.concatenate(([True], out[1:] != out[:-1]))]


def sorted_intersection(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.intersect1d(a, b)`` of integer arrays (sorted, unique), by sorting (see :func:`sorted_unique`).

    >>> sorted_intersection(np.array([4, 1, 4, 9]), np.array([9, 2, 4])).tolist()
    [4, 9]
    """
    x, y = sorted_unique(a), sorted_unique(b)
    if not len(x) or not len(y):
        return x[:0]
    at = np.minimum(np.searchsorted(y, x), len(y) - 1)
    return x[y[at] == x]


_MAX_WORKERS = 4


def cores() -> int:
    """The cores this process may use (its CPU affinity where the system has one), 1 inside a worker of
    :func:`process_map` (whose siblings use the others).

    >>> cores() >= 1
    True
    """
    if _in_worker:
        return 1
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


@functools.cache
def workers() -> int:
    """Threads for numpy work split in blocks: the cores this process may use, at most 4."""
    return max(1, min(_MAX_WORKERS, cores()))


@functools.cache
def _pool() -> ThreadPoolExecutor:
    return ThreadPoolExecutor(max_workers=workers(), thread_name_prefix="solverplan")


def thread_map(fn: Callable[[T], R], items: Sequence[T]) -> list[R]:
    """``[fn(x) for x in items]``, computed in a pool of threads (:func:`workers`) when there are several items and
    cores: for blocks of numpy work, whose loops release the GIL. Results come in the order of ``items``; the
    first exception (in that order) is raised as the loop would raise it. Each call runs in a copy of the
    caller's context, so the progress reports and the timeout of :mod:`solverplan.progress` apply inside; at
    most twice as many calls as threads are in flight, so memory stays that of a few blocks.

    >>> thread_map(lambda x: x * x, range(5))
    [0, 1, 4, 9, 16]
    """
    items = list(items)
    if len(items) < 2 or workers() < 2:
        return [fn(x) for x in items]
    pool = _pool()
    window = 2 * workers()
    pending: collections.deque = collections.deque()
    out: list[R] = []
    try:
        for x in items:
            pending.append(pool.submit(contextvars.copy_context().run, fn, x))
            if len(pending) >= window:
                out.append(pending.popleft().result())
        while pending:
            out.append(pending.popleft().result())
    finally:
        for future in pending:  # an exception: the calls not started are not made
            future.cancel()
    return out


# ---------------------------------------------------------------------------------------------
# forked worker processes
# ---------------------------------------------------------------------------------------------
_in_worker = False
_tasks: dict[int, tuple[Callable, list, mmap.mmap | None, int]] = {}  # the calls of the running process_map()s, inherited by their forked workers
_tasks_lock = threading.Lock()


def _after_fork_in_child() -> None:
    # a thread pool's threads do not survive a fork: a child that submitted to the inherited pool would wait forever
    _pool.cache_clear()
    workers.cache_clear()


os.register_at_fork(after_in_child=_after_fork_in_child)


def keep_freed_memory() -> None:
    """Let this process's C allocator keep the memory numpy frees, for its next arrays, rather than handing it back
    to the system and faulting it in again page by page (glibc: blocks up to 32 MB come from the heap, which is not
    trimmed). For short-lived processes that make many arrays of a few MB: the safe BVG's build faults in 0.2 M
    pages less, 0.5 s of system time out of 6 s. Nothing where the allocator has no such settings.

    >>> keep_freed_memory()
    """
    import ctypes

    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):  # not glibc
        return
    mallopt(-3, 32 << 20)  # M_MMAP_THRESHOLD: the largest allowed; fixes it (no more dynamic threshold)
    mallopt(-1, 512 << 20)  # M_TRIM_THRESHOLD


def _start_worker(parent: int) -> None:
    global _in_worker
    _in_worker = True
    keep_freed_memory()
    workers.cache_clear()
    # Ctrl-C (to the whole process group) and SIGTERM are the parent's to answer: it stops handing out items and
    # its workers end after the one they are on; a worker dies with its parent (Linux), never left behind
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    try:
        import ctypes

        ctypes.CDLL(None).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):  # not Linux
        pass
    if os.getppid() != parent:  # the parent died before that
        os._exit(1)


def _run_task(key: int, index: int) -> object:
    fn, items, slots, slot_bytes = _tasks[key]
    out = fn(items[index])
    if slots is not None and isinstance(out, bytes) and len(out) <= slot_bytes:
        at = (index % (len(slots) // slot_bytes)) * slot_bytes  # the parent has copied this slot's previous bytes
        slots[at : at + len(out)] = out
        return _InSlot(at, len(out))
    return out


class _InSlot:
    """A worker's bytes result, left in the shared slots at ``at``."""

    def __init__(self, at: int, size: int) -> None:
        self.at, self.size = at, size


def can_fork() -> bool:
    """Whether :func:`process_map` can use worker processes here (the ``fork`` start method exists: Linux, macOS).

    >>> isinstance(can_fork(), bool)
    True
    """
    import multiprocessing

    return "fork" in multiprocessing.get_all_start_methods()


def process_map(fn: Callable[[T], R], items: Sequence[T], jobs: int, *, slot_bytes: int = 0) -> Iterator[R]:
    """Yield ``fn(x)`` for each x of ``items`` in order, computed in ``jobs`` forked worker processes.

    The workers are forked when the call starts, so ``fn`` and ``items`` reach them as they are in this process
    (closures, large arrays: nothing is pickled on the way there); only each result is pickled on its way back.
    At most twice as many items as workers are in flight, so results waiting to be read stay few. A worker killed
    (by the out-of-memory killer, say) raises :class:`MemoryError` here rather than leaving the loop waiting. Inside a
    worker :func:`cores` is 1 (a nested call runs in the worker itself), Ctrl-C and SIGTERM are left to the parent
    (its workers end after their current item), and a worker dies with its parent. An exception in ``fn`` is raised here, for its item, as the loop would
    raise it (pickled: give exceptions the arguments their constructor takes); leaving the loop early (a
    ``break``, an exception of the caller) drops the items not started. With ``jobs`` < 2, one item, inside a worker or
    where processes cannot be forked, this is the plain loop.

    ``slot_bytes``: results that are ``bytes`` of at most this size come back through memory shared with the
    workers (one slot per item in flight) instead of a pipe: one copy instead of four — for large texts.

    >>> list(process_map(lambda x: x * x, range(5), jobs=2))
    [0, 1, 4, 9, 16]
    """
    items = list(items)
    jobs = min(jobs, len(items))
    if jobs < 2 or _in_worker or not can_fork():
        yield from (fn(x) for x in items)
        return
    import multiprocessing

    window = 2 * jobs
    slots = mmap.mmap(-1, window * slot_bytes) if slot_bytes > 0 else None  # anonymous, shared with the forks

    def result(pending: collections.deque) -> R:
        got = pending.popleft().result()
        if isinstance(got, _InSlot):
            return slots[got.at : got.at + got.size]  # type: ignore[index, return-value]  # a copy: the slot is free
        return got

    with _tasks_lock:
        key = max(_tasks, default=0) + 1
        _tasks[key] = (fn, items, slots, slot_bytes)
    pool = ProcessPoolExecutor(jobs, mp_context=multiprocessing.get_context("fork"), initializer=_start_worker,
                               initargs=(os.getpid(),))
    pending: collections.deque = collections.deque()
    finished = False
    try:
        for index in range(len(items)):  # item i uses the slot of item i − window, whose bytes were copied
            pending.append(pool.submit(_run_task, key, index))
            if len(pending) >= window:
                yield result(pending)
        while pending:
            yield result(pending)
        finished = True
    except BrokenProcessPool:  # a worker was killed (the kernel's out-of-memory killer, most likely)
        raise MemoryError("a worker process was killed (out of memory?); try --jobs 1 or --max-memory") from None
    finally:
        # the items not started are dropped; a busy worker ends after its item (not killed: a worker killed while
        # sending its result would leave the pool's reader waiting for the rest of the message at exit)
        pool.shutdown(wait=finished, cancel_futures=True)
        with _tasks_lock:
            del _tasks[key]
        if slots is not None:
            slots.close()
