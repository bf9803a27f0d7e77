"""Small numpy helpers shared by the vectorised kernels."""

from __future__ import annotations

import numpy as np

__all__ = ["ragged_arange"]


def ragged_arange(counts: np.ndarray) -> np.ndarray:
    """Concatenated ``arange(c)`` for each c in ``counts`` (int64).

    >>> ragged_arange(np.array([3, 0, 2])).tolist()
    [0, 1, 2, 0, 1]
    """
    counts = np.asarray(counts, dtype=np.int64)
    total = int(counts.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    ends = np.cumsum(counts)
    return np.arange(total, dtype=np.int64) - np.repeat(ends - counts, counts)
