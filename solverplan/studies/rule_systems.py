"""Comparing bounce-rule families by the reachability of the transition systems they induce (paper §8.2).

The paper proposes to compare families of bounce strategies "by comparing the reachability of the
transition systems induced by each strategy family", without saying how (and notes it is unclear for
relative rules, whose outgoing heading depends on the incoming one). We make it precise in two ways,
both on the segments of P′ (the nodes of the BVG), so they are comparable with Fig. 15's metric.

**Families.** A family F is a set of deterministic rules the robot may choose from at every bounce
(:mod:`solverplan.bounce.rules`). Spelled as in :func:`parse_family`:

- ``any`` — every heading in (0, π): the paper's planner, whose actions are free (the baseline);
- ``fixed`` — Fixed(θ) for θ = kπ/(m+1), k = 1..m (m = ``family_size``);
- ``monotone`` — MonotoneFixed(θ) for the same θ with θ ≤ π/2 (θ and π − θ name the same rule);
- ``relative`` — Relative(θ) (the paper's b = α − θ, rotated clockwise into the free space), same θ;
- ``specular`` — the mirror reflection (one member);
- ``fixed:THETA``, ``monotone:THETA``, ``relative:THETA`` — one member (radians, ``pi/3`` allowed).

**1. The guaranteed system G_F (exact, from the safe BVG).** Let H_r(i) be the set of headings rule
r may execute on segment i over *all* arrival directions: {θ} for Fixed(θ); {θ, π − θ} for
MonotoneFixed(θ) (only θ on an edge perpendicular to its axis, or when θ = π/2); all of (0, π) for the
specular and relative rules (their heading sweeps (0, π) as the arrival angle does); for ``any`` the
robot picks one heading. G_F has an arc i → j iff some member r has H_r(i) inside the safe set of the
BVG arc i → j (for ``any``: the safe set is non-empty) — i.e. the rule **guarantees** that every
point of segment i lands on segment j, whatever the robot's arrival. So G_any is the safe BVG (the
paper's Fig. 15 system), G_fixed ⊆ G_any is the safe BVG "reduced given constraints on possible
bounces" (§8.2), and the specular and relative families guarantee nothing: without knowing the
incoming direction their next segment is not determined by the current one. Columns: ``guaranteed_arcs``,
``unreachable`` (perimeter share of segments with no incoming arc of G_F, as Fig. 15), ``scc``, ``wcc``.

**2. The sampled dynamics D_F (Monte Carlo, seeded).** ``trials`` robots start uniformly on ∂P (by arc
length) with uniform headings in (0, π) and bounce ``bounces`` times; robot k obeys member k mod |F|
of the family for its whole run (a robot runs one rule; ``any`` draws a uniform heading at every
bounce) — :func:`solverplan.rollout.simulate_policy`. Only legs executed by the rule count (from the
first bounce on). Columns:

- ``visited`` — perimeter share of the segments hit by at least one robot: the reachability of the
  union of the members' systems (the dynamic analogue of 1 − ``unreachable``; it saturates near 1
  for every family in the paper's star polygons: *something* reaches almost everything);
- ``coverage`` — the mean, over robots, of the perimeter share one robot hits: how much of the
  boundary a single run of the rule explores;
- ``recurrent`` — the same mean over the last half of the bounces only: where the dynamics settle
  (a fixed rule converges to limit cycles touching few segments, specular billiards keep spreading);
- ``flagged`` — share of robots stopped at a vertex or a float near-tie.

D_F under-approximates the existential system (arcs that *can* occur) and converges to it as
trials × bounces grow; the rows are reproducible from their seed.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from solverplan.bounce.rules import HEADING_MARGIN, BounceRule, Fixed, MonotoneFixed, Relative, Specular, parse_rule
from solverplan.errors import InputError
from solverplan.rollout import Contacts, Outcome, simulate_policy
from solverplan.studies.metrics import component_counts, safe_graph_summary, unreachable_fraction

if TYPE_CHECKING:  # pragma: no cover
    from solverplan.environment import Environment

__all__ = ["RuleFamily", "parse_family", "FamilyPolicy", "RuleReachability", "DEFAULT_FAMILIES"]

DEFAULT_FAMILIES = ("any", "fixed", "monotone", "relative", "specular")
"""The families compared by default (``solverplan study rules``)."""

_FAMILY = re.compile(r"^(any|specular|fixed|monotone|relative)(?::(.+))?$")


@dataclass(frozen=True)
class RuleFamily:
    """A set of deterministic bounce rules the robot may choose from at each bounce; ``members == ()``
    is the free family ``any`` (every heading in (0, π))."""

    spec: str
    members: tuple[BounceRule, ...]

    @property
    def is_free(self) -> bool:
        return not self.members


def parse_family(spec: str, *, family_size: int = 5) -> RuleFamily:
    """A family from its spelling (module docstring); ``family_size`` members for the bare names.

    >>> [round(r.theta, 4) for r in parse_family("fixed", family_size=3).members]
    [0.7854, 1.5708, 2.3562]
    >>> [round(r.theta, 4) for r in parse_family("monotone", family_size=3).members]
    [0.7854, 1.5708]
    >>> parse_family("fixed:pi/3").members
    (Fixed(theta=1.0471975511965976, epsilon=0.0),)
    >>> parse_family("bouncy")
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: unknown rule family 'bouncy': use any, specular, fixed, monotone, relative, or fixed:THETA, monotone:THETA, relative:THETA
    """
    text = spec.strip().lower() if isinstance(spec, str) else ""
    match = _FAMILY.match(text)
    if not match:
        raise InputError(
            f"unknown rule family {spec!r}: use any, specular, fixed, monotone, relative, "
            "or fixed:THETA, monotone:THETA, relative:THETA"
        )
    name, angle = match.groups()
    if name in ("any", "specular") and angle is not None:
        raise InputError(f"rule family {spec!r}: {name} takes no angle")
    if name == "any":
        return RuleFamily(text, ())
    if name == "specular":
        return RuleFamily(text, (Specular(),))
    if angle is not None:
        return RuleFamily(text, (parse_rule(f"{name}:{angle}"),))
    if isinstance(family_size, bool) or not isinstance(family_size, int) or family_size < 1:
        raise InputError(f"expected family_size >= 1, got family_size={family_size!r}")
    thetas = [k * math.pi / (family_size + 1) for k in range(1, family_size + 1)]
    make = {"fixed": Fixed, "monotone": MonotoneFixed, "relative": Relative}[name]
    if name == "monotone":
        thetas = [t for t in thetas if t <= math.pi / 2 + 1e-12]
    return RuleFamily(text, tuple(make(t) for t in thetas))


# ---------------------------------------------------------------------- the sampled dynamics
@dataclass(frozen=True)
class FamilyPolicy:
    """Simulator policy: a uniform launch heading, then robot k obeys member k mod |F| (``any``: a
    uniform heading at every bounce)."""

    family: RuleFamily

    def headings(self, contacts: Contacts, rng: np.random.Generator) -> np.ndarray:
        m = len(contacts)
        if contacts.step == 0 or self.family.is_free:
            return rng.uniform(HEADING_MARGIN, math.pi - HEADING_MARGIN, size=m)
        members = self.family.members
        choice = contacts.rollout % len(members)
        out = np.empty(m)
        for k, rule in enumerate(members):
            rows = np.flatnonzero(choice == k)
            if len(rows):
                out[rows] = rule.nominal(contacts.env, contacts.edge[rows], contacts.incoming[rows])
        return out

    def check(self, contacts: Contacts) -> np.ndarray:
        return np.full(len(contacts), Outcome.RUNNING, dtype=np.int8)

    def __str__(self) -> str:
        return f"family {self.family.spec}"


# ---------------------------------------------------------------------- the guaranteed system
def _required_headings(rule: BounceRule, edge_vectors: np.ndarray) -> list[np.ndarray] | None:
    """H_r per source segment as a list of heading arrays (all must be safe), ``None`` = all of (0, π).

    ``edge_vectors`` (m, 2): the direction of each source segment's edge."""
    m = len(edge_vectors)
    if isinstance(rule, Fixed):
        return [np.full(m, rule.theta)]
    if isinstance(rule, MonotoneFixed):
        # the rule's tie: an edge perpendicular to the axis (or θ = π/2) always gets θ
        one_choice = (edge_vectors @ np.asarray(rule.axis) == 0) | (rule.theta == math.pi / 2)
        return [np.full(m, rule.theta), np.where(one_choice, rule.theta, math.pi - rule.theta)]
    return None  # specular, relative: the heading sweeps (0, π) with the arrival direction


