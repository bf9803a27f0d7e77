"""Properties of the tracing on arbitrary occupancy grids (hypothesis, derandomized in CI)."""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction
from pathlib import Path

import numpy as np
import shapely
from hypothesis import example, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from solverplan.errors import InputError
from solverplan.floorplan import OccupancyMap, trace_free_space

# a saddle: free cells meeting only at a corner, inside one component (the outline must not touch itself there)
SADDLE = np.array([[1, 1, 1, 1, 1],
                   [1, 0, 1, 0, 1],
                   [1, 1, 0, 1, 1],
                   [1, 0, 1, 0, 1],
                   [1, 1, 1, 1, 1]], bool)


def _grid(free: np.ndarray, resolution: str) -> OccupancyMap:
    padded = np.pad(free, 1, constant_values=False)
    return OccupancyMap(padded, ~padded, Decimal(resolution), (Fraction(-3, 2), Fraction(7, 4)), 0.0, Path("g.yaml"),
                        Path("g.pgm"))


@settings(max_examples=150)
@given(
    free=arrays(bool, st.tuples(st.integers(2, 24), st.integers(2, 24))),
    resolution=st.sampled_from(["0.05", "0.1", "1"]),
    simplify_cells=st.sampled_from([0, 0.5, 1, 3]),
    rectilinear=st.sampled_from([0, 5, 20]),
    spur=st.booleans(),
)
@example(free=SADDLE, resolution="1", simplify_cells=0, rectilinear=0, spur=False)
@example(free=SADDLE, resolution="0.1", simplify_cells=1, rectilinear=20, spur=False)
def test_every_free_component_traces_to_a_valid_environment_or_one_clear_error(free, resolution, simplify_cells,
                                                                                 rectilinear, spur):
    """Whatever the cells, the import gives a valid environment (the validator ran) that covers the kept
    component's cells up to the simplification, or refuses with an InputError (never another exception)."""
    grid = _grid(free, resolution)
    res = float(resolution)
    try:
        environment, dropped = trace_free_space(grid, simplify=simplify_cells * res, rectilinear=rectilinear,
                                                spur_width=None if spur else 0, min_hole_area=0)
    except InputError as exc:
        assert "no free space" in str(exc) or "narrower than --spur-width" in str(exc)
        return
    traced = environment.to_shapely()
    assert traced.is_valid and traced.area > 0
    if simplify_cells == 0 and rectilinear == 0 and not spur:
        # unsimplified: the outline runs along cell edges, except the corners marching squares cuts (an eighth of
        # a cell each) where it cannot put them back (saddles, features one cell wide): at most one per edge
        from scipy import ndimage

        labels, _ = ndimage.label(grid.free)
        sizes = np.bincount(labels.ravel())
        sizes[0] = 0
        kept = labels == int(np.argmax(sizes))
        edges = int(np.sum(kept[1:] != kept[:-1]) + np.sum(kept[:, 1:] != kept[:, :-1]))
        assert abs(traced.area - kept.sum() * res * res) <= edges * res * res / 8 + 1e-9
