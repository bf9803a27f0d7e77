"""The region a family of rays sweeps, for drawing plan and funnel stages (floats; private).

A stage moves the robot from a piece of one wall at every heading of an interval; the rays it may follow fill
the convex hull of the piece and the first wall hits of its four corner rays (piece ends × interval ends),
which is what the paper's Figs. 12–14 shade. The hits come from the geometry kernel's batch caster.
"""

from __future__ import annotations

import numpy as np
import shapely

from solverplan.environment import Environment
from solverplan.geometry.raycast import cast_from_boundary

__all__ = ["swept_regions", "cone_headings"]

# Corner rays leave the piece this fraction of its length inside its ends: a ray from the end point itself
# may start at a vertex and slide along the next wall (a move into the adjacent wall of a corner), while the
# rays of the stage leave from the open piece.
_END_PULL = 1e-6


def swept_regions(env: Environment, edges, t0, t1, lo, hi) -> list[np.ndarray | None]:
    """For every piece ``(edges[k], t0[k], t1[k])`` and heading interval ``[lo[k], hi[k]]`` (radians, CCW from
    the edge), the corners of the swept region as an (n, 2) array (convex, in order), or None when a corner
    ray meets no wall or the region is degenerate."""
    edges = np.asarray(edges, dtype=np.int64).reshape(-1)
    if len(edges) == 0:
        return []
    t0, t1 = np.asarray(t0, dtype=float).reshape(-1), np.asarray(t1, dtype=float).reshape(-1)
    lo, hi = np.asarray(lo, dtype=float).reshape(-1), np.asarray(hi, dtype=float).reshape(-1)
    pull = _END_PULL * (t1 - t0)
    starts = np.stack([t0 + pull, t0 + pull, t1 - pull, t1 - pull], axis=1).reshape(-1)
    headings = np.stack([lo, hi, lo, hi], axis=1).reshape(-1)
    hits = cast_from_boundary(env, np.repeat(edges, 4), starts, headings, exact_ties=True)
    corners = hits.points.reshape(-1, 4, 2)
    landed = ((hits.edge >= 0) & np.isfinite(hits.x) & np.isfinite(hits.y)).reshape(-1, 4).all(axis=1)
    ends = np.stack([env.points_at(edges, t0), env.points_at(edges, t1)], axis=1)
    regions: list[np.ndarray | None] = []
    for k in range(len(edges)):
        hull = shapely.MultiPoint(np.vstack([ends[k], corners[k]])).convex_hull if landed[k] else None
        regions.append(np.asarray(hull.exterior.coords)[:-1] if isinstance(hull, shapely.Polygon) else None)
    return regions


def cone_headings(env: Environment, edge: int, cone) -> tuple[float, float]:
    """The headings (radians, CCW from ``edge``) of the two world directions of an exact cone ``(d_lo, d_hi)``."""
    e = env.edge_end[edge] - env.edge_start[edge]
    out = []
    for d in cone:
        dx, dy = float(d[0]), float(d[1])
        out.append(float(np.arctan2(e[0] * dy - e[1] * dx, e[0] * dx + e[1] * dy)))
    return out[0], out[1]
