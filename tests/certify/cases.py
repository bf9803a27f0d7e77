"""Hand-built certificates (JSON data) on shipped models, for the checker, CLI and writer tests.

The geometry (sources, directions, targets) is chosen by hand and explained next to each case; the
width claims are computed here with mpmath at 60 digits and rounded inwards by 1e-12 — independently
of the checker's own atan enclosures, which is what these tests are checking.
"""

from __future__ import annotations

import copy
import json
from fractions import Fraction
from pathlib import Path

import mpmath

from solverplan.certify.schema import SCHEMA, VERSION, json_value

MODELS = Path(__file__).resolve().parent.parent.parent / "solverplan" / "models"

mpmath.mp.dps = 60


def rings_of(model: str) -> list:
    data = json.loads((MODELS / f"{model}.json").read_text())
    return [data["outer"], *data.get("holes", [])]


def _edge_vector(rings: list, edge: int) -> tuple[Fraction, Fraction]:
    for ring in rings:
        if edge < len(ring):
            a, b = ring[edge], ring[(edge + 1) % len(ring)]
            return (Fraction(b[0]) - Fraction(a[0]), Fraction(b[1]) - Fraction(a[1]))
        edge -= len(ring)
    raise IndexError(edge)


def _mp(x) -> mpmath.mpf:
    x = Fraction(x)
    return mpmath.mpf(x.numerator) / x.denominator


def heading(rings: list, edge: int, d) -> mpmath.mpf:
    """The heading of d from edge (radians), with mpmath: independent of the checker."""
    e = _edge_vector(rings, edge)
    dx, dy = Fraction(d[0]), Fraction(d[1])
    return mpmath.atan2(_mp(e[0] * dy - e[1] * dx), _mp(e[0] * dx + e[1] * dy))


def _round(x: mpmath.mpf, up: bool) -> Fraction:
    scaled = x * 10**12
    n = int(mpmath.ceil(scaled) if up else mpmath.floor(scaled))
    return Fraction(n, 10**12)


def with_claims(cert: dict, *, intervals: bool = True) -> dict:
    """Fill in stage intervals, min_width, tolerance, bounces (and sum_width) from the directions."""
    rings = cert["environment"]["rings"]
    widths = []
    for stage in cert["stages"]:
        lo = max(heading(rings, m["edge"], m["d_lo"]) for m in stage["moves"])
        hi = min(heading(rings, m["edge"], m["d_hi"]) for m in stage["moves"])
        lo_r, hi_r = _round(lo, True), _round(hi, False)
        if intervals:
            stage["interval"] = [json_value(lo_r), json_value(hi_r)]
            widths.append(hi_r - lo_r)
        else:
            widths.append(max(Fraction(0), _round(hi - lo, False)))
    width = min(widths)
    cert["claims"] = {"bounces": len(cert["stages"]), "min_width": json_value(width), "tolerance": json_value(width / 2)}
    return cert


def _base(model: str, kind: str = "plan") -> dict:
    return {
        "schema": SCHEMA,
        "version": VERSION,
        "kind": kind,
        "environment": {"name": model, "rings": rings_of(model)},
    }


def move(edge, source, d_lo, d_hi, target_edge, target, *, source_segment=None, target_segment=None) -> dict:
    m = {"edge": edge, "source": [json_value(Fraction(x)) for x in source], "d_lo": list(d_lo), "d_hi": list(d_hi),
         "target_edge": target_edge, "target": [json_value(Fraction(x)) for x in target]}
    if source_segment is not None:
        m["source_segment"] = source_segment
    if target_segment is not None:
        m["target_segment"] = target_segment
    return m


SQUARE_SEGMENTS = [
    {"id": 0, "edge": 0, "t0": 0, "t1": 1, "a": [0, 0], "b": [10, 0]},
    {"id": 1, "edge": 1, "t0": 0, "t1": 1, "a": [10, 0], "b": [10, 10]},
    {"id": 2, "edge": 2, "t0": 0, "t1": 1, "a": [10, 10], "b": [0, 10]},
    {"id": 3, "edge": 3, "t0": 0, "t1": 1, "a": [0, 10], "b": [0, 0]},
]


