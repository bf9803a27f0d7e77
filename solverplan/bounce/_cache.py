"""Reuse of built safe bounce visibility graphs: in memory per process, on disk when asked.

A safe BVG is a function of its partition P′ alone: the environment's exact rings and the exact cut
points of every segment (Algorithm 1's, and any extra cut a planner refines the partition with). So a
graph is keyed by the **partition digest** (:func:`partition_digest`): the SHA-256 of the rings and of
every segment's exact ``(edge, t0, t1)``. Computing it reads the partition the caller already has; it
never rebuilds one. The graph of P′ itself — the partition :func:`~solverplan.bounce.partitions.partition`
makes, which is a function of the environment's exact rings alone — is keyed by the **environment digest**
(:func:`environment_digest`, the SHA-256 of the exact rings: of the canonical walls when the planners ask) and
its entry keeps P′'s inserted points, so a process that finds it rebuilds neither the graph nor the
partition (Algorithm 1 is most of a large map's cost); the partition read back is checked against the entry's
partition digest and remembered as the environment's partition for the rest of the process.

- **in memory** (always): the last few graphs built or read in this process, by partition digest (and,
  for a call with an environment, by the environment, so that a second query on it does not even
  partition it again);
- **on disk** (when a directory is set, :func:`set_graph_cache`; the command line sets one by
  default, see docs/contract.md): one file per graph, ``<name>.spg``, where the name is the SHA-256
  of (format version, construction parameters, partition digest).

The disk format (version :data:`FORMAT_VERSION`) is plain bytes, no pickle, no zip::

    MAGIC | header length (8 bytes, little endian) | header (JSON, padded to 8 bytes)
          | the arrays, raw little-endian, in the fixed order of _LAYOUT
          | SHA-256 of everything before it (32 bytes, written last)

The header names the format version, the construction parameters, the partition digest it was built
for, the number of segments, arcs and safe intervals (and, for P′ itself, the environment digest and the
inserted points as exact ``[edge, t numerator, t denominator, reflex vertex, from vertex, sources]``); the
loader computes every array's place from those counts (the file says nothing else about its layout) and
requires the file size to match.

**What is checked on load, and what a failed check does.** An entry is used only if it is a regular
file (not a symlink, not a device), no larger than the cache's size cap, starts with the magic, its
trailing SHA-256 matches its bytes (a truncated, corrupted or partially edited file fails here), its
header names this format version, these parameters and *this* partition digest (an entry of another
polygon or partition copied under this name fails here), its sizes match the partition (segment
count, at most N(N − 1) arcs, the exact file size), and its arrays have the invariants of a graph
(sorted unique arcs, ids in range, consistent interval offsets). Anything else is a **miss**: logged
(INFO: ``-v`` shows it), rebuilt, and the entry overwritten — never an error, never trusted.

**What it does not protect against**: someone who rewrites an entry *and* its digest (the digest is
not a signature: anyone who can write the folder can forge one). That is why every answer the command
line gives is checked by the independent exact checker before it leaves
(:mod:`solverplan.certify.gate`), whatever the cache said; a failed check discards the cached graphs
(:func:`discard_graphs`) and answers again with freshly built ones (:func:`fresh_graphs`).

Writes are atomic (a temporary file in the folder, flushed, then renamed over the entry), with the
permissions of a plain ``open(path, "w")`` (``0o666 & ~umask``), so concurrent processes sharing a
folder see either a whole entry or none. Only graphs of at least ``min_arcs`` arcs are written (smaller
ones are faster to rebuild than to read: the threshold is the graph's size, not the build's wall time,
so whether a graph is kept does not depend on the machine's load; an optional ``min_seconds`` keeps graphs
whose build took that much CPU time, not wall time, for the same reason). The folder is capped at
``max_bytes``: after a write, the least recently used entries (a hit refreshes an entry's time) are
removed until it fits. :func:`purge_graph_cache` empties it (``solverplan cache clear``).

The arrays of a cached graph are shared by every caller that gets it, so they are read-only.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import logging
import os
import re
import secrets
import stat
import threading
import time
from collections import OrderedDict
from dataclasses import dataclass, replace
from fractions import Fraction
from pathlib import Path
from typing import TYPE_CHECKING, Iterator

import numpy as np

from solverplan.limits import memory_limit
from solverplan.result import EnvironmentRecord
from solverplan.runtime import DEFAULT_MAX_BYTES, DEFAULT_MIN_ARCS, configure, default_cache_directory, settings

if TYPE_CHECKING:
    from solverplan.bounce.bvg.graph import SafeBVG
    from solverplan.bounce.partitions import InsertedPoint, Partition
    from solverplan.environment import Environment

__all__ = ["FORMAT_VERSION", "DEFAULT_MIN_ARCS", "DEFAULT_MAX_BYTES", "GraphCacheReport", "set_graph_cache",
           "graph_cache_directory", "clear_graph_cache", "default_cache_directory", "partition_digest", "environment_digest",
           "purge_graph_cache", "graph_cache_report", "discard_graphs", "fresh_graphs", "read_from_disk"]

logger = logging.getLogger(__name__)

FORMAT_VERSION = 4
"""Version of the cached arrays and of the construction that made them: bump it whenever either
changes, and every older entry is ignored.

