"""Strategy 6: pursuit with the contact and pebble sensors only — from the cut ordering alone (§VI-E).

Without a gap or bitangent sensor the pursuer cannot tell when a shadow splits or merges; it reasons from the cut
ordering (which Strategy 1 learns with the touch and pebble sensors) about where bitangents *might* be, and
treats every possibility pessimistically. Nothing here looks at the geometry: the input is a
:class:`~solverplan.wallfollow.ordering.CutOrdering`.

- **Primitives** and their activity are those of Strategy 3 (:mod:`~solverplan.wallfollow.pursuit_primitives`):
  ``R{c₁}`` active strictly inside (v_{c₁}, r_{c₁}), ``L{c_k}`` strictly inside (ℓ_{c_k}, v_{c_k}).
- **Candidates** (Prop. 11): reflex vertices v_i, v_j of different chains, right-handed (v_j ∈ [v_i, r_i]),
  with v_i ∉ (r_j, ℓ_j) and v_j ∉ (r_i, ℓ_i). Every candidate is assumed to be a bitangent. The paper says
  every bitangent is right-handed from one of its ends; with reflex chains it need not be (the tests have
  polygons where it is from neither), so the candidates right-handed in the **mirror image** (clockwise order,
  left and right cuts swapped) are taken too, with the propositions applied there.
- **Approximate end points** (Props. 13–15): b̂_ij starts as whichever of ℓ_i, ℓ_j is nearer before v_i,
  and moves towards v_i past the end s of any cut whose other end lies in (v_i, v_j) (a cut's two ends see
  each other); b̂_ji likewise from r_i, r_j after v_j. The true end points satisfy b_ij ∈ [b̂_ij, v_i] and
  b_ji ∈ [v_j, b̂_ji] (tested), so the boundary stretches [b̂_ij, v_i) and (v_j, b̂_ji] contain every point
  of the ordering on the side of a ray where the far shadow is merged into the near one (at the near vertex
  itself the pursuer sees the far shadow on its own). A ray whose stretch lies on an edge of its own reflex
  vertex is dropped: a bitangent ray ends on an edge not incident to its vertex (general position), and every ray
  of a pair starts next to its near vertex, so a longer one in the same direction covers these cells anyway
  (issue #26: a pair right-handed both ways made 6-vertex polygons that one RFOLLOW clears unsolvable).
- **Labels**: a shadow component is a compound (a set of primitives) with a label. An action that passes a
  stretch where a candidate may merge two shadows merges *every* active primitive of the near vertex's chain
  with every active one of the far vertex's chain (the pursuer cannot tell which shadows they are) — a merge
  ORs the labels;
  splits are never assumed (a compound only shrinks when a primitive disappears: its label stays with the
  rest); a primitive that appears is a new compound labelled 0. Within one action: appearances, then merges,
  then disappearances (Lemma 16).

Every step over-approximates where the evader may be, so a plan that ends with every label 0 is correct
(Prop. 17) — the tests replay each with the geometric ground truth. The search may miss plans (completeness is
open, and the pessimism here is coarser than the paper's), so finding none proves nothing: ``not-found``.

>>> from solverplan.wallfollow.ordering import CutOrdering
>>> order = CutOrdering.from_labels(["v0", "l3", "v1", "v2", "v3", "v4", "v5", "r3"])
>>> pursuer = ContactPursuit(order)
>>> pursuer.primitives, sorted(pursuer.active("v1")), pursuer.candidates
(('R3', 'L3'), ['L3'], ())
"""

from __future__ import annotations

from dataclasses import dataclass

from solverplan.wallfollow.ordering import CutOrdering

__all__ = ["ContactPursuit", "Candidate", "ContactStatus"]

#: The pursuit status: every compound (a set of primitives) with its label (True: the evader may be there).
ContactStatus = frozenset[tuple[frozenset[str], bool]]


@dataclass(frozen=True, slots=True)
class Candidate:
    """A bitangent candidate ``(i, j)`` (right-handed) and the approximate end points of its two rays, as
    points of the cut ordering: ``b_ij`` before v_i, ``b_ji`` after v_j — counter-clockwise, or clockwise when
    ``mirrored`` (right-handed in the mirror image)."""

    i: int
    j: int
    b_ij: str
    b_ji: str
    mirrored: bool = False


def _unmirror(label: str) -> str:
    return {"l": "r", "r": "l"}.get(label[0], label[0]) + label[1:]


