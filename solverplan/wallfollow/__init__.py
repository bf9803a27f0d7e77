"""The wall-following robot (Yershova, Tovar, Katsev, Ghrist and LaValle, *Mapping and pursuit-evasion
strategies for a simple wall-following robot*).

A robot in an unknown simply connected polygon that can only follow walls (RFOLLOW counter-clockwise, LFOLLOW
clockwise), JUMP straight on past a reflex vertex, and carry one pebble; it senses whether it is in the
interior, on an edge, at a convex or at a reflex vertex, and whether it is at the pebble.

- :mod:`~solverplan.wallfollow.cuts` — the exact cuts of the reflex vertices, general position, and the
  geometric cut ordering.
- :mod:`~solverplan.wallfollow.ordering` — the cut ordering as a combinatorial object: canonical form under
  renaming, the chord-alternation test of Prop. 4.
"""

from solverplan.wallfollow.cuts import Cut, check_general_position, collinear_triple, cut_ordering, cuts
from solverplan.wallfollow.ordering import CutOrdering, parse_label

__all__ = ["Cut", "CutOrdering", "check_general_position", "collinear_triple", "cut_ordering", "cuts", "parse_label"]
