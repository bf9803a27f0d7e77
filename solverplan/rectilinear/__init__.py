"""Rooms and doors of rectilinear polygons (Çağırıcı, Bahoo and LaValle, "Bouncing robots in rectilinear polygons").

- :mod:`~solverplan.rectilinear.decomposition` — Algorithm 1: bottleneck segments from reflex vertices become
  virtual doors, the polygon splits into rooms along them, and rooms and doors form a tree (Remark 5).
- :mod:`~solverplan.rectilinear.metrics` — escapability Φ, reachability Ψ, the reachability graph and the
  rule recommendation (§VII).
- :mod:`~solverplan.rectilinear.doors` — the rooms as the simulator's walls, doors open or closed per robot,
  and the door-control policy for a room sequence (§V–VI).
- :mod:`~solverplan.rectilinear.rules` — the billiard, random and one-bit smart rules (§VI, Eq. 1).
- :mod:`~solverplan.rectilinear.simulation` — the rules simulated through the rooms and compared (§VIII,
  Table I) on the rollout engine (:mod:`solverplan.rollout`), door control and exact periodic orbits.

Pictures are in :mod:`solverplan.render.rooms`; the command is ``solverplan rooms``.

>>> import solverplan as sp
>>> rooms = sp.decompose_rooms(sp.load_environment("three_chambers"))
>>> len(rooms.rooms), len(rooms.doors), str(reachability(rooms, 0, 2).psi)
(5, 4, '1/300')
"""

from solverplan.rectilinear.decomposition import Decomposition, Door, Room, decompose_rooms
from solverplan.rectilinear.doors import DoorControl, RoomWorld
from solverplan.rectilinear.metrics import (SMART_THRESHOLD, RoomReachability, RuleRecommendation, escapability,
                                            reachability, reachability_along, reachability_graph, recommend_rule)

from solverplan.rectilinear.rules import RULES, Billiard, Random, Smart, make_rule, room_tangents, smart_tangent
from solverplan.rectilinear.simulation import RoomRuns, RuleComparison, compare_rules, periodic_orbit, simulate_rooms

__all__ = ["Decomposition", "Door", "Room", "decompose_rooms", "SMART_THRESHOLD", "RoomReachability", "RuleRecommendation",
           "escapability", "reachability", "reachability_along", "reachability_graph", "recommend_rule", "DoorControl", "RoomWorld",
           "RULES", "Billiard", "Random", "Smart", "make_rule", "room_tangents", "smart_tangent",
           "RoomRuns", "RuleComparison", "compare_rules", "periodic_orbit", "simulate_rooms"]
