"""Read and rewrite entries of the safe-BVG disk cache (format 4, solverplan.bounce._cache) for tampering tests.

The format is parsed here from its description (magic, 8-byte header length, JSON header, the arrays in the
documented order, a trailing SHA-256), not with the cache's own reader: a test that tampers must not trust it.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np

from solverplan.bounce._cache import _LAYOUT, _MAGIC

ARC_ARRAYS = ("source", "target", "lo", "hi", "n_intervals", "transition", "phi")
SET_ARRAYS = ("set_lo", "set_hi", "lo_from", "lo_to", "hi_from", "hi_to")


def read_entry(path: Path) -> tuple[dict, dict[str, np.ndarray]]:
    """The header and (writable copies of) the arrays of an entry."""
    data = path.read_bytes()
    start = len(_MAGIC) + 8
    assert data[: len(_MAGIC)] == _MAGIC
    size = int.from_bytes(data[len(_MAGIC) : start], "little")
    header = json.loads(data[start : start + size])
    n, m = header["n_arcs"], header["n_intervals"]
    offset, arrays = start + size, {}
    for name, dtype, kind in _LAYOUT:
        count = {"n": n, "n+1": n + 1, "m": m}[kind]
        arrays[name] = np.frombuffer(data, dtype=dtype, count=count, offset=offset).copy()
        offset += count * np.dtype(dtype).itemsize
    assert offset + 32 == len(data)
    return header, arrays


def write_entry(path: Path, header: dict, arrays: dict[str, np.ndarray], *, digest: bytes | None = None) -> None:
    """Write an entry; its trailing SHA-256 is recomputed (a forger's entry) unless ``digest`` is given (an edit
    that keeps the old one)."""
    text = json.dumps(header, sort_keys=True, separators=(",", ":")).encode()
    text += b" " * (-(len(_MAGIC) + 8 + len(text)) % 8)
    body = _MAGIC + len(text).to_bytes(8, "little") + text
    body += b"".join(np.ascontiguousarray(arrays[name], dtype=dtype).tobytes() for name, dtype, _ in _LAYOUT)
    path.write_bytes(body + (digest if digest is not None else hashlib.sha256(body).digest()))


def old_digest(path: Path) -> bytes:
    return path.read_bytes()[-32:]


def with_sets(arrays: dict[str, np.ndarray], sets: list[list[int]]) -> dict[str, np.ndarray]:
    """``arrays`` with arc k's safe intervals replaced by the rows ``sets[k]`` of the original interval arrays
    (indices into set_lo, set_hi and the end arrays), or new rows given as (lo, hi, copied-from-row) tuples."""
    out = dict(arrays)
    rows: dict[str, list] = {k: [] for k in SET_ARRAYS}
    counts, lo, hi = [], [], []
    for k, chosen in enumerate(sets):
        widest = None
        for item in chosen:
            if isinstance(item, tuple):
                a, b, like = item
            else:
                a, b, like = arrays["set_lo"][item], arrays["set_hi"][item], item
            rows["set_lo"].append(a)
            rows["set_hi"].append(b)
            for name in SET_ARRAYS[2:]:
                rows[name].append(arrays[name][like])
            if widest is None or b - a > widest[1] - widest[0]:
                widest = (a, b)
        counts.append(len(chosen))
        lo.append(np.nan if widest is None else widest[0])
        hi.append(np.nan if widest is None else widest[1])
    for name in SET_ARRAYS:
        out[name] = np.array(rows[name], dtype=arrays[name].dtype)
    out["n_intervals"] = np.array(counts, dtype=np.int64)
    out["set_offsets"] = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    out["lo"], out["hi"] = np.array(lo, dtype=float), np.array(hi, dtype=float)
    return out


def interval_rows(arrays: dict[str, np.ndarray]) -> list[list[int]]:
    off = arrays["set_offsets"]
    return [list(range(off[k], off[k + 1])) for k in range(len(arrays["source"]))]
