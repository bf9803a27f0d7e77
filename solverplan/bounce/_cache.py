"""Reuse of built safe bounce visibility graphs: in memory per process, on disk when asked.

A safe BVG depends only on the environment's exact rings (the partition P′ is a function of them)
and on the construction's version, so a built graph is reused whenever the same rings come again:

- **in memory** (always): the last few graphs built in this process, keyed by the environment
  (exact rings) — a second query on one environment in one process does not rebuild it;
- **on disk** (when a directory is set, :func:`set_graph_cache`; the command line sets one by
  default, see docs/contract.md): one ``.npz`` file of plain numpy arrays per graph (no pickle),
  named by the SHA-256 of (format version, the environment's SHA-256, the construction
  parameters), written atomically (temporary file + rename). Only graphs that took at least
  ``min_seconds`` to build are written: smaller ones are faster to rebuild than to read.

A disk entry is never trusted blindly: it must carry the same format version, environment digest
and construction parameters, its partition's fingerprint (the float start points and edge ids of
every segment) must equal the partition rebuilt from the environment, and its arrays must have the
shapes, types and invariants of a graph (sorted unique arcs, consistent interval offsets). An entry
that fails any check — stale, truncated, corrupt, or of another version — is ignored and rebuilt
(and overwritten).

The arrays of a cached graph are shared by every caller that gets it, so they are read-only.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import tempfile
import threading
from collections import OrderedDict
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from solverplan.result import EnvironmentRecord

if TYPE_CHECKING:
    from solverplan.bounce.bvg import SafeBVG
    from solverplan.bounce.partition import Partition
    from solverplan.environment import Environment

__all__ = ["FORMAT_VERSION", "set_graph_cache", "graph_cache_directory", "clear_graph_cache", "default_cache_directory"]

logger = logging.getLogger(__name__)

FORMAT_VERSION = 2  # 2: float ends refined where rounding could show (translated or tiny features)
"""Version of the cached arrays and of the construction that made them: bump it whenever either
changes, and every older entry is ignored."""

_PARAMETERS = "partition=algorithm1;safe=exact"
"""The construction parameters a graph depends on (none can be chosen yet; part of every key)."""

_ARRAYS = ("source", "target", "lo", "hi", "n_intervals", "set_offsets", "set_lo", "set_hi", "transition", "phi")
_END_ARRAYS = ("lo_from", "lo_to", "hi_from", "hi_to")

# in memory: at most this many graphs and this many arcs in all (about 110 bytes per arc)
_MEMORY_GRAPHS = 4
_MEMORY_ARCS = 4_000_000

_lock = threading.Lock()
_memory: OrderedDict[Environment, SafeBVG] = OrderedDict()
_directory: Path | None = None
_min_seconds = 1.0


def default_cache_directory() -> Path:
    """``$XDG_CACHE_HOME/solverplan/graphs``, or ``~/.cache/solverplan/graphs`` when it is unset."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "solverplan" / "graphs"


def set_graph_cache(directory: str | os.PathLike[str] | None, *, min_seconds: float = 1.0) -> None:
    """Keep built safe BVGs on disk in ``directory`` (created when first written), or nowhere (``None``).

    Parameters
    ----------
    directory
        Where the ``.npz`` entries live; ``None`` turns the disk cache off (the in-memory one stays).
    min_seconds
        Only graphs whose build took at least this long (seconds) are written.
    """
    global _directory, _min_seconds
    _directory = None if directory is None else Path(directory)
    _min_seconds = float(min_seconds)


def graph_cache_directory() -> Path | None:
    """The disk cache's directory, ``None`` when it is off."""
    return _directory


def clear_graph_cache() -> None:
    """Forget the graphs kept in memory (the disk entries stay)."""
    with _lock:
        _memory.clear()


# ---------------------------------------------------------------------- lookup and store
def lookup(env: Environment, partition: Partition | None) -> SafeBVG | None:
    """The cached graph of ``env`` (for ``partition`` when given: it must be P′ of ``env``), or ``None``."""
    with _lock:
        graph = _memory.get(env)
        if graph is not None:
            _memory.move_to_end(env)
    if graph is None and _directory is not None:
        graph = _load(env, partition)
        if graph is not None:
            _remember(env, graph)
    if graph is None:
        return None
    return _for(graph, env, partition)


def store(env: Environment, graph: SafeBVG, seconds: float) -> SafeBVG:
    """Keep ``graph`` (built for ``env`` in ``seconds``); returns it with its arrays read-only."""
    for name in (*_ARRAYS, "_set_ends"):
        arrays = getattr(graph, name)
        for a in arrays if isinstance(arrays, tuple) else (arrays,):
            a.setflags(write=False)
    _remember(env, graph)
    if _directory is not None and seconds >= _min_seconds:
        _save(env, graph)
    return graph


def _remember(env: Environment, graph: SafeBVG) -> None:
    with _lock:
        _memory[env] = graph
        _memory.move_to_end(env)
        while len(_memory) > _MEMORY_GRAPHS or (len(_memory) > 1 and sum(g.n_arcs for g in _memory.values()) > _MEMORY_ARCS):
            _memory.popitem(last=False)


