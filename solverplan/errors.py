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
    """Base of every error solverplan raises on purpose.

    Catch it to handle any of solverplan's errors at once; an error of another type escaping solverplan is a bug.

    Examples
    --------
    >>> import solverplan as sp
    >>> try:
    ...     sp.load_environment("square").boundary_set("e17")
    ... except sp.SolverplanError as error:
    ...     print(type(error).__name__, "-", error)
    InvalidBoundarySet - unknown edge e17: edges are e0..e3
    """


class InputError(SolverplanError, ValueError):
    """Bad user input: reported as one line, CLI exit code 2.

    Also a :class:`ValueError`, so callers who do not know solverplan's names still catch it. Its subclasses say
    which input was wrong; the message names what, where, and the offending value.

    Examples
    --------
    >>> import solverplan as sp
    >>> sp.find_plan(sp.load_environment("square"), "e0", "e2", objective="shortest")
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: unknown objective 'shortest': use fewest, tolerance, sum, constant
    >>> issubclass(sp.InputError, ValueError)
    True
    """


class InvalidEnvironment(InputError):
    """The polygon is not a valid environment (self-intersecting, empty, NaN, ...).

    Raised when an environment is built or loaded; the message names the ring, edge or point at fault.

    Examples
    --------
    >>> import solverplan as sp
    >>> sp.Environment.from_coords([[0, 0], [2, 2], [2, 0], [0, 2]])   # a bowtie
    Traceback (most recent call last):
    ...
    solverplan.errors.InvalidEnvironment: outer ring self-intersects: edge 0 crosses edge 2 at (1, 1)
    """


class InvalidBoundarySet(InputError):
    """A boundary-set string (``e3:0.25:0.75,e4``) or heading interval is malformed.

    Raised for an unknown edge, a boundary parameter outside [0, 1] or a reversed piece (t0 ≥ t1).

    Examples
    --------
    >>> import solverplan as sp
    >>> sp.load_environment("square").boundary_set("e2:0.5:0.2")
    Traceback (most recent call last):
    ...
    solverplan.errors.InvalidBoundarySet: boundary set piece 'e2:0.5:0.2': need 0 <= t0 < t1 <= 1, got t0=0.5, t1=0.2
    """


class MalformedFile(InputError):
    """An input file cannot be read or parsed (truncated JSON, bad WKT, unknown format).

    Raised by the readers of environments, plans, answers and certificates; a missing file is one too.

    Examples
    --------
    >>> import solverplan as sp
    >>> sp.load_environment("no_such_floor.json")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    solverplan.errors.MalformedFile: no_such_floor.json: no such file, nor a shipped model (19 models, e.g. comb, ...)
    """


class SolverFailed(SolverplanError, RuntimeError):
    """An internal computation broke down (not the user's fault): CLI exit code 1.

    For instance an LP solver that returns no optimum, or a consistency check of a planner that fails; the message
    names the solver and what it returned. A proved infeasibility is an answer, never this error. Also a
    :class:`RuntimeError`.

    Examples
    --------
    >>> import solverplan as sp
    >>> try:
    ...     raise sp.SolverFailed("HiGHS returned 'solver_error' for the tolerance MILP")
    ... except RuntimeError as error:
    ...     print(error)
    HiGHS returned 'solver_error' for the tolerance MILP
    """
