"""The seeded generator of random simple rectilinear polygons (the test bed of the rooms decomposition)."""

from __future__ import annotations

import pytest

from solverplan.errors import InputError
from solverplan.generators import generate, rectilinear_polygon


@pytest.mark.parametrize("seed", range(40))
def test_polygons_are_simple_rectilinear_integer_and_without_collinear_vertices(seed):
    env = rectilinear_polygon(1 + seed % 30, seed=seed, max_size=1 + seed % 6)
    ring = env.outer
    assert env.holes == () and not any(env.reoriented[1:])
    edges = list(zip(ring, ring[1:] + ring[:1]))
    assert all(a[0] == b[0] or a[1] == b[1] for a, b in edges)
    assert all(x.denominator == 1 for p in ring for x in p)
    # consecutive edges turn (alternate horizontal and vertical): no collinear vertices
    assert all((a[0] == b[0]) != (b[0] == c[0]) for (a, b), (_, c) in zip(edges, edges[1:] + edges[:1]))
    assert len(env.reflex_vertices) == (len(ring) - 4) // 2  # a rectilinear polygon has r = (n − 4)/2 reflex vertices


def test_one_cell_is_a_rectangle_and_seeds_reproduce():
    assert rectilinear_polygon(1, seed=3).n_vertices == 4
    assert rectilinear_polygon(15, seed=9) == rectilinear_polygon(15, seed=9) != rectilinear_polygon(15, seed=10)
    assert generate("polyomino", n_cells=15, seed=9) == rectilinear_polygon(15, seed=9)


def test_area_is_the_sum_of_the_cells_and_grows_with_their_number():
    small, large = rectilinear_polygon(3, seed=1, max_size=1), rectilinear_polygon(30, seed=1, max_size=1)
    assert (small.area, large.area) == (3, 30)  # unit cells: the area counts them


def test_bad_parameters_are_one_line_errors():
    with pytest.raises(InputError, match=r"n_cells"):
        rectilinear_polygon(0, seed=1)
    with pytest.raises(InputError, match=r"^a 2 x 2 grid holds fewer than n_cells = 5 cells$"):
        rectilinear_polygon(5, seed=1, grid=2)
