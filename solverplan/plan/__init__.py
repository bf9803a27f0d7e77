"""Solver-backed queries (paper §7–8): optimal plans over the safe bounce visibility graph.

- :func:`find_plan` — objectives ``fewest``, ``tolerance``, ``sum``, ``constant`` (belief-state search when
  the start set spans several segments), each with its optimality argument and bound;
- :func:`pareto_front` — the bounces ↔ tolerance front;
- :func:`patrol` (:mod:`~solverplan.plan.patrols`, Def. 15: contracting patrol cycles), :func:`funnel`
  (:mod:`~solverplan.plan.funnels`) and :func:`localize` (:mod:`~solverplan.plan.localization`): position-set
  plans that use contraction, paper §6.2, §8.4;
- :mod:`~solverplan.plan.margins` — the one margin policy every planner uses;
- :class:`Plan`, :class:`ParetoFront`, :class:`Patrol`, :class:`Funnel`, :class:`Localization` — the results,
  on the shared protocol of :mod:`solverplan.result` (``status``, ``optimality``, ``stats``, ``environment``,
  ``to_json()``, ``to_text()``; the plan JSON of ``docs/contract.md``); :func:`load_plan` / :func:`parse_plan`
  read plans back.

Modules are named for what they hold (``patrols``, ``funnels``, ``localization``) and never like a function they
define, so ``solverplan.plan.patrol`` is always the function and ``solverplan.plan.patrols`` the module.
"""

from solverplan.plan.result import (
    OBJECTIVES,
    ParetoFront,
    ParetoPoint,
    Plan,
    load_plan,
    parse_plan,
)
from solverplan.plan.export import EXPORT_FORMATS, export_plan, plan_in_world
from solverplan.plan.funnels import Funnel, funnel
from solverplan.plan.localization import Localization, localize
from solverplan.plan.patrols import Patrol, patrol
from solverplan.plan.search import (
    DEFAULT_HEADING_MARGIN,
    DEFAULT_SAFE_MARGIN,
    METHODS,
    find_plan,
    pareto_front,
    planning_problem,
)

__all__ = [
    "EXPORT_FORMATS",
    "export_plan",
    "plan_in_world",
    "Funnel",
    "Localization",
    "Patrol",
    "funnel",
    "localize",
    "patrol",
    "OBJECTIVES",
    "METHODS",
    "DEFAULT_HEADING_MARGIN",
    "DEFAULT_SAFE_MARGIN",
    "ParetoFront",
    "ParetoPoint",
    "Plan",
    "find_plan",
    "load_plan",
    "parse_plan",
    "pareto_front",
    "planning_problem",
]
