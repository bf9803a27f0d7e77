"""Issue #22's acceptance study: do answers change when the walls are rewritten (same free space, same question)?

Run ``python benchmarks/invariance_study.py --queries 300 --seed 0`` from the repository root (package installed or
on ``PYTHONPATH``). Each query draws an environment — a shipped model (up to 40 edges) or a random star polygon,
star polygon with holes or rectilinear polygon (:mod:`solverplan.generators`) — a start and a goal set
that end inside edges (one piece, or a piece running over a vertex into the next edge, like the issue's
``e3:0.15:1,e4:0:0.25``) and a bounce budget K ∈ [4, 6]. It answers ``find_plan`` for the four objectives
(``fewest``, ``tolerance``, ``sum``, ``constant``, each within K) and the Pareto front within K, then the same
after each rewriting of :mod:`solverplan.studies.rewrite` with the query mapped:

(a) ``ends``  — collinear vertices exactly where the sets end inside edges (:func:`at_set_ends`);
(b) ``split`` — every edge split at its midpoint;
(c) ``motion`` — an exact rational rotation (Pythagorean triple), a translation and a scaling;
(d) ``roll``  — every ring written from another vertex;
(e) ``reverse`` — every ring written in the opposite order (the loader renormalises it);
(f) ``mirror`` — the mirror image (with ``--mirror``).

With ``--patrols`` each query also asks for a patrol (:func:`~solverplan.plan.patrols.patrol`) of the outer ring's
first and middle edges from the start set (objectives ``contraction`` and ``rate``, ε = 0.01, at most one
intermediate bounce). A visit names whole edges, which a vertex inside them would split (no visit list names "e′ or
e″"), so for patrols (a) and (b) put their vertices only where no visited edge is: at the start set's ends and at
the midpoints of the edges not visited; the other rewritings are the same. Patrols compare status, proof, cycle and
entry bounces, periods, contraction, rate and tolerance.

An answer *changes* when :func:`~solverplan.studies.rewrite.answer_differences` finds a difference: status,
proof, bounces, the objective's value (to 10⁻⁹ rad), the Pareto points. Printed: a table of changed answers per
rewriting and objective, the first examples of changes (environment, query, both answers) and the total time.
Every planner call has a timeout (``--timeout``, seconds); answers cut by it are counted apart, not compared.
"""

from __future__ import annotations

import argparse
import os
import platform
import random
import sys
import time
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from fractions import Fraction

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir))

from solverplan import models  # noqa: E402
from solverplan.environment import BoundaryPiece, BoundarySet, Environment  # noqa: E402
from solverplan.plan import find_plan, pareto_front  # noqa: E402
from solverplan.plan.patrols import patrol  # noqa: E402
from solverplan.studies import rewrite as rw  # noqa: E402
from solverplan.generators import rectilinear_polygon, star_polygon, star_polygon_with_holes  # noqa: E402

ANSWERS = ("fewest", "tolerance", "sum", "constant", "pareto")
PATROLS = ("patrol-contraction", "patrol-rate")
REWRITINGS = ("ends", "split", "motion", "roll", "reverse", "mirror")
MAX_MODEL_EDGES = 40


@dataclass
class Outcome:
    """One query's comparisons: per (rewriting, answer) 'same', 'changed', 'timeout' or 'error'."""

    index: int
    env_name: str
    query: str
    verdicts: dict[tuple[str, str], str] = field(default_factory=dict)
    changes: list[tuple[str, str, list[str], str, str]] = field(default_factory=list)
    kinds: dict[tuple[str, str], tuple[str, float]] = field(default_factory=dict)
    seconds: float = 0.0


def _environment(rng: random.Random) -> Environment:
    kind = rng.choice(["model", "model", "star", "star_holes", "rectilinear"])
    seed = rng.randrange(10**6)
    if kind == "model":
        names = [n for n in models.names() if models.load(n).n_edges <= MAX_MODEL_EDGES]
        return models.load(rng.choice(names))
    if kind == "star":
        return star_polygon(rng.randint(6, 10), 0.3, 0.3, seed=seed, radius=10.0, decimals=3)
    if kind == "star_holes":
        return star_polygon_with_holes(rng.randint(6, 9), rng.randint(1, 2), seed=seed, radius=10.0, decimals=3)
    return rectilinear_polygon(rng.randint(4, 7), seed=seed)


def _t(rng: random.Random) -> Fraction:
    return Fraction(rng.randint(1, 19), 20)


def _set(env: Environment, rng: random.Random) -> BoundarySet:
    """A set ending inside edges: one piece, or a piece over a vertex into the next edge of the ring."""
    e = rng.randrange(env.n_edges)
    if rng.random() < 0.5:
        ring = int(env.ring_of[e])
        first, size = env.ring_offsets[ring], env.ring_offsets[ring + 1] - env.ring_offsets[ring]
        nxt = first + (e - first + 1) % size
        return BoundarySet((BoundaryPiece(e, _t(rng), Fraction(1)), BoundaryPiece(nxt, Fraction(0), _t(rng))))
    a, b = sorted(rng.sample(range(1, 20), 2))
    return BoundarySet((BoundaryPiece(e, Fraction(a, 20), Fraction(b, 20) if rng.random() < 0.7 else Fraction(1)),))


