"""The errors solverplan raises on purpose.

One base class; every bad-input error is also a :class:`ValueError`, so callers
need not know our names. The CLI maps :class:`InputError` to exit code 2 and any
other :class:`SolverplanError` to exit code 1 (see docs/contract.md, "Exit codes").

Messages are one sentence naming what is wrong, where, and the offending value,
e.g. ``outer ring self-intersects: edge 0 crosses edge 2 at (1, 1)``. Tests pin
them whole: changing a message is an API change.
"""

from __future__ import annotations

__all__ = [
    "SolverplanError",
    "InputError",
    "InvalidEnvironment",
    "InvalidBoundarySet",
    "MalformedFile",
    "SolverFailed",
]


class SolverplanError(Exception):
    """Base of every error solverplan raises on purpose."""


class InputError(SolverplanError, ValueError):
    """Bad user input: reported as one line, CLI exit code 2."""


class InvalidEnvironment(InputError):
    """The polygon is not a valid environment (self-intersecting, empty, NaN, ...)."""


class InvalidBoundarySet(InputError):
    """A boundary-set string (``e3:0.25:0.75,e4``) or heading interval is malformed."""


class MalformedFile(InputError):
    """An input file cannot be read or parsed (truncated JSON, bad WKT, unknown format)."""


class SolverFailed(SolverplanError, RuntimeError):
    """An internal computation broke down (not the user's fault): CLI exit code 1."""
