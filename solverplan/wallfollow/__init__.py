"""The wall-following robot (Yershova, Tovar, Katsev, Ghrist and LaValle, *Mapping and pursuit-evasion
strategies for a simple wall-following robot*).

A robot in an unknown simply connected polygon that can only follow walls (RFOLLOW counter-clockwise, LFOLLOW
clockwise), JUMP straight on past a reflex vertex, and carry one pebble; it senses whether it is in the
interior, on an edge, at a convex or at a reflex vertex, and whether it is at the pebble.

- :mod:`~solverplan.wallfollow.cut` — the exact cuts of the reflex vertices, general position, and the
  geometric cut ordering.
- :mod:`~solverplan.wallfollow.ordering` — the cut ordering as a combinatorial object: canonical form under
  renaming, the chord-alternation test of Prop. 4.
- :mod:`~solverplan.wallfollow.world` — the geometric simulator: actions, touch and pebble sensors.
- :mod:`~solverplan.wallfollow.combinatorial` — the simulator driven by the cut ordering alone (Prop. 7).
- :mod:`~solverplan.wallfollow.filters` — vertex counting and winding number (§IV, corrected).
- :mod:`~solverplan.wallfollow.learning` — Strategy 1: learning the cut ordering from sensing alone.
- :mod:`~solverplan.wallfollow.bitangent` — inflections and bitangents (exact), their end points in the cut
  ordering: the events of pursuit-evasion (Props. 11, 13, 18 hold and are tested).
- :mod:`~solverplan.wallfollow.pursuit_check` — the geometric ground truth of pursuit-evasion: exact shadow
  components along a plan and their labels.
- :mod:`~solverplan.wallfollow.pursuit` — Strategy 2 (gap sensor): shortest pursuit plans, or a proof that
  none exists (Prop. 8); :mod:`~solverplan.wallfollow.pursuit_primitives` — Strategy 3 (bitangent sensor:
  primitives and compounds, Prop. 10); :mod:`~solverplan.wallfollow.pursuit_contact` — Strategy 6 (touch and
  pebble sensors only, from the cut ordering alone: sound, Prop. 17).

The command is ``solverplan wallfollow``.

>>> import solverplan as sp
>>> room = sp.Environment.from_coords([[0, 0], [9, 0], [9, 4], [4, 5], [3, 9], [0, 8]])
>>> sp.cut_ordering(room).labels
('v0', 'l3', 'v1', 'v2', 'v3', 'v4', 'v5', 'r3')
>>> sp.learn_cut_ordering(room).matches_geometry
True
"""

from solverplan.wallfollow.bitangent import Bitangent, bitangents, inflections, mutually_visible, reflex_chains
from solverplan.wallfollow.combinatorial import OrderingWorld
from solverplan.wallfollow.cut import Cut, check_general_position, collinear_triple, cut_ordering, cuts
from solverplan.wallfollow.filters import (CountingFilter, count_walk, printed_vertex_count, printed_winding,
                                           step_value)
from solverplan.wallfollow.learning import LearnedOrdering, Robot, learn_cut_ordering, strategy1
from solverplan.wallfollow.ordering import CutOrdering, parse_label
from solverplan.wallfollow.pebble import LearnedBitangent, LearnedBitangents, PebbleWorld, learn_bitangents
from solverplan.wallfollow.pursuit import GapSensor, PursuitPlan, pursuit_plan
from solverplan.wallfollow.pursuit_check import PursuitCheck, PursuitStep, check_pursuit
from solverplan.wallfollow.world import Action, ActionNotApplicable, Observation, Touch, WallWorld, parse_action

__all__ = ["Action", "ActionNotApplicable", "Bitangent", "CountingFilter", "Cut", "CutOrdering", "GapSensor",
           "LearnedOrdering", "Observation", "OrderingWorld", "PursuitCheck", "PursuitPlan", "PursuitStep", "Robot",
           "Touch", "WallWorld", "bitangents", "check_general_position", "check_pursuit", "pursuit_plan",
           "collinear_triple", "count_walk", "cut_ordering", "cuts", "inflections", "learn_cut_ordering",
           "mutually_visible", "parse_action", "parse_label", "printed_vertex_count", "printed_winding",
           "reflex_chains", "step_value", "strategy1",
           "LearnedBitangent", "LearnedBitangents", "PebbleWorld", "learn_bitangents"]
