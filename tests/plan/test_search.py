"""Optimality of the planners against brute force, infeasibility reasons, belief-state plans, the Pareto front."""

from __future__ import annotations

from pathlib import Path

import math
from fractions import Fraction

import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st

from solverplan.bounce.bvg import safe_bounce_visibility_graph
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError, InvalidBoundarySet
from solverplan.plan import find_plan, pareto_front, planning_problem
from tests.plan.brute import EPS, admissible, enumerate_plans, start_elements
from tests.strategies import convex_polygons, polygons_with_holes, simple_polygons
from tests.shapes import SQUARE

K = 3

MODELS = Path(__file__).resolve().parents[2] / "solverplan" / "models"


@st.composite
def queries(draw):
    """A small environment, a start set of one or two pieces (on different edges) and a goal edge."""
    env = draw(st.one_of(convex_polygons(max_coord=20), simple_polygons(3, 7, 30), polygons_with_holes(5, 1, 40)))
    n = env.n_edges
    edges = draw(st.lists(st.integers(0, n - 1), min_size=2, max_size=3, unique=True))
    goal_edge = edges[-1]
    pieces = []
    for e in edges[:-1][: draw(st.integers(1, 2))]:
        a = draw(st.sampled_from([Fraction(0), Fraction(1, 4), Fraction(1, 2)]))
        b = draw(st.sampled_from([Fraction(3, 4), Fraction(1)]))
        pieces.append((e, a, b))
    return env, pieces, goal_edge


def _spec(pieces) -> str:
    return ",".join(f"e{e}:{a.numerator}/{a.denominator}:{b.numerator}/{b.denominator}" for e, a, b in pieces)


def _prepared(query):
    """A drawn query as the planners take it: the environment, its safe BVG, the start set and the goal set."""
    env, pieces, goal_edge = query
    return env, safe_bounce_visibility_graph(env), _spec(pieces), f"e{goal_edge}"


@settings(max_examples=60)
@given(queries())
def test_planners_are_optimal_against_brute_force_enumeration(query):
    """fewest, tolerance (with budget and the whole Pareto front), sum and constant, all ≤ K stages."""
    env, pieces, goal_edge = query
    graph = safe_bounce_visibility_graph(env)
    start, parts = start_elements(graph, pieces)  # the start set as given: segments and parts of segments
    goal = set(graph.partition.edge_segments[goal_edge])
    brute = enumerate_plans(admissible(graph, pieces=parts), start, goal, K)
    S, G = _spec(pieces), f"e{goal_edge}"
    event(f"start segments: {min(len(start), 3)}{'+' if len(start) >= 3 else ''}")
    event(f"plans with ≤ {K} stages: {'none' if not brute.plans else 'some'}")
    event(f"Pareto points: {len(brute.front(K))}")

    fewest = find_plan(env, S, G, objective="fewest", graph=graph)
    if brute.fewest() is not None:
        assert fewest.found and fewest.bounces == brute.fewest()
        assert fewest.optimality.proved and fewest.optimality.bound == brute.fewest()
        assert abs(fewest.min_width - brute.best_min_width(brute.fewest())) <= EPS  # ties: the most tolerant
    else:
        assert not fewest.found or fewest.bounces > K

    tolerance = find_plan(env, S, G, objective="tolerance", max_bounces=K, graph=graph)
    front = pareto_front(env, S, G, max_bounces=K, graph=graph)
    expected = brute.front(K)
    assert [(p.bounces, pytest.approx(p.min_width, abs=EPS)) for p in front.points] == expected
    if expected:
        assert tolerance.found
        assert (tolerance.bounces, tolerance.min_width) == (expected[-1][0], pytest.approx(expected[-1][1], abs=EPS))
    else:
        assert not tolerance.found and tolerance.optimality.proved and tolerance.reason

    total = find_plan(env, S, G, objective="sum", max_bounces=K, graph=graph)
    if brute.best_sum() is None:
        assert not total.found
    else:
        assert total.sum_width == pytest.approx(brute.best_sum(), abs=EPS)

    constant = find_plan(env, S, G, objective="constant", max_bounces=K, graph=graph)
    if brute.best_constant() > EPS:
        assert constant.found and constant.min_width == pytest.approx(brute.best_constant(), abs=EPS)
        assert len({s.interval for s in constant.stages}) == 1
    else:
        assert not constant.found and constant.optimality.proved and constant.reason