def square_up() -> dict:
    """Square 10 × 10: from x ∈ [1, 9] of the bottom straight up, headings π/2 ± atan(1/20).

    Corner hits on the top (edge 2, from (10, 10) to (0, 10), τ = (10 − x)/10): from x = 1 at
    x = 1.5 and 0.5, from x = 9 at 9.5 and 8.5 — all strictly inside. (From the whole bottom edge no
    cone around π/2 is safe: Prop. 2's interval is the single heading π/2.)
    """
    cert = _base("square")
    cert["segments"] = [SQUARE_SEGMENTS[0], SQUARE_SEGMENTS[2]]
    cert["start"] = [{"edge": 0, "t0": "0.1", "t1": "0.9"}]
    cert["goal"] = [{"edge": 2, "t0": 0, "t1": 1}]
    cert["stages"] = [{"moves": [move(0, ["1/10", "9/10"], (1, 20), (-1, 20), 2, [0, 1], source_segment=0, target_segment=2)]}]
    return with_claims(cert)


def square_adjacent() -> dict:
    """Square: bottom → right → top through adjacent edges (paper Cor. 1), whole edges as sources.

    Stage 0 from the whole bottom edge with headings atan(1/10)..atan(9/10) (< π/4): from (0, 0) the
    rays hit the right wall at y = 1 and 9; from (10, 0) — the vertex shared with the target — at
    itself (s = 0), which a vertex end of the source may do. Stage 1 is the same turned by +90°.
    """
    cert = _base("square")
    cert["segments"] = [SQUARE_SEGMENTS[0], SQUARE_SEGMENTS[1], SQUARE_SEGMENTS[2]]
    cert["start"] = [{"edge": 0, "t0": 0, "t1": 1}]
    cert["goal"] = [{"edge": 2, "t0": 0, "t1": 1}]
    cert["stages"] = [
        {"moves": [move(0, [0, 1], (10, 1), (10, 9), 1, [0, "9/10"], source_segment=0, target_segment=1)]},
        {"moves": [move(1, [0, 1], (-1, 10), (-9, 10), 2, [0, 1], source_segment=1, target_segment=2)]},
    ]
    return with_claims(cert)


def square_belief() -> dict:
    """Square, start on the bottom *or* the left edge (the robot does not know which): one heading
    interval, measured from whichever edge it is on, takes both to the next edge CCW; twice."""
    cert = _base("square")
    cert["segments"] = list(SQUARE_SEGMENTS)
    cert["start"] = [{"edge": 0, "t0": 0, "t1": 1}, {"edge": 3, "t0": 0, "t1": 1}]
    cert["goal"] = [{"edge": 1, "t0": 0, "t1": 1}, {"edge": 2, "t0": 0, "t1": 1}]
    cert["stages"] = [
        {"moves": [move(0, [0, 1], (10, 1), (10, 9), 1, [0, 1], source_segment=0, target_segment=1),
                   move(3, [0, 1], (1, -10), (9, -10), 0, [0, 1], source_segment=3, target_segment=0)]},
        {"moves": [move(1, [0, 1], (-1, 10), (-9, 10), 2, [0, 1], source_segment=1, target_segment=2),
                   move(0, [0, 1], (10, 1), (10, 9), 1, [0, 1], source_segment=0, target_segment=1)]},
    ]
    return with_claims(cert)


# relative cone (10, 1)..(10, 3) of the four square edges, in the world frame
_SQUARE_TURNS = [lambda x, y: (x, y), lambda x, y: (-y, x), lambda x, y: (-x, -y), lambda x, y: (y, -x)]


def _compose(maps):
    alpha, beta = Fraction(1), Fraction(0)
    for a, b in maps:
        alpha, beta = a * alpha, a * beta + b
    return alpha, beta


