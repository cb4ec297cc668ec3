"""Benchmark: the sweeps on one thread and on several (not a test; no assertions).

    python tests/benchmarks/bench_threads.py            # boxes of 64 .. 400 on a 400 x 400 grid
    python tests/benchmarks/bench_threads.py --threads 1

Times the serial and the parallel compilation of the row loops of the RKC stage sweep
(``porenet.kinds.viscous.kernels.chebyshev._stage_rows_serial`` and ``_stage_rows_parallel``, what
``grid_stage`` picks between at ``PARALLEL_MIN`` pores) and of the explicit sweep
(``porenet.kinds.viscous.kernels.diffusion._sweep_rows_*``, ``grid_sweep``'s) on square boxes of an
n x n grid: conductances uniform in [0.5, 2] (seed 0), no outlet, random volumes and pressures.
Medians of ``--repeat`` single calls after a warm-up; the parallel one runs on ``--threads``
threads. Both give the same bits (checked).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from porenet.jit.jit import PARALLEL_MIN, set_threads
from porenet.kinds.viscous.kernels import chebyshev, diffusion
from porenet.kinds.viscous.kernels.state import Sweep


def median_us(call, repeat: int) -> float:
    call()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return float(np.median(times)) * 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=400, help="grid side")
    parser.add_argument(
        "--sizes", type=int, nargs="+", default=[48, 64, 96, 128, 160, 200, 300, 400]
    )
    parser.add_argument("--threads", type=int, default=None, help="default: every core")
    parser.add_argument("--repeat", type=int, default=500)
    args = parser.parse_args()
    n = args.n
    threads = set_threads(args.threads)
    rng = np.random.default_rng(0)
    g = rng.uniform(0.5, 2.0, 2 * n * (n - 1))
    g_out = np.zeros(n * n)
    inv_vol = 1.0 / rng.uniform(0.5, 2.0, n * n)
    y1, y2, f0 = rng.random(n * n), rng.random(n * n), rng.random(n * n)
    vol = 1.0 / inv_vol
    coef = (0.5, 0.5, 0.1, 0.1)
    print(f"n = {n}, {threads} thread(s) for the parallel loops, PARALLEL_MIN = {PARALLEL_MIN}")
    print("| box | pores | stage: serial (us) | parallel (us) | ratio "
          "| explicit: serial (us) | parallel (us) | ratio |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|")
    for m in args.sizes:
        box = np.array([0, m, 0, m], dtype=np.int64)
        field = Sweep(n, box, 0, np.zeros(1, np.int64), np.zeros(1, np.int64),
                      np.zeros(1, np.int64), np.zeros(1, np.int64), np.zeros(1, np.int64), g,
                      g_out, inv_vol, np.zeros(n * n), box)  # fmt: skip
        cells = []
        for kernel_name in ("stage", "sweep"):
            results = {}
            for name in ("serial", "parallel"):
                out = np.zeros(n * n)
                if kernel_name == "stage":
                    kernel = getattr(chebyshev, f"_stage_rows_{name}")
                    partial = np.empty(m)
                    rest = (y1, y2, f0, coef, out, False, partial)
                else:
                    kernel = getattr(diffusion, f"_sweep_rows_{name}")
                    partial = np.empty((2, m))
                    rest = (0.1, vol, y1, out, partial)

                def call(kernel=kernel, rest=rest, field=field):
                    kernel(field, *rest)

                results[name] = (median_us(call, args.repeat), out)
            assert np.array_equal(results["serial"][1], results["parallel"][1])
            serial, parallel = results["serial"][0], results["parallel"][0]
            cells.append(f"{serial:.1f} | {parallel:.1f} | {serial / parallel:.2f}")
        print(f"| {m} x {m} | {m * m} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
