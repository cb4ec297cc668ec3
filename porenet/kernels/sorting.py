"""Sorting kernels: a stable O(M) argsort of floats, and the ranks it implies.

:func:`rank_order` sorts the values by their IEEE-754 bit patterns, mapped to unsigned integers
that order like the floats (``-0.0`` counts as ``0.0``, NaNs go last as in numpy). It is a
two-level bucket sort in the spirit of an MSD radix sort:

1. one stable counting scatter of ``(key, index)`` pairs into at most a few thousand coarse
   buckets (one bucket per leading bit pattern of ``key - min``), so the scatter writes only
   that many sequential streams and stays cache friendly;
2. inside each coarse bucket (which fits in the L1/L2 cache) another stable counting scatter
   into one or two buckets per value, by the bits of ``key - bucket minimum``, then an
   insertion pass that repairs the few remaining inversions.

Both scatters are stable and the insertion pass moves an element only past strictly larger
keys, so equal values keep their index order, exactly like ``np.argsort(kind="stable")``.
Once the insertion passes have moved more than :data:`MAX_BUCKET` elements per value in all
(values crowded far below the bucket resolution), the kernel gives up and the callers fall back
on numpy's O(M log M) stable sort.
"""

from __future__ import annotations

import numpy as np

from porenet.jit.jit import njit

#: Average insertion moves per value after which :func:`rank_order` gives up (numpy fallback).
MAX_BUCKET = 64

#: Target size of a coarse bucket, the most coarse buckets (the streams of the first scatter),
#: and the number of fine buckets per value in a coarse bucket.
_COARSE_SIZE = 1024
_MAX_COARSE = 2048
_FINE = 2

#: Coarse buckets up to this size are insertion-sorted without checking the budget on the way
#: (at worst ``_SMALL_COARSE**2 / 2`` moves).
_SMALL_COARSE = 8 * _COARSE_SIZE

_SIGN = np.uint64(0x8000000000000000)
_ABS = np.uint64(0x7FFFFFFFFFFFFFFF)
_INF = np.uint64(0x7FF0000000000000)
_ALL = np.uint64(0xFFFFFFFFFFFFFFFF)


@njit
def _key(bits: np.uint64) -> np.uint64:
    """Unsigned key that orders like the float with these bits (-0 = +0, NaN last)."""
    if bits == _SIGN:
        return _SIGN
    if (bits & _ABS) > _INF:
        return _ALL
    if bits & _SIGN:
        return ~bits
    return bits | _SIGN


@njit
def _shift_for(span: np.uint64, buckets: int) -> np.uint64:
    """Smallest shift with ``span >> shift < buckets``, capped at 63 (shifting a 64-bit word by
    64 is undefined): for ``span >= 2**63`` and ``buckets == 1`` it leaves ``span >> 63 == 1``,
    i.e. two buckets."""
    shift = np.uint64(0)
    while shift < np.uint64(63) and (span >> shift) >= np.uint64(buckets):
        shift += np.uint64(1)
    return shift


@njit(helper=True)
def _insertion_sort(keys: np.ndarray, index: np.ndarray, c: int, budget: int, check: bool) -> int:
    """Stable insertion sort of ``keys[:c]`` (and ``index[:c]`` alike) that gives up once it
    has moved more than ``budget`` elements; returns the budget left (negative if exceeded).

    With ``check`` false the budget is only counted, not checked on the way (the cheapest loop,
    for inputs whose worst case is affordable anyway)."""
    for j in range(1, c):
        k = keys[j]
        if keys[j - 1] <= k:
            continue
        x = index[j]
        q = j - 1
        while q >= 0 and keys[q] > k:
            keys[q + 1] = keys[q]
            index[q + 1] = index[q]
            q -= 1
        keys[q + 1] = k
        index[q + 1] = x
        budget -= j - 1 - q
        if check and budget < 0:
            break
    return budget