@settings(max_examples=40)
@given(queries())
def test_unbudgeted_tolerance_is_the_limit_of_the_pareto_front(query):
    """The max-min Dijkstra's W* equals the last point of the complete front; the plan has its fewest bounces."""
    env, graph, S, G = _prepared(query)
    plan = find_plan(env, S, G, objective="tolerance", graph=graph)
    front = pareto_front(env, S, G, graph=graph)
    if not front.points:
        assert not plan.found
        return
    last = front.points[-1]
    assert plan.found and plan.min_width == pytest.approx(last.min_width, abs=EPS)
    assert plan.bounces == last.bounces
    assert plan.optimality.bound == pytest.approx(last.min_width, abs=EPS)


@settings(max_examples=12)
@given(queries())
def test_lp_and_milp_agree_with_the_label_searches(query):
    """sum: LP over path flows (clarabel, duality gap) = DP; tolerance: MILP (HiGHS) = Pareto labels."""
    env, graph, S, G = _prepared(query)
    dp, lp = (find_plan(env, S, G, objective="sum", max_bounces=K, method=m, graph=graph) for m in ("auto", "lp"))
    assert dp.found == lp.found
    if dp.found:
        assert lp.sum_width == pytest.approx(dp.sum_width, abs=1e-7)
        assert lp.optimality.method == "lp-duality" and lp.optimality.proved
        assert 0 <= lp.optimality.gap <= 1e-6 and lp.optimality.bound >= lp.sum_width
    label, milp = (find_plan(env, S, G, objective="tolerance", max_bounces=K, method=m, graph=graph)
                   for m in ("auto", "milp"))
    assert label.found == milp.found
    if label.found:
        # HiGHS decides big-M constraints to its feasibility tolerance (~1e-7): near-ties between paths whose
        # widths differ by less than that may be broken the wrong way
        assert milp.min_width == pytest.approx(label.min_width, abs=1e-6)
        assert milp.optimality.method == "milp" and milp.optimality.proved


# ---------------------------------------------------------------------- shipped models
@pytest.fixture(scope="module")
def two_rooms():
    env = load_environment(MODELS / "two_rooms.json")
    return env, safe_bounce_visibility_graph(env)


def test_two_rooms_pareto_front_is_monotone_and_ends_at_the_max_tolerance_plan(two_rooms):
    env, graph = two_rooms
    front = pareto_front(env, "e0:0.2:0.8", "e4:0.5:1", graph=graph)
    bounces = [p.bounces for p in front.points]
    widths = [p.min_width for p in front.points]
    assert bounces == sorted(set(bounces)) and all(b > a for a, b in zip(widths, widths[1:]))
    assert front.optimality.proved
    best = find_plan(env, "e0:0.2:0.8", "e4:0.5:1", objective="tolerance", graph=graph)
    assert (best.bounces, best.min_width) == (front.points[-1].bounces, pytest.approx(front.points[-1].min_width))
    fewest = find_plan(env, "e0:0.2:0.8", "e4:0.5:1", objective="fewest", graph=graph)
    assert fewest.bounces == front.points[0].bounces
    for point in front.points:  # each point's plan is the most tolerant with that many bounces
        budgeted = find_plan(env, "e0:0.2:0.8", "e4:0.5:1", objective="tolerance", max_bounces=point.bounces, graph=graph)
        assert budgeted.min_width == pytest.approx(point.min_width) and budgeted.bounces == point.bounces
        assert point.plan.min_width == pytest.approx(point.min_width)


def test_options_wider_than_a_threshold_are_exactly_the_wide_options(two_rooms):
    """The bottleneck search's pre-filtered intersection drops only options no wider than its lower bound."""
    from solverplan.plan._search import _options_wider

    env, graph = two_rooms
    problem = planning_problem(env, "e0:0.2:0.8,e9", "e4:0.5:1", graph=graph)
    beliefs = [problem.start_belief] + [o.next for o in problem.options(problem.start_belief)][:20]
    checked = 0
    for b in beliefs:
        every = problem.options(b)
        for threshold in (0.0, 1e-3, 0.02, 0.1):
            expected = sorted((o.lo, o.hi, o.next) for o in every if threshold == 0.0 or o.hi - o.lo > threshold)
            assert sorted((o.lo, o.hi, o.next) for o in _options_wider(problem, b, threshold)) == expected
            checked += len(expected)
    assert checked > 0