def _rewritten(name: str, env: Environment, start: BoundarySet, goal: BoundarySet, rng: random.Random) -> rw.Rewritten:
    if name == "ends":
        return rw.at_set_ends(env, start, goal)
    if name == "split":
        return rw.split_edges(env, 2, start, goal)
    if name == "motion":
        c, s = rng.choice(rw.RATIONAL_ROTATIONS)
        return (rw.rotate(env, c, s, start, goal)
                .then(rw.translate, Fraction(rng.randint(-50, 50), 7), Fraction(rng.randint(-50, 50), 3))
                .then(rw.scale, Fraction(rng.randint(2, 2000), rng.randint(2, 20))))
    if name == "roll":
        r = rw.roll_ring_start(env, 0, rng.randrange(1, len(env.outer)), start, goal)
        for k in range(1, len(env.rings)):
            r = r.then(rw.roll_ring_start, k, 1)
        return r
    if name == "reverse":
        return rw.reverse_rings(env, start, goal)
    if name == "mirror":
        return rw.mirror(env, start, goal)
    raise ValueError(f"unknown rewriting {name!r}")


def _patrol_rewritten(name: str, env: Environment, start: BoundarySet, visit: tuple[int, ...], r: rw.Rewritten,
                      ) -> rw.Rewritten:
    """The rewriting a patrol is compared under: ``r``, except that vertices go only where no edge is visited."""
    if name == "ends":
        points = [(p.edge, t) for p in start.pieces for t in (p.t0, p.t1) if 0 < t < 1 and p.edge not in visit]
        return rw.insert_vertices(env, points, start) if points else rw.identity(env, start)
    if name == "split":
        return rw.insert_vertices(env, [(e, Fraction(1, 2)) for e in range(env.n_edges) if e not in visit], start)
    return r


def _patrols(env: Environment, visit: tuple[int, ...], start: BoundarySet, timeout: float) -> dict[str, object]:
    return {what: patrol(env, list(visit), start=start, objective=what.removeprefix("patrol-"), tolerance=0.01,
                         max_between=1, timeout=timeout) for what in PATROLS}


def _answers(env: Environment, start: BoundarySet, goal: BoundarySet, k: int, timeout: float) -> dict[str, object]:
    out: dict[str, object] = {}
    for objective in ANSWERS[:4]:
        out[objective] = find_plan(env, start, goal, objective=objective, max_bounces=k, timeout=timeout)
    out["pareto"] = pareto_front(env, start, goal, max_bounces=k, timeout=timeout)
    return out


def _timed_out(answer) -> bool:
    return any(str(x).startswith("timeout") for x in answer.optimality.limits)


def _brief(answer) -> str:
    summary = rw.answer_summary(answer)
    return ", ".join(f"{k}={rw._show(v)}" for k, v in summary.items() if k != "kind")


def _kind(a, b, length_scale) -> tuple[str, float]:
    """How an answer changed: ``status`` (or proof), ``bounces`` (or the front's points), else ``value`` with the
    largest difference of a width (radians)."""
    sa, sb = rw.answer_summary(a), rw.answer_summary(b, length_scale=length_scale)
    if sa["status"] != sb["status"] or sa.get("proved") != sb.get("proved"):
        return "status", 0.0
    if (sa.get("bounces") != sb.get("bounces") or sa.get("entry") != sb.get("entry")
            or [p[0] for p in sa.get("front", [])] != [p[0] for p in sb.get("front", [])]):
        return "bounces", 0.0
    deltas = [abs(x - y) for key in ("min_width", "sum_width", "contraction", "rate", "tolerance")
              if isinstance(x := sa.get(key), float)
              and isinstance(y := sb.get(key), float)]
    deltas += [abs(p[1] - q[1]) for p, q in zip(sa.get("front", []), sb.get("front", []))]
    return "value", max(deltas, default=0.0)


