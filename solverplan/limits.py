"""The documented limits of what solverplan reads (docs/contract.md, "Limits").

Every number, file and option crosses these bounds once, where it is read, so that a malformed or
outsized input gets one clear line (exit code 2) instead of a hang, an overflow or a wrong answer.
The bounds sit far above any floor plan in practice; each says why it exists.
"""

from __future__ import annotations

__all__ = [
    "MAX_FILE_BYTES",
    "MAX_JSON_DEPTH",
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
    "MAX_SEED",
    "MAX_QUOTED_CHARS",
    "quote",
]

MAX_FILE_BYTES = 64 * 1024 * 1024
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

MAX_GENERATED_VERTICES = 10_000
"""Most vertices ``generate`` is asked for (``--n``, ``--hole-vertices``, ``--width``, ``--height``): a
random star of 10,000 vertices already takes seconds to draw and validate."""

MAX_ROOMS = 1_000
"""Most rooms, holes, loops or pillars ``generate`` is asked for (``--rooms``, ``--holes``, ``--loops``,
``--pillars``): 1,000 rectilinear rooms take about ten seconds to lay out."""

MAX_SEED = 2**64 - 1
"""Largest random seed (``--seed``): seeds are unsigned 64-bit integers."""

MAX_QUOTED_CHARS = 40
"""Longest run of the input an error message quotes (characters); longer runs are cut with ``…``."""


def quote(value: object, limit: int = MAX_QUOTED_CHARS) -> str:
    """``repr(value)``, cut to ``limit`` characters with ``…`` so an error message stays one short line."""
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 1] + "…"