2: float ends refined where rounding could show (translated or tiny features). 3: own format with a trailing
SHA-256, keyed by the partition's exact content. 4: the graph of P′ itself keyed by the environment's exact rings,
with P′'s inserted points (no partition is rebuilt to find it)."""

_PARAMETERS = "partition=given;safe=exact"
"""The construction parameters a graph depends on besides its partition (part of every key)."""

_MAGIC = b"solverplan safe-bvg\n"
_SUFFIX = ".spg"
_DIGEST = 32
_MAX_HEADER = 1 << 26  # the inserted points of P′ are in the header: ≈ 40 bytes each

# (name, dtype, length: "n" arcs, "n+1", "m" safe intervals), in file order
_LAYOUT: tuple[tuple[str, str, str], ...] = (
    ("source", "<i8", "n"), ("target", "<i8", "n"), ("lo", "<f8", "n"), ("hi", "<f8", "n"),
    ("n_intervals", "<i8", "n"), ("set_offsets", "<i8", "n+1"), ("set_lo", "<f8", "m"), ("set_hi", "<f8", "m"),
    ("transition", "|i1", "n"), ("phi", "<f8", "n"),
    ("lo_from", "<i8", "m"), ("lo_to", "<i8", "m"), ("hi_from", "<i8", "m"), ("hi_to", "<i8", "m"),
)
_ARRAYS = ("source", "target", "lo", "hi", "n_intervals", "set_offsets", "set_lo", "set_hi", "transition", "phi")
_END_ARRAYS = ("lo_from", "lo_to", "hi_from", "hi_to")

_STALE_TEMPORARY = 3600.0  # seconds after which a temporary file left by a killed writer is removed

# in memory: at most this many graphs and this many arcs in all (about 110 bytes per arc)
_MEMORY_GRAPHS = 4
_MEMORY_ARCS = 4_000_000

_lock = threading.Lock()
_memory: OrderedDict[str, SafeBVG] = OrderedDict()
_aliases: OrderedDict[Environment, str] = OrderedDict()  # environment → digest of its plain P′
_read_here: dict[str, Path] = {}  # digests of the graphs this process read from disk → their files
_fresh = 0  # > 0 inside fresh_graphs(): no graph is reused

_OURS = re.compile(r"[0-9a-f]{64}\.(spg|npz)|\.[0-9a-f]{16}\.[0-9a-z_]+\.tmp")


def set_graph_cache(directory: str | os.PathLike[str] | None, *, min_arcs: int = DEFAULT_MIN_ARCS,
                    min_seconds: float | None = None, max_bytes: int = DEFAULT_MAX_BYTES) -> None:
    """Keep built safe BVGs on disk in ``directory`` (created when first written), or nowhere (``None``), in the
    whole process: ``configure(graph_cache=...)`` by another name; :func:`solverplan.config` changes it for a block.

    Parameters
    ----------
    directory
        Where the entries live; ``None`` turns the disk cache off (the in-memory one stays).
    min_arcs
        Only graphs with at least this many arcs are written (0: every graph).
    min_seconds
        Also write graphs whose build took at least this much CPU time (seconds of this process, not wall
        time); ``None`` (default): the size alone decides, so the same graphs are kept whatever the machine's load.
    max_bytes
        The folder's size cap: after a write, least recently used entries are removed until it fits.
    """
    configure(graph_cache=None if directory is None else Path(directory), graph_cache_min_arcs=min_arcs,
              graph_cache_min_seconds=min_seconds, graph_cache_max_bytes=max_bytes)