def test_belief_state_plan_from_a_start_spanning_segments(two_rooms):
    """e0:0.2:0.8 covers segments 2–5 of e0 — 3 and 4 whole, 2 and 5 in part: one interval must work from every
    point of the start set (conformant plan), and only from those (the parts of 2 and 5 are the sources)."""
    from solverplan.bounce.safe import safe_set

    env, graph = two_rooms
    plan = find_plan(env, "e0:0.2:0.8", "e4:0.5:1", graph=graph)
    first = plan.stages[0]
    assert first.from_segments == (2, 3, 4, 5)
    assert sorted(i for i, _ in first.moves) == [2, 3, 4, 5]
    assert set(first.to_segments) == {j for _, j in first.moves}
    assert (0, Fraction(1, 5), graph.partition.segments[2].t1) in [(p.edge, p.t0, p.t1) for p in first.sources]
    assert min(p.t0 for p in first.sources) == Fraction(1, 5) and max(p.t1 for p in first.sources) == Fraction(4, 5)
    for stage, nxt in zip(plan.stages, plan.stages[1:]):
        assert nxt.from_segments == stage.to_segments
    for stage in plan.stages:  # the interval is inside the exact safe set of every move (from its source piece)
        for k, (i, j) in enumerate(stage.moves):
            if stage.sources:
                p, seg = stage.sources[k], graph.partition.segments[j]
                found = safe_set(env, (env.exact_point_at(p.edge, p.t0), env.exact_point_at(p.edge, p.t1)), (seg.a, seg.b))
            else:
                found = graph.safe_set(i, j)
            assert any(s.lo < stage.interval.lo and stage.interval.hi < s.hi for s in found.intervals)


def test_belief_spanning_the_outer_ring_and_a_hole():
    env = load_environment(MODELS / "one_hole.json")  # edges 0-3: outer ring; 4-7: the hole
    plan = find_plan(env, "e1,e5", "e3", objective="tolerance")
    problem = planning_problem(env, "e1,e5", "e3")
    rings = {problem.user_partition.ring_of_segment(s) for s in plan.stages[0].from_segments}
    assert plan.found and rings == {0, 1} and plan.stages[0].from_segments == problem.user_segments(problem.start_belief)


def test_a_goal_inside_one_segment_is_reached_by_cutting_the_last_interval(two_rooms):
    """e0:0.6:0.8 lies inside segment 5 (e0, t in [0.4, 1]): the last stage lands there, inside the piece."""
    env, graph = two_rooms
    problem = planning_problem(env, "e5", "e0:0.6:0.8", graph=graph)
    assert problem.goal_whole == frozenset() and problem.user_segments(problem.goal_partial) == (5,)
    plan = find_plan(env, "e5", "e0:0.6:0.8", objective="fewest", graph=graph)
    assert plan.found and plan.stages[-1].to_segments == (5,)
    last = plan.stages[-1]
    (source, _), = last.moves
    # the last interval is inside the cone of Prop. 2 with the piece's ends: [ang(g0 − b), ang(g1 − a)]
    seg = graph.partition.segments[source]
    e = (float(seg.b[0] - seg.a[0]), float(seg.b[1] - seg.a[1]))
    g0, g1 = env.point_at(0, 0.6), env.point_at(0, 0.8)

    def ang(w):
        return math.atan2(e[0] * w[1] - e[1] * w[0], e[0] * w[0] + e[1] * w[1])

    assert ang((g0[0] - float(seg.b[0]), g0[1] - float(seg.b[1]))) < last.interval.lo
    assert last.interval.hi < ang((g1[0] - float(seg.a[0]), g1[1] - float(seg.a[1])))


def test_start_inside_the_goal_is_a_plan_with_no_stages():
    plan = find_plan(SQUARE, "e1:0.25:0.5", "e1:0:0.75,e2")
    assert plan.found and plan.bounces == 0 and plan.stages == () and plan.optimality.bound == 0
    assert plan.to_json()["stages"] == []


def test_square_floor_to_ceiling_needs_two_bounces():
    """Prop. 2's parallel case is a single heading, not an executable interval (Cor. 1 gives the rest)."""
    plan = find_plan(SQUARE, "e0", "e2", objective="fewest")
    assert plan.bounces == 2 and [s.moves for s in plan.stages] in ([((0, 1),), ((1, 2),)], [((0, 3),), ((3, 2),)])


# ---------------------------------------------------------------------- infeasible answers
def test_infeasible_goal_without_incoming_safe_arc(two_rooms):
    env, graph = two_rooms  # segment 24 (e5, t in [9/10, 14/15]) has no incoming safe arc (paper Prop. 5)
    plan = find_plan(env, "e0", "e5:9/10:14/15", graph=graph)
    assert plan.status == "infeasible"
    assert plan.reason == "goal segments have no incoming safe arc (segment 24 of P′)"
    assert plan.optimality.proved and plan.bounces is None and plan.min_width is None


