"""Solver-backed queries (paper §7–8): optimal plans over the safe bounce visibility graph.

- :func:`find_plan` — objectives ``fewest``, ``tolerance``, ``sum``, ``constant`` (belief-state search when
  the start set spans several segments), each with its optimality argument and bound;
- :func:`pareto_front` — the bounces ↔ tolerance front;
- :func:`patrol` (Def. 15: contracting patrol cycles), :func:`funnel` and :func:`localize` (position-set
  plans that use contraction, paper §6.2, §8.4);
- :class:`Plan`, :class:`Stage`, :class:`ParetoFront`, :class:`Optimality` — the results
  (the plan JSON of docs/contract.md via ``to_json()``); :func:`load_plan` / :func:`parse_plan` read plans back.
"""

from solverplan.plan.result import (
    OBJECTIVES,
    Optimality,
    ParetoFront,
    ParetoPoint,
    Plan,
    Stage,
    Status,
    load_plan,
    parse_plan,
)
from solverplan.plan.funnel import Funnel, funnel
from solverplan.plan.localize import localize
from solverplan.plan.patrol import Patrol, patrol
from solverplan.plan.search import (
    DEFAULT_HEADING_MARGIN,
    DEFAULT_SAFE_MARGIN,
    METHODS,
    environment_record,
    find_plan,
    pareto_front,
    planning_problem,
)

__all__ = [
    "Funnel",
    "funnel",
    "localize",
    "Patrol",
    "patrol",
    "OBJECTIVES",
    "METHODS",
    "DEFAULT_HEADING_MARGIN",
    "DEFAULT_SAFE_MARGIN",
    "Optimality",
    "ParetoFront",
    "ParetoPoint",
    "Plan",
    "Stage",
    "Status",
    "environment_record",
    "find_plan",
    "load_plan",
    "parse_plan",
    "pareto_front",
    "planning_problem",
]