def graph_cache_directory() -> Path | None:
    """The disk cache's directory in force here, ``None`` when it is off."""
    return settings().graph_cache


def clear_graph_cache() -> None:
    """Forget the graphs kept in memory (the disk entries stay; :func:`purge_graph_cache` removes them)."""
    with _lock:
        _memory.clear()
        _aliases.clear()


def discard_graphs() -> int:
    """Forget every graph kept in memory and delete the disk entries this process read (a graph that
    gave an answer the exact checker refused is not to be reused). Returns the number of files deleted."""
    with _lock:
        _memory.clear()
        _aliases.clear()
        files = list(_read_here.values())
        _read_here.clear()
    deleted = 0
    for path in files:
        try:
            os.unlink(path)
            deleted += 1
            logger.info("graph cache: deleted %s", path.name)
        except FileNotFoundError:
            pass
        except OSError as exc:
            logger.info("graph cache: cannot delete %s (%s)", path, exc.strerror or exc)
    return deleted


def read_from_disk() -> bool:
    """Whether this process has used a graph read from the disk cache (since the last :func:`discard_graphs`)."""
    with _lock:
        return bool(_read_here)


@contextlib.contextmanager
def fresh_graphs() -> Iterator[None]:
    """Within this block no graph is reused (neither from memory nor from disk): every one is built; built
    graphs are still kept (and written) as usual."""
    global _fresh
    with _lock:
        _fresh += 1
    try:
        yield
    finally:
        with _lock:
            _fresh -= 1


# ---------------------------------------------------------------------- the key
def partition_digest(p: Partition) -> str:
    """SHA-256 (hex) of a partition's exact content: the environment's exact rings, the ring offsets and every
    segment's exact ``(edge, t0, t1)``. Equal digests mean equal partitions (whatever the objects or the
    environment's name), so equal safe BVGs. Cost: one pass over the segments (no geometry)."""
    h = hashlib.sha256(b"solverplan partition/1\n")
    h.update(EnvironmentRecord.of(p.env).sha256.encode())
    h.update(("\n" + ",".join(map(str, p.ring_offsets)) + "\n").encode())
    h.update("".join(f"{s.edge} {s.t0.numerator}/{s.t0.denominator} {s.t1.numerator}/{s.t1.denominator}\n"
                     for s in p.segments).encode())
    return h.hexdigest()


def environment_digest(env: Environment) -> str:
    """SHA-256 (hex) of an environment's exact rings, whatever its name or file: P′ (so its safe BVG) is a function
    of them alone. It is :class:`~solverplan.result.EnvironmentRecord`'s digest."""
    return EnvironmentRecord.of(env).sha256


def _entry_name(digest: str, kind: str = "partition") -> str:
    """The file name of the entry of a partition digest (``kind`` "partition") or of P′ of an environment digest
    ("environment")."""
    key = digest if kind == "partition" else f"{kind}/{digest}"
    return hashlib.sha256(f"solverplan-safe-bvg/{FORMAT_VERSION}/{_PARAMETERS}/{key}".encode()).hexdigest()


def _is_plain(p: Partition) -> bool:
    """Is ``p`` P′ of its environment, as :func:`~solverplan.bounce.partitions.partition` made it in this process?"""
    from solverplan.bounce.partitions import is_remembered

    return is_remembered(p)


# ---------------------------------------------------------------------- lookup and store
def lookup_environment(env: Environment) -> SafeBVG | None:
    """The graph of ``env``'s plain partition P′ if it is in memory or in the disk cache, else ``None``; no partition
    is made (one read from disk comes with its P′, which :func:`~solverplan.bounce.partitions.partition` then
    returns for ``env`` in this process)."""
    with _lock:
        if _fresh:
            return None
        digest = _aliases.get(env)
        graph = _memory.get(digest) if digest is not None else None
        if graph is not None:
            _memory.move_to_end(digest)  # type: ignore[arg-type]
    if graph is None:
        directory = settings().graph_cache
        graph = _load_plain(directory, env) if directory is not None else None
        if graph is None:
            return None
        _remember(graph.stats["partition_digest"], graph, env)
    if env is graph.partition.env:
        return graph
    return replace(graph, partition=replace(graph.partition, env=env))


