"""The named studies (``solverplan study NAME``) and the default grids of each generator.

=================  ====================================================  =====================================
study              measures (per environment)                            heatmaps
=================  ====================================================  =====================================
``reachability``   :class:`~solverplan.studies.metrics.ReachabilityMetric`     unreachable share of ∂P′ (Fig. 15)
``connectivity``   :class:`~solverplan.studies.metrics.ConnectivityMetric`     strong / weak components (Fig. 16)
``rules``          :class:`~solverplan.studies.rule_systems.RuleReachability`  per rule family: guaranteed
                                                                         unreachable share, single-run coverage
=================  ====================================================  =====================================

>>> study = build_study("rules", per_cell=2, families=["fixed", "specular"], grid=["spikiness=0.3"])
>>> study.n_cells, study.option_axes
(10, (('rule', ('fixed', 'specular')),))
"""

from __future__ import annotations

from typing import Sequence

from solverplan.choices import StudyGenerator
from solverplan.errors import InputError
from solverplan.studies.metrics import ConnectivityMetric, Metric, ReachabilityMetric
from solverplan.studies.rule_systems import DEFAULT_FAMILIES, RuleReachability
from solverplan.studies.study import PAPER_GRID, Study, parse_grid

__all__ = ["STUDIES", "DEFAULT_GRIDS", "build_study"]

STUDIES = ("reachability", "connectivity", "rules")

DEFAULT_GRIDS: dict[str, tuple[tuple[str, tuple], ...]] = {
    "star": PAPER_GRID,
    "holes": (("n", (20,)), ("n_holes", (1, 2, 3)), ("hole_vertices", (4, 6))),
    "rooms": (("n_rooms", (3, 5, 8)), ("loops", (0, 1))),
    "rectilinear": (("n_rooms", (2, 4, 6)), ("pillars", (0, 1, 2))),
}
"""Each generator's grid when the user gives none: the paper's for ``star``, small ones for the others."""
assert set(DEFAULT_GRIDS) == set(StudyGenerator.values()), "a study generator without a default grid"


def build_study(
    name: str,
    *,
    generator: str = "star",
    grid: Sequence[str] = (),
    per_cell: int = 10,
    seed: int = 0,
    families: Sequence[str] | None = None,
    family_size: int = 5,
    trials: int = 200,
    bounces: int = 50,
) -> Study:
    """The study ``name`` (:data:`STUDIES`) over ``generator``'s default grid changed by ``grid``
    (``NAME=VALUES`` strings, :func:`~solverplan.studies.study.parse_grid`); the rules study's options
    are ``families`` (default :data:`~solverplan.studies.rule_systems.DEFAULT_FAMILIES`),
    ``family_size``, ``trials`` and ``bounces``.
    """
    if name not in STUDIES:
        raise InputError(f"unknown study {name!r}: use {', '.join(STUDIES)}")
    generator = StudyGenerator.parse(generator, "generator").value  # those with a default grid
    metric: Metric
    if name == "reachability":
        metric = ReachabilityMetric()
    elif name == "connectivity":
        metric = ConnectivityMetric()
    else:
        metric = RuleReachability(tuple(families or DEFAULT_FAMILIES), family_size=family_size, trials=trials, bounces=bounces)
    axes = parse_grid(grid, base=DEFAULT_GRIDS[generator])
    return Study(metric, generator=generator, grid=axes, per_cell=per_cell, seed=seed)
