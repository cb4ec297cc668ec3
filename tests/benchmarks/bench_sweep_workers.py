"""Benchmark: one sweep with 1 and 2 local workers, and a 2-worker dask LocalCluster.

    python tests/benchmarks/bench_sweep_workers.py                 # the built-in sweep
    python tests/benchmarks/bench_sweep_workers.py --repeat 5
    python tests/benchmarks/bench_sweep_workers.py --sweep examples/sweeps/demo.toml

The built-in sweep: viscous drainage in a rigid medium, n = 100, lattice.disorder in
{0.3, 0.6} x ca_star in {1, 10, 100}, 2 replicates (12 runs of 0.5-2 s). Each round runs the
whole sweep into a fresh directory (``porenet.sweep.run_sweep``), so the times include
starting the worker processes (and the cluster); medians over ``--repeat`` rounds. After each
round the summary rows (apart from ``wall_time_s``) and every run file's drained pores are
compared with those of the 1-worker run: they must be identical, bit for bit.
"""

from __future__ import annotations

import argparse
import csv
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

SWEEP = """
name = "bench-workers"
replicates = 2
[base]
lattice = { n = 100, disorder = 0.3, pore_size = 1e-7 }
fluid = { kind = "viscous", viscosity = 1e-3, interfacial_tension = 0.07 }
[[axes]]
key = "lattice.disorder"
values = [0.3, 0.6]
[[axes]]
key = "ca_star"
values = [1, 10, 100]
"""


def rows(out: Path) -> list[dict[str, str]]:
    with (out / "summary.csv").open(newline="") as f:
        return [{k: v for k, v in r.items() if k != "wall_time_s"} for r in csv.DictReader(f)]


def drained(out: Path) -> dict[str, np.ndarray]:
    from porenet.io.runfile import read_run

    return {p.name: read_run(p).drained for p in sorted((out / "runs").glob("*.h5"))}


def same(a: Path, b: Path) -> bool:
    da, db = drained(a), drained(b)
    return (
        rows(a) == rows(b)
        and da.keys() == db.keys()
        and all(np.array_equal(da[k], db[k]) for k in da)
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sweep", type=Path, help="sweep file (default: the built-in one)")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-dask", action="store_true", help="skip the LocalCluster")
    args = parser.parse_args()

    from porenet.sweep import run_sweep

    try:
        import distributed  # noqa: F401

        dask = not args.no_dask
    except ImportError:
        dask = False
        print('dask.distributed not installed (pip install "porenet[dask]"): no LocalCluster')
    configs = [("1 worker (in process)", {"workers": 1}), ("2 local workers", {"workers": 2})]
    if dask:
        configs.append(("2-worker LocalCluster", {"workers": 2, "dask_local": True}))

    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        sweep = args.sweep
        if sweep is None:
            sweep = root / "bench.toml"
            sweep.write_text(SWEEP)
        run_sweep(sweep, root / "warm-up", workers=1)  # numba caches, imports
        times: dict[str, list[float]] = {name: [] for name, _ in configs}
        identical = True
        for i in range(args.repeat):
            for name, kwargs in configs:
                out = root / f"{name.split()[0]}-{name.split()[-1]}-{i}"
                t0 = time.perf_counter()
                report = run_sweep(sweep, out, **kwargs)
                times[name].append(time.perf_counter() - t0)
                if report.failed:
                    print(f"  {name}: {report.failed} runs failed", file=sys.stderr)
                if not same(out, root / "warm-up"):
                    identical = False
                    print(f"  {name} (round {i}): results differ from 1 worker", file=sys.stderr)
        n_runs = len(rows(root / "warm-up"))
    print(f"sweep: {sweep if args.sweep else 'built-in'}, {n_runs} runs; {os.cpu_count()} CPUs, "
          f"load average {os.getloadavg()[0]:.2f}; medians of {args.repeat} rounds")  # fmt: skip
    base = statistics.median(times[configs[0][0]])
    for name, _ in configs:
        med = statistics.median(times[name])
        print(f"  {name:<24} {med:7.2f} s   speed-up {base / med:4.2f}x   "
              f"(rounds: {', '.join(f'{t:.2f}' for t in times[name])})")  # fmt: skip
    print(
        "results identical to 1 worker (summary rows apart from wall time, drained pores): "
        + ("yes" if identical else "NO")
    )
    if not identical:
        sys.exit(1)


if __name__ == "__main__":
    main()
