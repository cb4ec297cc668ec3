"""A priority queue of distinct integer keys ``0 <= key < M`` as a 64-ary bitmap tree.

Level 0 holds one bit per key; each bit of level ``l+1`` says whether the 64-bit word below it
is non-empty. Insert, delete and find-min touch one word per level (4 levels for M up to
16.7 million), with no comparisons of keys, so it beats a binary heap for invasion
percolation, whose keys are throat ranks (see :mod:`porenet.kernels.ip`). Unlike a heap it can
delete any key in O(levels), so the queue holds exactly the invadable throats.

All functions are numba kernels operating on the ``(words, offsets)`` arrays made by
:func:`queue_new`: level ``l`` occupies ``words[offsets[l]:offsets[l+1]]``.
"""

from __future__ import annotations

import numpy as np

from porenet.kernels._jit import njit

_DEBRUIJN = np.uint64(0x03F79D71B4CB0A89)
_DEBRUIJN_TABLE = np.array(
    [
        0, 1, 48, 2, 57, 49, 28, 3, 61, 58, 50, 42, 38, 29, 17, 4,
        62, 55, 59, 36, 53, 51, 43, 22, 45, 39, 33, 30, 24, 18, 12, 5,
        63, 47, 56, 27, 60, 41, 37, 16, 54, 35, 52, 21, 44, 32, 23, 11,
        46, 26, 40, 15, 34, 20, 31, 10, 25, 14, 19, 9, 13, 8, 7, 6,
    ],
    dtype=np.int64,
)  # fmt: skip


@njit
def _lowest_bit(x: np.uint64) -> int:
    """Index of the least significant set bit of a non-zero word (de Bruijn multiplication)."""
    isolated = x & (~x + np.uint64(1))
    return _DEBRUIJN_TABLE[(isolated * _DEBRUIJN) >> np.uint64(58)]


@njit
def queue_new(m: int) -> tuple[np.ndarray, np.ndarray]:
    """An empty queue for keys in ``[0, m)``: returns ``(words, offsets)``."""
    sizes = []
    size = max(m, 1)
    while True:
        size = (size + 63) // 64
        sizes.append(size)
        if size == 1:
            break
    offsets = np.zeros(len(sizes) + 1, dtype=np.int64)
    for i in range(len(sizes)):
        offsets[i + 1] = offsets[i] + sizes[i]
    return np.zeros(offsets[-1], dtype=np.uint64), offsets


@njit
def queue_insert(words: np.ndarray, offsets: np.ndarray, key: int) -> None:
    """Add ``key`` (no effect if present)."""
    levels = offsets.shape[0] - 1
    for level in range(levels):
        w = offsets[level] + (key >> 6)
        before = words[w]
        words[w] = before | (np.uint64(1) << np.uint64(key & 63))
        if before != 0:
            return
        key >>= 6


@njit
def queue_remove(words: np.ndarray, offsets: np.ndarray, key: int) -> None:
    """Remove ``key`` (no effect if absent)."""
    levels = offsets.shape[0] - 1
    for level in range(levels):
        w = offsets[level] + (key >> 6)
        after = words[w] & ~(np.uint64(1) << np.uint64(key & 63))
        words[w] = after
        if after != 0:
            return
        key >>= 6


@njit
def queue_min(words: np.ndarray, offsets: np.ndarray) -> int:
    """Smallest key present, or -1 if the queue is empty."""
    levels = offsets.shape[0] - 1
    top = words[offsets[levels - 1]]
    if top == 0:
        return -1
    index = _lowest_bit(top)
    for level in range(levels - 2, -1, -1):
        index = (index << 6) + _lowest_bit(words[offsets[level] + index])
    return index
