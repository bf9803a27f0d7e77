"""How large a safe BVG would be, and the refusals when it would not fit in the memory limit.

:func:`estimate_graph` counts the sweeps' entries on a sample of vertices; :func:`check_graph_memory` refuses a
whole build up front, :func:`refuse_reachable` a query's reachable part that outgrew the limit, both naming the
``--simplify`` tolerance that would fit (:func:`fitting_simplification`).
"""

from __future__ import annotations

import math

from solverplan.bounce import _sweep
from solverplan.bounce.bvg.graph import as_partition
from solverplan.bounce.partitions import Partition
from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.limits import memory_limit

__all__ = ["GraphTooLarge", "BYTES_PER_ARC", "BASE_BYTES", "PLANNED_BYTES_PER_ARC", "estimate_graph",
           "check_graph_memory", "refuse_reachable", "fitting_simplification"]


class GraphTooLarge(InputError):
    """The safe BVG of an environment would not fit in the memory limit (raised before building it)."""


BYTES_PER_ARC = 200
"""Peak build memory per arc of the safe BVG (bytes; measured ≈ 175, see ``benchmarks/README.md``)."""
BASE_BYTES = 150 * 2**20
"""Bytes of the process, the environment and the partition around the graph (added to every estimate)."""


def estimate_graph(partition: Partition | Environment) -> tuple[int, int]:
    """(estimated arcs, estimated peak bytes) of the safe BVG of ``partition``, from the sweeps of
    an evenly spaced sample of 256 of its vertices' frames — under a second for the largest inputs.

    The sweeps' entries are counted exactly on the sample and scaled to all sweeps; the arcs are
    0.95 times the entries, as measured where size matters (stars, rooms with many pillars: within
    3 % of the true count). Where each segment is seen whole from both its ends, as in a convex
    room, there are about two entries per arc and the estimate is up to twice too high: it errs on
    the safe side.

    >>> from solverplan.environment import Environment
    >>> square = Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> estimate_graph(square)[0]      # 12 arcs, each seen from both ends of its source: 24 entries
    23
    """
    p = as_partition(partition)
    entries, _ = _sweep.estimate_entries(p)
    arcs = int(round(0.95 * entries))
    return arcs, BASE_BYTES + BYTES_PER_ARC * entries


def _gib(n: float) -> str:
    return f"{n / 2**30:.1f} GB" if n >= 2**30 else f"{n / 2**20:.0f} MB"


def check_graph_memory(p: Partition, estimate: tuple[int, int] | None = None) -> None:
    """Raise :class:`GraphTooLarge` when the safe BVG of ``p`` is estimated to exceed the memory limit
    (:func:`solverplan.limits.memory_limit`). Free for graphs that would fit even with every pair of segments
    as an arc; otherwise it samples the sweeps (:func:`estimate_graph`), unless the caller has its ``estimate``."""
    limit, source = memory_limit()
    N = len(p.segments)
    if limit is None or BASE_BYTES + BYTES_PER_ARC * N * (N - 1) <= limit:
        return
    arcs, need = estimate if estimate is not None else estimate_graph(p)
    if need > limit:
        raise GraphTooLarge(f"the safe BVG of {_short_name(p)!r} would need ≈ {_gib(need)} (≈ {arcs:,} arcs, {N:,} "
                            f"segments), more than {source} ({_gib(limit)}){_advice(p, arcs, limit, '; see --max-memory')}")


# Arcs grow about as the fourth power of the vertex count on ragged floor plans (segments of P′ as its square:
# every reflex vertex casts a line through every vertex it sees; arcs as the segments' square), measured on the
# warehouse maps of benchmarks/README.md; a smaller exponent would promise too much of a simplification.
_ARCS_EXPONENT = 4.0


def fitting_simplification(env: Environment, arcs: int, limit: int) -> tuple[float, int] | None:
    """The smallest simplification tolerance (a round number in the environment's units: 1, 2 or 5 × 10^k) after
    which the safe BVG is estimated to fit in ``limit`` bytes, and the vertex count it leaves; None if none does.

    The outline is simplified as the importer does (topology-preserving Douglas–Peucker, :mod:`shapely`), and the
    arcs are extrapolated from ``arcs`` (the estimate for ``env``) by the vertex count to the power 4 — a rule of
    thumb for the message of :class:`GraphTooLarge`, not a promise.

    >>> from solverplan.environment import Environment
    >>> ring = [[x / 10, (x % 2) / 100] for x in range(0, 101)] + [[10, 5], [0, 5]]
    >>> fitting_simplification(Environment.from_coords(ring), arcs=10**9, limit=2**30)
    (0.01, 4)
    """
    import shapely

    n = env.n_vertices
    shape = env.to_shapely()
    lo, hi = shape.bounds[:2], shape.bounds[2:]
    size = max(hi[0] - lo[0], hi[1] - lo[1])
    if not size > 0:
        return None
    step = 10.0 ** math.floor(math.log10(size * 1e-4))
    while step < size / 10:
        for factor in (1, 2, 5):
            tolerance = float(f"{factor * step:.1g}")
            simple = shapely.simplify(shape, tolerance, preserve_topology=True)
            if simple.is_empty or simple.geom_type != "Polygon":
                return None
            m = len(simple.exterior.coords) - 1 + sum(len(r.coords) - 1 for r in simple.interiors)
            if BASE_BYTES + BYTES_PER_ARC * arcs * (m / n) ** _ARCS_EXPONENT <= limit:
                return tolerance, m
        step *= 10
    return None


PLANNED_BYTES_PER_ARC = 400
"""Memory per safe arc a query keeps (bytes): the graph's arrays, and the planner's admissible intervals (Python
lists of floats per source) — what :func:`~solverplan.bounce.bvg.build.reachable_safe_graph` checks against the memory limit as it grows."""


def refuse_reachable(p: Partition, kept: int, sources: int, limit: int, source: str) -> None:
    """Raise :class:`GraphTooLarge` for a reachable part that outgrew the memory limit, naming a simplification."""
    advice = _advice(p, estimate_graph(p)[0], limit, "")
    raise GraphTooLarge(f"the safe arcs a query reaches in {_short_name(p)!r} outgrew {source} ({_gib(limit)}) after "
                        f"{kept:,} arcs from {sources:,} of {len(p.segments):,} segments{advice}")


def _short_name(p: Partition) -> str:
    name = p.env.name
    return name if len(name) <= 30 else name[:29] + "…"


def _advice(p: Partition, arcs: int, limit: int, otherwise: str) -> str:
    """The end of a refusal: the ``--simplify`` tolerance that would fit, else ``otherwise``."""
    hint = fitting_simplification(p.env, arcs, limit)
    return f"; --simplify {hint[0]:g} at import would fit (≈ {hint[1]:,} vertices)" if hint is not None else otherwise
