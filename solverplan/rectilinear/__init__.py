"""Rooms and doors of rectilinear polygons (Çağırıcı, Bahoo and LaValle, "Bouncing robots in rectilinear polygons").

- :mod:`~solverplan.rectilinear.decomposition` — Algorithm 1: bottleneck segments from reflex vertices become
  virtual doors, the polygon splits into rooms along them, and rooms and doors form a tree (Remark 5).
- :mod:`~solverplan.rectilinear.metrics` — escapability Φ, reachability Ψ, the reachability graph and the
  rule recommendation (§VII).
"""

from solverplan.rectilinear.decomposition import Decomposition, Door, Room, decompose
from solverplan.rectilinear.metrics import (SMART_THRESHOLD, Reachability, RuleRecommendation, escapability,
                                            reachability, reachability_graph, recommend_rule)

__all__ = ["Decomposition", "Door", "Room", "decompose", "SMART_THRESHOLD", "Reachability", "RuleRecommendation",
           "escapability", "reachability", "reachability_graph", "recommend_rule"]
