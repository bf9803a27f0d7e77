"""Algorithm A: depth-first exploration of an unknown polygon with discrete views (no range limit).

Ghosh, Burdick, Bhattacharya and Sarkar, "Online algorithms with discrete visibility", section "An
Exploration Algorithm". The robot starts at p₁ and computes visibility polygons only at viewpoints it stops
at. Each next viewpoint is a point of a constructed edge (a window) of the current view that is not yet
explored, so it lies in an earlier view (the viewpoints are chained); when the current view has no unexplored
window left the robot backtracks to the previous viewpoint on an explicit stack. The exploration stops when the
stack is empty: every window of every view is explored, so the union of the views is the whole free space
(Lemma 2) — with at most r + 1 views (Theorem 1).

The explored region is the union of the views taken so far (exact visibility polygons); it is opaque in the
sense of the paper: a window counts only as far as it leads out of that region
(:func:`~solverplan.explore.window.unexplored_parts`), so a view never sends the robot back into known space.
"""

from __future__ import annotations

import math
import random
import time
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Callable, Sequence

from solverplan.choices import ViewChoice
from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.exact import ExactPoint, exact_point, format_number, format_point
from solverplan.explore.bounds import Cost, exploration_cost, views_bound
from solverplan.explore.window import Window, point_on_part, unexplored_parts, windows
from solverplan.geometry.visibility import VisibilityPolygon, visibility_polygon
from solverplan.geometry.walls import StraightWalls
from solverplan.result import Answer, EnvironmentRecord, Method, Optimality, Reader, Stats, Status, answer_dataclass
from typing import Any

__all__ = ["CHOICES", "Exploration", "explore_depth_first"]

CHOICES: tuple[str, ...] = ViewChoice.values()
"""The z-choice rules: ``first`` — the first unexplored window part in the current view's CCW ring order;
``random`` — a uniformly random one (seeded); ``far`` — the one whose chosen point is farthest from the
current viewpoint. On the chosen part the viewpoint is the simplest rational point of its middle third."""


@dataclass(frozen=True, kw_only=True)
class ViewpointRun(Answer):
    """The fields every exploration answer has, and what it derives from its viewpoints and path: the counts, the
    path's length, the cost T and the answer fields they share (Algorithm A's :class:`Exploration` and
    Algorithm B's :class:`~solverplan.explore.range_limited.RangeExploration`, which add their views)."""

    status: Status
    viewpoints: tuple[ExactPoint, ...]
    parents: tuple[int, ...]
    path: tuple[ExactPoint, ...]
    reflex: int
    bound: int
    covered_fraction: float
    choice: str
    optimality: Optimality
    stats: Stats = field(default_factory=Stats)
    environment: EnvironmentRecord | None = None
    algorithm: str

    @property
    def n_views(self) -> int:
        """N_S, the number of views."""
        return len(self.viewpoints)

    @property
    def moves(self) -> int:
        """N_M, the number of straight moves (forward and backward)."""
        return max(0, len(self.path) - 1)

    @property
    def path_length(self) -> float:
        """d, the length of the path (float, length units)."""
        return sum(math.dist(tuple(map(float, p)), tuple(map(float, q))) for p, q in zip(self.path, self.path[1:]))

    def cost(self, *, t_move: float = 1.0, t_sense: float = 1.0, speed: float = 1.0) -> Cost:
        """T = t_M·N_M + t_S·N_S + d/r of this exploration (:func:`~solverplan.explore.bounds.exploration_cost`)."""
        return exploration_cost(self.moves, self.n_views, self.path_length, t_move=t_move, t_sense=t_sense,
                                speed=speed)

    def _answer_json(self) -> dict:
        """The contract's exploration fields, then the counts, the cost, the chain and the path."""
        return {
            "algorithm": self.algorithm,
            "viewpoints": [[float(x), float(y)] for x, y in self.viewpoints],
            "views": self.n_views,
            "reflex": self.reflex,
            "bound": self.bound,
            "path_length": self.path_length,
            "covered_fraction": self.covered_fraction,
            "moves": self.moves,
            "cost": self.cost().to_json(),
            "parents": list(self.parents),
            "path": [[float(x), float(y)] for x, y in self.path],
            "choice": self.choice,
            # the exact points (the floats above are for plotting): what the answer is read back from
            "viewpoints_exact": [[format_number(x), format_number(y)] for x, y in self.viewpoints],
            "path_exact": [[format_number(x), format_number(y)] for x, y in self.path],
        }

    def _text(self, heading: str, counts: str, via: Callable[[int], str], width: int) -> str:
        """The short report every exploration gives: a heading, its counts, moves and coverage, the optimality, then
        the viewpoints (``via(k)``: how viewpoint k was reached)."""
        lines = [heading, counts,
                 f"moves {self.moves}, path length {self.path_length:.6g}, covered {self.covered_fraction:.12g}",
                 f"optimality: {self.optimality.to_text()}"]
        for k, p in enumerate(self.viewpoints):
            lines.append(f"  p{k + 1} = ({float(p[0]):.6g}, {float(p[1]):.6g}){via(k)}"[:width])
        return "\n".join(lines)

    @classmethod
    def _read_run(cls, data: Any, env: Environment | None) -> tuple[Reader, Environment, dict]:
        """How every exploration is read back: a reader of ``data``, ``env`` (required) and the fields every
        exploration's JSON has (the exact points)."""
        r, env, record = cls._reader_in(data, env, cls.kind)
        fields = {"status": r.status(), "viewpoints": tuple(r.points("viewpoints_exact")), "parents": tuple(r.ints("parents")),
                  "path": tuple(r.points("path_exact")), "reflex": r.integer("reflex"), "bound": r.integer("bound"),
                  "covered_fraction": r.number("covered_fraction"), "optimality": r.optimality(), "stats": r.stats(),
                  "environment": record, "algorithm": r.string("algorithm"), "choice": r.string("choice")}
        return r, env, fields


