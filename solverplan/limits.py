"""The documented limits of what solverplan reads (docs/contract.md, "Limits").

Every number, file and option crosses these bounds once, where it is read, so that a malformed or
outsized input gets one clear line (exit code 2) instead of a hang, an overflow or a wrong answer.
The bounds sit far above any floor plan in practice; each says why it exists.
"""

from __future__ import annotations

from typing import Any

from solverplan._io import MAX_INPUT_BYTES, MAX_JSON_VALUES, read_input_text, shown_path
from solverplan.errors import InputError, MalformedFile
from solverplan.runtime import configure, settings

__all__ = [
    "MAX_FILE_BYTES",
    "MAX_JSON_DEPTH",
    "MAX_JSON_VALUES",
    "MAX_NUMBER_CHARS",
    "MAX_DECIMAL_EXPONENT",
    "MAX_COORDINATE",
    "COORDINATE_RESOLUTION",
    "MAX_VERTICES",
    "MAX_HOLES",
    "MIN_HEADING",
    "MAX_COUNT",
    "MAX_BOUNCES",
    "MAX_TRIALS",
    "MAX_TRAJECTORIES",
    "MAX_GENERATED_VERTICES",
    "MAX_ROOMS",
    "MAX_PIXELS",
    "BYTES_PER_PIXEL",
    "MAX_SEED",
    "MAX_INDENT",
    "MAX_STUDY_ROWS",
    "MAX_QUOTED_CHARS",
    "quote",
    "available_memory",
    "memory_limit",
    "set_memory_limit",
    "reset_memory_limit",
    "refuse_beyond_memory",
    "checked_file_size",
    "read_text_within_limits",
]

MAX_FILE_BYTES = MAX_INPUT_BYTES
"""Largest input file read (bytes): 64 MiB holds millions of vertices, far beyond what the planner builds."""

MAX_JSON_DEPTH = 64
"""Deepest nesting of arrays and objects in a JSON input (environments need 4, certificates about 10);
checked before parsing, so a file nested 10⁵ deep is refused instead of exhausting the parser's stack."""

MAX_NUMBER_CHARS = 1000
"""Longest spelling of one number (characters), e.g. a 5,000-digit integer is refused when read."""

MAX_DECIMAL_EXPONENT = 1000
"""Largest decimal exponent read exactly (``1e-999999`` is refused: its exact value has a million digits)."""

MAX_COORDINATE = 10**100
"""Largest coordinate magnitude: squares of coordinate differences must stay well inside the float range
(about 1.8e308), where the planner's float filters and float replays work."""

COORDINATE_RESOLUTION = 10**100
"""Finest coordinate step read: a coordinate's exact denominator is at most this (so 1e-100 is read,
1e-101 is not); finer values cost unbounded exact arithmetic and are lost in floats anyway."""

MAX_VERTICES = 100_000
"""Most vertices of an environment file (all rings together)."""

MAX_HOLES = 10_000
"""Most holes of an environment file."""

MIN_HEADING = 1e-9
"""Smallest angle (radians) between a heading and a wall (0 or π) that is read: headings closer to the
wall than this run along it for floats, and their exact form has denominators floats cannot carry."""

MAX_COUNT = MAX_VERTICES
"""Bound of the other count options (``--family-size``, ``--per-cell``, ``--workers``, ``--wall``, ``--door``)."""

MAX_BOUNCES = 10_000_000
"""Most bounces of any option (``--bounces``, ``--max-bounces``, ``--max-between``)."""

MAX_TRIALS = 100_000_000
"""Most simulated rollouts (``--trials``)."""

MAX_TRAJECTORIES = 100_000
"""Most trajectories drawn in one picture (``render --trajectories``)."""

MAX_PIXELS = 40_000_000
"""Largest occupancy image ``import`` reads (pixels): 4·10⁷ cells (40 hectares at 10 cm). Reading and tracing
one costs about :data:`BYTES_PER_PIXEL` bytes a pixel at the peak (measured on 1-bit and RGB maps), so the
largest image needs about 1 GB."""

BYTES_PER_PIXEL = 26
"""Peak memory of ``import`` per pixel of an occupancy image (bytes; 16 million pixels peak at ~450 MB)."""

MAX_GENERATED_VERTICES = 10_000
"""Most vertices ``generate`` is asked for (``--n``, ``--hole-vertices``, ``--width``, ``--height``): a
random star of 10,000 vertices already takes seconds to draw and validate."""

MAX_ROOMS = 1_000
"""Most rooms, holes, loops or pillars ``generate`` is asked for (``--rooms``, ``--holes``, ``--loops``,
``--pillars``): 1,000 rectilinear rooms take about ten seconds to lay out."""

MAX_STUDY_ROWS = 100_000
"""Most rows of one study (grid cells × ``--per-cell``), and most values of one grid axis: at a tenth of a
second a row (the fastest metric), 10⁵ rows are three hours on one core; the row list stays a few MB."""

MAX_INDENT = 16
"""Largest ``--indent`` (spaces per level): the text of a deep answer grows with the indent times its lines."""

MAX_SEED = 2**64 - 1
"""Largest random seed (``--seed``): seeds are unsigned 64-bit integers."""

