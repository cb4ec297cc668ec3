"""Burst (Haines jump) statistics of a quasi-static pressure signal (docs/model.md section 3)."""

from __future__ import annotations

import numpy as np

from porenet.jit.jit import njit


def burst_sizes(pressure: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bursts of a quasi-static pressure signal: runs between successive record highs.

    Parameters
    ----------
    pressure : ndarray, shape (K,)
        Entry pressure accepted at each step (inlet steps excluded).

    Returns
    -------
    start : ndarray of int64
        Index of the step opening each burst (a new running maximum).
    size : ndarray of int64
        Number of steps in each burst (the record step included).
    """
    p = np.ascontiguousarray(pressure, dtype=np.float64)
    start = np.empty(p.size, dtype=np.int64)
    count = _record_steps(p, start)
    start = start[:count].copy()
    size = np.diff(np.append(start, p.size)).astype(np.int64)
    return start, size


@njit
def _record_steps(p: np.ndarray, start: np.ndarray) -> int:
    """Write the steps where ``p`` exceeds every earlier value into ``start``; return their
    number (a NaN never opens a burst)."""
    count = 0
    high = -np.inf
    for i in range(p.shape[0]):
        if p[i] > high:
            high = p[i]
            start[count] = i
            count += 1
    return count