def lookup(p: Partition, digest: str, *, plain: bool = False) -> SafeBVG | None:
    """The cached graph of partition ``p`` (``digest`` = :func:`partition_digest` of it), or ``None``.
    ``plain``: ``p`` is ``partition(p.env)`` (then later calls with the environment find it too)."""
    with _lock:
        if _fresh:
            return None
        graph = _memory.get(digest)
        if graph is not None:
            _memory.move_to_end(digest)
    directory = settings().graph_cache
    if graph is None and directory is not None:
        graph = _load(directory, digest, p, plain=plain or _is_plain(p))
        if graph is None:
            return None
        _remember(digest, graph, p.env if plain else None)
    elif graph is not None and plain:
        _remember(digest, graph, p.env)
    if graph is None:
        return None
    return graph if graph.partition is p else replace(graph, partition=p)


def store(p: Partition, digest: str, graph: SafeBVG, seconds: float, *, plain: bool = False) -> SafeBVG:
    """Keep ``graph`` (the safe BVG of ``p``, built in ``seconds`` of CPU time); returns it with its arrays read-only."""
    for name in (*_ARRAYS, "_set_ends"):
        arrays = getattr(graph, name)
        for a in arrays if isinstance(arrays, tuple) else (arrays,):
            a.setflags(write=False)
    _remember(digest, graph, p.env if plain else None)
    now = settings()
    directory, min_seconds = now.graph_cache, now.graph_cache_min_seconds
    if directory is not None and (graph.n_arcs >= now.graph_cache_min_arcs or (min_seconds is not None and seconds >= min_seconds)):
        written = _save(directory, digest, graph, plain=plain or _is_plain(p))
        if written is not None:
            _evict(directory, now.graph_cache_max_bytes, keep=written)
    return graph


def _remember(digest: str, graph: SafeBVG, env: Environment | None) -> None:
    with _lock:
        _memory[digest] = graph
        _memory.move_to_end(digest)
        if env is not None:
            _aliases[env] = digest
            _aliases.move_to_end(env)
        while len(_memory) > _MEMORY_GRAPHS or (len(_memory) > 1 and sum(g.n_arcs for g in _memory.values()) > _MEMORY_ARCS):
            _memory.popitem(last=False)
        while len(_aliases) > 2 * _MEMORY_GRAPHS:
            _aliases.popitem(last=False)


# ---------------------------------------------------------------------- the disk format
def _lengths(n: int, m: int) -> list[int]:
    return [{"n": n, "n+1": n + 1, "m": m}[kind] for _, _, kind in _LAYOUT]


def _save(directory: Path, digest: str, graph: SafeBVG, *, plain: bool = False) -> Path | None:
    """Write ``graph``'s entry atomically (``plain``: the graph of P′ itself, keyed by the environment, with P′'s
    inserted points); the path written, or ``None`` when the folder cannot be written."""
    arrays = {k: getattr(graph, k) for k in _ARRAYS}
    arrays.update(zip(_END_ARRAYS, graph._set_ends))
    n, m = graph.n_arcs, len(graph.set_lo)
    header = {"format": FORMAT_VERSION, "parameters": _PARAMETERS, "partition": digest,
              "n_segments": graph.n_segments, "n_arcs": n, "n_intervals": m,
              "stats": {k: v for k, v in graph.stats.items() if isinstance(v, (int, float)) and not isinstance(v, bool)}}
    if plain:
        env = graph.partition.env
        key = environment_digest(env)
        header["environment"] = key
        header["inserted"] = _inserted_rows(graph.partition)
        name = _entry_name(key, "environment")
    else:
        name = _entry_name(digest)
    text = json.dumps(header, sort_keys=True, separators=(",", ":")).encode()
    text += b" " * (-(len(_MAGIC) + 8 + len(text)) % 8)
    chunks: list[bytes | memoryview] = [_MAGIC, len(text).to_bytes(8, "little"), text]
    for (key, dtype, _), length in zip(_LAYOUT, _lengths(n, m)):
        a = np.ascontiguousarray(arrays[key], dtype=np.dtype(dtype))
        if a.shape != (length,):
            logger.info("graph cache: not writing %s (array %s has shape %s, expected (%d,))", name, key, a.shape, length)
            return None
        chunks.append(a.data.cast("B"))
    tmp = directory / f".{name[:16]}.{secrets.token_hex(8)}.tmp"
    final = directory / f"{name}{_SUFFIX}"
    try:
        directory.mkdir(parents=True, exist_ok=True)
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_BINARY", 0),
                     0o666)  # the umask applies, as for open(path, "w")
        try:
            with os.fdopen(fd, "wb") as fh:
                h = hashlib.sha256()
                for chunk in chunks:
                    h.update(chunk)
                    fh.write(chunk)
                fh.write(h.digest())  # last: a file cut short anywhere fails its digest
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(tmp, final)  # a symlink planted at `final` is replaced, never followed
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise
    except OSError as exc:  # a cache that cannot be written is no error: the answer stands
        logger.info("graph cache: cannot write in %s (%s)", directory, exc.strerror or exc)
        return None
    logger.debug("graph cache: wrote %s (%d arcs)", final.name, n)
    return final


