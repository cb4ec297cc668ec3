"""Benchmark: invasion percolation on one 3-D network, porenet against OpenPNM 3.6.

    python tests/benchmarks/bench_openpnm_network.py --openpnm-python /path/to/venv/bin/python
    python tests/benchmarks/bench_openpnm_network.py --openpnm-python PY --shape 100 100 100

OpenPNM runs in its own interpreter (``--openpnm-python``, an environment with OpenPNM 3.6;
porenet does not depend on it). That process builds an OpenPNM ``Cubic`` network of the given
shape with random throat diameters (seeded), saves it as an ``.npz`` network dict, then times
``InvasionPercolation`` from the centre pore with entry pressures ``2 gamma / r`` (the whole
network: OpenPNM's ``run`` always invades everything). This process loads the same file as a
porenet ``network`` lattice and times invasion percolation from the same pore to completion
without trapping. Both are timed warm (the second of two runs in one process; porenet's
kernels compiled). It prints both times, the ratio and whether both invade the pores in the
same order. Not a test. docs/lattices.md ("Speed") quotes it.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

OPENPNM = r"""
import json, sys, time
import numpy as np
import openpnm as op
shape, path, seed = json.loads(sys.argv[1]), sys.argv[2], int(sys.argv[3])
op.visualization.set_mpl_style = lambda: None
pn = op.network.Cubic(shape=shape, spacing=2e-6)
rng = np.random.default_rng(seed)
r = rng.uniform(0.5e-6, 1.5e-6, pn.Nt)
conns = pn["throat.conns"]
np.savez(path, **{"pore.coords": pn["pore.coords"], "throat.conns": conns,
                  "throat.diameter": 2 * r, "throat.total_length": np.full(pn.Nt, 2e-6),
                  "pore.volume": np.full(pn.Np, 1e-18)})
centre = int(np.argmin(np.linalg.norm(pn["pore.coords"] - pn["pore.coords"].mean(0), axis=1)))
times = []
for _ in range(2):
    phase = op.phase.Phase(network=pn)
    phase["throat.entry_pressure"] = 2 * 0.07 / r
    ip = op.algorithms.InvasionPercolation(network=pn, phase=phase)
    ip.set_inlet_BC(pores=[centre])
    t0 = time.perf_counter()
    ip.run()
    times.append(time.perf_counter() - t0)
seq = np.asarray(ip["pore.invasion_sequence"], dtype=float)
order = np.argsort(seq, kind="stable").tolist()
print(json.dumps({"seconds": times[-1], "centre": centre, "order": order}))
"""


def porenet_invasion(path: Path, pore_size: float, centre: int) -> tuple[float, float, np.ndarray]:
    """Seconds of the second of two runs: building the simulation (reading the file, the
    lattice, the plan) and running it (the invasion, as OpenPNM's ``run``); the pores in
    order."""
    from porenet.simulation import Simulation

    scene = {
        "lattice": {"kind": "network", "file": str(path), "pore_size": pore_size},
        "fluid": {"kind": "invasion-percolation", "trapping": False},
        "injection": {"at": [centre]},
        "stop": {"at": "complete"},
        "classifier": {"kind": "none"},
    }
    build = run = 0.0
    for _ in range(2):
        t0 = time.perf_counter()
        sim = Simulation.from_scene(scene)
        t1 = time.perf_counter()
        data = sim.run().data
        build, run = t1 - t0, time.perf_counter() - t1
    return build, run, np.asarray(data.order)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--openpnm-python", required=True)
    parser.add_argument("--shape", type=int, nargs=3, default=[100, 100, 100])
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "cubic.npz"
        proc = subprocess.run(
            [args.openpnm_python, "-c", OPENPNM, json.dumps(args.shape), str(path),
             str(args.seed)], capture_output=True, text=True, check=True,
        )  # fmt: skip
        pnm = json.loads(proc.stdout.strip().splitlines()[-1])
        build, ours, order = porenet_invasion(path, 1e-6, pnm["centre"])
    same = np.array_equal(order, np.asarray(pnm["order"]))
    pores = int(np.prod(args.shape))
    print("| network | OpenPNM 3.6 run (s) | porenet run (s) | ratio | porenet build (s) | "
          "ratio with build | same order |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    print(f"| cubic {'x'.join(map(str, args.shape))} ({pores:,} pores) | {pnm['seconds']:.2f} | "
          f"{ours:.2f} | {pnm['seconds'] / ours:.1f} | {build:.2f} | "
          f"{pnm['seconds'] / (build + ours):.1f} | {same} |")  # fmt: skip


if __name__ == "__main__":
    main()