def test_infeasible_within_the_budget(two_rooms):
    env, graph = two_rooms
    plan = find_plan(env, "e0", "e4", objective="fewest", max_bounces=2, graph=graph)
    assert plan.status == "infeasible" and plan.reason.startswith("exhausted all plans with ≤ 2 bounces")
    assert find_plan(env, "e0", "e4", objective="fewest", max_bounces=3, graph=graph).bounces == 3


def test_infeasible_constant_strategy_is_proved(two_rooms):
    env, graph = two_rooms
    plan = find_plan(env, "e17,e0", "e4:0.25:1", objective="constant", graph=graph)
    assert plan.status == "infeasible" and plan.reason.startswith("no constant interval survives")
    assert find_plan(env, "e17,e0", "e4:0.25:1", objective="fewest", graph=graph).found


def test_infeasible_after_exhausting_every_reachable_belief():
    env = load_environment(MODELS / "narrow_door.json")
    plan = find_plan(env, "e9:0.1:0.75", "e5:0:0.6", objective="tolerance")
    assert plan.status == "infeasible"
    assert plan.reason.startswith("exhausted all ") and plan.reason.endswith("reachable beliefs: no plan reaches the goal")


def test_infeasible_when_no_interval_works_from_every_start_segment(two_rooms):
    env, graph = two_rooms
    plan = find_plan(env, "e1,e6", "e14", graph=graph, heading_margin=0.5)
    assert plan.reason == ("no heading interval is admissible from every start segment at once (segments 6, 27, 28, 29): "
                           "a belief-state plan cannot even begin")
    # every common interval turns the whole boundary into itself (the beliefs differ only in the corners the
    # robot may have just arrived near)
    square = find_plan(SQUARE, "e0,e1,e2,e3", "e1")
    assert square.reason == "exhausted all 3 reachable beliefs: no plan reaches the goal"


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"objective": "fastest"}, r"^unknown objective 'fastest': use fewest, tolerance, sum, constant$"),
        ({"objective": "sum"}, r"^objective 'sum' needs max_bounces \(--max-bounces K\): every extra stage adds width$"),
        ({"objective": "fewest", "method": "lp"}, r"^unknown method 'lp' for objective 'fewest': use auto, bfs$"),
        ({"max_bounces": 0}, r"^max_bounces must be an integer in \[1, 10,000,000\], got 0$"),
        ({"objective": "tolerance", "method": "milp"}, r"^method 'milp' needs max_bounces"),
    ],
)
def test_bad_arguments_are_input_errors(kwargs, message):
    with pytest.raises(InputError, match=message):
        find_plan(SQUARE, "e0", "e2", **kwargs)


def test_bad_boundary_sets_are_reported():
    with pytest.raises(InvalidBoundarySet, match=r"^unknown edge e9: edges are e0..e3$"):
        find_plan(SQUARE, "e9", "e2")
    with pytest.raises(InvalidBoundarySet, match="malformed"):
        find_plan(SQUARE, "e0", "edge two")


def test_heading_margin_bounds_every_interval():
    plan = find_plan(SQUARE, "e0", "e1", objective="tolerance", heading_margin=0.05)
    assert plan.stages[0].interval.lo == pytest.approx(0.05) and plan.to_json()["margins"]["heading"] == 0.05
    assert all(0.05 <= s.interval.lo and s.interval.hi <= math.pi - 0.05 for s in plan.stages)


@st.composite
def interval_lists(draw):
    """2–4 sources, each a sorted list of disjoint intervals with targets."""
    lists = []
    for _ in range(draw(st.integers(2, 4))):
        cuts = sorted(draw(st.lists(st.integers(1, 60), min_size=0, max_size=10, unique=True)))
        los, his, tgts = [], [], []
        for a, b in zip(cuts[::2], cuts[1::2]):
            los.append(a / 20)
            his.append(b / 20)
            tgts.append(draw(st.integers(0, 5)))
        lists.append((los, his, tgts))
    return lists


def _every_choice(belief, lists) -> list:
    """(lo, hi, moves) of every choice of one interval per source with a common interval of positive width, sorted."""
    import itertools

    out = []
    for combo in itertools.product(*[range(len(l[0])) for l in lists]):
        lo = max(lists[q][0][k] for q, k in enumerate(combo))
        hi = min(lists[q][1][k] for q, k in enumerate(combo))
        if hi > lo:
            out.append((lo, hi, tuple((belief[q], lists[q][2][k]) for q, k in enumerate(combo))))
    return sorted(out)


