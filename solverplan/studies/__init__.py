"""Studies: random environments, reachability/connectivity sweeps, batch execution (the paper's §7.3–7.4, §8.1–8.2).

- The random environments of a study come from :mod:`solverplan.generators` (their one home: seeded
  generators that always return valid, exact environments).
- :mod:`~solverplan.studies.study` — a :class:`Study` is a grid of generator parameters × N seeds per
  cell; one tidy row per environment, with the seed that regenerates it; tables and heatmap data.
- :mod:`~solverplan.studies.metrics` — the :class:`Metric` interface and the paper's metrics on the
  safe BVG (Fig. 15 reachability, Fig. 16 connectivity); :mod:`~solverplan.studies.rule_systems` —
  §8.2's comparison of bounce-rule families.
- :mod:`~solverplan.studies.execute` — :func:`run_study`: in process, on a local process pool or on a
  Dask cluster, written row by row so an interrupted study resumes (:mod:`~solverplan.studies.store`).
- :mod:`~solverplan.studies.catalog` — the named studies of ``solverplan study``.
- :mod:`~solverplan.studies.rewrite` — the same walls written differently (collinear vertices, split edges,
  exact rotations, another ring start, the opposite vertex order) with the query mapped exactly, and answer
  summaries to compare: issue #22's invariance tests and ``benchmarks/invariance_study.py``.

The rooms model's simulation (the smart, random and billiard rules side by side, their Table I) sits with its
model in :mod:`solverplan.rectilinear.simulation`, on the rollout engine below the models
(:mod:`solverplan.rollout`); it is re-exported here for the studies that compare rules.

Programs that run a study on a process pool must guard their entry point
(``if __name__ == "__main__":``): the workers start with the ``forkserver`` method.
"""

from solverplan.studies.catalog import DEFAULT_GRIDS, STUDIES, build_study
from solverplan.studies.execute import StudyInterrupted, StudyResult, run_study
from solverplan.studies.metrics import ConnectivityMetric, Metric, ReachabilityMetric
from solverplan.rectilinear.simulation import RoomRuns, RuleComparison, compare_rules, periodic_orbit, simulate_rooms
from solverplan.studies.rule_systems import RuleReachability
from solverplan.studies.study import Heatmap, Study, StudyTable, parse_grid, parse_values, row_seed, run_task

__all__ = [
    "Study",
    "StudyTable",
    "Heatmap",
    "parse_grid",
    "parse_values",
    "row_seed",
    "run_task",
    "Metric",
    "ReachabilityMetric",
    "ConnectivityMetric",
    "RuleReachability",
    "run_study",
    "StudyResult",
    "StudyInterrupted",
    "build_study",
    "STUDIES",
    "DEFAULT_GRIDS",
    "simulate_rooms",
    "compare_rules",
    "periodic_orbit",
    "RoomRuns",
    "RuleComparison",
]
