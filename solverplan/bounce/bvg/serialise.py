"""The safe BVG's outputs: JSON (whole, or streamed a chunk of arcs at a time), text, GraphML, DOT and networkx.

These are the bodies of :class:`~solverplan.bounce.bvg.graph.SafeBVG`'s ``to_*`` and ``json_*`` methods; call them
through the graph. The arcs are read column by column from the graph's arrays, never as one Python object per arc
held at once (the JSON of a large graph is encoded a chunk of arcs at a time, :func:`json_chunks`).
"""

from __future__ import annotations

import html
import io
from typing import TYPE_CHECKING, Iterator

import numpy as np

from solverplan.interval import Interval
from solverplan.runtime import jobs, parallel_map

if TYPE_CHECKING:  # networkx costs ~0.1 s to import: only the conversions load it
    import networkx as nx

    from solverplan.bounce.bvg.graph import SafeBVG

__all__ = ["TRANSITION_NAMES", "to_networkx", "float_sets", "to_json", "json_bytes", "json_chunks", "json_header",
           "arc_dicts", "arcs_text", "to_text", "to_graphml", "to_dot"]

TRANSITION_NAMES = {1: "right", -1: "left", 0: "parallel"}
"""Def. 8's side of an arc by its ``transition`` code."""


def to_networkx(graph: SafeBVG, *, safe_only: bool = False) -> nx.DiGraph:
    """The body of :meth:`SafeBVG.to_networkx <solverplan.bounce.bvg.graph.SafeBVG.to_networkx>`."""
    import networkx as nx  # here, not at the top: only the conversions load it (~0.1 s)

    g = nx.DiGraph(name=f"safe BVG of {graph.partition.env.name!r}")
    for s in graph.partition.segments:
        g.add_node(s.id, edge=s.edge, t0=float(s.t0), t1=float(s.t1))
    sets = float_sets(graph)
    names = graph.transitions
    for k in range(graph.n_arcs):
        if safe_only and not graph.n_intervals[k]:
            continue
        safe = Interval(float(graph.lo[k]), float(graph.hi[k])) if graph.n_intervals[k] else Interval.EMPTY
        g.add_edge(int(graph.source[k]), int(graph.target[k]), safe=safe, safe_set=sets[k],
                   transition=names[k], phi=float(graph.phi[k]))
    return g


def float_sets(graph: SafeBVG) -> list[tuple[Interval, ...]]:
    """Every arc's safe intervals, as float :class:`~solverplan.interval.Interval` tuples."""
    out = []
    off = graph.set_offsets
    for k in range(graph.n_arcs):
        out.append(tuple(Interval(float(graph.set_lo[r]), float(graph.set_hi[r])) for r in range(int(off[k]), int(off[k + 1]))))
    return out


def to_json(graph: SafeBVG, *, safe: bool | None = None) -> dict:
    """The body of :meth:`SafeBVG.to_json <solverplan.bounce.bvg.graph.SafeBVG.to_json>`."""
    safe = graph.labelled if safe is None else safe
    out = json_header(graph, safe)
    out["arcs"] = arc_dicts(graph, 0, graph.n_arcs, safe)
    return out


def json_bytes(graph: SafeBVG, *, safe: bool | None = None, end: bytes = b"", arcs_per_chunk: int = 1 << 13) -> bytearray:
    """The body of :meth:`SafeBVG.json_bytes <solverplan.bounce.bvg.graph.SafeBVG.json_bytes>`."""
    out = bytearray()
    for chunk in json_chunks(graph, safe=safe, end=end, arcs_per_chunk=arcs_per_chunk):
        out += chunk
    return out