@given(interval_lists())
def test_options_are_exactly_the_cells_where_every_source_has_an_interval(lists):
    """Problem._combine (a merge) against the product of one interval per source (brute force)."""
    from solverplan.plan._problem import Problem

    belief = tuple(range(10, 10 + len(lists)))
    got = sorted((o.lo, o.hi, o.moves) for o in Problem._combine(belief, lists))
    assert got == _every_choice(belief, lists)
    for o in Problem._combine(belief, lists):
        assert o.next == tuple(sorted({j for _, j in o.moves}))


@st.composite
def overlapping_interval_lists(draw):
    """2–4 sources, each a list of intervals sorted by low ends that may overlap (landings on units inside the
    landing on their segment), with targets."""
    lists = []
    for _ in range(draw(st.integers(2, 4))):
        pairs = draw(st.lists(st.tuples(st.integers(0, 59), st.integers(1, 20)), max_size=8))
        rows = sorted((a / 20, min(a + w, 60) / 20, draw(st.integers(0, 5))) for a, w in pairs)
        lists.append(([r[0] for r in rows], [r[1] for r in rows], [r[2] for r in rows]))
    return lists


@given(overlapping_interval_lists())
def test_options_over_overlapping_lists_are_every_undominated_choice(lists):
    """Problem._combine with overlapping lists against the product of one interval per source (brute force): every
    option is a choice of intervals with a common interval of positive width; every such choice has an option with
    the same next belief whose interval holds its own (rule (a): nothing is lost); and no option's interval holds
    another's with the same next belief (the dominated ones are gone)."""
    from solverplan.plan._problem import Problem

    belief = tuple(range(10, 10 + len(lists)))
    options = Problem._combine(belief, lists)
    every = _every_choice(belief, lists)
    assert {(o.lo, o.hi, o.moves) for o in options} <= set(every)
    for lo, hi, moves in every:
        nxt = tuple(sorted({j for _, j in moves}))
        assert any(o.next == nxt and o.lo <= lo and hi <= o.hi for o in options)
    for o in options:
        assert o.next == tuple(sorted({j for _, j in o.moves}))
        assert not any(p is not o and p.next == o.next and p.lo <= o.lo and o.hi <= p.hi for p in options)


def _cut_sources(k: int, shift: float):
    """k sources that each land at headings [0.2, 2.8] on segment 5 and, at a narrower interval shifted by
    ``shift`` per source, inside a piece of it (element 100); finer(100, 5)."""
    lists = []
    for i in range(k):
        lo, hi = 0.6 + shift * i, 2.0 + shift * i
        lists.append(([0.2, lo], [2.8, hi], [5, 100]))
    return lists


@pytest.mark.parametrize("shift", [0.0, 0.001])
def test_options_of_many_cut_sources_do_not_multiply(shift):
    """Issue #24: 200 sources whose landings may end on a piece or on its whole segment gave 2^200 choices at one
    heading (refused past 200,000). Now the dominated ones are dropped as they arise: the options are the whole
    segment over the common interval, the piece over the intersection of the pieces' intervals, and mixtures only
    where one source's piece interval is not held by the others' — checked against brute force for 8 sources."""
    import time

    from solverplan.plan._problem import Problem

    finer = lambda a, b: a == 100 and b == 5  # noqa: E731
    t0 = time.process_time()
    options = Problem._combine(tuple(range(200)), _cut_sources(200, shift), finer=finer)
    assert time.process_time() - t0 < 2.0
    nexts = {o.next for o in options}
    assert (5,) in nexts and ((100,) in nexts) == (shift * 199 < 1.4)
    widest = {nxt: max(o.hi - o.lo for o in options if o.next == nxt) for nxt in nexts}
    assert widest[(5,)] == pytest.approx(2.6)
    assert len(options) <= 2 * 200 + 2
    belief = tuple(range(8))
    lists = _cut_sources(8, shift)
    options = Problem._combine(belief, lists, finer=finer)
    for lo, hi, moves in _every_choice(belief, lists):
        nxt = tuple(sorted({j for _, j in moves}))
        # every choice is matched by an option with an interval as wide and a next belief no larger (a piece for
        # its segment: the belief the robot is in is smaller)
        assert any(o.lo <= lo and hi <= o.hi and set(o.next) <= set(nxt) | {100}
                   and (5 not in o.next or 5 in nxt) for o in options), (lo, hi, nxt)
    if shift == 0.0:  # every piece interval is the same: at its headings every source lands on the piece
        assert sorted((o.lo, o.hi, o.next) for o in options) == [(0.2, 2.8, (5,)), (0.6, 2.0, (100,))]