def _in_safe_set(graph: Any, arcs: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """For each arc k (rows ``arcs``), is heading theta[k] in one of its safe intervals (closed)?"""
    out = np.zeros(len(arcs), dtype=bool)
    off = graph.set_offsets
    counts = (off[arcs + 1] - off[arcs]).astype(np.int64)
    if counts.sum() == 0:
        return out
    rows = np.repeat(np.arange(len(arcs)), counts)
    flat = np.concatenate([np.arange(off[a], off[a + 1]) for a in arcs[counts > 0]])
    inside = (graph.set_lo[flat] <= theta[rows]) & (theta[rows] <= graph.set_hi[flat])
    np.logical_or.at(out, rows, inside)
    return out


def guaranteed_arcs(summary: Any, family: RuleFamily) -> np.ndarray:
    """Boolean mask over the BVG arcs: the arcs of the guaranteed system G_F (module docstring)."""
    graph = summary.graph
    safe = graph.safe
    if family.is_free:
        return safe.copy()
    env = graph.partition.env
    seg_edge = np.asarray(graph.partition.seg_edge, dtype=np.int64)
    vectors = np.asarray(env.edge_end, dtype=float) - np.asarray(env.edge_start, dtype=float)
    arcs = np.flatnonzero(safe)
    src_vectors = vectors[seg_edge[graph.source[arcs]]]
    keep = np.zeros(graph.n_arcs, dtype=bool)
    for rule in family.members:
        required = _required_headings(rule, src_vectors)
        if required is None:
            continue
        ok = np.ones(len(arcs), dtype=bool)
        for theta in required:
            ok &= _in_safe_set(graph, arcs, theta)
        keep[arcs[ok]] = True
    return keep


# ---------------------------------------------------------------------- the metric
@dataclass(frozen=True)
class RuleReachability:
    """§8.2: reachability of the systems a rule family induces (module docstring), one family per row.

    The family is the row's ``rule`` option (a grid axis of the study, :data:`DEFAULT_FAMILIES`).
    """

    families: tuple[str, ...] = DEFAULT_FAMILIES
    family_size: int = 5
    trials: int = 200
    bounces: int = 50

    name: ClassVar[str] = "rules"
    columns: ClassVar[tuple[str, ...]] = (
        "segments", "arcs", "safe_arcs", "members", "guaranteed_arcs", "unreachable", "scc", "wcc",
        "visited", "coverage", "recurrent", "flagged",
    )

    labels: ClassVar[dict[str, str]] = {"unreachable": "guaranteed: unreachable share", "coverage": "one run: share of ∂P′ hit"}

    def __post_init__(self) -> None:
        for name, value, low in (("family_size", self.family_size, 1), ("trials", self.trials, 1), ("bounces", self.bounces, 2)):
            if isinstance(value, bool) or not isinstance(value, int) or value < low:
                raise InputError(f"expected {name} >= {low}, got {name}={value!r}")
        if not self.families:
            raise InputError("expected at least one rule family")
        for spec in self.families:
            parse_family(spec, family_size=self.family_size)  # a bad family is reported before any work
        object.__setattr__(self, "families", tuple(s.strip().lower() for s in self.families))

    @property
    def options(self) -> tuple[tuple[str, tuple], ...]:
        return (("rule", self.families),)

    @property
    def panels(self) -> tuple[tuple[str, dict], ...]:
        return tuple((column, {"rule": f}) for column in ("unreachable", "coverage") for f in self.families)

    def __call__(self, env: Environment, *, seed: int, rule: str = "any", **options: Any) -> dict:
        family = parse_family(rule, family_size=self.family_size)
        summary = safe_graph_summary(env)
        graph = summary.graph
        keep = guaranteed_arcs(summary, family)
        src, dst = graph.source[keep], graph.target[keep]
        _, unreachable = unreachable_fraction(summary.lengths, src, dst)
        counts = component_counts(summary.n_segments, src, dst)
        runs = simulate_policy(env, FamilyPolicy(family), None, bounces=self.bounces, trials=self.trials,
                               seed=np.random.default_rng([int(seed), 8, 2]))
        segs = runs.segments(graph.partition)
        total = float(summary.lengths.sum())
        lengths = summary.lengths / total if total > 0 else summary.lengths

        def hits(block: np.ndarray) -> np.ndarray:  # (robots, segments): robot r hit segment s
            out = np.zeros((block.shape[0], summary.n_segments), dtype=bool)
            r, c = np.nonzero(block >= 0)
            out[r, block[r, c]] = True
            return out

        legs, late = hits(segs[:, 2:]), hits(segs[:, self.bounces // 2 + 1:])
        return {
            **summary.sizes(),
            "members": len(family.members),
            "guaranteed_arcs": int(np.count_nonzero(keep)),
            "unreachable": unreachable,
            "scc": counts["scc"],
            "wcc": counts["wcc"],
            "visited": float(lengths[legs.any(axis=0)].sum()),
            "coverage": float(np.mean(legs @ lengths)),
            "recurrent": float(np.mean(late @ lengths)),
            "flagged": float(np.mean(runs.flagged)),
        }

    def spec(self) -> dict:
        return {"metric": self.name, "family_size": self.family_size, "trials": self.trials, "bounces": self.bounces}

