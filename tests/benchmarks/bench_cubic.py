"""Benchmark: invasion percolation with trapping on a large cubic lattice (issue 22's goal:
200 x 200 x 200, 8 M pores, in at most 15 s on the project's 2-core machine).

    python tests/benchmarks/bench_cubic.py                 # 200^3, 3 runs
    python tests/benchmarks/bench_cubic.py --n 100 --repeat 5

Each run builds the lattice (drawing 24 M apertures) and invades from the centre to
breakthrough with trapping, in one process after a warm-up run of a small lattice (the
kernels compiled); it prints the build and run times, the total and the median, and the
process's peak memory. Not a test. docs/lattices.md ("The cubic lattice") quotes it.
"""

from __future__ import annotations

import argparse
import resource
import statistics
import time

from porenet.simulation import Simulation


def scene(n: int, seed: int) -> dict:
    return {"seed": seed, "lattice": {"kind": "cubic", "shape": [n, n, n], "disorder": 0.5},
            "fluid": {"kind": "invasion-percolation", "trapping": True},
            "classifier": {"kind": "none"}}  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=200)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    Simulation.from_scene(scene(16, 0)).run()  # compile (or load) the kernels
    totals = []
    print("| seed | build (s) | run (s) | total (s) | drained |\n|---|---|---|---|---|")
    for seed in range(args.repeat):
        t0 = time.perf_counter()
        sim = Simulation.from_scene(scene(args.n, seed))
        t1 = time.perf_counter()
        data = sim.run().data
        t2 = time.perf_counter()
        totals.append(t2 - t0)
        print(f"| {seed} | {t1 - t0:.2f} | {t2 - t1:.2f} | {t2 - t0:.2f} | {len(data.order):,} |")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2
    print(f"n = {args.n}: median {statistics.median(totals):.2f} s, peak memory {peak:.1f} GB")


if __name__ == "__main__":
    main()