def test_choices_that_still_blow_up_are_refused_in_one_line(monkeypatch):
    """The guard that is left: when the undominated choices of a belief still exceed the entries it may hold (here
    lowered to 1,000: 16 sources with two overlapping intervals of distinct targets each, no piece finer than any,
    have 2^16), the query is refused with one line, not a memory error."""
    from solverplan.plan import _problem
    from solverplan.plan._problem import Problem

    monkeypatch.setattr(_problem, "MAX_JOINED_ENTRIES", 1_000)
    lists = [([0.0, 1.0], [2.0, 3.0], [2 * q, 2 * q + 1]) for q in range(16)]
    with pytest.raises(InputError, match=r"^a belief of 16 segments of P′ has [0-9,]+ undominated ways to leave it") as err:
        Problem._combine(tuple(range(16)), lists, finer=lambda a, b: False)
    assert "\n" not in str(err.value)


def test_a_query_whose_landing_options_multiplied_is_answered():
    """Issue #24: on this polygon with holes (an invariance-study draw) a belief of 22 sources had more than 200,000
    choices of landing on a piece or on its whole segment at one heading, and every objective was refused; with
    the dominated choices dropped each answers at once, proved."""
    from solverplan.generators import star_polygon_with_holes

    env = star_polygon_with_holes(6, 2, seed=752531, radius=10.0, decimals=3)
    start, goal = "e4:0.8:1,e5:0:0.85", "e2:0.5:1,e3:0:0.9"
    plans = {o: find_plan(env, start, goal, objective=o, max_bounces=4) for o in ("fewest", "tolerance", "sum")}
    assert all(p.found and p.optimality.proved for p in plans.values())
    assert plans["fewest"].bounces == plans["tolerance"].bounces == 2
    assert plans["tolerance"].min_width == pytest.approx(0.0553346943, abs=1e-9)
    assert plans["sum"].bounces == 4 and plans["sum"].sum_width == pytest.approx(0.33845488, abs=1e-7)


def test_an_arc_listed_twice_is_one_interval():
    """Issue #24: the graph built on demand listed some arcs two or three times; each copy was an interval of its own,
    a source's list overlapped itself and the options of a belief doubled with every such source. The problem
    reads a row listed twice once: its options are those of the graph listing it once."""
    from solverplan.bounce.bvg.build import _concat_rows
    from solverplan.plan._problem import Problem

    env = load_environment("two_rooms")
    once = planning_problem(env, "e0", "e4")
    twice = Problem(_concat_rows(once.partition, [once.graph, once.graph]), once.user_start_set, once.user_goal_set,
                    margins=once.margins, walls=once.walls)
    assert twice.graph.n_arcs == 2 * once.graph.n_arcs and twice.n_admissible == once.n_admissible
    for belief in (once.start_belief, *{o.next for o in once.options(once.start_belief)}):
        assert twice.options(belief) == once.options(belief)


QUERY_CUTS = [("l_shape", "e3:0.15:1,e4:0:0.25", "e3:0.4:1,e4:0:0.05"), ("two_rooms", "e0:0.2:0.8", "e4:0.5:1"),
              ("hallway", "e8:0.28:1", "e9:0.51:1"), ("three_arms", "e3:0.15:1,e4:0:0.25", "e3:0.4:1,e4:0:0.05"),
              ("narrow_door", "e3:0.15:1,e4:0:0.25", "e3:0.4:1,e4:0:0.05")]


@pytest.mark.parametrize("name, start, goal", QUERY_CUTS)
def test_landing_units_only_add_plans(name, start, goal):
    """Landing on the pieces between the query's set ends keeps every whole-segment landing open: the fewest stages
    never grow and the widest min width never shrinks against the search with whole-segment landings only (the
    class before #22's last gap), here within 4 bounces, and the objectives agree on the abstraction."""
    from solverplan.plan import _search
    from solverplan.plan._problem import Problem

    env = load_environment(name)
    units = planning_problem(env, start, goal)
    whole = Problem(units.graph, units.user_start_set, units.user_goal_set, margins=units.margins, walls=units.walls,
                    landing_units=False)
    assert units.units and len(whole.units) <= len(units.units)
    new, old = _search.layered_front(units, 4), _search.layered_front(whole, 4)
    if old.points:
        assert new.points and new.points[0][0] <= old.points[0][0]
        assert max(w for _, w, _ in new.points) >= max(w for _, w, _ in old.points) - EPS
    plans = {o: find_plan(env, start, goal, objective=o, max_bounces=4) for o in ("fewest", "tolerance", "sum")}
    if new.points:
        assert plans["fewest"].bounces == new.points[0][0]
        assert plans["tolerance"].min_width == pytest.approx(max(w for _, w, _ in new.points), abs=1e-12)
        assert plans["sum"].found
    else:
        assert not any(p.found for p in plans.values())