def _load(directory: Path, digest: str, p: Partition, *, plain: bool = False) -> SafeBVG | None:
    """The graph of entry ``digest`` (``plain``: of P′ of ``p.env``, which ``p`` is) if it passes every check (module
    docstring), else ``None`` (a miss)."""
    name = _entry_name(environment_digest(p.env), "environment") if plain else _entry_name(digest)
    found = _read_entry(directory / f"{name}{_SUFFIX}", digest, len(p.segments))
    if found is None:
        return None
    header, arrays, path = found
    if plain and (header.get("environment") != environment_digest(p.env) or header.get("inserted") != _inserted_rows(p)):
        # the arrays are this partition's, but a process asking by the environment would rebuild P′ from these
        logger.info("graph cache: ignoring %s (its inserted points are not those of the partition)", path.name)
        return None
    return _graph(p, header, arrays, path, digest)


def _inserted_rows(p: Partition) -> list[list]:
    """P′'s inserted points as an entry keeps them (JSON: exact parameters as integers)."""
    return [[q.edge, q.t.numerator, q.t.denominator, q.reflex_vertex, q.from_vertex, [list(src) for src in q.sources]]
            for q in p.inserted]


def _load_plain(directory: Path, env: Environment) -> SafeBVG | None:
    """The graph of P′ of ``env`` with P′ itself rebuilt from the entry's inserted points (no Algorithm 1), if the
    entry passes every check and P′ has the partition digest it names; else ``None`` (a miss)."""
    from solverplan.bounce.partitions import assemble, remember

    path = directory / f"{_entry_name(environment_digest(env), 'environment')}{_SUFFIX}"
    found = _read_entry(path, None, None)
    if found is None:
        return None
    header, arrays, path = found
    try:
        if header.get("environment") != environment_digest(env):
            raise ValueError("written for another environment (copied under this name?)")
        p = assemble(env, _inserted_points(env, header.get("inserted")))
        digest = partition_digest(p)
        if digest != header["partition"] or len(p.segments) != header["n_segments"]:
            raise ValueError("its inserted points do not make the partition it names")
    except ValueError as exc:
        logger.info("graph cache: ignoring %s (%s)", path.name, exc)
        return None
    remember(p)
    return _graph(p, header, arrays, path, digest)


def _inserted_points(env: Environment, rows: object) -> list[InsertedPoint]:
    """The inserted points of an entry's header, checked to be points strictly inside edges of ``env`` with
    provenance in range (their exact points are computed here, not read)."""
    from solverplan.bounce.partitions import InsertedPoint

    n = env.n_vertices
    if not isinstance(rows, list):
        raise ValueError("no inserted points")
    out = []
    for row in rows:
        if not (isinstance(row, list) and len(row) == 6 and all(type(x) is int for x in row[:4])
                and (row[4] is None or type(row[4]) is int) and isinstance(row[5], list)):
            raise ValueError("unreadable inserted points")
        edge, num, den, reflex, frm, sources = row
        if not (0 <= edge < env.n_edges and 0 < num < den and 0 <= reflex < n and (frm is None or 0 <= frm < n)
                and all(isinstance(q, list) and len(q) == 2 and type(q[0]) is int and (q[1] is None or type(q[1]) is int)
                        for q in sources)):
            raise ValueError("inserted points out of range")
        t = Fraction(num, den)
        out.append(InsertedPoint(env.exact_point_at(edge, t), edge, t, reflex, frm, tuple((r, v) for r, v in sources)))
    keys = [(q.edge, q.t) for q in out]
    if any(a >= b for a, b in zip(keys, keys[1:])):
        raise ValueError("inserted points not sorted and unique")
    return out


