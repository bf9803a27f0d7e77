"""Online exploration of unknown polygons with discrete views (Ghosh, Burdick, Bhattacharya and Sarkar,
"Online algorithms with discrete visibility: exploring unknown polygonal environments").

A point robot that knows nothing of the polygon computes visibility polygons only where it stops, and each
stop lies in an earlier view; the goal is few views.

- :mod:`~solverplan.explore.window` — the constructed edges (windows) of a view and their unexplored parts,
  exact.
- :mod:`~solverplan.explore.depth_first` — Algorithm A: depth-first over unexplored windows with an explicit
  stack, at most r + 1 views (Theorem 1); z-choice rules ``first``, ``random``, ``far``.
- :mod:`~solverplan.explore.range_view` — range-limited views RVP(z) = VP(z) ∩ disc(z, R) with explicit arcs.
- :mod:`~solverplan.explore.range_limited` — Algorithm B: range-limited exploration boundary by boundary,
  complete (Theorem 4) within Lemma 4's bound; Algorithm A when R reaches across P (Theorem 3).
- :mod:`~solverplan.explore.bounds` — the cost T = t_M·N_M + t_S·N_S + d/r and the paper's bounds (r + 1,
  Lemma 4, Theorem 5).
- :mod:`~solverplan.explore.optimum` — the offline optimum over candidate points (a set cover MILP with a
  connectivity constraint), to measure the competitive ratio.

The command is ``solverplan explore``.

>>> import solverplan as sp
>>> run = sp.explore_depth_first(sp.load_environment("comb"), (1, 1))
>>> run.n_views <= run.bound, run.covered_fraction > 1 - 1e-9
(True, True)
"""

from solverplan.explore.bounds import (Cost, depth_first_ratio, exploration_cost, range_ratio_bound,
                                       range_views_bound, range_views_lower_bound, views_bound)
from solverplan.explore.depth_first import CHOICES, Exploration, covered_fraction, explore_depth_first
from solverplan.explore.range_limited import RangeExploration, covers_every_segment, explore_range_limited
from solverplan.explore.range_view import Arc, RangeSegment, RangeView, range_visibility
from solverplan.explore.window import Window, unexplored_parts, windows

__all__ = ["Arc", "CHOICES", "Cost", "Exploration", "RangeExploration", "RangeSegment", "RangeView", "Window",
           "covers_every_segment", "explore_range_limited", "range_visibility", "covered_fraction", "depth_first_ratio",
           "explore_depth_first", "exploration_cost", "range_ratio_bound", "range_views_bound",
           "range_views_lower_bound", "unexplored_parts", "views_bound", "windows"]
