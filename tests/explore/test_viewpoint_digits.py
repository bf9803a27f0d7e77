"""Chained viewpoints keep short exact coordinates (end-to-end seed 12: a 308-vertex map with holes exited 2,
its 41st viewpoint having a 454-digit denominator, past the documented input resolution, after 90 s of work)."""

from __future__ import annotations

from fractions import Fraction

import solverplan as sp
from solverplan.explore.window import Window, point_on_part
from solverplan.generators import rooms_and_corridors


def test_a_chain_of_viewpoints_grows_by_a_few_digits_a_step():
    env = rooms_and_corridors(8, seed=3)
    v = env.exact_vertices
    run = sp.explore_depth_first(env, ((v[0][0] + v[1][0] + v[2][0]) / 3, (v[0][1] + v[1][1] + v[2][1]) / 3),
                                 choice="random", seed=2)
    assert run.status.value == "found" and len(run.viewpoints) >= 8
    digits = max(len(str(c.denominator)) for p in run.viewpoints for c in p)
    assert digits <= 12, digits  # the window-parameter rule reached 37 digits here


def test_the_point_on_a_window_lies_on_its_unexplored_part_and_moves_with_the_room():
    # a window from the reflex vertex u = (2, 1) away from the viewpoint p = (0, 0), hitting a wall at u' = (6, 3)
    p, u, far = (Fraction(0), Fraction(0)), (Fraction(2), Fraction(1)), (Fraction(6), Fraction(3))
    part = (Fraction(1, 4), Fraction(3, 4))
    for a, b, lam_part in [(u, far, part), (far, u, (1 - part[1], 1 - part[0]))]:  # either ring direction
        z = point_on_part(Window(a, b, 0, 0), lam_part, p)
        lam = (z[0] - a[0]) / (b[0] - a[0])
        assert (z[0] - a[0]) * (b[1] - a[1]) == (z[1] - a[1]) * (b[0] - a[0])  # on the window's line
        third = (lam_part[1] - lam_part[0]) / 3
        assert lam_part[0] + third <= lam <= lam_part[1] - third  # in the middle third of the part
    # moved, turned by a right angle and scaled by 3: the image of the same point
    move = lambda q: (3 * -q[1] + 7, 3 * q[0] - 5)  # noqa: E731
    z = point_on_part(Window(u, far, 0, 0), part, p)
    assert point_on_part(Window(move(u), move(far), 0, 0), part, move(p)) == move(z)
