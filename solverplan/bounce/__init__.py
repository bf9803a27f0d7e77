"""The main paper (Nilles et al.): bounce rules, partition, safe intervals, the bounce visibility graph,
transitions, contraction and limit cycles."""

from solverplan.bounce.interval import Interval, heading_interval

__all__ = ["Interval", "heading_interval"]
