"""A priority queue of distinct integer keys ``0 <= key < M`` as a 64-ary bitmap tree.

Level 0 holds one bit per key; each bit of level ``l+1`` says whether the 64-bit word below it
is non-empty. Insert, delete and find-min touch one word per level (4 levels for M up to
16.7 million), with no comparisons of keys, so it beats a binary heap for invasion
percolation, whose keys are throat ranks (see :mod:`porenet.kinds.invasion.kernels.ip`). Unlike a
heap it can delete any key in O(levels), so the queue holds exactly the current candidates (in the
invasion: one rank per pore next to the invader).

All functions are numba kernels operating on the ``(words, offsets)`` arrays made by
:func:`queue_new`: level ``l`` occupies ``words[offsets[l]:offsets[l+1]]``.

:func:`queue_pop_min` removes the smallest key and finds the next one in a single walk: up from
the removed key's word only as far as words empty out, then down again.
"""

from __future__ import annotations

import numpy as np

from porenet.jit.jit import njit, trailing_zeros


@njit
def _lowest_bit(x: np.uint64) -> int:
    """Index of the least significant set bit of a non-zero word."""
    return np.int64(trailing_zeros(x))


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


@njit(helper=True)
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


@njit(helper=True)
def _clear(words: np.ndarray, offsets: np.ndarray, key: int) -> int:
    """Clear ``key``'s bit, and each bit above it whose word empties out; return the first
    level whose word stays non-empty (the number of levels if the queue is now empty)."""
    levels = offsets.shape[0] - 1
    for level in range(levels):
        w = offsets[level] + (key >> 6)
        after = words[w] & ~(np.uint64(1) << np.uint64(key & 63))
        words[w] = after
        if after != 0:
            return level
        key >>= 6
    return levels


@njit(helper=True)
def _descend(words: np.ndarray, offsets: np.ndarray, level: int, word: int) -> int:
    """Smallest key below the (non-empty) word ``word`` of level ``level``."""
    index = word
    for below in range(level, -1, -1):
        index = (index << 6) + _lowest_bit(words[offsets[below] + index])
    return index


@njit(helper=True)
def queue_remove(words: np.ndarray, offsets: np.ndarray, key: int) -> None:
    """Remove ``key`` (no effect if absent)."""
    _clear(words, offsets, key)


@njit(helper=True)
def queue_min(words: np.ndarray, offsets: np.ndarray) -> int:
    """Smallest key present, or -1 if the queue is empty."""
    levels = offsets.shape[0] - 1
    if words[offsets[levels - 1]] == 0:
        return -1
    return _descend(words, offsets, levels - 1, 0)


@njit(helper=True)
def queue_pop_min(words: np.ndarray, offsets: np.ndarray, key: int) -> int:
    """Remove ``key``, which must be the smallest key present, and return the new smallest key
    (-1 if the queue is now empty).

    Equivalent to ``queue_remove(words, offsets, key); return queue_min(words, offsets)`` but
    cheaper: every key left is larger, so the first word on the way up that stays non-empty
    holds the path to the new minimum.
    """
    level = _clear(words, offsets, key)
    if level == offsets.shape[0] - 1:
        return -1
    return _descend(words, offsets, level, key >> (6 * (level + 1)))
