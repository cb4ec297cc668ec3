"""Sorting kernels."""

from __future__ import annotations

import numpy as np

from porenet.kernels._jit import njit

#: Largest bucket the bucket sort finishes by insertion sort before giving up.
MAX_BUCKET = 64


@njit
def _bucket_argsort(values: np.ndarray, max_bucket: int) -> tuple[np.ndarray, bool]:
    m = values.shape[0]
    order = np.empty(m, dtype=np.int64)
    lo = values.min()
    hi = values.max()
    if hi == lo:
        for i in range(m):
            order[i] = i
        return order, True
    scale = m / (hi - lo)
    bucket = np.empty(m, dtype=np.int32)
    start = np.zeros(m + 1, dtype=np.int32)
    for i in range(m):
        b = int((values[i] - lo) * scale)
        if b >= m:
            b = m - 1
        bucket[i] = b
        start[b + 1] += 1
    for b in range(m):
        start[b + 1] += start[b]
    fill = start[:-1].copy()
    for i in range(m):  # stable scatter: equal values keep index order
        b = bucket[i]
        order[fill[b]] = i
        fill[b] += 1
    for b in range(m):
        s, e = start[b], start[b + 1]
        if e - s < 2:
            continue
        if e - s > max_bucket:
            return order, False
        for j in range(s + 1, e):  # insertion sort by (value, index)
            item = order[j]
            v = values[item]
            k = j - 1
            while k >= s and (values[order[k]] > v or (values[order[k]] == v and order[k] > item)):
                order[k + 1] = order[k]
                k -= 1
            order[k + 1] = item
    return order, True


def stable_argsort(values: np.ndarray) -> np.ndarray:
    """Indices that sort ``values`` ascending, ties in index order (like ``kind="stable"``).

    A bucket sort with ``len(values)`` equal-width buckets costs O(M) for the smooth aperture
    distributions porenet draws; if any bucket holds more than :data:`MAX_BUCKET` values (a
    very uneven distribution) it falls back to numpy's O(M log M) stable sort.

    Parameters
    ----------
    values : ndarray of float64, shape (M,)
        Finite values.

    Returns
    -------
    ndarray of int64, shape (M,)
    """
    values = np.ascontiguousarray(values, dtype=np.float64)
    if values.shape[0] >= 2**31 - 1:
        return np.argsort(values, kind="stable").astype(np.int64)
    if values.shape[0] == 0:
        return np.zeros(0, dtype=np.int64)
    order, ok = _bucket_argsort(values, MAX_BUCKET)
    if not ok:
        order = np.argsort(values, kind="stable").astype(np.int64)
    return order
