"""Studies: random environments, reachability/connectivity sweeps, batch execution.

The generators (:mod:`solverplan.studies.generators`) always return valid, exact environments:
random star polygons (the paper's §7.3 family, with the irregularity scaled properly), star
polygons with holes for ray-casting tests and benchmarks, and the paper's worst case for
Algorithm 1 (§4.0.1).
"""

from solverplan.studies.generators import star_polygon, star_polygon_with_holes, worst_case_polygon

__all__ = ["star_polygon", "star_polygon_with_holes", "worst_case_polygon"]
