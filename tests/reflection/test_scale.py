"""The fields answer does not depend on the scale, position or turn of the coordinates (issue #23).

A line field's flow-through is a similarity invariant: moving, turning and scaling the cell by s while dividing the
gain by s multiplies n·v·|w|² at every vertex by s³ > 0 (sympy below), so the exact verdict cannot change. The
composition is built to keep it so: default gains and goal radius are relative to the environment's mean width,
the LP fit works in its cell's units. The properties here check the whole chain — cells, sequence, fields,
found/not-found and the exact checker's verdict on the certificate — at scales 10⁻³, 1 and 10⁴, and turned; the
simulator gives the same runs when the robot's lengths and speeds are scaled with the room.

The pinned example is the reproducer of the end-to-end runs (a 32-vertex star with a hole: ``found`` at scale 1,
``not-found`` at 10⁻³ before the gains were made relative to the room).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
import sympy as sym
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from solverplan.certify.build_models import fields_certificate
from solverplan.certify.check_models import check_model_certificate
from solverplan.environment import Environment
from solverplan.exact import cross
from solverplan.reflection.cells import cut_at_sides, decompose_free_space
from solverplan.reflection.compose import FieldPlan, compose_fields, default_gains, mean_width
from solverplan.reflection.fields import LineField, line_flows_through
from solverplan.reflection.navigation import navigate_fields
from solverplan.reflection.simulate import FieldRobotDynamics
from solverplan.studies import rewrite as rw
from tests.test_model_invariance import field_queries  # a polygon (with holes or not), two cells' vertex averages

F = Fraction
SCALES = (F(1, 1000), F(10**4))
TURN = (F(20, 29), F(21, 29))  # a rational rotation (cos, sin) of about 46°

# the reproducer (end-to-end runs, seed 7): scale 1 here; the same coordinates × 10⁻³ were not-found
F7_RINGS = (
    [["-0.8549412", "0.2621434"], ["-0.9287224", "-0.0356632"], ["-0.9186248", "-0.3673364"], ["-0.93913", "-0.740625"],
     ["-0.7457416", "-0.7727413"], ["-0.5523532", "-0.8048576"], ["-0.1926246", "-0.8616378"],
     ["0.1017826", "-0.8914082"], ["0.2773868", "-0.9737376"], ["0.452991", "-1.056067"], ["0.53077475", "-0.99601825"],
     ["0.764126", "-0.815872"], ["0.6874396", "-0.3414472"], ["1.136579", "-0.089483"], ["1.1354582", "0.0265576"],
     ["1.1320958", "0.3746794"], ["0.6875518", "0.6261474"], ["0.3480442", "0.5899006"], ["0.3041752", "0.73898485"],
     ["0.1725682", "1.1862376"], ["-0.1993614", "0.9823398"], ["-0.4309318", "0.6533226"], ["-0.7588286", "0.5692002"]],
    [["0.0808472", "0.4186596"], ["0.0649412", "0.4656891"], ["0.0490352", "0.5127186"], ["0.0877899", "0.5394232"],
     ["0.1265446", "0.5661278"], ["0.239743", "0.562639"], ["0.2434066", "0.4665988"], ["0.2347829", "0.45686095"],
     ["0.2089118", "0.4276474"]])
F7 = Environment.from_coords(F7_RINGS[0], holes=F7_RINGS[1:])
F7_QUERY = (F7, (F("-0.06384"), F("0.0153")), (F("-0.61931"), F("0.1742")))
# the same room, start and goal in the cells with the fields the old absolute gains could not make at 10⁻³
F7_ACROSS = (F7, (F("-0.8"), F("-0.5")), (F("0.9"), F("0.2")))

# a star with a hole (random stars, seed 5, trial 62): cell 0's outlet has no line field flowing through it
# (every direction and gain fails the exact test), so the composition cuts a triangle off it
NO_LINE_FIELD = (Environment.from_coords(
    [["70.814", 0], ["37.295", "15.448"], ["61.806", "61.806"], ["35.233", "85.061"], [0, "77.382"],
     ["-21.583", "52.106"], ["-33.002", "33.002"], ["-30.233", "12.523"], ["-63.235", 0], ["-77.079", "-31.927"],
     ["-26.463", "-26.463"], ["-33.603", "-81.124"], [0, "-94.023"], ["13.548", "-32.708"], ["52.782", "-52.782"],
     ["44.827", "-18.568"]],
    holes=[[["6.452", "4.524"], ["2.687", "12.342"], ["-5.773", "14.273"], ["-12.558", "8.862"], ["-12.558", "0.185"],
            ["-5.773", "-5.226"], ["2.687", "-3.295"]]]),
    (F(-12401, 1500), F(-242839, 6000)), (F(7739, 500), F(16157, 1500)))

FEW = settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.filter_too_much,
                                                                      HealthCheck.too_slow])

Point = tuple[Fraction, Fraction]


def _area(cell) -> Fraction:
    v = cell.vertices
    return sum((v[k][0] * v[(k + 1) % len(v)][1] - v[(k + 1) % len(v)][0] * v[k][1] for k in range(len(v))), F(0)) / 2


def _verified(plan: FieldPlan) -> bool:
    """The exact standard-library checker's verdict on the plan's certificate."""
    return check_model_certificate(fields_certificate(plan, plan.env)).valid


def structure(plan: FieldPlan, scale: Fraction) -> tuple:
    """What must not change with the scale: found, the cells (exact areas / s², in cell order), the adjacency, the
    sequence, and every field brought back to scale 1 (line: origin/s, target/s, gain·s — exactly)."""
    fields = []
    for c in sorted(plan.policies):
        f = plan.policies[c].field
        if isinstance(f, LineField):
            fields.append((c, "line", (f.origin[0] / scale, f.origin[1] / scale),
                           (f.target[0] / scale, f.target[1] / scale), f.gain * scale))
        else:
            fields.append((c, f.kind))
    return (plan.flow_through, [_area(c) / scale**2 for c in plan.cells], plan.decomposition.adjacency,
            plan.sequence, fields, plan.reflection_cells)


def shape(plan: FieldPlan) -> tuple:
    """What must not change when the room turns (cell numbers may): found, the cells' areas, the areas along the
    sequence, the field kinds along it and the number of reflection zones."""
    areas = [_area(c) for c in plan.cells]
    return (plan.flow_through, sorted(areas), [areas[c] for c in plan.sequence],
            [plan.policies[c].field.kind for c in plan.sequence], len(plan.zones))


@FEW
@given(query=field_queries())
@example(query=F7_QUERY)
@example(query=F7_ACROSS)
@example(query=NO_LINE_FIELD)
def test_fields_answer_is_scale_invariant(query):
    """Scaled by 10⁻³ and 10⁴, and turned and moved: the same found/not-found, the same cells and sequence, the
    scaled fields (exactly, under scaling), and a certificate the exact checker accepts whenever it is found."""
    env, start, goal = query
    assume(start != goal)
    plan = compose_fields(env, start, goal)
    before = structure(plan, F(1))
    assert not plan.flow_through or _verified(plan)
    for s in SCALES:
        scaled = rw.scale(env, s).env
        image = compose_fields(scaled, (start[0] * s, start[1] * s), (goal[0] * s, goal[1] * s))
        assert structure(image, s) == before, f"scale {s}"
        assert image.flow_through == _verified(image) or not image.flow_through
    c, si = TURN
    turned = rw.rotate(env, c, si).then(rw.translate, F(7, 3), -5).env
    move = lambda p: (c * p[0] - si * p[1] + F(7, 3), si * p[0] + c * p[1] - 5)  # noqa: E731
    image = compose_fields(turned, move(start), move(goal))
    assert shape(image) == shape(plan)
    assert not image.flow_through or _verified(image)


def test_fields_reproducer_is_found_at_every_scale():
    """The end-to-end reproducer: found (and certified) at 10⁻³, 1 and 10⁴, with the gain scaled with the room."""
    env, start, goal = F7_QUERY
    gains = []
    for s in (F(1, 1000), F(1), F(10**4)):
        plan = compose_fields(rw.scale(env, s).env, (start[0] * s, start[1] * s), (goal[0] * s, goal[1] * s))
        assert plan.flow_through and plan.proved and _verified(plan), f"scale {s}"
        gains.append(default_gains(plan.env)[0] * s)
    assert gains[0] == gains[1] == gains[2] == 3 * F("0.4422") / mean_width(env)


def test_line_field_flow_through_is_similarity_invariant():
    """The theorem the scale-free composition relies on, in sympy: under q ↦ sRq + t (R a rotation, s > 0) with
    the gain divided by s, n·v·|w|² (the quantity whose sign :func:`line_flows_through` decides at each vertex)
    is multiplied by s³ > 0."""
    c, si, s, p, tx, ty = sym.symbols("c si s p t_x t_y", real=True)
    ox, oy, wx, wy, nx, ny, qx, qy = sym.symbols("o_x o_y w_x w_y n_x n_y q_x q_y", real=True)
    length = sym.Symbol("L", positive=True)  # |w|

    def inward(o, w, n, q, gain, norm_w):
        a = (o[0] - q[0], o[1] - q[1])
        nw = n[0] * w[0] + n[1] * w[1]
        l2 = w[0] ** 2 + w[1] ** 2
        return nw * norm_w + gain * (l2 * (n[0] * a[0] + n[1] * a[1]) - nw * (w[0] * a[0] + w[1] * a[1]))

    def move(v, shift=True):  # sRv (+ t for points; directions and normals do not move)
        x, y = s * (c * v[0] - si * v[1]), s * (si * v[0] + c * v[1])
        return (x + tx, y + ty) if shift else (x, y)

    w_image = move((wx, wy), shift=False)
    # |sRw| = s|w| when c² + si² = 1 (s > 0)
    assert sym.expand((w_image[0] ** 2 + w_image[1] ** 2) - s**2 * (wx**2 + wy**2)).subs(si**2, 1 - c**2).expand() == 0
    before = inward((ox, oy), (wx, wy), (nx, ny), (qx, qy), p, length)
    after = inward(move((ox, oy)), w_image, move((nx, ny), shift=False), move((qx, qy)), p / s, s * length)
    difference = sym.expand(sym.expand(after - s**3 * before).subs(si**2, 1 - c**2))
    assert sym.simplify(difference.subs(si**2, 1 - c**2)) == 0


@settings(max_examples=20, deadline=None)
@given(scale=st.sampled_from(SCALES), gain=st.fractions(F(1, 10), F(20), max_denominator=50))
def test_line_field_verdict_is_scale_invariant(scale, gain):
    """The exact verdict of a line field and its image (room × s, gain / s) agree, cell by cell of a room."""
    env, _, _ = F7_QUERY
    scaled = rw.scale(env, scale).env
    cells, images = decompose_free_space(env).cells, decompose_free_space(scaled).cells
    for cell, image in zip(cells, images):
        for i in range(len(cell.sides)):
            f = LineField(cell.sides[(i + 1) % len(cell.sides)].midpoint, cell.sides[i].midpoint, gain)
            g = LineField((f.origin[0] * scale, f.origin[1] * scale), (f.target[0] * scale, f.target[1] * scale),
                          gain / scale)
            assert line_flows_through(f, cell, {i}).valid == line_flows_through(g, image, {i}).valid


@pytest.mark.parametrize("scale", SCALES)
def test_fields_simulation_is_scale_invariant(scale):
    """The rollouts in the room scaled by s, with the robot's lengths and speeds scaled too (times unchanged):
    the same successes and the same times to the goal (noise is in radians and shares: scale-free)."""
    env, start, goal = F7_QUERY

    def run(s: Fraction):
        robot = FieldRobotDynamics(kind="integrator", accel=2.0 * float(s), goal_radius=0.02 * float(s),
                                   dead_band=0.05 * float(s))
        return navigate_fields(rw.scale(env, s).env, (start[0] * s, start[1] * s), (goal[0] * s, goal[1] * s),
                               model=robot, trials=4, seed=3, fast=1.5 * float(s), slow=0.8 * float(s),
                               reflections="none")

    a, b = run(F(1)), run(scale)
    assert a.status == b.status
    for name in a.runs:
        assert a.runs[name].success == b.runs[name].success
        np.testing.assert_allclose(b.runs[name].times, a.runs[name].times, rtol=1e-6)


def test_default_simulation_lengths_follow_the_room():
    """Not given, the goal radius shrinks with rooms narrower than the serpentine (never a radius holding the whole
    room, so no run starts at the goal), the dead band with the commanded speeds; the answer says which were
    derived, and given values are kept."""
    env, start, goal = F7_QUERY
    tiny = rw.scale(env, F(1, 1000)).env
    nav = navigate_fields(tiny, (start[0] / 1000, start[1] / 1000), (goal[0] / 1000, goal[1] / 1000),
                          scenarios=("constrained",), model="integrator", trials=2, slow=0.0008, fast=0.0015)
    assert nav.model.goal_radius == pytest.approx(0.1 * float(mean_width(tiny)) / 0.4422)
    assert nav.model.dead_band == pytest.approx(0.0008 / 16)
    assert nav.runs["constrained"].success == 1.0 and min(nav.runs["constrained"].times) > 0
    scale_record = nav.to_json()["scale"]
    assert scale_record["derived"] == ["dead_band", "gain_arc", "gain_line", "goal_radius"]
    assert scale_record["mean_width_exact"] == "0.0007483"
    given_ = navigate_fields(tiny, (start[0] / 1000, start[1] / 1000), (goal[0] / 1000, goal[1] / 1000),
                             scenarios=("constrained",), model="integrator", trials=1, slow=0.0008, fast=0.0015,
                             goal_radius=1e-5, dead_band=0.0, gain_line="1000")
    assert (given_.model.goal_radius, given_.model.dead_band, given_.gains[0]) == (1e-5, 0.0, 1000)
    assert given_.to_json()["scale"]["derived"] == ["gain_arc"]


def test_a_cell_without_a_line_field_is_cut_and_the_answer_is_certified():
    """No line field flows through cell 0's outlet (the LP over every direction, the gain ladders): the cell is cut
    along a diagonal into a triangle on its outlet and the rest; the cells still tile the room exactly, every
    field verifies, and the exact checker accepts the certificate — at every scale."""
    env, start, goal = NO_LINE_FIELD
    dec = decompose_free_space(env)
    plan = compose_fields(env, start, goal)
    assert len(plan.cells) == len(dec.cells) + 1 and plan.flow_through and plan.proved and _verified(plan)
    assert sum(_area(c) for c in plan.cells) == env.area
    for s in SCALES:
        image = compose_fields(rw.scale(env, s).env, (start[0] * s, start[1] * s), (goal[0] * s, goal[1] * s))
        assert structure(image, s) == structure(plan, F(1)) and _verified(image)


def test_cutting_a_side_off_keeps_the_cells_a_convex_tiling():
    """:func:`cut_at_sides`: one more cell per cut, each strictly convex, the cut side on a triangle, the exact
    area kept, and every facet shared whole (a side names a neighbour exactly when the neighbour has it reversed)."""
    env, _, _ = NO_LINE_FIELD
    dec = decompose_free_space(env)
    cuts = {c.id: len(c.sides) - 1 for c in dec.cells if len(c.vertices) > 3}
    cut = cut_at_sides(dec, cuts)
    assert len(cut.cells) == len(dec.cells) + len(cuts)
    assert sum(_area(c) for c in cut.cells) == env.area
    sides = {(s.a, s.b): c.id for c in cut.cells for s in c.sides}
    for c in cut.cells:
        v = c.vertices
        assert all(cross((v[k][0] - v[k - 1][0], v[k][1] - v[k - 1][1]),
                         (v[(k + 1) % len(v)][0] - v[k][0], v[(k + 1) % len(v)][1] - v[k][1])) > 0 for k in range(len(v)))
        for s in c.sides:
            assert s.neighbour == sides.get((s.b, s.a))
    for cid, side in cuts.items():
        old = dec.cells[cid].sides[side]
        assert any(len(c.vertices) == 3 and (old.a, old.b) in {(s.a, s.b) for s in c.sides} for c in cut.cells)



coords = st.integers(-50, 50)


@settings(max_examples=60, deadline=None)
@given(st.tuples(coords, coords), st.tuples(coords, coords), st.tuples(coords, coords), st.integers(0, 2))
def test_triangle_median_field_flows_through_when_gentle(a, b, c, side):
    """What makes cutting down to triangles end: in a triangle, the line field along the median from the vertex
    opposite the outlet (vertex average → outlet midpoint) flows through the outlet once its gain is small enough —
    at p = 0 it is the constant direction from the apex into the open outlet, strictly inward on the other two
    sides — and the gains compose tries (p/8, p/64, …) reach it."""
    assume(cross((b[0] - a[0], b[1] - a[1]), (c[0] - a[0], c[1] - a[1])) > 0)
    tri = decompose_free_space(Environment.from_coords([a, b, c])).cells[0]
    v, out = tri.vertices, tri.sides[side]
    average = (sum((p[0] for p in v), F(0)) / 3, sum((p[1] for p in v), F(0)) / 3)
    assert line_flows_through(LineField(average, out.midpoint, F(0)), tri, {side}).valid  # the constant field
    assert any(line_flows_through(LineField(average, out.midpoint, F(3) / 2**k), tri, {side}).valid
               for k in range(3, 40, 3))


def test_fields_of_a_star_with_holes_at_ten_thousand_are_found_at_every_scale():
    """The second end-to-end reproducer (404 vertices, 182 cells, coordinates ~10⁴: not-found on the old absolute
    gains): found (exactly), and the same cells, sequence and scaled fields at 10⁻⁷ of it (coordinates ~10⁻³)."""
    from pathlib import Path

    from solverplan.environment import load_environment

    env = load_environment(Path(__file__).parent / "data" / "holes_808345.json")
    start, goal = (F("4517.8"), F("2350.3")), (F(-7789), F("-8.7"))
    plan = compose_fields(env, start, goal)
    assert plan.flow_through and plan.proved and len(plan.cells) == 182
    s = F(1, 10**7)
    image = compose_fields(rw.scale(env, s).env, (start[0] * s, start[1] * s), (goal[0] * s, goal[1] * s))
    assert structure(image, s) == structure(plan, F(1))
