"""The main paper (Nilles et al.): bounce rules, partition, safe intervals, the bounce visibility graph,
transitions, contraction and limit cycles (the constant map f_θ in :mod:`~solverplan.bounce.constant_map`,
its cycles in :mod:`~solverplan.bounce.cycles`, Prop. 4's constant controller in
:mod:`~solverplan.bounce.controller`).

Modules are named for what they hold and never like a function they define: the partition P′ (Algorithm 1) is
:func:`partition`, made in :mod:`~solverplan.bounce.partitions`."""

from solverplan.interval import Interval, heading_interval
from solverplan.bounce.partitions import InsertedPoint, Partition, PartitionSegment, partition
from solverplan.bounce.rules import BounceRule, Fixed, FixedInterval, MonotoneFixed, Relative, Specular, parse_rule
from solverplan.bounce.bvg import SafeBVG, bounce_visibility_graph, safe_bounce_visibility_graph
from solverplan.bounce.safe import SafeSet, safe_interval, safe_set
from solverplan.bounce.transitions import AffineMap, affine_map, exact_transition, transition, transition_set
from solverplan.bounce.dynamics import (ExactHeading, composite_contraction, contraction_coefficient, cycles_to_epsilon,
                                        distance_bound, is_contracting, lemma3_max_heading, lemma3_range, parse_heading,
                                        theorem1_fixed_point, worst_case_contraction)
from solverplan.bounce.constant_map import ConstantMap
from solverplan.bounce.cycles import CyclePoint, LimitCycle, limit_cycle, limit_cycles
from solverplan.bounce.controller import DEFAULT_CONTROLLER_TANGENTS, ConstantController, constant_controller
from solverplan.bounce.cones import heading_cone, heading_direction

__all__ = ["Interval", "heading_interval", "InsertedPoint", "Partition", "PartitionSegment", "partition",
           "BounceRule", "Fixed", "FixedInterval", "MonotoneFixed", "Relative", "Specular", "parse_rule",
           "SafeBVG", "bounce_visibility_graph", "safe_bounce_visibility_graph", "SafeSet", "safe_interval", "safe_set",
           "AffineMap", "affine_map", "exact_transition", "transition", "transition_set",
           "ExactHeading", "composite_contraction", "contraction_coefficient", "cycles_to_epsilon", "distance_bound",
           "is_contracting", "lemma3_max_heading", "lemma3_range", "parse_heading", "theorem1_fixed_point",
           "worst_case_contraction", "ConstantMap", "CyclePoint", "LimitCycle", "limit_cycle", "limit_cycles",
           "ConstantController", "constant_controller", "DEFAULT_CONTROLLER_TANGENTS",
           "heading_cone", "heading_direction"]
