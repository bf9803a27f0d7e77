"""The main paper (Nilles et al.): bounce rules, partition, safe intervals, the bounce visibility graph,
transitions, contraction and limit cycles."""

from solverplan.bounce.interval import Interval, heading_interval
from solverplan.bounce.partition import InsertedPoint, Partition, PartitionSegment, partition

__all__ = ["Interval", "heading_interval", "InsertedPoint", "Partition", "PartitionSegment", "partition"]
