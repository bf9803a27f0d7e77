"""Collinear vertices never change an answer: the planner searches the straight walls (collinear vertices merged)
and answers in the user's edge and segment ids; the answers replay, and their certificates verify."""

from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan import models
from solverplan.bounce.partitions import partition
from solverplan.certify.build import certificate
from solverplan.certify.check import check_certificate
from solverplan.certify.schema import Certificate
from solverplan.environment import BoundarySet, Environment
from solverplan.plan.funnels import funnel
from solverplan.plan.localization import localize
from solverplan.plan.patrols import patrol
from solverplan.plan.search import find_plan, pareto_front
from solverplan.plan._walls import PartitionedWalls, collinear_vertices
from solverplan.result import Method, Status
from solverplan.simulate import StagePolicy, simulate_plan, simulate_policy


def with_points(env: Environment, inserts: dict[int, list[Fraction]]) -> tuple[Environment, list[list[int]]]:
    """``env`` with collinear vertices inserted: at the fractions ``inserts[k]`` (in (0, 1)) of edge k. Returns
    the new environment and, for every old edge, its new edges in order."""
    rings, new_of = [], []
    edge = count = 0
    for ring in env.rings:
        out = []
        for i, a in enumerate(ring):
            b = ring[(i + 1) % len(ring)]
            out.append(a)
            fracs = sorted(set(inserts.get(edge, ())))
            out.extend(tuple(a[c] + f * (b[c] - a[c]) for c in range(2)) for f in fracs)
            new_of.append(list(range(count, count + len(fracs) + 1)))
            count += len(fracs) + 1
            edge += 1
        rings.append(tuple(out))
    return Environment(tuple(rings), name=env.name, reoriented=env.reoriented), new_of


def midpoints(env: Environment) -> tuple[Environment, list[list[int]]]:
    """Every edge's midpoint inserted: edge k becomes edges 2k, 2k + 1."""
    return with_points(env, {k: [Fraction(1, 2)] for k in range(env.n_edges)})


def edges_text(edges) -> str:
    return ",".join(f"e{e}" for e in edges)


def same(plan, other) -> None:
    assert plan.status == other.status
    assert plan.bounces == other.bounces
    if plan.found:
        assert abs(plan.min_width - other.min_width) <= 1e-12
        assert abs(plan.sum_width - other.sum_width) <= 1e-12


def sound(env: Environment, plan) -> None:
    """The plan's certificate verifies exactly and its rollouts all reach the goal."""
    report = check_certificate(certificate(plan, env=env))
    assert report.valid, [str(f) for f in report.failures]
    runs = simulate_plan(env, plan, trials=300, seed=7, sampling="endpoints")
    assert runs.success_rate == 1.0


def test_walls_of_a_split_square_are_the_square():
    square = models.load("square")
    split, new_of = midpoints(square)
    walls = PartitionedWalls(split)
    assert not walls.identity and collinear_vertices(split) == (1, 3, 5, 7)
    assert walls.merged.rings == square.rings
    assert walls.edge_map[3] == (1, Fraction(1, 2), Fraction(1))
    assert str(walls.to_merged(split.boundary_set("e0,e1:0:0.5"))) == "e0:0:0.75"
    assert PartitionedWalls(square).identity and PartitionedWalls(square).merged is square
    runs = walls.runs(partition(square))
    assert runs == ((0, 1), (2, 3), (4, 5), (6, 7))


CASES = [("irregular_convex", 0, 3), ("hexagon", 1, 4), ("l_shape", 0, 3), ("one_hole", 0, 2), ("one_hole", 4, 1)]


@pytest.mark.parametrize("objective", ["fewest", "tolerance"])
@pytest.mark.parametrize("name, start, goal", CASES)
def test_midpoint_split_keeps_the_optimum(name, start, goal, objective):
    env = models.load(name)
    split, new_of = midpoints(env)
    plan = find_plan(env, f"e{start}", f"e{goal}", objective=objective)
    again = find_plan(split, edges_text(new_of[start]), edges_text(new_of[goal]), objective=objective)
    same(plan, again)
    assert again.optimality.proved and "collinear vertices merged" in again.optimality.scope
    assert again.environment.matches(split) and again.start == "e" + ",e".join(map(str, new_of[start]))
    if again.found:
        sound(split, again)


def test_midpoint_split_goal_on_half_a_wall_is_sound():
    """A goal on one half of a wall: the last stage is cut to land inside it; the certificate claims images."""
    split, new_of = midpoints(models.load("irregular_convex"))
    plan = find_plan(split, edges_text(new_of[0]), f"e{new_of[3][1]}", objective="tolerance")
    assert plan.found and set(plan.stages[-1].to_segments) <= set(
        s.id for s in partition(split).segments
        if s.edge == new_of[3][1])
    sound(split, plan)


