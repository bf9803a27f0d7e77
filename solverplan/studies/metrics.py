"""What a study measures on one environment: the :class:`Metric` interface and the paper's metrics.

A metric is a small, picklable object (it travels to worker processes and Dask workers) that maps
one environment to a flat dict of numbers, one per declared column::

    class Metric(Protocol):
        name: str                               # the study's name: "reachability", "connectivity", ...
        columns: tuple[str, ...]                # the keys __call__ returns, in table order
        options: tuple[tuple[str, tuple], ...]  # extra grid axes of the metric itself (rules: "rule")
        panels: tuple[tuple[str, dict], ...]    # heatmap panels: (column, option filter)
        labels: dict[str, str]                  # optional: panel titles per column
        def __call__(self, env, *, seed: int, **options) -> dict: ...
        def spec(self) -> dict: ...             # its parameters (part of the study's identity)

``seed`` is the row's seed (for metrics that sample, e.g. :class:`~solverplan.studies.rule_systems.RuleReachability`);
deterministic metrics ignore it. A metric must be a pure function of its arguments: a row is
recomputed identically from its parameters and seed on any machine, in any process.

The paper's metrics (§7.3–7.4) are computed on the **safe bounce visibility graph**
(:func:`solverplan.bounce.bvg.safe_bounce_visibility_graph`), nodes = the segments of P′, an arc
i → j when the arc of the BVG has at least one safe heading:

- :class:`ReachabilityMetric` (Fig. 15): ``unreachable`` = (total length of the segments with **no incoming
  safe arc**) / (perimeter of P, holes included); also the count of such segments, and
  ``unreachable_nonadjacent``, the same share when the arcs between neighbouring segments of P′
  (sharing an end point) are ignored — what an implementation that drops Cor. 1's adjacent arcs
  would report (a diagnostic: in star polygons it changes the share very little).
- :class:`ConnectivityMetric` (Fig. 16): numbers of strongly (``scc``) and weakly (``wcc``) connected
  components of the safe BVG (every segment is a node, so a segment without safe arcs is a component
  of its own), and the share of the perimeter in the largest strongly connected component.

>>> from solverplan.environment import Environment
>>> square = Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]])
>>> ReachabilityMetric()(square, seed=0)
{'segments': 4, 'arcs': 12, 'safe_arcs': 12, 'unreachable_segments': 0, 'unreachable': 0.0, 'unreachable_nonadjacent': 0.0}
>>> ConnectivityMetric()(square, seed=0)["scc"], ConnectivityMetric()(square, seed=0)["wcc"]
(1, 1)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Protocol, runtime_checkable

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.bounce.bvg import SafeBVG
    from solverplan.environment import Environment

__all__ = [
    "Metric",
    "ReachabilityMetric",
    "ConnectivityMetric",
    "SafeGraphSummary",
    "safe_graph_summary",
    "unreachable_fraction",
    "component_counts",
]


@runtime_checkable
class Metric(Protocol):
    """What a study computes per environment (see the module docstring).

    The four attributes are read-only: a metric may give them as class variables or properties.
    """

    @property
    def name(self) -> str: ...

    @property
    def columns(self) -> tuple[str, ...]: ...

    @property
    def options(self) -> tuple[tuple[str, tuple], ...]: ...

    @property
    def panels(self) -> tuple[tuple[str, dict], ...]: ...

    def __call__(self, env: Environment, *, seed: int, **options: Any) -> dict: ...

    def spec(self) -> dict: ...


# ---------------------------------------------------------------------- graph measures
def unreachable_fraction(lengths: np.ndarray, source: np.ndarray, target: np.ndarray) -> tuple[int, float]:
    """Segments with no incoming arc: (their number, their total length / the total length).

    ``lengths`` per node; ``source``/``target`` the arcs (self-loops never count as incoming).

    >>> unreachable_fraction(np.array([1.0, 2.0, 1.0]), np.array([0, 1]), np.array([1, 0]))
    (1, 0.25)
    """
    lengths = np.asarray(lengths, dtype=float)
    reached = np.zeros(len(lengths), dtype=bool)
    keep = np.asarray(source) != np.asarray(target)
    reached[np.asarray(target)[keep]] = True
    total = float(lengths.sum())
    return int(np.count_nonzero(~reached)), (float(lengths[~reached].sum()) / total if total > 0 else 0.0)


def component_counts(n: int, source: np.ndarray, target: np.ndarray, lengths: np.ndarray | None = None) -> dict:
    """Strongly / weakly connected components of the directed graph on nodes 0..n−1.

    Returns ``{"scc", "wcc", "largest_scc"}``, the last the share of ``lengths`` (default: of the
    nodes) in the heaviest strongly connected component.

    >>> component_counts(4, np.array([0, 1, 2]), np.array([1, 0, 3]))
    {'scc': 3, 'wcc': 2, 'largest_scc': 0.5}
    """
    import networkx as nx

    if n == 0:
        return {"scc": 0, "wcc": 0, "largest_scc": 0.0}
    graph = nx.DiGraph()
    graph.add_nodes_from(range(n))
    graph.add_edges_from(zip(np.asarray(source).tolist(), np.asarray(target).tolist()))
    weights = np.ones(n) if lengths is None else np.asarray(lengths, dtype=float)
    strong = [weights[list(c)].sum() for c in nx.strongly_connected_components(graph)]
    total = float(weights.sum())
    return {"scc": len(strong), "wcc": nx.number_weakly_connected_components(graph),
            "largest_scc": float(max(strong)) / total if total > 0 else 0.0}


@dataclass(frozen=True)
class SafeGraphSummary:
    """The safe BVG of an environment reduced to what the metrics need (arrays over segments / arcs)."""

    graph: SafeBVG
    lengths: np.ndarray  # per segment of P′ (length units)

    @property
    def n_segments(self) -> int:
        return self.graph.n_segments

    @property
    def safe_source(self) -> np.ndarray:
        return self.graph.source[self.graph.safe]

    @property
    def safe_target(self) -> np.ndarray:
        return self.graph.target[self.graph.safe]

    def sizes(self) -> dict:
        return {"segments": self.n_segments, "arcs": int(self.graph.n_arcs), "safe_arcs": int(self.graph.n_safe_arcs)}


def safe_graph_summary(env: Environment) -> SafeGraphSummary:
    """Partition ``env`` (Algorithm 1), build its safe BVG, and measure the segments' lengths."""
    from solverplan.bounce.bvg import safe_bounce_visibility_graph
    from solverplan.bounce.partitions import partition

    p = partition(env)
    graph = safe_bounce_visibility_graph(p)
    lengths = np.hypot(*(np.asarray(p.seg_end, dtype=float) - np.asarray(p.seg_start, dtype=float)).T)
    return SafeGraphSummary(graph, lengths)