def run_query(index: int, seed: int, rewritings: tuple[str, ...], timeout: float, patrols: bool = False) -> Outcome:
    rng = random.Random(f"{seed}:{index}")
    t0 = time.perf_counter()
    env = _environment(rng)
    start, goal = _set(env, rng), _set(env, rng)
    k = rng.randint(4, 6)
    visit = (0, len(env.outer) // 2)
    query = f"--from {start} --to {goal} --max-bounces {k}" + (f" (patrol e{visit[0]},e{visit[1]})" if patrols else "")
    out = Outcome(index, env.name or "unnamed", query)
    answers = ANSWERS + (PATROLS if patrols else ())
    base = _answers(env, start, goal, k, timeout)
    if patrols:
        base.update(_patrols(env, visit, start, timeout))
    for name in rewritings:
        try:
            r = _rewritten(name, env, start, goal, rng)
            again = _answers(r.env, *r.sets, k, timeout)
            if patrols:
                rp = _patrol_rewritten(name, env, start, visit, r)
                again.update(_patrols(rp.env, rp.map_edges(visit), rp.sets[0], timeout))
        except Exception as exc:  # a crash on a rewritten environment is a finding too
            for what in answers:
                out.verdicts[(name, what)] = "error"
            out.changes.append((name, "all", [f"{type(exc).__name__}: {exc}"], "", ""))
            continue
        for what in answers:
            a, b = base[what], again[what]
            if what in PATROLS and name in ("ends", "split"):
                r_len = rp.length_scale
            else:
                r_len = r.length_scale
            if _timed_out(a) or _timed_out(b):
                out.verdicts[(name, what)] = "timeout"
                continue
            diff = rw.answer_differences(a, b, length_scale=r_len)
            out.verdicts[(name, what)] = "changed" if diff else "same"
            if diff:
                out.kinds[(name, what)] = _kind(a, b, r_len)
                mapped = f"--from {r.sets[0]} --to {r.sets[1]}"
                out.changes.append((name, what, diff, _brief(a), f"{_brief(b)}   [{r.description}: {mapped}]"))
    out.seconds = time.perf_counter() - t0
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--queries", type=int, default=300)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--jobs", type=int, default=min(2, os.cpu_count() or 1), help="worker processes")
    parser.add_argument("--timeout", type=float, default=20.0, help="seconds per planner call")
    parser.add_argument("--mirror", action="store_true", help="also compare the mirror image")
    parser.add_argument("--patrols", action="store_true", help="also compare a patrol from the start set")
    parser.add_argument("--examples", type=int, default=3, help="examples of changes printed per rewriting")
    args = parser.parse_args(argv)
    rewritings = REWRITINGS if args.mirror else REWRITINGS[:-1]
    answers = ANSWERS + (PATROLS if args.patrols else ())
    t0 = time.perf_counter()
    print(f"python {platform.python_version()}, {platform.machine()}; {args.queries} queries, seed {args.seed}, "
          f"{args.jobs} jobs, timeout {args.timeout:g} s per planner call\n")
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs) as pool:
            outcomes = list(pool.map(run_query, range(args.queries), [args.seed] * args.queries,
                                     [rewritings] * args.queries, [args.timeout] * args.queries,
                                     [args.patrols] * args.queries))
    else:
        outcomes = [run_query(i, args.seed, rewritings, args.timeout, args.patrols) for i in range(args.queries)]
    counts = Counter((name, what, o.verdicts.get((name, what))) for o in outcomes for name in rewritings
                     for what in answers)
    print("Changed answers (changed / compared; timeouts and errors apart):\n")
    print("| rewriting | " + " | ".join(answers) + " | queries with any change |")
    print("|---|" + "---:|" * (len(answers) + 1))
    for name in rewritings:
        cells = []
        for what in answers:
            changed, same = counts[(name, what, "changed")], counts[(name, what, "same")]
            extra = [f"{counts[(name, what, v)]} {v}" for v in ("timeout", "error") if counts[(name, what, v)]]
            cells.append(f"{changed} / {changed + same}" + (f" ({', '.join(extra)})" if extra else ""))
        anyc = sum(any(o.verdicts.get((name, w)) in ("changed", "error") for w in answers) for o in outcomes)
        print(f"| {name} | " + " | ".join(cells) + f" | {anyc} / {len(outcomes)} |")
    print("\nHow they changed (all answers of the table together): status or proof / bounce counts or front points / "
          "only a width (largest |Δ| in radians):\n")
    print("| rewriting | status | bounces | width only | largest width Δ (query, answer) |")
    print("|---|---:|---:|---:|---:|")
    for name in rewritings:
        kinds = [(k, o.index, what) for o in outcomes for (rname, what), k in o.kinds.items() if rname == name]
        by = Counter(k for (k, _), _, _ in kinds)
        widths = [(d, i, what) for (k, d), i, what in kinds if k == "value"]
        largest = max(widths, default=(0.0, None, ""))
        where = f" (query {largest[1]}, {largest[2]})" if largest[1] is not None else ""
        print(f"| {name} | {by['status']} | {by['bounces']} | {by['value']} | {largest[0]:.3g}{where} |")
    print("\nExamples (status changes first; one answer per query):\n")
    severity = {"status": 0, "bounces": 1, "value": 2}
    for name in rewritings:
        ranked = sorted(((severity[o.kinds.get((c[0], c[1]), ("status", 0.0))[0]], o.index, o, c)
                         for o in outcomes for c in o.changes if c[0] == name), key=lambda x: x[:2])
        seen: set[int] = set()
        for _, index, o, (_, what, diff, before, after) in ranked:
            if index in seen or len(seen) >= args.examples:
                continue
            seen.add(index)
            print(f"- {name} / {what}: query {o.index} in {o.env_name}: `{o.query}`\n"
                  f"    differences: {'; '.join(diff)}\n    before: {before}\n    after:  {after}")
    total = time.perf_counter() - t0
    slowest = max(outcomes, key=lambda o: o.seconds) if outcomes else None
    print(f"\ntotal {total:.1f} s" + (f"; slowest query {slowest.index} ({slowest.env_name}) {slowest.seconds:.1f} s"
                                      if slowest else ""))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
