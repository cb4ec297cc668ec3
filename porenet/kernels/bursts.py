"""Burst (Haines jump) statistics of a quasi-static pressure signal (MODEL.md section 3)."""

from __future__ import annotations

import numpy as np


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
    p = np.asarray(pressure, dtype=np.float64)
    if p.size == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    prev_max = np.concatenate([[-np.inf], np.maximum.accumulate(p)[:-1]])
    start = np.flatnonzero(p > prev_max).astype(np.int64)
    size = np.diff(np.append(start, p.size)).astype(np.int64)
    return start, size
