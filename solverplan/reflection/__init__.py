"""Reflection-aware navigation with composed local potential fields in convex cells (Stager and Tanner,
"Composition of local potential functions with reflection").

A collision-capable point robot is driven by vector fields defined cell by cell over a convex decomposition of the
free space; each cell's field carries every point of the cell through its outlet into the next cell (sequential
composition ⇒ global convergence), and in cells where the inlet and outlet normals make an angle α ≤ π/2 a hybrid
controller aims at a wall first, bouncing off it, then switches to the nominal field.

- :mod:`~solverplan.reflection.cells` — exact convex cells (holes included), facet adjacency, cell sequences.
- :mod:`~solverplan.reflection.fields` — the line field (Eq. 2), the arc field (Eq. 3, reconstructed), the goal
  field; the flow-through verifier (exact for line fields, dense sample otherwise).
- :mod:`~solverplan.reflection.zones` — reflection candidates and zones (Eq. 4 corrected, with the tie-break).
- :mod:`~solverplan.reflection.compose` — the composed policy over every cell, with the reflection zones.
- :mod:`~solverplan.reflection.simulate` — single-integrator and inertial rollouts, the three scenarios.
- :mod:`~solverplan.reflection.navigation` — the ``solverplan fields`` answer (result protocol).

The symbolic proofs are in ``solverplan.proofs.line_field``; the command is ``solverplan fields``.

>>> import solverplan as sp
>>> nav = sp.navigate_fields(sp.load_environment("serpentine"), (3, "2.25"), (3, "0.25"), trials=2)
>>> nav.plan.reflection_cells, nav.runs["reflection"].success     # the zones that pay for the inertial robot
((2, 0, 7, 5), 1.0)
"""

from solverplan.reflection.cells import Cell, CellDecomposition, Side, decompose_free_space
from solverplan.reflection.compose import CellPolicy, FieldPlan, compose_fields
from solverplan.reflection.fields import (ArcField, FlowCheck, GoalField, LineField, dense_flows_through,
                                          flows_through, line_flows_through)
from solverplan.reflection.navigation import FieldNavigation, navigate_fields
from solverplan.reflection.simulate import (FieldRobotDynamics, Scenario, ScenarioRun, default_scenarios,
                                           simulate_scenarios)
from solverplan.reflection.zones import ReflectionZone, is_reflection_candidate, rank_zones, select_zone, zone_cost

__all__ = ["ArcField", "Cell", "CellDecomposition", "CellPolicy", "FieldNavigation", "FieldPlan", "FieldRobotDynamics",
           "FlowCheck", "GoalField", "LineField", "ReflectionZone", "Scenario", "ScenarioRun", "Side", "compose_fields",
           "decompose_free_space", "default_scenarios", "dense_flows_through", "flows_through",
           "is_reflection_candidate", "line_flows_through", "navigate_fields", "rank_zones", "select_zone",
           "simulate_scenarios", "zone_cost"]