def json_chunks(graph: SafeBVG, *, safe: bool | None = None, end: bytes = b"", arcs_per_chunk: int = 1 << 13) -> Iterator[bytes]:
    """The body of :meth:`SafeBVG.json_chunks <solverplan.bounce.bvg.graph.SafeBVG.json_chunks>`."""
    import orjson

    safe = graph.labelled if safe is None else safe
    head = orjson.dumps(json_header(graph, safe))
    yield head[:-1] + (b',"arcs":[' if len(head) > 2 else b'"arcs":[')
    n = graph.n_arcs
    if n >= SPLIT_MIN_ARCS and jobs() > 1:  # the texts of runs of chunks, made by forked workers (the same bytes)
        per_run = arcs_per_chunk * max(1, SPLIT_ARCS_PER_RUN // arcs_per_chunk)

        def run(a: int) -> bytes:
            b = min(n, a + per_run)
            return b"".join(_chunk_text(graph, c, min(b, c + arcs_per_chunk), safe) for c in range(a, b, arcs_per_chunk))

        # a run's text is ≈ 135 bytes per arc with the safe sets: larger ones come through the pipe
        yield from parallel_map(run, range(0, n, per_run), slot_bytes=192 * per_run)
    else:
        for a in range(0, n, arcs_per_chunk):
            yield _chunk_text(graph, a, min(n, a + arcs_per_chunk), safe)
    yield b"]}" + end


SPLIT_MIN_ARCS = 200_000
"""Graphs with fewer arcs are encoded in this process (:func:`json_chunks`); larger ones by the worker processes of
:func:`~solverplan._arrays.process_map` when the setting ``jobs`` allows (by default the cores available)."""
SPLIT_ARCS_PER_RUN = 1 << 16
"""Arcs a worker encodes at a time (about 9 MB of text with the safe sets)."""


def _chunk_text(graph: SafeBVG, a: int, b: int, safe: bool) -> bytes:
    """Arcs a..b−1 as they follow the list's opening bracket: :func:`arcs_text`, after a comma unless a is 0."""
    text = arcs_text(graph, a, b, safe)
    return b"," + text if a else text


# The constant pieces of an arc's JSON, in the order of the segments arcs_text assembles.
_OPEN = (b'{"from":', b',{"from":')
_TO = b',"to":'
_SAFE = b',"safe":'
_NULL = b"null"
_SET = b',"safe_set":['
_CLOSE = b"]}"


def arcs_text(graph: SafeBVG, a: int, b: int, safe: bool) -> bytes:
    """The compact JSON of arcs a..b−1, comma-separated without the list's brackets: the same bytes as
    ``orjson.dumps(arc_dicts(graph, a, b, safe))[1:-1]``, made without a Python object per arc.

    Each column is encoded once by orjson from its numpy array (numbers never contain a comma, so the commas of its
    text mark where each value starts), and the arcs' text is gathered from those texts and a few constants by one
    index array: every arc is the same sequence of segments (a constant, a value, a constant, …), a safe set is one
    contiguous run of ``[lo,hi]`` pairs of the encoded list of all the chunk's intervals.
    """
    import orjson

    n = b - a
    if n <= 0:
        return b""
    pool = _Pool()
    codes = graph.transition[a:b].astype(np.int64) + 1  # −1, 0, 1 → 0, 1, 2
    src = pool.numbers(graph.source[a:b])
    dst = pool.numbers(graph.target[a:b])
    first = np.zeros(n, dtype=np.int64)
    first[1:] = 1
    columns: list[tuple[np.ndarray, np.ndarray]] = [pool.constants(_OPEN, first), src, pool.constant(_TO, n), dst]
    if not safe:
        ends = tuple(f',"transition":"{TRANSITION_NAMES[c]}"}}'.encode() for c in (-1, 0, 1))
        columns.append(pool.constants(ends, codes))
    else:
        count = graph.n_intervals[a:b]
        has = count > 0
        widest = pool.constants((_NULL,), np.zeros(n, dtype=np.int64))
        w_start, w_stop = pool.pairs(orjson, graph.lo[a:b][has], graph.hi[a:b][has])
        widest[0][has], widest[1][has] = w_start, w_stop - w_start
        mids = tuple(f',"transition":"{TRANSITION_NAMES[c]}","phi":'.encode() for c in (-1, 0, 1))
        off = graph.set_offsets[a : b + 1]
        r0 = int(off[0])
        p_start, p_stop = pool.pairs(orjson, graph.set_lo[r0 : int(off[-1])], graph.set_hi[r0 : int(off[-1])])
        run_start = np.zeros(n, dtype=np.int64)
        run_len = np.zeros(n, dtype=np.int64)
        first_pair, last_pair = off[:-1][has] - r0, off[1:][has] - r0 - 1
        run_start[has] = p_start[first_pair]
        run_len[has] = p_stop[last_pair] - p_start[first_pair]
        columns += [pool.constant(_SAFE, n), widest, pool.constants(mids, codes), pool.numbers(graph.phi[a:b]),
                    pool.constant(_SET, n), (run_start, run_len), pool.constant(_CLOSE, n)]
    starts = np.stack([c[0] for c in columns], axis=1).ravel()
    lengths = np.stack([c[1] for c in columns], axis=1).ravel()
    placed = np.cumsum(lengths) - lengths  # where each segment starts in the output
    index = np.repeat(starts - placed, lengths) + np.arange(int(placed[-1] + lengths[-1]), dtype=np.int64)
    return pool.array()[index].tobytes()


class _Pool:
    """The texts :func:`arcs_text` gathers from, one byte array, and the segments (start in the pool, length) of
    each value or constant."""

    def __init__(self) -> None:
        self.parts: list[np.ndarray] = []
        self.size = 0

    def add(self, data: bytes) -> tuple[int, np.ndarray]:
        text = np.frombuffer(data, dtype=np.uint8)
        self.parts.append(text)
        self.size += len(text)
        return self.size - len(text), text

    def array(self) -> np.ndarray:
        return np.concatenate(self.parts)

    def constant(self, data: bytes, n: int) -> tuple[np.ndarray, np.ndarray]:
        at, _ = self.add(data)
        return np.full(n, at, dtype=np.int64), np.full(n, len(data), dtype=np.int64)

    def constants(self, options: tuple[bytes, ...], which: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per row, the constant ``options[which[row]]``."""
        at = np.array([self.add(o)[0] for o in options], dtype=np.int64)
        size = np.array([len(o) for o in options], dtype=np.int64)
        return at[which], size[which]

    def numbers(self, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every value of a 1-d numeric array, as orjson writes it."""
        import orjson

        at, text = self.add(orjson.dumps(np.ascontiguousarray(values), option=orjson.OPT_SERIALIZE_NUMPY))
        if not len(values):
            return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
        commas = np.flatnonzero(text == ord(","))
        starts = np.concatenate([[1], commas + 1])
        stops = np.concatenate([commas, [len(text) - 1]])
        return at + starts, stops - starts

    def pairs(self, orjson, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The text ``[lo,hi]`` of every pair: where its ``[`` is, and one past its ``]``."""
        if not len(lo):
            return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
        at, text = self.add(orjson.dumps(np.column_stack([lo, hi]), option=orjson.OPT_SERIALIZE_NUMPY))
        opens = np.flatnonzero(text[1:] == ord("[")) + 1
        closes = np.flatnonzero(text[:-1] == ord("]"))
        return at + opens, at + closes + 1


def json_header(graph: SafeBVG, safe: bool) -> dict:
    """The JSON answer's fields before its arcs: name and counts."""
    out = {
        "name": graph.partition.env.name,
        "n_segments": graph.n_segments,
        "n_arcs": graph.n_arcs,
    }
    if safe:
        out["n_safe_arcs"] = graph.n_safe_arcs
    return out


def arc_dicts(graph: SafeBVG, a: int, b: int, safe: bool) -> list[dict]:
    """The JSON arcs of rows a..b−1."""
    # Built column-wise with zip (no per-arc indexing, one list slice per safe set): this runs
    # once per `solverplan graph` over up to ~10⁶ arcs, where it was the slowest step.
    names = [TRANSITION_NAMES[t] for t in graph.transition[a:b].tolist()]
    src, dst = graph.source[a:b].tolist(), graph.target[a:b].tolist()
    if not safe:
        return [{"from": i, "to": j, "transition": t} for i, j, t in zip(src, dst, names)]
    off = graph.set_offsets[a : b + 1]
    r0, r1 = int(off[0]), int(off[-1])
    pieces = [[x, y] for x, y in zip(graph.set_lo[r0:r1].tolist(), graph.set_hi[r0:r1].tolist())]
    off = (off - r0).tolist()
    sets = [pieces[x:y] for x, y in zip(off, off[1:])]
    widest = [[x, y] if c else None for x, y, c in zip(graph.lo[a:b].tolist(), graph.hi[a:b].tolist(), graph.n_intervals[a:b].tolist())]
    return [
        {"from": i, "to": j, "safe": w, "transition": t, "phi": f, "safe_set": ss}
        for i, j, w, t, f, ss in zip(src, dst, widest, names, graph.phi[a:b].tolist(), sets)
    ]


def to_text(graph: SafeBVG, *, width: int = 100, safe: bool | None = None) -> str:
    """The body of :meth:`SafeBVG.to_text <solverplan.bounce.bvg.graph.SafeBVG.to_text>`."""
    safe = graph.labelled if safe is None else safe
    buffer = io.StringIO()
    env = graph.partition.env
    buffer.write(f"{'safe ' if safe else ''}bounce visibility graph of {env.name!r}\n")
    buffer.write(f"  segments: {graph.n_segments}   arcs: {graph.n_arcs}")
    if safe:
        buffer.write(f"   safe arcs: {graph.n_safe_arcs}")
        multi = int(np.count_nonzero(graph.n_intervals > 1))
        if multi:
            buffer.write(f"   arcs with several safe intervals: {multi}")
    buffer.write("\n")
    starts = np.searchsorted(graph.source, np.arange(graph.n_segments + 1))
    for i in range(graph.n_segments):
        rows = range(int(starts[i]), int(starts[i + 1]))
        if not rows:
            continue
        seg = graph.partition.segments[i]
        head = f"{i:>5} (e{seg.edge}) →"
        if not safe:
            items = [str(int(graph.target[k])) for k in rows]
        else:
            items = []
            for k in rows:
                j = int(graph.target[k])
                if graph.n_intervals[k]:
                    extra = f"+{int(graph.n_intervals[k]) - 1}" if graph.n_intervals[k] > 1 else ""
                    items.append(f"{j}[{graph.lo[k]:.4f},{graph.hi[k]:.4f}]{extra}")
                else:
                    items.append(f"{j}")
        line, lines = head, []
        for item in items:
            if len(line) + 1 + len(item) > width:
                lines.append(line)
                line = " " * len(head)
            line += " " + item
        lines.append(line)
        buffer.write("\n".join(lines) + "\n")
    return buffer.getvalue()


def to_graphml(graph: SafeBVG, *, safe: bool | None = None) -> str:
    """The body of :meth:`SafeBVG.to_graphml <solverplan.bounce.bvg.graph.SafeBVG.to_graphml>`."""
    import json

    import networkx as nx  # here, not at the top: only this conversion needs it

    safe = graph.labelled if safe is None else safe
    g = nx.DiGraph()
    for s in graph.partition.segments:
        g.add_node(s.id, edge=int(s.edge), t0=float(s.t0), t1=float(s.t1))
    names = graph.transitions
    off = graph.set_offsets
    for k in range(graph.n_arcs):
        attrs = {"transition": names[k], "phi": float(graph.phi[k])}
        if safe:
            if graph.n_intervals[k]:
                attrs["safe_lo"] = float(graph.lo[k])
                attrs["safe_hi"] = float(graph.hi[k])
            attrs["safe_set"] = json.dumps([[float(graph.set_lo[r]), float(graph.set_hi[r])] for r in range(int(off[k]), int(off[k + 1]))])
        g.add_edge(int(graph.source[k]), int(graph.target[k]), **attrs)
    return "\n".join(nx.generate_graphml(g)) + "\n"


def to_dot(graph: SafeBVG, *, safe: bool | None = None) -> str:
    """The body of :meth:`SafeBVG.to_dot <solverplan.bounce.bvg.graph.SafeBVG.to_dot>`."""
    safe = graph.labelled if safe is None else safe
    out = io.StringIO()
    name = graph.partition.env.name.replace('"', "'")
    out.write(f'digraph "bvg {html.escape(name)}" {{\n  node [shape=circle, fontsize=10];\n')
    for s in graph.partition.segments:
        out.write(f'  {s.id} [tooltip="e{s.edge} t=[{float(s.t0):.4g}, {float(s.t1):.4g}]"];\n')
    names = graph.transitions
    for k in range(graph.n_arcs):
        i, j = int(graph.source[k]), int(graph.target[k])
        if safe and graph.n_intervals[k]:
            label = f"[{graph.lo[k]:.3f}, {graph.hi[k]:.3f}]"
            if graph.n_intervals[k] > 1:
                label += f" +{int(graph.n_intervals[k]) - 1}"
            out.write(f'  {i} -> {j} [label="{label}", transition={names[k]}];\n')
        elif safe:
            out.write(f'  {i} -> {j} [style=dashed, color=gray70, transition={names[k]}];\n')
        else:
            out.write(f"  {i} -> {j} [transition={names[k]}];\n")
    out.write("}\n")
    return out.getvalue()
