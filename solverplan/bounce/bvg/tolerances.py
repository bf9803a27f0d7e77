"""Float tolerances of the safe BVG's build, and its exact-on-ties comparison of interval ends.

Every float decision of the build is either safe by a margin or settled exactly. The margins are the sweeps'
(:data:`solverplan.bounce._sweep.ANGLE_REL` for headings, :data:`~solverplan.bounce._sweep.CROSS_REL` for cross
products, :data:`~solverplan.bounce._sweep.REFINE` for the float ends that are recomputed from the exact
coordinates), read from that module when used so that one setting governs both steps, plus :data:`SAT_REL` for the
separating-axis tests of single-heading regions. :class:`EndComparator` compares interval ends in the float
headings and falls back to integer arithmetic when two floats are within their error bounds.
"""

from __future__ import annotations

import numpy as np

from solverplan.bounce import _sweep
from solverplan.bounce._sweep import ExactPoints, max_norm
from solverplan.bounce.partitions import Partition

__all__ = ["SAT_REL", "EndComparator", "angle_error"]

SAT_REL = 1e-12
"""Float separating-axis tests of single-heading regions: orientations within this times the squared coordinate
scale of zero are decided exactly."""


class EndComparator:
    """Compares heading ends given as (from P′ id, to P′ id or mark, float heading, error bound), all in the frame
    of one edge per row; exact (integer) arithmetic when the floats are too close. ``checks`` counts the exact
    comparisons made.

    Examples
    --------
    >>> import numpy as np
    >>> from solverplan.bounce._sweep import SweepContext
    >>> from solverplan.bounce.partitions import partition
    >>> from solverplan.environment import Environment
    >>> ends = EndComparator(SweepContext(partition(Environment.from_coords([[0, 0], [1, 0], [1, 1], [0, 1]]))).exact)
    >>> zero, at = np.array([0]), lambda *v: np.array(v)
    >>> ends.cmp(zero, zero, at(2), at(0.78), at(0.01), zero, at(3), at(1.57), at(0.01)).tolist(), ends.checks
    ([-1], 0)
    >>> ends.cmp(zero, zero, at(2), at(0.78), at(1.0), zero, at(3), at(1.57), at(1.0)).tolist(), ends.checks
    ([-1], 1)
    """

    def __init__(self, exact: ExactPoints) -> None:
        self.exact = exact
        self.checks = 0

    def cmp(self, edge, f1, t1, a1, e1, f2, t2, a2, e2) -> np.ndarray:
        """Sign of (end 1 − end 2) per row (int8), exact where ``|a1 − a2| ≤ e1 + e2``."""
        d = a1 - a2
        out = np.sign(d).astype(np.int8)
        unsure = np.abs(d) <= e1 + e2
        idx = np.flatnonzero(unsure)
        self.checks += len(idx)
        hc = self.exact.heading_cmp
        for i in idx.tolist():
            out[i] = hc(int(edge[i]), int(f1[i]), int(t1[i]), int(f2[i]), int(t2[i]))
        return out


def angle_error(p: Partition, frm: np.ndarray, to: np.ndarray) -> np.ndarray:
    """Error bound (radians) of the float heading from P′ point ``frm`` to P′ point ``to``, with the sweeps' margin
    (:data:`~solverplan.bounce._sweep.ANGLE_REL` × coordinate magnitude / length)."""
    P = np.asarray(p.seg_start, dtype=float)
    rel = P[to] - P[frm]
    mag = max_norm(P[frm]) + max_norm(P[to])
    return _sweep.ANGLE_REL * mag / np.hypot(rel[:, 0], rel[:, 1]) + 1e-15