@settings(max_examples=40)
@given(queries())
def test_start_pieces_are_never_worse_than_their_whole_segments(query):
    """A plan that works from whole segments works from every part of them: answering the start set as given
    (start pieces, with their own safe sets) never needs more bounces nor gives a narrower optimum than the same
    query with the start set grown to the whole segments it touches — and it can do better."""
    env, graph, S, G = _prepared(query)
    pieces = query[1]
    touched = sorted({s.id for s in graph.partition.segments for e, a, b in pieces
                      if s.edge == e and s.t0 < b and a < s.t1})
    segs = graph.partition.segments
    grown = ",".join(f"e{segs[k].edge}:{segs[k].t0}:{segs[k].t1}" for k in touched)
    for objective in ("fewest", "tolerance"):
        exact = find_plan(env, S, G, objective=objective, max_bounces=K, graph=graph)
        whole = find_plan(env, grown, G, objective=objective, max_bounces=K, graph=graph)
        if whole.found:
            assert exact.found
            if objective == "fewest":
                assert exact.bounces <= whole.bounces
            else:
                assert exact.min_width >= whole.min_width - EPS


@pytest.mark.parametrize("name", ["two_rooms", "one_hole"])
def test_answers_do_not_change_under_an_exact_rotation(name):
    """A rotation by atan2(4, 3) (exact: rational cosine and sine) and a translation change no answer: the margins
    are scaled by the environment's diameter, not by its bounding box (which a rotation changes: proved optima
    moved by ~1e-6 when they were)."""
    from solverplan.plan.margins import Margins

    env = load_environment(MODELS / f"{name}.json")
    c, s = Fraction(3, 5), Fraction(4, 5)
    turned = Environment(tuple(tuple((c * x - s * y + 7, s * x + c * y - 3) for x, y in ring) for ring in env.rings))
    assert Margins.for_environment(turned).size == pytest.approx(Margins.for_environment(env).size, rel=1e-15)
    start, goal = ("e0:0.2:0.8", "e4:0.5:1") if name == "two_rooms" else ("e0:0.1:0.7", "e2")
    for objective in ("fewest", "tolerance"):
        a = find_plan(env, start, goal, objective=objective)
        b = find_plan(turned, start, goal, objective=objective)
        assert a.found and b.found and a.bounces == b.bounces
        assert b.min_width == pytest.approx(a.min_width, abs=1e-9)


def test_environment_diameter_ignores_collinear_vertices_on_the_hull():
    """A vertex on an edge of the outer ring's hull (here where a set ends, #22's rewriting) once stopped the calipers
    early: 42.202 instead of 42.450, and every margin moved with it."""
    from solverplan.environment import Environment
    from solverplan.plan.margins import environment_diameter

    ring = [[10, 0], [17, 22], [-2, 10], [-24, 12], [-14, -7], [-3, -13], [6, -8]]
    with_vertex = ring[:4] + [[-24 + Fraction(4, 10) * 10, 12 - Fraction(4, 10) * 19]] + ring[4:]
    assert environment_diameter(Environment.from_coords(with_vertex)) == pytest.approx(
        environment_diameter(Environment.from_coords(ring)), rel=1e-14) == pytest.approx(math.hypot(31, 29), rel=1e-14)


def test_environment_diameter_turns_with_a_rectilinear_room():
    """Rotating calipers tied on the parallel hull edges of a rectilinear room and stopped at another vertex once it
    was turned (17.692 × 551/7 ≠ 1229.556): the invariance study's one remaining change under a motion (min width
    0.4624116894 → 0.462439313)."""
    from solverplan.generators import rectilinear_polygon
    from solverplan.plan.margins import environment_diameter
    from solverplan.studies import rewrite as rw

    env = rectilinear_polygon(n_cells=4, max_size=6, seed=473979)
    moved = rw.rotate(env, Fraction(8, 17), Fraction(15, 17)).then(rw.translate, Fraction(-5, 7), -9).then(
        rw.scale, Fraction(551, 7))
    assert environment_diameter(moved.env) == pytest.approx(environment_diameter(env) * 551 / 7, rel=1e-13)


@settings(max_examples=60)
@given(st.one_of(convex_polygons(max_coord=20), simple_polygons(3, 9, 30), polygons_with_holes(5, 1, 40)))
def test_environment_diameter_is_the_largest_distance_between_two_vertices(env):
    """The margins' diameter (every pair of hull corners) against every pair of vertices (the brute-force reference)."""
    from solverplan.plan.margins import environment_diameter
    from tests.plan.brute import diameter

    assert environment_diameter(env) == pytest.approx(diameter(env), rel=1e-12)


