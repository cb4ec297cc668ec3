"""Benchmark: invasion percolation, porenet vs OpenPNM (when installed), side by side.

Not a test (no timing assertions): run it directly and read the medians.

    python tests/benchmarks/bench_ip.py                 # 400 x 400 and 2000 x 2000
    python tests/benchmarks/bench_ip.py --sizes 400 --repeat 9

For each size and trapping setting it times, on the same apertures (uniform in [0.7a, 1.3a],
seed 0), full invasion (stop at "complete"):

* ``porenet run``: ``Simulation.run()`` after the lattice is built (adjacency, sort, invasion,
  trapping, records, summary): what a user waits for, less the aperture draw;
* ``kernel``: ``porenet.kinds.invasion.kernels.ip.invasion_sequence`` alone;
* ``openpnm``: OpenPNM's ``InvasionPercolation.run()`` plus ``apply_trapping()`` on the same
  apertures (``tests/benchmarks/openpnm_ip.py``), after its numba warm-up, and checks that both
  give the same invasion order.

It also times cold ``porenet run --example quickstart`` processes (imports included, numba
cache already on disk). Every number is a median over ``--repeat`` runs in this process.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from openpnm_ip import openpnm_available, openpnm_invasion

from porenet.config.loading import load_scene
from porenet.core.plan import make_plan
from porenet.hooks import get_registry
from porenet.kinds.invasion.kernels import ip
from porenet.simulation import Simulation


def median_time(fn, repeat: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), out


def porenet_case(n: int, trapping: bool, apertures_file: Path, repeat: int):
    reg = get_registry()
    scene = load_scene(
        {
            "lattice": {"n": n, "apertures_file": str(apertures_file), "pore_size": 1.0},
            "fluid": {"trapping": trapping, "interfacial_tension": 1.0},
            "stop": {"at": "complete"},
            # like for like with OpenPNM, which does not classify the pattern: porenet's
            # default classification adds ~15 ms at n = 400 (docs/performance.md)
            "classifier": {"kind": "none"},
        },
        registry=reg,
    )
    plan = make_plan(scene, reg)
    Simulation(plan, reg).run()  # warm-up: compile or load the numba cache

    def one_run():
        sim = Simulation(plan, reg)
        t0 = time.perf_counter()
        result = sim.run()
        one_run.last = time.perf_counter() - t0
        return result

    times, result = [], None
    for _ in range(repeat):
        result = one_run()
        times.append(one_run.last)
    lat = result.lattice
    entry = ip.entry_pressures(lat.initial_apertures)
    t_kernel, _ = median_time(
        lambda: ip.invasion_sequence(
            lat.adjacency,
            entry,
            lat.inlet_pores("centre"),
            lat.boundary_pores,
            trapping=trapping,
            stop_at_outlet=False,
            max_steps=lat.n_pores,
        ),
        repeat,
    )
    return float(np.median(times)), t_kernel, result


def cold_quickstart(repeat: int) -> float:
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [
            sys.executable,
            "-m",
            "porenet",
            "run",
            "--example",
            "quickstart",
            "-q",
            "-o",
            str(Path(tmp) / "q.h5"),
        ]
        subprocess.run(cmd, check=True)  # make sure the numba cache exists
        t, _ = median_time(lambda: subprocess.run(cmd, check=True), repeat)
    return t


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[400, 2000])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--repeat-large", type=int, default=3, help="repeats for n >= 1000")
    parser.add_argument(
        "--openpnm-max-n",
        type=int,
        default=400,
        help="largest n to run OpenPNM on (it is slow on big lattices)",
    )
    args = parser.parse_args()
    have_openpnm = openpnm_available()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.sizes:
            rng = np.random.default_rng(0)
            apertures = rng.uniform(0.7, 1.3, 2 * n * (n - 1))
            path = Path(tmp) / f"ap{n}.npz"
            np.savez(path, apertures=apertures)
            repeat = args.repeat if n < 1000 else args.repeat_large
            for trapping in (False, True):
                t_run, t_kernel, result = porenet_case(n, trapping, path, repeat)
                t_pnm, same = None, None
                if have_openpnm and n <= args.openpnm_max_n:
                    ref = None
                    times = []
                    for _ in range(repeat):
                        ref = openpnm_invasion(apertures, n, trapping, outlet_ring=trapping)
                        times.append(ref["seconds_run"])
                    t_pnm = float(np.median(times))
                    same = bool(np.array_equal(ref["order"], result.data.order))
                rows.append((n, trapping, t_run, t_kernel, t_pnm, same, result.summary))
                ratio = f"{t_pnm / t_run:6.1f}x" if t_pnm else "     -"
                pnm = f"{1e3 * t_pnm:9.1f}" if t_pnm else "        -"
                print(
                    f"n={n:5d} trapping={trapping!s:5}  porenet run {1e3 * t_run:9.1f} ms  "
                    f"kernel {1e3 * t_kernel:9.1f} ms  openpnm {pnm} ms  ratio {ratio}  "
                    f"same order: {same}  drained {result.summary['n_drained']}",
                    flush=True,
                )
    from porenet.kinds.square.model import SquareLattice, SquareLatticeConfig
    from porenet.testing.reference import reference_invasion

    n = min(args.sizes)
    lat = SquareLattice(SquareLatticeConfig(n=n, disorder=0.3), np.random.default_rng(0))
    t_ref, _ = median_time(
        lambda: reference_invasion(
            lat.throat_pores,
            2.0 / lat.initial_apertures,
            lat.inlet_pores("centre"),
            lat.boundary_pores,
            trapping=False,
            stop_at_outlet=False,
        ),
        1,
    )
    print(f"pure-Python heapq reference, n={n}, no trapping: {t_ref:.2f} s")
    t_cold = cold_quickstart(args.repeat if args.repeat < 5 else 5)
    print(f"cold `porenet run --example quickstart` (process, imports, n=200): {t_cold:.2f} s")
    print(f"openpnm available: {have_openpnm}; python {sys.version.split()[0]}")


if __name__ == "__main__":
    main()