def square_cycle() -> dict:
    """Theorem 1's period-4 cycle in the square, headings atan(1/10)..atan(3/10) from every edge.

    Per bounce the boundary parameter maps as τ = (1 − t)·(tan θ) (right transition, φ = π/2:
    C = tan θ), so with the nominal heading atan(1/10) each stage is t ↦ −t/10 + 1/10 and the worst
    case over the cone is |α| = 3/10 per bounce, (3/10)^4 = 81/10000 per cycle.
    """
    cert = _base("square", "cycle")
    cert["segments"] = list(SQUARE_SEGMENTS)
    cert["start"] = [{"edge": 0, "t0": 0, "t1": 1}]
    cert["goal"] = None
    stages = []
    for k in range(4):
        turn = _SQUARE_TURNS[k]
        stages.append({"moves": [move(k, [0, 1], turn(10, 1), turn(10, 3), (k + 1) % 4, [0, "3/10"],
                                      source_segment=k, target_segment=(k + 1) % 4)]})
    cert["stages"] = stages
    alpha, beta = _compose([(Fraction(-1, 10), Fraction(1, 10))] * 4)
    cert["cycle"] = {
        "stages": [0, 1, 2, 3],
        "nominal": [list(_SQUARE_TURNS[k](10, 1)) for k in range(4)],
        "alpha": json_value(alpha),
        "beta": json_value(beta),
        "fixed_point": json_value(beta / (1 - alpha)),
        "contraction": json_value(Fraction(81, 10000)),
        "visits": [0, 1, 2, 3],
    }
    return with_claims(cert)


def square_neutral_cycle(claimed_contraction: str = "1/2") -> dict:
    """The 45° period-4 orbit family of the square from t ∈ [1/10, 9/10]: each bounce is t ↦ 1 − t
    (α = −1), the return map is the identity — a cycle that chains but does not contract."""
    cert = _base("square", "cycle")
    cert["segments"] = list(SQUARE_SEGMENTS)
    cert["start"] = [{"edge": 0, "t0": "0.1", "t1": "0.9"}]
    cert["goal"] = None
    stages = []
    for k in range(4):
        d = _SQUARE_TURNS[k](1, 1)
        stages.append({"moves": [move(k, ["1/10", "9/10"], d, d, (k + 1) % 4, ["1/10", "9/10"],
                                      source_segment=k, target_segment=(k + 1) % 4)]})
    cert["stages"] = stages
    cert["cycle"] = {
        "stages": [0, 1, 2, 3],
        "nominal": [list(_SQUARE_TURNS[k](1, 1)) for k in range(4)],
        "alpha": 1,
        "beta": 0,
        "fixed_point": "1/2",
        "contraction": claimed_contraction,
    }
    return with_claims(cert, intervals=False)


L_SEGMENTS = {
    0: {"id": 0, "edge": 0, "t0": 0, "t1": "2/5", "a": [0, 0], "b": [4, 0]},
    1: {"id": 1, "edge": 0, "t0": "2/5", "t1": "2/3", "a": [4, 0], "b": ["20/3", 0]},
    5: {"id": 5, "edge": 3, "t0": 0, "t1": 1, "a": [4, 4], "b": [4, 10]},
    6: {"id": 6, "edge": 4, "t0": 0, "t1": 1, "a": [4, 10], "b": [0, 10]},
}


def l_shape_plan() -> dict:
    """L-shape (reflex vertex (4, 4); partition segments as computed by Alg. 1). Stage 0: from
    x ∈ [0.5, 3.5] of segment 0 (the bottom under the vertical arm) nearly straight up to the top of
    the arm, segment 6. Stage 1: from all of segment 6 back down-right onto the arm's inner wall,
    segment 5, which shares the vertex (4, 10) with it (Cor. 1 towards e_{i−1}: headings in
    (ang(c − b), π) ≈ (2.159, π); we use ≈ 2.678..2.850)."""
    cert = _base("l_shape")
    cert["segments"] = [L_SEGMENTS[0], L_SEGMENTS[5], L_SEGMENTS[6]]
    cert["start"] = [{"edge": 0, "t0": "1/20", "t1": "7/20"}]
    cert["goal"] = [{"edge": 3, "t0": 0, "t1": 1}]
    cert["stages"] = [
        {"moves": [move(0, ["1/20", "7/20"], (1, 40), (-1, 40), 4, [0, 1], source_segment=0, target_segment=6)]},
        {"moves": [move(4, [0, 1], (10, -5), (10, -3), 3, [0, 1], source_segment=6, target_segment=5)]},
    ]
    return with_claims(cert)