def _read_entry(path: Path, digest: str | None, n_segments: int | None) -> tuple[dict, dict[str, np.ndarray], Path] | None:
    """Header and arrays of the entry at ``path`` if it passes the checks of :func:`_read` and :func:`_parse`
    (``digest``, ``n_segments``: what it must have been written for, None: any), else ``None`` (a logged miss)."""
    try:
        data = _read(path, n_segments)
    except FileNotFoundError:
        logger.debug("graph cache: no entry %s", path.name)
        return None
    except (OSError, ValueError) as exc:
        logger.info("graph cache: ignoring %s (%s)", path.name, getattr(exc, "strerror", None) or exc)
        return None
    try:
        header, arrays = _parse(data, digest, n_segments)
    except ValueError as exc:
        logger.info("graph cache: ignoring %s (%s)", path.name, exc)
        return None
    return header, arrays, path


def _graph(p: Partition, header: dict, arrays: dict[str, np.ndarray], path: Path, digest: str) -> SafeBVG:
    from solverplan.bounce.bvg.graph import SafeBVG

    stats: dict = {k: v for k, v in (header.get("stats") or {}).items() if isinstance(v, (int, float))}
    stats["cached"] = True
    stats["partition_digest"] = digest
    with _lock:
        _read_here[digest] = path
    logger.debug("graph cache: read %s (%d arcs)", path.name, header["n_arcs"])
    return SafeBVG(partition=p, source=arrays["source"], target=arrays["target"], lo=arrays["lo"], hi=arrays["hi"],
                   n_intervals=arrays["n_intervals"], set_offsets=arrays["set_offsets"], set_lo=arrays["set_lo"],
                   set_hi=arrays["set_hi"], transition=arrays["transition"], phi=arrays["phi"],
                   _set_ends=(arrays["lo_from"], arrays["lo_to"], arrays["hi_from"], arrays["hi_to"]), stats=stats)


def _read(path: Path, n_segments: int | None) -> bytes:
    """The bytes of a regular file no larger than the cap (not through a symlink); refreshes its time (LRU).

    The header is read first and the entry's size computed from its counts (at most N(N − 1) arcs): a file
    whose size does not match them — a sparse file of gigabytes under an entry's name, say — is a miss
    before its body is read, and so is an entry larger than the memory this process may use. Reading an
    entry never costs more than the graph it holds.
    """
    if stat.S_ISLNK(os.lstat(path).st_mode):
        raise ValueError("a symbolic link, not an entry")
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_BINARY", 0) | getattr(os, "O_NONBLOCK", 0))
    with os.fdopen(fd, "rb") as fh:
        st = os.fstat(fh.fileno())
        if not stat.S_ISREG(st.st_mode):
            raise ValueError("not a regular file")
        if st.st_size > settings().graph_cache_max_bytes:
            raise ValueError(f"{st.st_size} bytes, more than the cache's cap of {settings().graph_cache_max_bytes}")
        start = len(_MAGIC) + 8
        head = fh.read(start)
        if len(head) < start or head[: len(_MAGIC)] != _MAGIC:
            raise ValueError("not an entry of this cache (no magic)")
        size = int.from_bytes(head[len(_MAGIC):], "little")
        if size > _MAX_HEADER or start + size + _DIGEST > st.st_size:
            raise ValueError("bad header length")
        header_bytes = fh.read(size)
        expected = _entry_size(header_bytes, start + size, n_segments)
        if expected and expected != st.st_size:  # (an unreadable header is judged by _parse, after the memory check)
            raise ValueError(f"its size does not match its counts ({st.st_size} bytes, not {expected}): truncated or grown")
        limit, _source = memory_limit()
        if limit is not None and 2 * st.st_size > limit:
            raise ValueError(f"{st.st_size} bytes, more than half the memory this process may use")
        data = head + header_bytes + fh.read(st.st_size - start - size + 1)
        if len(data) != st.st_size:
            raise ValueError("its size changed while it was read")
        with contextlib.suppress(OSError, NotImplementedError):
            os.utime(fh.fileno() if os.utime in os.supports_fd else path)
    return data