class ContactPursuit:
    """Strategy 6's bookkeeping on a cut ordering."""

    def __init__(self, ordering: CutOrdering) -> None:
        self.ordering = ordering
        labels = ordering.labels
        self._size = len(labels)
        self._at = {label: k for k, label in enumerate(labels)}
        n = ordering.n
        reflex = set(ordering.reflex)
        chains: list[tuple[int, ...]] = []
        for v in sorted(reflex):
            if (v - 1) % n in reflex and len(reflex) < n:
                continue
            chain = [v]
            while (chain[-1] + 1) % n in reflex and (chain[-1] + 1) % n != v:
                chain.append((chain[-1] + 1) % n)
            chains.append(tuple(chain))
        self._chain = {v: c for c in chains for v in c}
        self.primitives = tuple(p for c in chains for p in (f"R{c[0]}", f"L{c[-1]}"))
        self._interval = {}
        for c in chains:
            self._interval[f"R{c[0]}"] = (self._at[f"v{c[0]}"], self._at[f"r{c[0]}"])
            self._interval[f"L{c[-1]}"] = (self._at[f"l{c[-1]}"], self._at[f"v{c[-1]}"])
        # Candidates right-handed as the paper states them, and those right-handed in the mirror image (clockwise
        # order, left and right swapped): with reflex chains a bitangent may be right-handed from neither end
        # in the counter-clockwise order (the tests show such polygons), and the paper's Props. 11–15 hold for it
        # in the mirror.
        mirror = {f"{ {'l': 'r', 'r': 'l', 'v': 'v'}[label[0]] }{label[1:]}": self._size - 1 - k
                  for k, label in enumerate(labels)}
        found = [(c, False) for c in self._candidates(sorted(reflex), self._at)]
        found += [(c, True) for c in self._candidates(sorted(reflex), mirror)]
        self.candidates = tuple(Candidate(c.i, c.j, _unmirror(c.b_ij) if flip else c.b_ij,
                                          _unmirror(c.b_ji) if flip else c.b_ji, flip) for c, flip in found)
        # The boundary as 2|M| cells: cell 2k is the k-th point of the ordering, cell 2k + 1 the open stretch to the
        # next. Each candidate's two rays: (near, far, the cells where the far shadow may be merged into the near
        # one) — [b̂_ij, v_i) and (v_j, b̂_ji] (in the mirror for a mirrored candidate): at the near vertex itself the
        # far shadow is seen on its own.
        self._cells = 2 * self._size
        self._rays: list[tuple[int, int, frozenset[int]]] = []
        for cand, flip in found:
            at = mirror if flip else self._at
            vi, vj = 2 * at[f"v{cand.i}"], 2 * at[f"v{cand.j}"]
            for near, far, cells in ((cand.i, cand.j, self._cell_range(2 * at[cand.b_ij], vi - 1)),
                                     (cand.j, cand.i, self._cell_range(vj + 1, 2 * at[cand.b_ji]))):
                stretch = frozenset(self._unmirror_cell(c) for c in cells) if flip else cells
                if not any(c % 2 == 0 and labels[c // 2].startswith("v") for c in stretch):
                    # The stretch lies on an edge of the near vertex itself; a bitangent ray ends on an edge not
                    # incident to its vertex (general position: the line through v_i and v_j holds no edge), so
                    # the true end is not here. Every ray of (near, far) starts next to the near vertex, so any
                    # longer one in this direction holds these cells too: dropping it loses no merge (#26).
                    continue
                self._rays.append((near, far, stretch))

    def _unmirror_cell(self, cell: int) -> int:
        """The cell of the ordering that is ``cell`` of the mirror image."""
        k = cell // 2
        if cell % 2 == 0:
            return 2 * (self._size - 1 - k)
        return 2 * ((self._size - 2 - k) % self._size) + 1

    # ------------------------------------------------------------------ the ordering as a circle
    def _walk(self, a: int, x: int) -> int:
        """Steps counter-clockwise from a to x."""
        return (x - a) % self._size

    def _closed(self, a: int, b: int, x: int) -> bool:
        return self._walk(a, x) <= self._walk(a, b)

    def _open(self, a: int, b: int, x: int) -> bool:
        return 0 < self._walk(a, x) < self._walk(a, b)

    def _candidates(self, reflex: list[int], at: dict[str, int]):
        """Right-handed candidates in the counter-clockwise order whose positions are ``at`` (labels of that
        order)."""
        names = {k: label for label, k in at.items()}
        cut_pairs = [(at[f"v{w}"], at[f"{side}{w}"]) for w in reflex for side in "lr"]
        for i in reflex:
            for j in reflex:
                if i == j or self._chain[i] == self._chain[j]:
                    continue
                vi, vj = at[f"v{i}"], at[f"v{j}"]
                if not self._closed(vi, at[f"r{i}"], vj):
                    continue  # not right-handed (the pair is met the other way round)
                if self._open(at[f"r{j}"], at[f"l{j}"], vi) or self._open(at[f"r{i}"], at[f"l{i}"], vj):
                    continue  # Prop. 11: no bitangent
                # Prop. 13, then Prop. 14: the end beyond v_i
                li, lj = at[f"l{i}"], at[f"l{j}"]
                b_ij = li if self._closed(lj, vi, li) else lj
                for w, e in cut_pairs:
                    for s, t in ((e, w), (w, e)):
                        if self._open(vi, vj, t) and self._closed(b_ij, vi, s) and s != vi:
                            b_ij = s if self._walk(b_ij, s) > 0 else b_ij
                # Props. 13 and 15: the end beyond v_j
                ri, rj = at[f"r{i}"], at[f"r{j}"]
                b_ji = ri if self._closed(vj, rj, ri) else rj
                for w, e in cut_pairs:
                    for s, t in ((e, w), (w, e)):
                        if self._open(vi, vj, t) and self._closed(vj, b_ji, s) and s != vj:
                            b_ji = s if self._walk(vj, s) < self._walk(vj, b_ji) else b_ji
                yield Candidate(i, j, names[b_ij], names[b_ji])

    def _cell_range(self, a: int, b: int) -> frozenset[int]:
        """Cells a, a + 1, …, b (cyclically)."""
        return frozenset((a + k) % self._cells for k in range((b - a) % self._cells + 1))

    def _path(self, x: str, y: str, action: str) -> frozenset[int]:
        """The cells a motion passes: the boundary between x and y for a follow, the two ends for a JUMP (its
        inside crosses a ray's possible positions only if an end lies on the merging side: chords that do not
        alternate do not cross)."""
        cx, cy = 2 * self._at[x], 2 * self._at[y]
        if action == "RFOLLOW":
            return self._cell_range(cx, cy)
        if action == "LFOLLOW":
            return self._cell_range(cy, cx)
        return frozenset({cx, cy})

    # ------------------------------------------------------------------ status
    def active(self, label: str) -> frozenset[str]:
        """The primitives active at a point of the cut ordering (as in Strategy 3)."""
        k = self._at[label]
        return frozenset(p for p, (a, b) in self._interval.items() if self._open(a, b, k))

    def start(self, label: str) -> ContactStatus:
        """Every active primitive its own compound, labelled 1 (nothing is known yet)."""
        return frozenset((frozenset({p}), True) for p in self.active(label))

    def _chain_primitives(self, v: int) -> set[str]:
        chain = self._chain[v]
        return {f"R{chain[0]}", f"L{chain[-1]}"}

    def apply(self, x: str, y: str, status: ContactStatus, action: str) -> ContactStatus:
        """The status after ``action`` (RFOLLOW, LFOLLOW or JUMP) from point x to point y of the ordering."""
        before, after = self.active(x), self.active(y)
        compounds = [(set(c), label) for c, label in status]
        for p in after - before:  # appearances: new, seen a moment ago
            compounds.append(({p}, False))
        live = set(before | after)
        path = self._path(x, y, action)
        for near, far, cells in self._rays:
            if not path & cells:
                continue  # nowhere near a place where the far shadow may merge into the near one
            near_prims = self._chain_primitives(near) & live
            far_prims = self._chain_primitives(far) & live
            if not near_prims or not far_prims:
                continue
            touched = [k for k, (c, _) in enumerate(compounds) if c & (near_prims | far_prims)]
            merged = set().union(*(compounds[k][0] for k in touched))
            label = any(compounds[k][1] for k in touched)
            compounds = [cl for k, cl in enumerate(compounds) if k not in touched] + [(merged, label)]
        gone = before - after
        out = []
        for c, label in compounds:
            rest = c - gone
            if rest:
                out.append((frozenset(rest), label))
        return frozenset(out)

    @staticmethod
    def won(status: ContactStatus) -> bool:
        """No compound may hold the evader."""
        return not any(label for _, label in status)
