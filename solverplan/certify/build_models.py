"""Certificates of the other robot models' answers (version 4 :class:`~solverplan.certify.schema.ModelCertificate`).

One builder per answer type, registered with :func:`solverplan.certify.build.certificate`:

- a rooms decomposition (:class:`solverplan.rectilinear.decomposition.Decomposition`) → ``rooms``: rooms, doors,
  the tree, areas, Φ from both sides of every door, Ψ from room 0 to every room along the tree;
- an exploration (:class:`~solverplan.explore.depth_first.Exploration`,
  :class:`~solverplan.explore.range_limited.RangeExploration`) → ``exploration``: every view as its exact visibility
  polygon (cut by the exact disc of radius R for range views), the chain of parents, the counts and the bound;
- a cut ordering (:class:`~solverplan.wallfollow.ordering.CutOrdering`) → ``cut-ordering``: every cut's exact end
  point and the boundary order;
- a pursuit plan (:class:`~solverplan.wallfollow.pursuit.PursuitPlan`) → ``pursuit``: the positions after every
  action, the window set of the shadow and the contaminated windows there (from the geometric ground truth
  :func:`~solverplan.wallfollow.pursuit_check.check_pursuit`), and when the shadow is cleared;
- composed fields (:class:`~solverplan.reflection.navigation.FieldNavigation`,
  :class:`~solverplan.reflection.compose.FieldPlan`) → ``fields``: cells, neighbours, sequence and every cell's
  field and outlet.

The builders read the answers' exact data; the claims are re-derived by the independent checker
(:mod:`solverplan.certify.check_models`), never by the code that made them.

>>> from solverplan.environment import load_environment
>>> from solverplan.rectilinear import decompose_rooms
>>> from solverplan.certify.check import check_certificate
>>> cert = rooms_certificate(decompose_rooms(load_environment("three_chambers")))
>>> cert.kind, len(cert.claims["rooms"]), check_certificate(cert).valid
('rooms', 5, True)
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

from solverplan.certify.schema import EnvironmentRecord, ModelCertificate, number_text
from solverplan.environment import Environment
from solverplan.errors import InputError

__all__ = ["rooms_certificate", "exploration_certificate", "cut_ordering_certificate", "pursuit_certificate",
           "fields_certificate"]

PRODUCER = "solverplan"


def _x(value: Any) -> str | int:
    value = Fraction(value)
    return int(value) if value.denominator == 1 and abs(value.numerator).bit_length() < 4000 else number_text(value)


def _p(point: Any) -> list:
    return [_x(point[0]), _x(point[1])]


def _record(env: Environment) -> EnvironmentRecord:
    return EnvironmentRecord(env.rings, env.name)


def _env_of(result: Any, env: Environment | None, what: str) -> Environment:
    own = getattr(result, "env", None)
    if own is not None:
        if env is not None and env.rings != own.rings:
            raise InputError(f"the {what} was made in another environment ({own.name!r}), not in {env.name!r}")
        return own
    if env is None:
        raise TypeError(f"a {what} does not carry its environment: call certificate(answer, env=...)")
    record = getattr(result, "environment", None)
    if record is not None and hasattr(record, "matches") and not record.matches(env):
        raise InputError(f"the {what} was made in another environment (sha256 {record.sha256[:12]}…), not in {env.name!r}")
    return env


# ---------------------------------------------------------------------- rooms
def rooms_certificate(dec: Any, env: Environment | None = None) -> ModelCertificate:
    """The ``rooms`` certificate of a rooms decomposition (module docstring)."""
    from solverplan.rectilinear.metrics import reachability

    env = _env_of(dec, env, "rooms decomposition")
    rooms = [{"id": r.id, "polygon": [_p(p) for p in r.polygon], "area": _x(r.area)} for r in dec.rooms]
    doors = [{"id": d.id, "a": _p(d.a), "b": _p(d.b), "rooms": list(d.rooms), "length": _x(d.length),
              "escapability": [_x(d.escapability(r)) for r in d.rooms]} for d in dec.doors]
    tree = sorted(sorted(d.rooms) for d in dec.doors)
    reach = []
    for r in range(len(dec.rooms)):
        path = reachability(dec, 0, r)
        reach.append({"room": r, "path": list(path.rooms), "psi": _x(path.psi)})
    claims = {"area": _x(env.area), "rooms": rooms, "doors": doors, "tree": tree,
              "reachability": {"from": 0, "to": reach}}
    return ModelCertificate("rooms", _record(env), claims, PRODUCER)


# ---------------------------------------------------------------------- exploration
def exploration_certificate(run: Any, env: Environment | None = None) -> ModelCertificate:
    """The ``exploration`` certificate of an exploration with or without a range (module docstring)."""
    from solverplan.explore.range_limited import RangeExploration
    from solverplan.result import Status

    env = _env_of(run, env, "exploration")
    if run.status != Status.FOUND:
        from solverplan.certify.build import NothingToCertify

        raise NothingToCertify(f"the exploration has status {run.status.value!r}: its views do not cover the free space",
                               why="the exploration stopped before its views covered the free space")
    ranged = isinstance(run, RangeExploration)
    views = []
    for k, (z, view) in enumerate(zip(run.viewpoints, run.views)):
        ring = view.polygon.ring if ranged else view.ring
        parent = run.parents[k] if k else -1
        views.append({"viewpoint": _p(z), "parent": None if parent < 0 else parent, "polygon": [_p(p) for p in ring]})
    claims = {"range": _x(run.range) if ranged else None, "views": views, "reflex": run.reflex,
              "holes": len(env.holes), "bound": run.bound}
    return ModelCertificate("exploration", _record(env), claims, PRODUCER)


# ---------------------------------------------------------------------- wall following
def cut_ordering_certificate(ordering: Any, env: Environment | None = None) -> ModelCertificate:
    """The ``cut-ordering`` certificate of a cut ordering (computed or learned) in ``env``."""
    from solverplan.wallfollow.cut import cuts

    env = _env_of(ordering, env, "cut ordering")
    claims = {"cuts": [{"label": c.label, "vertex": c.vertex, "side": c.side, "edge": c.edge, "point": _p(c.point)}
                       for c in sorted(cuts(env), key=lambda c: (c.vertex, c.side))],
              "ordering": list(ordering.labels)}
    return ModelCertificate("cut-ordering", _record(env), claims, PRODUCER)


def pursuit_certificate(plan: Any, env: Environment | None = None) -> ModelCertificate:
    """The ``pursuit`` certificate of a pursuit plan that was found (its ground-truth replay supplies the labels)."""
    from solverplan.certify.build import NothingToCertify
    from solverplan.result import Status
    from solverplan.wallfollow.cut import corner_polygon
    from solverplan.wallfollow.pursuit_check import check_pursuit

    env = _env_of(plan, env, "pursuit plan")
    if plan.status != Status.FOUND:
        raise NothingToCertify(f"the pursuit plan has status {plan.status.value!r}: there is no plan to certify",
                               why=f"no pursuit plan ({plan.status.value})")
    replay = plan.check if plan.check is not None else check_pursuit(corner_polygon(env), plan.actions, plan.start)
    steps = []
    for k, step in enumerate(replay.steps):
        steps.append({"action": None if step.action is None else step.action.value,
                      "label": plan.positions[k] if k < len(plan.positions) else step.label,
                      "point": _p(step.point), "shadow": sorted(step.components), "contaminated": sorted(step.labels)})
    claims = {"start": plan.start, "steps": steps, "cleared_after": replay.cleared_after}
    return ModelCertificate("pursuit", _record(env), claims, PRODUCER)


# ---------------------------------------------------------------------- fields
def fields_certificate(answer: Any, env: Environment | None = None) -> ModelCertificate:
    """The ``fields`` certificate of composed fields (a :class:`FieldNavigation` or its :class:`FieldPlan`)."""
    plan = getattr(answer, "plan", answer)
    env = _env_of(plan, env, "field plan")
    cells = [{"id": cell.id, "polygon": [_p(p) for p in cell.vertices], "neighbours": [s.neighbour for s in cell.sides]}
             for cell in plan.cells]
    policies = []
    for c in sorted(plan.policies):
        policy = plan.policies[c]
        f = policy.field
        if f.kind == "line":
            field = {"kind": "line", "origin": _p(f.origin), "target": _p(f.target), "gain": _x(f.gain)}
        elif f.kind == "goal":
            field = {"kind": "goal", "goal": _p(f.goal)}
        else:
            field = {"kind": "arc", "centre": _p(f.centre), "radius": _x(Fraction(f.radius)), "gain": _x(f.gain),
                     "clockwise": bool(f.clockwise)}
        entry = {"cell": c, "next": policy.next_cell, "outlet_side": policy.outlet_side, "field": field}
        if f.kind == "line":
            entry["flows_through"] = bool(policy.check.valid)  # the planner's exact test (the checker redoes it)
        policies.append(entry)
    claims = {"area": _x(env.area), "cells": cells, "start": _p(plan.start), "goal": _p(plan.goal),
              "sequence": list(plan.sequence), "policies": policies}
    return ModelCertificate("fields", _record(env), claims, PRODUCER)