def _for(graph: SafeBVG, env: Environment, partition: Partition | None) -> SafeBVG | None:
    """``graph`` answering for this environment object and partition (names and identities matter
    to the answers; the arrays are shared)."""
    p = graph.partition
    if partition is not None and partition is not p:
        if partition.segments != p.segments or partition.ring_offsets != p.ring_offsets:
            return None  # another partition of these rings: not the graph asked for
        return replace(graph, partition=partition)
    if env is not p.env:
        return replace(graph, partition=replace(p, env=env))
    return graph


# ---------------------------------------------------------------------- the disk format
def _key(env: Environment) -> tuple[str, str]:
    digest = EnvironmentRecord.of(env).sha256
    name = hashlib.sha256(f"solverplan-safe-bvg/{FORMAT_VERSION}/{_PARAMETERS}/{digest}".encode()).hexdigest()
    return name, digest


def _fingerprint(partition: Partition) -> str:
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(partition.seg_start, dtype=np.float64).tobytes())
    h.update(np.ascontiguousarray(partition.seg_edge, dtype=np.int64).tobytes())
    h.update(np.asarray(partition.ring_offsets, dtype=np.int64).tobytes())
    return h.hexdigest()


def _save(env: Environment, graph: SafeBVG) -> None:
    assert _directory is not None
    name, digest = _key(env)
    meta = {"version": FORMAT_VERSION, "parameters": _PARAMETERS, "environment": digest,
            "partition": _fingerprint(graph.partition), "n_segments": graph.n_segments, "n_arcs": graph.n_arcs,
            "stats": {k: v for k, v in graph.stats.items() if isinstance(v, (int, float))}}
    arrays = {k: getattr(graph, k) for k in _ARRAYS}
    arrays.update(zip(_END_ARRAYS, graph._set_ends))
    tmp = None
    try:
        _directory.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{name[:16]}.", suffix=".tmp", dir=_directory)
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, meta=np.array(json.dumps(meta, sort_keys=True)), **arrays)
        os.replace(tmp, _directory / f"{name}.npz")
        tmp = None
        logger.debug("graph cache: wrote %s (%d arcs)", name, graph.n_arcs)
    except OSError as exc:  # a cache that cannot be written is no error: the answer stands
        logger.info("graph cache: cannot write in %s (%s)", _directory, exc.strerror or exc)
    finally:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass


def _load(env: Environment, partition: Partition | None) -> SafeBVG | None:
    assert _directory is not None
    name, digest = _key(env)
    path = _directory / f"{name}.npz"
    if not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            if (meta.get("version") != FORMAT_VERSION or meta.get("parameters") != _PARAMETERS
                    or meta.get("environment") != digest):
                raise ValueError("another version, parameters or environment")
            arrays = {k: data[k] for k in (*_ARRAYS, *_END_ARRAYS)}
    except Exception as exc:  # noqa: BLE001 - any unreadable entry is rebuilt, whatever broke it
        logger.info("graph cache: ignoring %s (%s)", path.name, exc)
        return None
    from solverplan.bounce.bvg import SafeBVG
    from solverplan.bounce.partition import partition as make_partition

    p = partition if partition is not None else make_partition(env)
    problem = _check(arrays, meta, p)
    if problem:
        logger.info("graph cache: ignoring %s (%s)", path.name, problem)
        return None
    for a in arrays.values():
        a.setflags(write=False)
    stats = dict(meta.get("stats") or {})
    stats["cached"] = True
    logger.debug("graph cache: read %s (%d arcs)", name, meta["n_arcs"])
    return SafeBVG(partition=p, **{k: arrays[k] for k in _ARRAYS},
                   _set_ends=tuple(arrays[k] for k in _END_ARRAYS), stats=stats)


def _check(arrays: dict[str, np.ndarray], meta: dict, p: Partition) -> str | None:
    """Why these arrays are not the safe BVG of ``p`` (``None`` when they pass every check)."""
    N = len(p.segments)
    if meta.get("n_segments") != N or meta.get("partition") != _fingerprint(p):
        return "its partition differs from this environment's"
    n = meta.get("n_arcs")
    kinds = {"source": "i", "target": "i", "n_intervals": "i", "set_offsets": "i", "transition": "i",
             "lo": "f", "hi": "f", "set_lo": "f", "set_hi": "f", "phi": "f",
             "lo_from": "i", "lo_to": "i", "hi_from": "i", "hi_to": "i"}
    for k, kind in kinds.items():
        if arrays[k].ndim != 1 or arrays[k].dtype.kind != kind:
            return f"array {k} has the wrong type or shape"
    if not isinstance(n, int) or any(len(arrays[k]) != n for k in ("source", "target", "lo", "hi", "n_intervals", "transition", "phi")):
        return "arc arrays of different lengths"
    off = arrays["set_offsets"]
    m = len(arrays["set_lo"])
    if len(off) != n + 1 or off[0] != 0 or off[-1] != m or (np.diff(off) != arrays["n_intervals"]).any():
        return "inconsistent interval offsets"
    if any(len(arrays[k]) != m for k in ("set_hi", *_END_ARRAYS)):
        return "interval arrays of different lengths"
    s, t = arrays["source"], arrays["target"]
    if n and (s.min() < 0 or t.min() < 0 or s.max() >= N or t.max() >= N):
        return "segment ids out of range"
    keys = s.astype(np.int64) * N + t
    if n > 1 and not (np.diff(keys) > 0).all():
        return "arcs not sorted and unique"
    return None
