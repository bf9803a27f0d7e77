"""Convex cells of the free space: exact, strictly convex, covering, with facets shared whole by two cells."""

from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import given, settings

from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError
from solverplan.reflection.cells import decompose_free_space
from tests.strategies import polygons_with_holes, simple_polygons


def _turn(a, b, c):
    return (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])


def _check_decomposition(env: Environment) -> None:
    dec = decompose_free_space(env)
    vertices = set(env.exact_vertices)
    area = Fraction(0)
    sides = {}
    for cell in dec.cells:
        n = len(cell.vertices)
        assert set(cell.vertices) <= vertices  # exact coordinates from the environment's vertices
        assert all(_turn(cell.vertices[i - 1], cell.vertices[i], cell.vertices[(i + 1) % n]) >= 0 for i in range(n))
        area += sum((cell.vertices[i][0] * cell.vertices[(i + 1) % n][1]
                     - cell.vertices[(i + 1) % n][0] * cell.vertices[i][1] for i in range(n)), Fraction(0)) / 2
        for s in cell.sides:
            sides[(s.a, s.b)] = (cell.id, s.neighbour)
    assert area == env.area
    for (a, b), (cid, neighbour) in sides.items():
        if neighbour is None:
            assert (b, a) not in sides  # a wall side is nobody's facet
        else:
            assert sides[(b, a)] == (neighbour, cid)  # a facet is a whole side of both cells
    assert dec.adjacency == tuple(sorted({(min(c, n), max(c, n)) for c, n in sides.values() if n is not None}))


@pytest.mark.parametrize("name", ["square", "l_shape", "one_hole", "two_holes", "degenerate", "spiral", "comb",
                                  "warehouse", "serpentine", "star"])
def test_shipped_models_decompose_into_exact_convex_cells(name):
    _check_decomposition(load_environment(name))


@settings(max_examples=40)
@given(simple_polygons())
def test_convex_decomposition_of_simple_polygons(env):
    _check_decomposition(env)


@settings(max_examples=30)
@given(polygons_with_holes())
def test_convex_decomposition_of_polygons_with_holes(env):
    _check_decomposition(env)


def test_serpentine_cells_are_the_corridor_rectangles_and_corner_triangles():
    dec = decompose_free_space(load_environment("serpentine"))
    sizes = sorted(len(c.vertices) for c in dec.cells)
    assert sizes == [3, 3, 3, 3, 4, 4, 4, 4, 4]  # four cut corners, five straight stretches
    for cell in dec.cells:
        if len(cell.vertices) == 3:  # isosceles right triangles: the two legs are the facets, the hypotenuse a wall
            legs = [s for s in cell.sides if not s.is_wall]
            assert len(legs) == 2 and legs[0].normal[0] * legs[1].normal[0] + legs[0].normal[1] * legs[1].normal[1] == 0
    assert dec.sequence(dec.locate((3, "2.25")), dec.locate((3, "0.25"))) == (4, 2, 1, 0, 3, 7, 6, 5, 8)


def test_locate_rejects_points_outside_and_on_walls():
    dec = decompose_free_space(load_environment("serpentine"))
    with pytest.raises(InputError, match=r"start \(1, 1.75\) is not in the free space of serpentine"):
        dec.locate((1, "1.75"), where="start")
    with pytest.raises(InputError, match="is on a wall"):
        dec.locate((1, 1), where="goal")
    assert dec.locate(("0.25", "1.5")) in (0, 1)  # on a facet: fine


def test_successors_lead_every_cell_to_the_goal_cell():
    dec = decompose_free_space(load_environment("one_hole"))
    nxt = dec.successors(0)
    for cell in range(len(dec.cells)):
        seen = 0
        while nxt[cell] is not None:
            cell, seen = nxt[cell], seen + 1
            assert seen <= len(dec.cells)
        assert cell == 0