@answer_dataclass("exploration", kw_only=True)
class Exploration(ViewpointRun):
    """An exploration: viewpoints in visiting order, the views, the path and what they cost.

    Attributes
    ----------
    status
        ``found`` when the views cover the free space (always, for Algorithm A); ``not-found`` when the view
        limit was hit first (``optimality.limits`` says which).
    viewpoints
        p₁, p₂, … exact, in the order visited (length units of the environment).
    views
        The exact visibility polygon of each viewpoint.
    parents
        For each viewpoint after the first, the index of the earlier viewpoint whose window it lies on
        (p_i ∈ VP(p_parent)): the chain; −1 for p₁.
    path
        The robot's positions, start first: forward moves to each new viewpoint, backward moves along the
        stack of viewpoints to the one whose window is explored next. Every leg is a straight segment in the
        free space.
    reflex
        r, the reflex vertices of the free space.
    bound
        The bound on the number of views of the algorithm that ran (r + 1 for Algorithm A).
    covered_fraction
        Area of the union of the views over the area of the free space (floats; 1 up to rounding).
    choice, seed
        The z-choice rule and its seed.

    Examples
    --------
    From the end of the L's bottom arm, the first view misses the top of the other arm; one window later the
    views cover the room, within Theorem 1's bound r + 1:

    >>> import solverplan as sp
    >>> run = sp.explore_depth_first(sp.load_environment("l_shape"), (8, 2))
    >>> run.status.value, run.n_views, run.bound, run.parents
    ('found', 2, 2, (-1, 0))
    >>> run.viewpoints[1], [view.area for view in run.views]         # exact, in the environment's units
    ((Fraction(2, 1), Fraction(5, 1)), [Fraction(44, 1), Fraction(55, 1)])
    """

    views: tuple[VisibilityPolygon, ...]
    seed: int | None
    algorithm: str = "A"

    def _fields(self) -> dict:
        """The exploration answer of ``docs/contract.md``."""
        out = self._answer_json()
        if self.seed is not None:
            out["seed"] = self.seed
        return out

    @classmethod
    def from_json(cls, data: Any, *, env: Environment | None = None) -> Exploration:
        """Read an exploration back in ``env`` (required): the exact viewpoints and path; the views recomputed exactly
        (a view is the visibility polygon of its viewpoint)."""
        r, env, fields = cls._read_run(data, env)
        views = tuple(visibility_polygon(env, p) for p in fields["viewpoints"])
        return cls(views=views, seed=r.integer("seed", None), **fields)

    def to_text(self, *, width: int = 100) -> str:
        """A short report: counts, bound, coverage, then the viewpoints."""
        return self._text(f"exploration (Algorithm {self.algorithm}, choice {self.choice}): {self.status.value}",
                          f"views {self.n_views} (bound {self.bound}, r = {self.reflex})",
                          lambda k: "" if self.parents[k] < 0 else f"  (on a window of p{self.parents[k] + 1})", width)


def covered_fraction(env: Environment, views: Sequence[VisibilityPolygon]) -> float:
    """Area of the union of ``views`` over the free space's area (floats, shapely)."""
    import shapely

    union = shapely.union_all([shapely.Polygon([tuple(map(float, p)) for p in vp.ring]) for vp in views])
    free = env.to_shapely()
    return float(union.intersection(free).area / free.area)


def _start_point(env: Environment, start: Sequence[object]) -> tuple[ExactPoint, VisibilityPolygon]:
    p = exact_point(start, where="start")
    try:
        return p, visibility_polygon(env, p)
    except InputError:
        raise InputError(f"start {format_point(p)} is not in the free space of {env.name or 'the environment'}") from None