def l_shape_around_the_corner() -> dict:
    """L-shape, from x ∈ [4, 5] (segment 1) up-left to the top of the arm: every corner ray's hit on
    the target *line* is inside segment 6, but the swept region holds the reflex vertex (4, 4): the
    ray from (5, 0) along (−1, 5) crosses edge 2 at (4.2, 4) long before reaching y = 10."""
    cert = _base("l_shape")
    cert["segments"] = [L_SEGMENTS[1], L_SEGMENTS[6]]
    cert["start"] = [{"edge": 0, "t0": "2/5", "t1": "1/2"}]
    cert["goal"] = [{"edge": 4, "t0": 0, "t1": 1}]
    cert["stages"] = [{"moves": [move(0, ["2/5", "1/2"], (-1, 5), (-1, 3), 4, [0, 1], source_segment=1, target_segment=6)]}]
    return with_claims(cert)


ONE_HOLE_SEGMENTS = {
    0: {"id": 0, "edge": 0, "t0": 0, "t1": "1/3", "a": [0, 0], "b": [4, 0]},
    13: {"id": 13, "edge": 2, "t0": "2/3", "t1": 1, "a": [4, 9], "b": [0, 9]},
}


def one_hole_plan() -> dict:
    """one_hole (12 × 9 with the hole (4,3),(4,5),(7,6),(8,3)): from x ∈ [1, 3] of the bottom nearly
    straight up to the top left of the hole's shadow, segment 13 (x ∈ [0, 4] at y = 9)."""
    cert = _base("one_hole")
    cert["segments"] = [ONE_HOLE_SEGMENTS[0], ONE_HOLE_SEGMENTS[13]]
    cert["start"] = [{"edge": 0, "t0": "1/12", "t1": "1/4"}]
    cert["goal"] = [{"edge": 2, "t0": "2/3", "t1": 1}]
    cert["stages"] = [{"moves": [move(0, ["1/12", "1/4"], (1, 30), (-1, 30), 2, ["2/3", 1], source_segment=0, target_segment=13)]}]
    return with_claims(cert)


def one_hole_through_the_hole() -> dict:
    """one_hole: from x ∈ [4, 9] of the bottom straight up to the top edge (no segment named: the
    target is the whole edge 2). The corner hits are all on the top edge, but the hole sits in the
    swept region."""
    cert = _base("one_hole")
    cert["segments"] = []
    cert["start"] = [{"edge": 0, "t0": "1/3", "t1": "3/4"}]
    cert["goal"] = [{"edge": 2, "t0": 0, "t1": 1}]
    cert["stages"] = [{"moves": [move(0, ["1/3", "3/4"], (1, 30), (-1, 30), 2, [0, 1])]}]
    return with_claims(cert)


def funnel_square() -> dict:
    """square_up as a funnel: the exact positions after the stage are the image of the corner rays,
    τ ∈ [1/20, 19/20] on the top edge."""
    cert = square_up()
    cert["kind"] = "funnel"
    cert["stages"][0]["moves"][0]["target"] = ["1/20", "19/20"]
    cert["stages"][0]["positions"] = [{"edge": 2, "t0": "1/20", "t1": "19/20"}]
    return cert


def localize_square(epsilon: str = "19/2") -> dict:
    """funnel_square as a localisation: the final positions t ∈ [1/20, 19/20] of the top edge (10 long)
    are one interval 9 long, shorter than ε = 9.5."""
    cert = funnel_square()
    cert["kind"] = "localize"
    cert["claims"]["epsilon"] = epsilon
    return cert


ALL_VALID = {
    "square_up": square_up,
    "square_adjacent": square_adjacent,
    "square_belief": square_belief,
    "square_cycle": square_cycle,
    "l_shape_plan": l_shape_plan,
    "one_hole_plan": one_hole_plan,
    "funnel_square": funnel_square,
    "localize_square": localize_square,
}


def tampered(cert: dict, path: str, value) -> dict:
    """A deep copy of ``cert`` with the value at ``path`` (``stages.0.moves.0.d_hi``) replaced."""
    out = copy.deepcopy(cert)
    *head, last = path.split(".")
    node = out
    for key in head:
        node = node[int(key)] if isinstance(node, list) else node[key]
    if isinstance(node, list):
        node[int(last)] = value
    else:
        node[last] = value
    return out
