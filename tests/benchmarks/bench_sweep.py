"""Benchmark: one explicit pressure sweep of the viscous model (not a test; no assertions).

    python tests/benchmarks/bench_sweep.py                     # n = 400
    python tests/benchmarks/bench_sweep.py --baseline 02a3cfb  # also the sweep of REV

Times ``porenet.kinds.viscous.kernels.diffusion.grid_sweep`` on the full box of an n x n grid:
conductances uniform in [0.5, 2] (seed 0), outlet links on the outer ring, unit pore volumes, random
pressures. Medians over ``--repeat`` rounds of 50 sweeps, after a warm-up. With
``--baseline REV`` the sweep of git revision REV is timed next, in the same process, and its
new pressures are compared with the current ones (they agree to round-off, not to the
bit: the current sweep multiplies by ``1/V`` where older ones divided, and reorders its
running sums).
"""

from __future__ import annotations

import argparse
import importlib
import sys
import time
from pathlib import Path

import numpy as np

from porenet.kinds.viscous.kernels import diffusion
from porenet.kinds.viscous.kernels.state import Sweep

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_kernels import load_baseline


def inputs(n: int):
    rng = np.random.default_rng(0)
    g = rng.uniform(0.5, 2.0, 2 * n * (n - 1))
    ring = np.zeros((n, n))
    ring[[0, -1], :] = 1.0
    ring[:, [0, -1]] = 1.0
    return g, ring.ravel(), np.ones(n * n), rng.random(n * n), np.array([0, n, 0, n])


def median_ms(call, repeat: int) -> float:
    call()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(50):
            call()
        times.append((time.perf_counter() - t0) / 50)
    return 1e3 * float(np.median(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=400)
    parser.add_argument("--repeat", type=int, default=11)
    parser.add_argument("--baseline", default=None)
    args = parser.parse_args()
    n = args.n
    g, g_out, vol, p, box = inputs(n)
    inv_vol = 1.0 / vol
    new = np.zeros_like(p)
    idx = np.zeros(1, dtype=np.int64)
    field = Sweep(n, box, 0, idx, idx, idx, idx, idx, g, g_out, inv_vol, new, box)
    current = median_ms(lambda: diffusion.grid_sweep(field, 0.1, vol, p, new), args.repeat)
    print(f"grid_sweep, n={n}: {current:.3f} ms ({1e6 * current / n**2:.2f} ns per pore)")
    if args.baseline:
        _, sha = load_baseline(args.baseline)
        old_sweep = importlib.import_module("porenet_baseline.kernels.diffusion").grid_sweep
        old = np.zeros_like(p)
        baseline = median_ms(lambda: old_sweep(n, box, 0.1, g, g_out, vol, p, old), args.repeat)
        diff = float(np.max(np.abs(old - new)))
        print(
            f"grid_sweep at {sha}: {baseline:.3f} ms ({1e6 * baseline / n**2:.2f} ns per pore); "
            f"ratio {baseline / current:.1f}x; largest difference {diff:.1e}"
        )


if __name__ == "__main__":
    main()