@njit
def rank_order(values: np.ndarray, by_rank: np.ndarray, rank: np.ndarray, keys: np.ndarray) -> bool:
    """Stable argsort of ``values`` and its inverse permutation, in O(M) for smooth data.

    The large arrays come from the caller (numpy backs big arrays with huge pages where the
    system allows, which makes their first touch much cheaper than numba's allocations).

    Parameters
    ----------
    values : ndarray of float64, shape (M,)
        C-contiguous.
    by_rank : ndarray of int, shape (M,)
        Output: index of the value at each rank (``np.argsort(values, kind="stable")``).
    rank : ndarray of int, shape (M,)
        Output: rank of each value (the inverse permutation).
    keys : ndarray of uint64, shape (M,)
        Scratch space.

    Returns
    -------
    bool
        False if the kernel gave up on a very clustered distribution (the outputs are then
        undefined; see :data:`MAX_BUCKET`).
    """
    m = values.shape[0]
    if m == 0:
        return True
    bits = values.view(np.uint64)
    kmin = _ALL
    kmax = np.uint64(0)
    for i in range(m):
        k = _key(bits[i])
        kmin = min(kmin, k)
        kmax = max(kmax, k)
    shift = _shift_for(kmax - kmin, max(1, min(m // _COARSE_SIZE, _MAX_COARSE)))
    n_coarse = np.int64((kmax - kmin) >> shift) + 1
    start = np.zeros(n_coarse + 1, dtype=np.int64)
    for i in range(m):
        start[np.int64((_key(bits[i]) - kmin) >> shift) + 1] += 1
    largest = 0
    for b in range(n_coarse):
        largest = max(largest, start[b + 1])
        start[b + 1] += start[b]
    fill = start[:-1].copy()
    bucket_min = np.full(n_coarse, _ALL, dtype=np.uint64)
    bucket_max = np.zeros(n_coarse, dtype=np.uint64)
    index = by_rank  # holds the coarse order until each bucket's final order replaces it
    for i in range(m):
        k = _key(bits[i])
        b = np.int64((k - kmin) >> shift)
        j = fill[b]
        fill[b] = j + 1
        keys[j] = k
        index[j] = i
        bucket_min[b] = min(bucket_min[b], k)
        bucket_max[b] = max(bucket_max[b], k)
    count = np.empty(_FINE * largest + 1, dtype=np.int64)
    bucket_keys = np.empty(largest, dtype=np.uint64)
    bucket_index = np.empty(largest, dtype=by_rank.dtype)
    budget = MAX_BUCKET * m
    for b in range(n_coarse):
        a = start[b]
        c = start[b + 1] - a
        if c == 0:
            continue
        lo = bucket_min[b]
        hi = bucket_max[b]
        if lo == hi:  # one value (or a single element): already in index order
            for j in range(a, a + c):
                x = index[j]
                by_rank[j] = x
                rank[x] = j
            continue
        fine = _shift_for(hi - lo, _FINE * c)
        n_fine = np.int64((hi - lo) >> fine) + 1
        for f in range(n_fine + 1):
            count[f] = 0
        for j in range(a, a + c):
            count[np.int64((keys[j] - lo) >> fine) + 1] += 1
        for f in range(n_fine):
            count[f + 1] += count[f]
        for j in range(a, a + c):
            k = keys[j]
            f = np.int64((k - lo) >> fine)
            d = count[f]
            count[f] = d + 1
            bucket_keys[d] = k
            bucket_index[d] = index[j]
        # Insertion pass: inversions are left only inside fine buckets. In a small coarse bucket
        # even the worst case is affordable, so the budget is checked once afterwards (the
        # cheapest loop); a large one (values crowded into few coarse buckets) checks it as it
        # goes.
        budget = _insertion_sort(bucket_keys, bucket_index, c, budget, c > _SMALL_COARSE)
        if budget < 0:
            return False
        for j in range(c):
            x = bucket_index[j]
            by_rank[a + j] = x
            rank[x] = a + j
    return True


def stable_argsort(values: np.ndarray) -> np.ndarray:
    """Indices that sort ``values`` ascending, ties in index order (like ``kind="stable"``).

    O(M) for the smooth aperture distributions porenet draws (:func:`rank_order`); numpy's
    O(M log M) stable sort for very clustered ones.

    Parameters
    ----------
    values : ndarray of float64, shape (M,)

    Returns
    -------
    ndarray of int64, shape (M,)
    """
    values = np.ascontiguousarray(values, dtype=np.float64)
    m = values.shape[0]
    by_rank = np.empty(m, dtype=np.int64)
    if rank_order(values, by_rank, np.empty(m, dtype=np.int64), np.empty(m, dtype=np.uint64)):
        return by_rank
    return np.argsort(values, kind="stable").astype(np.int64)