def _entry_size(header_bytes: bytes, offset: int, n_segments: int | None) -> int:
    """The file size an entry's header implies (0 when its counts are unreadable or impossible)."""
    try:
        header = json.loads(header_bytes)
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError):
        return 0
    if not isinstance(header, dict):
        return 0
    n, m, N = header.get("n_arcs"), header.get("n_intervals"), header.get("n_segments")
    if not (isinstance(n, int) and isinstance(m, int) and isinstance(N, int) and N == (N if n_segments is None else n_segments)
            and 0 <= n <= N * (N - 1) and m >= 0):
        return 0
    return offset + sum(length * np.dtype(dt).itemsize for (_, dt, _), length in zip(_LAYOUT, _lengths(n, m))) + _DIGEST


def _parse(data: bytes, digest: str | None, n_segments: int | None) -> tuple[dict, dict[str, np.ndarray]]:
    """Header and arrays of an entry's bytes (written for partition ``digest`` on ``n_segments`` segments; None: as
    its header says); ``ValueError`` saying what is wrong when any check fails."""
    start = len(_MAGIC) + 8
    if len(data) < start + _DIGEST or data[: len(_MAGIC)] != _MAGIC:
        raise ValueError("not an entry of this cache (no magic)")
    if hashlib.sha256(memoryview(data)[:-_DIGEST]).digest() != data[-_DIGEST:]:
        raise ValueError("its SHA-256 does not match its content (truncated or edited)")
    size = int.from_bytes(data[len(_MAGIC) : start], "little")
    if size > _MAX_HEADER or start + size + _DIGEST > len(data):
        raise ValueError("bad header length")
    try:
        header = json.loads(data[start : start + size])
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"unreadable header ({exc})") from None
    if not isinstance(header, dict):
        raise ValueError("unreadable header")
    if header.get("format") != FORMAT_VERSION or header.get("parameters") != _PARAMETERS:
        raise ValueError(f"format {header.get('format')!r}, not {FORMAT_VERSION}")
    if not isinstance(header.get("stats", {}), dict):
        raise ValueError("unreadable header")
    if header.get("partition") != (digest if digest is not None else header.get("partition")) or not isinstance(header.get("partition"), str):
        raise ValueError("written for another partition (copied under this name?)")
    n, m, N = header.get("n_arcs"), header.get("n_intervals"), header.get("n_segments")
    if not isinstance(N, int) or N != (n_segments if n_segments is not None else N):
        raise ValueError(f"{N!r} segments, not {n_segments}")
    if not (isinstance(n, int) and isinstance(m, int) and 0 <= n <= N * (N - 1) and m >= 0):
        raise ValueError(f"impossible counts: {n!r} arcs, {m!r} safe intervals")
    lengths = _lengths(n, m)
    offset = start + size
    if offset + sum(length * np.dtype(dt).itemsize for (_, dt, _), length in zip(_LAYOUT, lengths)) + _DIGEST != len(data):
        raise ValueError("its size does not match its counts")
    arrays = {}
    for (key, dtype, _), length in zip(_LAYOUT, lengths):
        arrays[key] = np.frombuffer(data, dtype=np.dtype(dtype), count=length, offset=offset)  # read-only views
        offset += length * np.dtype(dtype).itemsize
    problem = _check(arrays, N)
    if problem:
        raise ValueError(problem)
    return header, arrays


def _check(arrays: dict[str, np.ndarray], N: int) -> str | None:
    """Why these arrays are not a safe BVG on N segments (``None`` when they pass every check)."""
    off, counts = arrays["set_offsets"], arrays["n_intervals"]
    if off[0] != 0 or off[-1] != len(arrays["set_lo"]) or (np.diff(off) != counts).any():
        return "inconsistent interval offsets"
    s, t = arrays["source"], arrays["target"]
    if len(s) and (s.min() < 0 or t.min() < 0 or s.max() >= N or t.max() >= N):
        return "segment ids out of range"
    keys = s * N + t
    if len(s) > 1 and not (np.diff(keys) > 0).all():
        return "arcs not sorted and unique"
    if (s == t).any():
        return "a self-loop"
    if not np.isin(arrays["transition"], (-1, 0, 1)).all():
        return "unknown transition"
    return None


