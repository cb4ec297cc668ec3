"""Benchmark: the viscous model on lattices swept as lists (any lattice but the square grid),
on issue 22's 3-D scene: a 64 x 64 x 64 cubic lattice at Ca = 1e-3 to breakthrough (goal: at
most 3 minutes on the project's 2-core machine).

    python tests/benchmarks/bench_csr.py                    # kernels, then 3 whole runs
    python tests/benchmarks/bench_csr.py --repeat 1 --threads 1 auto

Part 1, the kernels: a run to 300 drained pores (nearly every pore active by then), then on
its state the list sweep's fluxes in the order the pores became active (as before the
index-order sweep, ``DENSE_ACTIVE`` in ``porenet/kinds/viscous/kernels/diffusion.py``) and in index
order, and the pressure's spread visiting every active pore (as before ``Front.settled``) and
only the unsettled ones; medians of 20 calls. Part 2: whole runs of
``examples/scenes/cubic-viscous.toml``, each a new process with a warm kernel cache, with the
given ``--threads``. Not a test. docs/lattices.md ("The viscous model in 3-D") quotes it.
"""

from __future__ import annotations

import argparse
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SCENE = str(ROOT / "examples/scenes/cubic-viscous.toml")


def _median_ms(call, repeat: int = 20) -> float:
    call()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        call()
        times.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(times)


def kernels() -> None:
    import numba

    from porenet.jit.threads import configure_threads
    from porenet.kinds.viscous.kernels import diffusion
    from porenet.kinds.viscous.kernels.state import Count, Sweep
    from porenet.simulation import Simulation

    @numba.njit(cache=True)
    def fluxes_in_activation_order(field, p, flux):  # the list sweep before index order
        act, apos, indptr, nbr, thr = (field.pores, field.pore_slot, field.indptr,
                                       field.neighbour, field.throat)  # fmt: skip
        for s in range(field.n_active):
            i = act[s]
            pi = p[i]
            total = -field.outlet[i] * pi
            for e in range(indptr[i], indptr[i + 1]):
                j = nbr[e]
                if apos[j] >= 0:
                    total += field.between[thr[e]] * (p[j] - pi)
            flux[i] = total

    configure_threads(1)
    sim = Simulation.from_scene(SCENE, ["stop.max_drained=300", "classifier.kind=none"])
    sim.run()
    f = sim.fluid
    net, cond, flow, front = f.network, f.conductances, f.flow, f.front
    na = int(flow.counters[Count.N_ACTIVE])
    flux = np.zeros(len(net.volume))
    field = Sweep(net.grid_n, front.box, na, front.pores, front.pore_slot, net.indptr,
                  net.neighbour, net.throat, cond.between, cond.outlet, net.inverse_volume,
                  flux, front.box)  # fmt: skip
    p = flow.pressure.copy()
    before = _median_ms(lambda: fluxes_in_activation_order(field, p, flux))
    now = _median_ms(lambda: diffusion.csr_fluxes(field, p, flux))
    floor = f.config.pressure_floor
    counters = flow.counters.copy()

    def spread_unsettled():  # every active pore visited, as before the mark
        diffusion.spread(field, np.zeros(len(p), dtype=bool), counters, flow.drained, p, floor)

    settled = np.zeros(len(p), dtype=bool)
    diffusion.spread(field, settled, counters, flow.drained, p, floor)
    visit_all = _median_ms(spread_unsettled)
    visit_unsettled = _median_ms(
        lambda: diffusion.spread(field, settled, counters, flow.drained, p, floor)
    )
    print(f"{na:,} of {len(p):,} pores active after 300 drained")
    print("| kernel | before (ms) | now (ms) |\n|---|---|---|")
    print(f"| fluxes (activation order / index order) | {before:.2f} | {now:.2f} |")
    print(f"| spread (every active pore / unsettled ones) | {visit_all:.2f} | "
          f"{visit_unsettled:.2f} |")  # fmt: skip


def runs(repeat: int, threads: list[str]) -> None:
    pattern = re.compile(r"breakthrough after (\d+) drained.*?, ([0-9.]+) s\n\s+model time "
                         r"\S+ s, (\d+) steps")  # fmt: skip
    print("| threads | run (s), each | median (s) | drained | steps |\n|---|---|---|---|---|")
    out_file = str(Path(tempfile.mkdtemp()) / "run.h5")
    run = [sys.executable, "-m", "porenet", "run", SCENE, "-o", out_file]
    subprocess.run([*run, "--set", "stop.max_drained=20", "-q"], check=True)  # compile
    for setting in threads:
        times, drained, steps = [], "", ""
        for _ in range(repeat):
            out = subprocess.run(
                [*run, "--threads", setting], capture_output=True, text=True, check=True
            )
            text = out.stdout + out.stderr
            m = pattern.search(text)
            assert m is not None, text[-500:]
            drained, steps = m.group(1), m.group(3)
            times.append(float(m.group(2)))
        each = ", ".join(f"{t:.1f}" for t in times)
        print(f"| {setting} | {each} | {statistics.median(times):.1f} | {drained} | {steps} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--threads", nargs="+", default=["auto", "1"])
    parser.add_argument("--skip-kernels", action="store_true")
    args = parser.parse_args()
    if not args.skip_kernels:
        kernels()
    if args.repeat > 0:
        runs(args.repeat, args.threads)


if __name__ == "__main__":
    main()
