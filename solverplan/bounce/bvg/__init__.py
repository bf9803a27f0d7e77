"""The bounce visibility graph (BVG) and the safe BVG of P′ (paper §4–5, Def. 5–8, Prop. 1–3, 5).

- :func:`bounce_visibility_graph` — the directed edge-visibility graph of P′: an arc i → j for every two segments
  whose **open** segments see each other (Def. 5), as a :class:`networkx.DiGraph`.
- :func:`safe_bounce_visibility_graph` — the same arcs, each labelled with the **exact set of safe headings**
  (Def. 7), its widest interval, the transition side (Def. 8) and φ_ij: a :class:`SafeBVG`.
- :func:`reachable_safe_graph` — only the safe arcs a search from given segments can use, built on demand.

The package's parts:

- :mod:`~solverplan.bounce.bvg.graph` — the graph type :class:`SafeBVG` (a structure of arrays) and its look-ups;
- :mod:`~solverplan.bounce.bvg.build` — the construction (the algorithm and its proof are in its docstring), with
  the private steps after the sweeps in :mod:`~solverplan.bounce.bvg._safe_sets`;
- :mod:`~solverplan.bounce.bvg.serialise` — JSON (streamed a chunk of arcs at a time), text, GraphML, DOT, networkx;
- :mod:`~solverplan.bounce.bvg.tolerances` — the float tolerances and the exact-on-ties comparison of ends;
- :mod:`~solverplan.bounce.bvg.size` — size estimates and the refusals of graphs that would not fit in memory.

The graph cache (:mod:`solverplan.bounce._cache`) keeps built graphs; its functions are re-exported here.

Examples
--------
>>> from solverplan.bounce.bvg import safe_bounce_visibility_graph
>>> from solverplan.environment import Environment
>>> g = safe_bounce_visibility_graph(Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]]))
>>> g.n_arcs, g.n_safe_arcs
(12, 12)
"""

from solverplan.bounce._cache import (
    DEFAULT_MAX_BYTES,
    DEFAULT_MIN_ARCS,
    GraphCacheReport,
    clear_graph_cache,
    default_cache_directory,
    discard_graphs,
    fresh_graphs,
    graph_cache_directory,
    graph_cache_report,
    partition_digest,
    purge_graph_cache,
    set_graph_cache,
)
from solverplan.bounce.bvg.build import _build, bounce_visibility_graph, reachable_safe_graph, safe_bounce_visibility_graph
from solverplan.bounce.bvg.graph import SafeBVG
from solverplan.bounce.bvg.size import (
    BASE_BYTES,
    BYTES_PER_ARC,
    PLANNED_BYTES_PER_ARC,
    GraphTooLarge,
    check_graph_memory,
    estimate_graph,
    fitting_simplification,
)

__all__ = ["SafeBVG", "bounce_visibility_graph", "safe_bounce_visibility_graph", "GraphTooLarge", "estimate_graph",
           "check_graph_memory", "fitting_simplification", "reachable_safe_graph", "LAZY_MIN_ARCS", "BYTES_PER_ARC",
           "BASE_BYTES", "PLANNED_BYTES_PER_ARC", "set_graph_cache", "clear_graph_cache", "graph_cache_directory",
           "default_cache_directory", "graph_cache_report", "purge_graph_cache", "GraphCacheReport", "DEFAULT_MIN_ARCS",
           "DEFAULT_MAX_BYTES", "partition_digest", "discard_graphs", "fresh_graphs"]

LAZY_MIN_ARCS = 2_000_000
"""Planners build only the reachable safe arcs (:func:`reachable_safe_graph`) when the whole safe BVG is estimated
to have at least this many arcs (and is not cached): below it the whole graph builds in a few seconds. Read here
at each query (``solverplan.bounce.bvg.LAZY_MIN_ARCS``), so setting it here takes effect."""