def test_a_plan_that_needs_the_set_ends_as_cut_points_is_found():
    """l_shape, --from e3:0.15:1,e4:0:0.25 --to e3:0.4:1,e4:0:0.05: a 4-bounce plan of min width 0.0292 exists
    (found on the same free space written with vertices where the sets end; 20,000 of 20,000 rollouts with
    endpoint headings reach the goal)."""
    env = load_environment("l_shape")
    plan = find_plan(env, "e3:0.15:1,e4:0:0.25", "e3:0.4:1,e4:0:0.05", objective="tolerance", max_bounces=4)
    assert plan.found and plan.bounces == 4 and plan.min_width >= 0.029 and plan.optimality.proved
    # a later stage leaves from the part of e3 above the goal set's end: the certificate claims exact images
    assert any(stage.sources for stage in plan.stages[1:])
    from solverplan.certify import certificate, check_certificate

    cert = certificate(plan, env=env)
    assert cert.bound is not None and check_certificate(cert).valid


# ---------------------------------------------------------------------- piece monotonicity (proofs/piece_monotonicity)
@st.composite
def piece_queries(draw):
    """A small environment, a start edge with a piece of it (ends at twentieths, inside the edge) and a goal edge."""
    env = draw(st.one_of(convex_polygons(max_coord=20), simple_polygons(3, 7, 30), polygons_with_holes(5, 1, 40)))
    start, goal = draw(st.lists(st.integers(0, env.n_edges - 1), min_size=2, max_size=2, unique=True))
    a = draw(st.integers(0, 18))
    b = draw(st.integers(a + 1, 20))
    if (a, b) == (0, 20):
        a = 1
    return env, start, (Fraction(a, 20), Fraction(b, 20)), goal


@settings(max_examples=30)
@given(piece_queries())
def test_piece_monotonicity_a_piece_has_every_admissible_interval_of_its_segment(query):
    """proofs/piece_monotonicity, in floats: the admissible intervals a piece gets from its own exact safe sets and
    cones (before :func:`~solverplan.plan._problem._holding`) hold every admissible interval of its segment with the
    same target, to 10⁻¹² rad (what the float ends of exact values can differ by); ``_holding`` only closes that."""
    from solverplan.plan._problem import _point_on

    env, start, (a, b), goal = query
    problem = planning_problem(env, f"e{start}:{float(a)}:{float(b)}", f"e{goal}")
    for u, unit in enumerate(problem.units):
        los, his, tgts, dives = problem._piece_intervals(problem.unit_code(u), unit)
        rows = list(zip(los, his, tgts, dives))
        rows += problem._landings(unit.a, unit.b, problem.partition.segments[unit.host], rows)
        host = problem.intervals(unit.host)
        for lo, hi, code in zip(*host):
            assert any(c == code and l2 <= lo + 1e-12 and hi - 1e-12 <= h2 for l2, h2, c, _ in rows), (u, lo, hi, code)
        # and the rows the search reads hold them exactly
        held = problem.intervals(problem.unit_code(u))
        for lo, hi, code in zip(*host):
            assert any(c == code and l2 <= lo and hi <= h2 for l2, h2, c in zip(*held))
        assert _point_on(problem.partition.segments[unit.host], unit.piece.t0) == unit.a


@settings(max_examples=30)
@given(piece_queries())
def test_piece_monotonicity_a_plan_from_the_whole_edge_works_from_a_piece(query):
    """proofs/piece_monotonicity, end to end: a start set inside another is never worse — the fewest bounces from a
    piece of an edge are at most those from the whole edge, its widest min width at least as wide (within 3
    bounces), as the dominance of :meth:`~solverplan.plan._problem.Problem._combine` requires of the search."""
    env, start, (a, b), goal = query
    piece, whole = f"e{start}:{float(a)}:{float(b)}", f"e{start}"
    big = find_plan(env, whole, f"e{goal}", objective="tolerance", max_bounces=3)
    if not big.found:
        event("no plan from the whole edge")
        return
    small = find_plan(env, piece, f"e{goal}", objective="tolerance", max_bounces=3)
    assert small.found and small.min_width >= big.min_width - 1e-12
    assert find_plan(env, piece, f"e{goal}", objective="fewest", max_bounces=3).bounces <= find_plan(
        env, whole, f"e{goal}", objective="fewest", max_bounces=3).bounces