MAX_QUOTED_CHARS = 40
"""Longest run of the input an error message quotes (characters); longer runs are cut with ``…``."""


def quote(value: object, limit: int = MAX_QUOTED_CHARS) -> str:
    """``repr(value)``, cut to ``limit`` characters with ``…`` so an error message stays one short line."""
    if isinstance(value, int) and value.bit_length() > 13_000:  # repr would hit Python's 4,300-digit guard
        return f"(an integer of about {int(value.bit_length() * 0.30103):,} digits)"
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 1] + "…"


def available_memory() -> int | None:
    """Bytes of memory this process can still allocate without swapping, or None where it cannot be told.

    Linux's ``MemAvailable`` (``/proc/meminfo``), capped by the cgroup's limit (containers) and by
    ``RLIMIT_AS`` when they are set; elsewhere ``None`` (no early refusal, as before).
    """
    import resource

    candidates: list[int] = []
    try:
        with open("/proc/meminfo", encoding="ascii") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    candidates.append(int(line.split()[1]) * 1024)
                    break
    except (OSError, ValueError, IndexError):
        pass
    for path in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            with open(path, encoding="ascii") as limit_file:
                text = limit_file.read().strip()
            if text.isdigit() and int(text) < 2**60:
                used_path = path.replace("memory.max", "memory.current").replace("limit_in_bytes", "usage_in_bytes")
                with open(used_path, encoding="ascii") as used_file:
                    candidates.append(max(0, int(text) - int(used_file.read().strip())))
            break
        except (OSError, ValueError):
            continue
    soft, _hard = resource.getrlimit(resource.RLIMIT_AS)
    if soft not in (resource.RLIM_INFINITY, -1) and soft > 0:
        # the cap counts the address space already mapped (the interpreter, numpy's libraries): what is left
        candidates.append(max(0, int(soft) - _mapped_bytes()))
    return min(candidates) if candidates else None


def _mapped_bytes() -> int:
    """This process's mapped address space (``VmSize`` in /proc/self/status), 0 where it cannot be told."""
    try:
        with open("/proc/self/status", encoding="ascii", errors="replace") as status:
            for line in status:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return 0


def set_memory_limit(limit: int | None) -> None:
    """Refuse jobs estimated to need more than ``limit`` bytes (``None``: no limit) in the whole process:
    ``configure(max_memory=limit)``, which checks it (:class:`~solverplan.runtime.Settings`);
    :func:`solverplan.config` changes it for a block (the CLI's ``--max-memory``).
    """
    configure(max_memory=limit)


def reset_memory_limit() -> None:
    """Back to the default limit in the whole process: the memory available when a job is checked."""
    configure(max_memory="available")


def memory_limit() -> tuple[int | None, str]:
    """The memory limit for one job (bytes, ``None`` for none) and where it comes from, for messages."""
    limit = settings().max_memory
    if limit == "available":
        free = available_memory()
        # half: a job sized to all of it would leave the machine unusable (swapping, other programs killed)
        return (None if free is None else free // 2), "half the memory available"
    return limit, "the memory limit"


def refuse_beyond_memory(estimate_bytes: float, what: str) -> None:
    """Raise :class:`~solverplan.errors.InputError` up front when ``estimate_bytes`` exceed :func:`memory_limit`.

    The job would otherwise run for a long time and end in ``MemoryError``. ``what`` names the job and its
    size for the message, e.g. ``"10,000,000 rollouts of 3 bounces"``.
    """
    limit, source = memory_limit()
    if limit is not None and estimate_bytes > limit:
        raise InputError(f"{what} would need about {estimate_bytes / 2**30:.1f} GiB of memory, more than {source} "
                         f"({limit / 2**30:.1f} GiB; see --max-memory)")


def checked_file_size(path: Any) -> int:
    """The size of the input file ``path`` in bytes: a regular file of at most :data:`MAX_FILE_BYTES`.

    Raises
    ------
    MalformedFile
        The file is missing, unreadable, not a regular file or larger than the limit (one line naming the file).

    Examples
    --------
    >>> checked_file_size("/no/such/file.json")
    Traceback (most recent call last):
    ...
    solverplan.errors.MalformedFile: /no/such/file.json: no such file
    """
    import os
    import stat

    name = shown_path(path)
    try:
        status = os.stat(path)
    except (OSError, ValueError) as exc:
        from solverplan._io import reason_of

        raise MalformedFile(f"{name}: {reason_of(exc) if isinstance(exc, OSError) else 'not a valid file name'}") from None
    if not stat.S_ISREG(status.st_mode):
        raise MalformedFile(f"{name}: not a regular file")
    if status.st_size > MAX_FILE_BYTES:
        raise MalformedFile(f"{name}: file is {status.st_size:,} bytes, more than the limit of {MAX_FILE_BYTES:,}")
    return status.st_size


def read_text_within_limits(path: Any) -> str:
    """The UTF-8 text of the input file ``path``, within :data:`MAX_FILE_BYTES` (the one bounded reader,
    :func:`solverplan._io.read_input_text`: regular files only, never read past the limit).

    Raises
    ------
    MalformedFile
        The file is missing, unreadable, not a regular file, not UTF-8 or larger than the limit (one line
        naming the file).
    """
    return read_input_text(path, limit=MAX_FILE_BYTES)