# ---------------------------------------------------------------------- the folder: size cap, report, purge
@dataclass(frozen=True, slots=True)
class GraphCacheReport:
    """The disk cache's folder: entries (and bytes) in it, or removed from it by :func:`purge_graph_cache`."""

    directory: str | None
    entries: int
    bytes: int
    removed: int | None = None
    max_bytes: int = DEFAULT_MAX_BYTES
    min_arcs: int = DEFAULT_MIN_ARCS

    def to_json(self) -> dict:
        out: dict = {"directory": self.directory, "entries": self.entries, "bytes": self.bytes,
                     "max_bytes": self.max_bytes, "min_arcs": self.min_arcs, "format": FORMAT_VERSION}
        if self.removed is not None:
            out["removed"] = self.removed
        return out

    def to_text(self, *, width: int = 100) -> str:
        where = self.directory or "(off)"
        if self.removed is not None:
            return f"graph cache {where}: removed {self.removed} files, {self.entries} entries left ({self.bytes} bytes)\n"
        return (f"graph cache {where}: {self.entries} entries, {self.bytes} bytes "
                f"(cap {self.max_bytes} bytes; graphs of at least {self.min_arcs} arcs are written)\n")


def _files(directory: Path) -> list[tuple[Path, os.stat_result]]:
    """The cache's own files in ``directory`` (entries, older formats' entries, temporary files), unfollowed."""
    out = []
    try:
        names = os.listdir(directory)
    except FileNotFoundError:
        return []
    except OSError as exc:
        logger.info("graph cache: cannot list %s (%s)", directory, exc.strerror or exc)
        return []
    for name in names:
        if _OURS.fullmatch(name):
            path = directory / name
            try:
                out.append((path, os.lstat(path)))
            except FileNotFoundError:
                pass
    return out


def _evict(directory: Path, max_bytes: int, *, keep: Path | None = None) -> int:
    """Remove temporary files left by killed writers, then the least recently used entries until the folder's
    entries fit in ``max_bytes`` (``keep`` last of all). Returns the number of files removed."""
    now = time.time()
    removed = 0
    entries = []
    for path, st in _files(directory):
        if path.name.endswith(".tmp"):
            if now - st.st_mtime > _STALE_TEMPORARY and _unlink(path):
                removed += 1
        else:
            entries.append((path == keep, st.st_mtime, st.st_size, path))
    total = sum(e[2] for e in entries)
    for _, _, size, path in sorted(entries):
        if total <= max_bytes:
            break
        if _unlink(path):
            removed += 1
            logger.info("graph cache: evicted %s (%d bytes; the folder's cap is %d)", path.name, size, max_bytes)
        total -= size
    return removed


def _unlink(path: Path) -> bool:
    """Remove ``path`` (a link itself, never its target); ``False`` when it is gone already or cannot go."""
    try:
        os.unlink(path)
        return True
    except FileNotFoundError:
        return False
    except OSError as exc:  # another user's file, a read-only folder: the cache is best effort
        logger.info("graph cache: cannot remove %s (%s)", path, exc.strerror or exc)
        return False


def graph_cache_report(directory: str | os.PathLike[str] | None = None) -> GraphCacheReport:
    """How many entries (and bytes) the disk cache holds (``directory``: default the one set)."""
    now = settings()
    where = Path(directory) if directory is not None else now.graph_cache
    if where is None:
        return GraphCacheReport(None, 0, 0, max_bytes=now.graph_cache_max_bytes, min_arcs=now.graph_cache_min_arcs)
    entries = [st for path, st in _files(where) if not path.name.endswith(".tmp")]
    return GraphCacheReport(str(where), len(entries), sum(st.st_size for st in entries), max_bytes=now.graph_cache_max_bytes,
                            min_arcs=now.graph_cache_min_arcs)


def purge_graph_cache(directory: str | os.PathLike[str] | None = None) -> GraphCacheReport:
    """Remove every file of the disk cache (entries of any format version, temporary files; nothing else in the
    folder, and symlinks are removed, not followed) and forget the graphs in memory."""
    clear_graph_cache()
    now = settings()
    where = Path(directory) if directory is not None else now.graph_cache
    if where is None:
        return GraphCacheReport(None, 0, 0, removed=0, max_bytes=now.graph_cache_max_bytes, min_arcs=now.graph_cache_min_arcs)
    removed = sum(_unlink(path) for path, _ in _files(where))
    left = graph_cache_report(where)
    return replace(left, removed=removed)
