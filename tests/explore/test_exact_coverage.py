"""Algorithm B's stop test (Theorem 4, Step 8) is exact: never ``found`` while some of the free space is unseen.

Issue #26: a room with a needle 1e-8 wide and 4 long was reported fully explored (the needle's area is below the
float sliver tolerance). The property: whenever Algorithm B answers ``found``, every point of the free space we
sample on the needle's axis lies in some view (exact ``RangeView.contains``), and every vertex too.
"""

from __future__ import annotations

from fractions import Fraction as F

from hypothesis import example, given, settings
from hypothesis import strategies as st

from solverplan.environment import Environment
from solverplan.explore import explore_range_limited


def needle_room(side: int, at: F, width: F, length: F, *, wall: str = "top") -> Environment:
    """A side × side square with a needle (an isosceles spike of the given mouth width and length) on one wall."""
    s = F(side)
    if wall == "top":
        ring = [(0, 0), (s, 0), (s, s), (at + width, s), (at + width / 2, s + length), (at, s), (0, s)]
    else:  # right wall, the needle pointing east
        ring = [(0, 0), (s, 0), (s, at), (s + length, at + width / 2), (s, at + width), (s, s), (0, s)]
    return Environment.from_coords([[F(x), F(y)] for x, y in ring])


def _axis_points(env: Environment, wall: str, side: int, at: F, width: F, length: F) -> list[tuple[F, F]]:
    steps = [F(k, 8) for k in range(1, 9)]
    if wall == "top":
        return [(at + width / 2, side + t * length * (1 - F(1, 10**6))) for t in steps]
    return [(side + t * length * (1 - F(1, 10**6)), at + width / 2) for t in steps]


def test_issue26_needle_1e8_wide_is_not_reported_explored():
    width, length = F(1, 10**8), F(4)
    env = needle_room(10, F(5), width, length)
    run = explore_range_limited(env, (5, 5), 3)
    tip = (F(5) + width / 2, F(14))
    assert not any(v.contains(tip) for v in run.views)
    assert run.status.value == "not-found"
    assert 4 in run.unseen_vertices  # the needle's tip
    assert run.to_json()["unseen_vertices"] == list(run.unseen_vertices)
    assert any(p.witness is None or not any(v.contains(p.witness) for v in run.views) for p in run.uncovered)


@given(at=st.integers(2, 8), width_exp=st.integers(3, 12), length=st.integers(1, 5), wall=st.sampled_from(["top", "right"]),
       range_=st.sampled_from([2, 3, 5]))
@settings(max_examples=20)
@example(at=5, width_exp=8, length=4, wall="top", range_=3)
@example(at=5, width_exp=8, length=4, wall="right", range_=3)
def test_theorem4_found_means_every_point_of_a_needle_is_seen(at, width_exp, length, wall, range_):
    width = F(1, 10**width_exp)
    env = needle_room(10, F(at), width, F(length), wall=wall)
    run = explore_range_limited(env, (5, 5), range_)
    if run.status.value == "found":
        for q in _axis_points(env, wall, 10, F(at), width, F(length)):
            assert any(v.contains(q) for v in run.views), q
        verts = env.exact_vertices
        assert all(any(v.contains(verts[k]) for v in run.views) for k in range(env.n_vertices))
    else:
        assert run.uncovered or run.unseen_vertices  # not-found says what is left


def test_found_runs_list_nothing_uncovered():
    square = Environment.from_coords([[0, 0], [8, 0], [8, 8], [0, 8]])
    run = explore_range_limited(square, (4, 4), 3)
    assert run.status.value == "found" and run.uncovered == () and run.unseen_vertices == ()