def explore_depth_first(env: Environment, start: Sequence[object], *, choice: ViewChoice | str = "first",
                        seed: int | None = None, max_views: int | None = None) -> Exploration:
    """Explore ``env`` from ``start`` with Algorithm A.

    Parameters
    ----------
    env
        The free space (outer ring and holes); unknown to the robot, which only sees its views.
    start
        p₁, a point of the closed free space (length units).
    choice
        The z-choice rule (:data:`CHOICES`): ``first``, ``random`` (with ``seed``) or ``far``.
    seed
        Seed of the ``random`` rule (default 0); not allowed with the other rules.
    max_views
        Stop after this many views (default 2(r + 1) + 2, more than Theorem 1 allows); hitting it gives status
        ``not-found``.

    Returns
    -------
    Exploration
        Status ``found`` with viewpoints, views, the chain and the path. The exploration runs on the canonical walls
        of ``env`` (:class:`~solverplan.geometry.walls.StraightWalls`; the views' edge ids are theirs), so that the
        answer does not depend on how the walls are written.

    Raises
    ------
    InputError
        If ``start`` is not in the free space, ``choice`` is unknown, or a seed is given to a rule without
        randomness.

    Examples
    --------
    >>> from solverplan.environment import Environment
    >>> ell = Environment.from_coords([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]])
    >>> run = explore_depth_first(ell, (3, 1))
    >>> run.n_views, run.bound, run.covered_fraction
    (2, 2, 1.0)
    """
    choice = ViewChoice.parse(choice, "z-choice rule").value
    if seed is not None and choice != "random":
        raise InputError(f"--seed only applies to the random z-choice rule, not to {choice!r}")
    walls = StraightWalls(env)
    if not walls.identity:
        # the same free space with its walls written canonically (collinear vertices merged, each ring from its
        # canonical vertex): views, windows and the "first" window's ring order then do not depend on how the walls
        # are written
        run = explore_depth_first(walls.merged, start, choice=choice, seed=seed, max_views=max_views)
        return replace(run, environment=EnvironmentRecord.of(env),
                       stats=run.stats.with_(collinear_vertices_merged=walls.n_merged_vertices))
    rng = random.Random(0 if seed is None else seed)
    bound = views_bound(env)
    limit = 2 * bound + 2 if max_views is None else max_views
    if limit < 1:
        raise InputError(f"max_views must be >= 1, got {max_views}")
    t0 = time.perf_counter()
    p, vp = _start_point(env, start)
    viewpoints, views, parents = [p], [vp], [-1]
    path: list[ExactPoint] = [p]
    stack = [0]  # indices of viewpoints whose windows may still lead somewhere (depth ≠ viewpoint index)
    explored: set[tuple[int, int]] = set()  # (view, window position) found explored: stays explored
    checks = 0
    hit_limit = False
    while stack:
        top = stack[-1]
        options: list[tuple[Window, tuple[Fraction, Fraction]]] = []
        for k, w in enumerate(windows(views[top], top)):
            if (top, k) in explored:
                continue
            checks += 1
            parts = unexplored_parts(w, views)
            if not parts:
                explored.add((top, k))
            options.extend((w, part) for part in parts)
        if not options:
            stack.pop()
            continue
        if len(viewpoints) >= limit:
            hit_limit = True
            break
        if choice == "first":
            w, part = options[0]
            z = point_on_part(w, part, viewpoints[w.view])
        elif choice == "random":
            w, part = options[rng.randrange(len(options))]
            z = point_on_part(w, part, viewpoints[w.view])
        else:
            here = viewpoints[top]
            candidates = [point_on_part(w, part, viewpoints[w.view]) for w, part in options]
            z = max(candidates, key=lambda q: (q[0] - here[0]) ** 2 + (q[1] - here[1]) ** 2)
        # the robot walks back along the stack to the viewpoint whose window it explores, then forward to z
        back = _walk_back(path[-1], viewpoints, parents, top)
        path.extend(back)
        path.append(z)
        viewpoints.append(z)
        views.append(visibility_polygon(env, z))
        parents.append(top)
        stack.append(len(viewpoints) - 1)
    seconds = time.perf_counter() - t0
    status = Status.NOT_FOUND if hit_limit else Status.FOUND
    limits = (f"max_views={limit}",) if hit_limit else ()
    optimality = Optimality(Method.NONE, False, None, scope="chained viewpoint sets covering the free space",
                            algorithm="Algorithm A (depth-first over unexplored constructed edges)", limits=limits)
    return Exploration(status=status, viewpoints=tuple(viewpoints), views=tuple(views), parents=tuple(parents),
                       path=tuple(path), reflex=len(env.reflex_vertices), bound=bound,
                       covered_fraction=covered_fraction(env, views), choice=choice,
                       seed=seed if choice == "random" else None, optimality=optimality,
                       stats=Stats(seconds_search=seconds, counts={"window_checks": checks}),
                       environment=EnvironmentRecord.of(env))


def _walk_back(here: ExactPoint, viewpoints: Sequence[ExactPoint], parents: Sequence[int], target: int) -> list[ExactPoint]:
    """The positions from ``here`` (the last viewpoint) back along the chain to viewpoint ``target``.

    The last viewpoint descends from ``target`` through the chain of parents (depth-first order), and each
    leg of the chain is a forward move taken earlier, so walking it backwards stays in the free space.
    """
    last = len(viewpoints) - 1
    if viewpoints[last] != here or last == target:
        return []
    out: list[ExactPoint] = []
    k = parents[last]
    while k >= 0:
        out.append(viewpoints[k])
        if k == target:
            return out
        k = parents[k]
    raise AssertionError("the stack top is an ancestor of the last viewpoint")  # pragma: no cover
