"""The geometry kernel: exact ray casting (scalar and vectorised batch) and visibility.

Imports only :mod:`solverplan.exact`, :mod:`solverplan.environment` and :mod:`solverplan.errors`.
"""

from solverplan.geometry.raycast import (
    RayCaster,
    RayHit,
    RayHits,
    cast_from_boundary,
    cast_ray,
    cast_rays,
    cast_rays_exact,
    heading_directions,
    ray_caster,
)
from solverplan.geometry.visibility import (
    Segment,
    VisibilityPiece,
    VisibilityPolygon,
    is_entirely_visible,
    segments_see_each_other,
    sees,
    visibility_polygon,
)

__all__ = [
    "RayCaster",
    "RayHit",
    "RayHits",
    "cast_from_boundary",
    "cast_ray",
    "cast_rays",
    "cast_rays_exact",
    "heading_directions",
    "ray_caster",
    "Segment",
    "VisibilityPiece",
    "VisibilityPolygon",
    "is_entirely_visible",
    "segments_see_each_other",
    "sees",
    "visibility_polygon",
]
