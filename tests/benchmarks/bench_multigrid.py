"""Benchmark: the frictional solid's multigrid on one component, m x m grid (not a test).

    python tests/benchmarks/bench_multigrid.py               # m = 399 (the paper's lattice)
    python tests/benchmarks/bench_multigrid.py --m 199 --repeat 9

Operators like those of ``u_x`` in an update: weights ~K across columns (normal stiffness of
x-springs, +-50 % disorder) and ~r_t K across rows, with a cross of open contacts (weights 1e-6
of the others) of half-length 150 at the centre; a right-hand side of 40 point forces. For
each stiffness ratio, the hierarchy's build time, then the conjugate gradient solve from zero
to round-off and to a deformation tolerance of 1e-3 a, with the smoother relaxing the lines of
the strong direction only (the default, :func:`porenet.kernels.mechanics.multigrid.
smoothing_lines`) and both directions (rows, then columns): iterations and median wall time
(docs/model.md, "Solver", quotes it).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from porenet.kernels.mechanics import multigrid as mg


def operator(m: int, ratio: float, crack: int, seed: int = 1) -> mg.Operator:
    rng = np.random.default_rng(seed)
    wc = 2.0 * (1 + 0.5 * rng.random((m, m + 1)))
    wr = ratio * 2.0 * (1 + 0.5 * rng.random((m + 1, m)))
    c0 = m // 2
    lo, hi = max(c0 - crack, 0), min(c0 + crack, m)
    wc[c0, lo:hi] = 2e-6
    wr[lo:hi, c0] = 2e-6 * ratio
    return mg.Operator(wc, wr, np.zeros((m, m)))


def timed_solve(op, hierarchy, rhs, tolerance, repeat):
    work = mg.workspace(hierarchy)
    times, its = [], 0
    for _ in range(repeat):
        x = np.zeros_like(rhs)
        t0 = time.perf_counter()
        its = mg.solve(op, hierarchy, work, rhs, x, tolerance, 1e-13 * np.abs(rhs).max(), 500)
        times.append(time.perf_counter() - t0)
    return its, statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--m", type=int, default=399)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    m = args.m
    warm = operator(15, 0.5, 3)
    timed_solve(warm, mg.build(warm), np.ones(15 * 15), 0.0, 1)  # compile
    print("| K_t / K_n | build (ms) | lines | to round-off: iterations, ms | to 1e-3 a: "
          "iterations, ms |")  # fmt: skip
    print("|---|---|---|---|---|")
    for ratio in (1e-3, 0.1, 0.5, 1.0):
        op = operator(m, ratio, 150)
        rhs = np.zeros(m * m)
        rhs[np.random.default_rng(3).integers(0, m * m, 40)] = 1.0
        t0 = time.perf_counter()
        hierarchy = mg.build(op)
        build = time.perf_counter() - t0
        for label, h in (("strong", hierarchy), ("both", hierarchy._replace(sweeps=3))):
            exact = timed_solve(op, h, rhs, 0.0, args.repeat)
            loose = timed_solve(op, h, rhs, 1e-3, args.repeat)
            print(f"| {ratio:g} | {1e3 * build:.0f} | {label} | {exact[0]}, {1e3 * exact[1]:.0f} | "
                  f"{loose[0]}, {1e3 * loose[1]:.0f} |")  # fmt: skip


if __name__ == "__main__":
    main()