def test_fifty_collinear_vertices_on_one_wall():
    env = models.load("irregular_convex")
    wall, new_of = with_points(env, {0: [Fraction(i, 51) for i in range(1, 51)]})
    assert len(collinear_vertices(wall)) == 50
    for start, goal in ((0, 3), (3, 0), (0, 2)):
        plan = find_plan(env, f"e{start}", f"e{goal}", objective="fewest")
        again = find_plan(wall, edges_text(new_of[start]), edges_text(new_of[goal]), objective="fewest")
        same(plan, again)
        sound(wall, again)
    # a stage landing on the wall lists every segment of the run it lands on
    plan = find_plan(wall, edges_text(new_of[3]), edges_text(new_of[0]), objective="fewest")
    assert len(plan.stages[-1].to_segments) >= 51


def test_pareto_front_on_a_split_polygon():
    env = models.load("l_shape")
    split, new_of = midpoints(env)
    front = pareto_front(env, "e5", "e0:0:0.3")
    again = pareto_front(split, edges_text(new_of[5]), "e0:0:0.6")
    assert [(p.bounces, round(p.min_width, 12)) for p in front.points] == \
        [(p.bounces, round(p.min_width, 12)) for p in again.points]


def test_patrol_on_a_split_square():
    """Patrols search the straight walls, cut where a visited edge ends inside a wall (their scope says so): a visit
    of a half means landing on that half; on the split square the optimal cycle lands on the visited halves, so the
    answer is the same."""
    square = models.load("square")
    split, new_of = midpoints(square)
    p = patrol(square, "e0,e1,e2,e3", tolerance=0.05, objective="contraction")
    q = patrol(split, ",".join(f"e{new_of[k][0]}" for k in range(4)), tolerance=0.05, objective="contraction")
    assert p.found and q.found and abs(p.contraction - q.contraction) <= 1e-12
    assert "cut where a visited edge ends inside a wall" in q.optimality.scope
    assert all(len(st.from_segments) == 1 for st in q.cycle)  # every stage leaves from one half (a user segment)


def test_the_checker_bounds_a_wall_landing_by_the_wall():
    """A move without a named segment lands on the straight wall through its target edge, and no further."""
    split, new_of = midpoints(models.load("irregular_convex"))
    plan = find_plan(split, edges_text(new_of[0]), edges_text(new_of[3]), objective="tolerance")
    cert = certificate(plan, env=split)
    data = cert.to_json()
    runs = [(k, m) for k, st_ in enumerate(data["stages"]) for m, mv in enumerate(st_["moves"]) if "target_segment" not in mv]
    assert runs, "the plan lands on a run of collinear segments somewhere"
    k, m = runs[0]
    move = data["stages"][k]["moves"][m]
    hi = Fraction(move["target"][1])
    assert hi > 1  # past the collinear vertex, in the first edge's parameter
    move["target"] = [move["target"][0], "3"]   # beyond the wall's far end (t = 2 on the first edge)
    report = check_certificate(Certificate.from_json(data))
    assert not report.valid
    assert any("straight wall through edge" in f.message for f in report.failures)


MODELS = ["square", "triangle", "irregular_convex", "hexagon", "l_shape", "one_hole"]


@st.composite
def collinear_queries(draw, names: list[str]):
    """A shipped model, the same walls with 1 to 3 collinear points inserted on 1 to 3 of its edges, what became of
    each old edge (``new_of``) and a start and a goal edge (distinct, in the old numbering)."""
    env = models.load(draw(st.sampled_from(names), label="model"))
    n = env.n_edges
    chosen = draw(st.lists(st.integers(0, n - 1), min_size=1, max_size=3, unique=True), label="edges")
    inserts = {k: draw(st.lists(st.fractions(Fraction(1, 20), Fraction(19, 20), max_denominator=40),
                                min_size=1, max_size=3), label=f"points on e{k}") for k in chosen}
    changed, new_of = with_points(env, inserts)
    start = draw(st.integers(0, n - 1), label="start")
    goal = draw(st.integers(0, n - 1).filter(lambda g: g != start), label="goal")
    return env, changed, new_of, start, goal


@settings(max_examples=12)
@given(query=collinear_queries(MODELS), objective=st.sampled_from(["fewest", "tolerance"]))
def test_random_collinear_points_change_nothing(query, objective):
    env, changed, new_of, start, goal = query
    plan = find_plan(env, f"e{start}", f"e{goal}", objective=objective)
    again = find_plan(changed, edges_text(new_of[start]), edges_text(new_of[goal]), objective=objective)
    assert plan.bounces == again.bounces
    if plan.found:
        assert abs(plan.min_width - again.min_width) <= 1e-12


def test_a_plan_onto_runs_reads_back_and_replays():
    """A plan's JSON with a source landing on a run (several pairs per source) reads back (simulate, render)."""
    from solverplan.plan.result import parse_plan

    split, new_of = midpoints(models.load("irregular_convex"))
    plan = find_plan(split, edges_text(new_of[0]), edges_text(new_of[3]), objective="tolerance")
    data = plan.to_json()
    assert any(len({i for i, _ in st_["moves"]}) < len(st_["moves"]) for st_ in data["stages"])
    back = parse_plan(data)
    assert back.stages == plan.stages
    assert simulate_plan(split, back, trials=200, seed=3).success_rate == 1.0


