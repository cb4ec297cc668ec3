"""Geometric features of invasion patterns (MODEL.md section 7)."""

from __future__ import annotations

import numpy as np


def longest_straight_run(grid: np.ndarray) -> int:
    """Most consecutive ``True`` cells along any row or column of a 2-D boolean grid: the
    longest straight drained segment of a pattern on a square lattice (fracturing opens
    segments much longer than fingering does)."""
    best = 0
    grid = np.asarray(grid, dtype=bool)
    for lines in (grid, grid.T):
        padded = np.zeros((lines.shape[0], lines.shape[1] + 2), dtype=np.int8)
        padded[:, 1:-1] = lines
        starts = np.argwhere(np.diff(padded, axis=1) == 1)
        ends = np.argwhere(np.diff(padded, axis=1) == -1)
        if len(starts):  # row-major order: the k-th start and the k-th end bound one run
            best = max(best, int(np.max(ends[:, 1] - starts[:, 1])))
    return best
