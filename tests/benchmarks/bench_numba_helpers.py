"""Benchmark: the cost of calling a small numba helper that writes into its array arguments.

    python tests/benchmarks/bench_numba_helpers.py

The helper adds a pore to an indexed set (``if pos[j] < 0: items[n] = j; ...``). It is
called 10^4 times per sweep for 1000 sweeps, and always finds the pore already present, so
each call does one comparison. Medians of 5 repeats, in ns per call. Four versions are
timed:

* ``act_a``: the helper compiled normally, with parameters named ``a, apos``;
* ``act_items``: the same helper with parameters named ``items, pos``;
* ``act_a_nrt``: the first one compiled without numba's reference counting
  (``_nrt=False``, which is what ``@njit(helper=True)`` in porenet's kernels does);
* ``inline``: the body written into the loop.

On the project's machine (numba 0.68.1) the first version costs ~16 ns per call and the other
three ~0.25 ns. The only difference between the first two is the parameter names. We do not
understand why numba sometimes fails to optimise such a call. Compiling the helper without
reference counting removed the cost in every case we tried, so porenet's array-writing
helpers are compiled that way.
"""

from __future__ import annotations

import time

import numba
import numpy as np


@numba.njit
def act_a(j, a, apos, cnt):
    if apos[j] < 0:
        a[cnt[0]] = j
        apos[j] = cnt[0]
        cnt[0] += 1


@numba.njit
def act_items(j, items, pos, cnt):
    if pos[j] < 0:
        items[cnt[0]] = j
        pos[j] = cnt[0]
        cnt[0] += 1


@numba.njit(_nrt=False)
def act_a_nrt(j, a, apos, cnt):
    if apos[j] < 0:
        a[cnt[0]] = j
        apos[j] = cnt[0]
        cnt[0] += 1


@numba.njit
def loop_a(reps, a, apos, cnt):
    for _r in range(reps):
        for j in range(a.shape[0]):
            act_a(j, a, apos, cnt)


@numba.njit
def loop_items(reps, a, apos, cnt):
    for _r in range(reps):
        for j in range(a.shape[0]):
            act_items(j, a, apos, cnt)


@numba.njit
def loop_a_nrt(reps, a, apos, cnt):
    for _r in range(reps):
        for j in range(a.shape[0]):
            act_a_nrt(j, a, apos, cnt)


@numba.njit
def inline(reps, a, apos, cnt):
    for _r in range(reps):
        for j in range(a.shape[0]):
            if apos[j] < 0:
                a[cnt[0]] = j
                apos[j] = cnt[0]
                cnt[0] += 1


def main() -> None:
    n, reps = 10_000, 1000
    print(f"numba {numba.__version__}")
    for name, fn in (
        ("act_a", loop_a),
        ("act_items", loop_items),
        ("act_a_nrt", loop_a_nrt),
        ("inline", inline),
    ):
        a, apos, cnt = np.zeros(n, np.int64), np.zeros(n, np.int64), np.zeros(1, np.int64)
        fn(1, a, apos, cnt)  # compile
        times = []
        for _ in range(5):
            t0 = time.perf_counter()
            fn(reps, a, apos, cnt)
            times.append(time.perf_counter() - t0)
        print(f"{name:<10} {1e9 * float(np.median(times)) / (n * reps):6.2f} ns per call")


if __name__ == "__main__":
    main()