# ---------------------------------------------------------------------- funnels and localisation
def sound_positions(env: Environment, answer) -> None:
    """A funnel or localisation strategy in ``env``'s own edges: its stages chain (each stage's sources are the
    positions before it), its certificate verifies exactly, and rollouts land where its positions say."""
    assert answer.env is env and answer.environment.matches(env)
    before = answer.start.merged().pieces
    for stage in answer.stages:
        assert BoundarySet(stage.sources).merged().pieces == before
        assert all(0 <= p.t0 < p.t1 <= 1 and 0 <= p.edge < env.n_edges for p in stage.positions)
        before = stage.positions
    report = check_certificate(certificate(answer), expected_rings=env.rings)
    assert report.valid, [str(f) for f in report.failures]
    intervals, targets, goal = answer.rollout_spec()
    runs = simulate_policy(env, StagePolicy(intervals, targets, goal=goal), answer.start, bounces=len(intervals),
                           trials=500, seed=5, ties="exact")
    assert runs.outcome_counts()["goal"] == 500


def same_strategy(answer, other) -> None:
    assert answer.status == other.status and answer.bounces == other.bounces
    assert [round(w, 9) for w in answer.widths] == [round(w, 9) for w in other.widths]


@pytest.mark.parametrize("name", ["triangle", "irregular_convex", "l_shape", "one_hole"])
def test_midpoint_split_keeps_funnels_and_localisation(name):
    env = models.load(name)
    split, new_of = midpoints(env)
    f = funnel(env, "e0", "e2")
    again = funnel(split, edges_text(new_of[0]), edges_text(new_of[2]))
    same_strategy(f, again)
    assert f.found and again.optimality.scope == f.optimality.scope and "straight wall" in f.optimality.scope
    sound_positions(split, again)
    loc = localize(env, 0.1)
    loc_again = localize(split, 0.1)
    same_strategy(loc, loc_again)
    assert loc.found
    sound_positions(split, loc_again)


def test_a_localisation_interval_across_a_collinear_vertex():
    """A collinear vertex inserted in the middle of the final interval: the strategy is the same, its final
    interval is on two user edges of one straight wall, and the checker measures it along the wall."""
    tri = models.load("triangle")
    loc = localize(tri, 0.05, start="e0", tolerance=0.002)
    (final,) = loc.goal.pieces
    cut, new_of = with_points(tri, {final.edge: [(final.t0 + final.t1) / 2]})
    again = localize(cut, 0.05, start=edges_text(new_of[0]), tolerance=0.002)
    same_strategy(loc, again)
    assert [p.edge for p in again.goal.pieces] == new_of[final.edge]
    sound_positions(cut, again)
    # the same claim with an ε just below the interval's length fails, measured along the wall
    cert = certificate(again)
    data = cert.to_json()
    length = float(final.t1 - final.t0) * float(tri.edge_lengths[final.edge])
    data["claims"]["epsilon"] = repr(length * 0.999)
    report = check_certificate(Certificate.from_json(data))
    assert not report.valid and any("straight wall" in f.message for f in report.failures)


def test_a_funnel_landing_across_a_collinear_vertex():
    """The square's funnel into the middle of e2, with a collinear vertex at the goal's centre: every stage
    is the same; the last one lands on two user edges (the certificate's move runs on over the neighbour)."""
    square = models.load("square")
    f = funnel(square, "e0", "e2:0.45:0.55", tolerance=0.005)
    cut, new_of = with_points(square, {2: [Fraction(1, 2)]})
    a, b = new_of[2]
    again = funnel(cut, "e0", f"e{a}:0.9:1,e{b}:0:0.1", tolerance=0.005)
    same_strategy(f, again)
    assert {p.edge for p in again.stages[-1].positions} == {a, b}
    sound_positions(cut, again)
    moves = certificate(again).stages[-1].moves
    assert any(m.target[1] > 1 or m.target[0] < 0 for m in moves)  # one image runs over the collinear vertex


@pytest.mark.parametrize("name, shift", [("square", 2), ("hexagon", 6)])
def test_a_split_symmetric_room_is_still_symmetric(name, shift):
    split, new_of = midpoints(models.load(name))
    loc = localize(split, 0.1)
    assert loc.status is Status.INFEASIBLE and loc.optimality.proved and loc.optimality.method is Method.SYMMETRY
    assert f"from edge e0 to the one from edge e{shift}" in loc.reason


LOCALISED = ["triangle", "irregular_convex", "l_shape", "one_hole"]


@settings(max_examples=10, deadline=None)
@given(query=collinear_queries(LOCALISED))
def test_random_collinear_points_change_no_funnel_or_localisation(query):
    env, changed, new_of, start, goal = query
    f = funnel(env, f"e{start}", f"e{goal}")
    again = funnel(changed, edges_text(new_of[start]), edges_text(new_of[goal]))
    same_strategy(f, again)
    if again.found:
        sound_positions(changed, again)
    loc, loc_again = localize(env, 0.1), localize(changed, 0.1)
    same_strategy(loc, loc_again)
    if loc_again.found:
        sound_positions(changed, loc_again)