# ---------------------------------------------------------------------- the paper's metrics
@dataclass(frozen=True)
class ReachabilityMetric:
    """Fig. 15: the share of the boundary of P′ that no safe action reaches from any other segment."""

    name: ClassVar[str] = "reachability"
    columns: ClassVar[tuple[str, ...]] = (
        "segments", "arcs", "safe_arcs", "unreachable_segments", "unreachable", "unreachable_nonadjacent",
    )
    options: ClassVar[tuple[tuple[str, tuple], ...]] = ()
    panels: ClassVar[tuple[tuple[str, dict], ...]] = (("unreachable", {}),)
    labels: ClassVar[dict[str, str]] = {
        "unreachable": "share of ∂P′ with no incoming safe arc",
        "unreachable_nonadjacent": "same, without arcs between neighbours",
    }

    def __call__(self, env: Environment, *, seed: int = 0, **options: Any) -> dict:
        summary = safe_graph_summary(env)
        source, target = summary.safe_source, summary.safe_target
        count, fraction = unreachable_fraction(summary.lengths, source, target)
        p = summary.graph.partition
        apart = (target != p.next_segment[source]) & (target != p.prev_segment[source])
        _, apart_fraction = unreachable_fraction(summary.lengths, source[apart], target[apart])
        return {**summary.sizes(), "unreachable_segments": count, "unreachable": fraction,
                "unreachable_nonadjacent": apart_fraction}

    def spec(self) -> dict:
        return {"metric": self.name}


@dataclass(frozen=True)
class ConnectivityMetric:
    """Fig. 16: strongly and weakly connected components of the safe BVG."""

    name: ClassVar[str] = "connectivity"
    columns: ClassVar[tuple[str, ...]] = ("segments", "arcs", "safe_arcs", "scc", "wcc", "largest_scc")
    options: ClassVar[tuple[tuple[str, tuple], ...]] = ()
    panels: ClassVar[tuple[tuple[str, dict], ...]] = (("scc", {}), ("wcc", {}))
    labels: ClassVar[dict[str, str]] = {"scc": "strongly connected components", "wcc": "weakly connected components"}

    def __call__(self, env: Environment, *, seed: int = 0, **options: Any) -> dict:
        summary = safe_graph_summary(env)
        counts = component_counts(summary.n_segments, summary.safe_source, summary.safe_target, summary.lengths)
        return {**summary.sizes(), **counts}

    def spec(self) -> dict:
        return {"metric": self.name}
