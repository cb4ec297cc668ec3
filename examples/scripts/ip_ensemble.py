"""Breakthrough statistics of invasion percolation over a seed ensemble.

    python examples/scripts/ip_ensemble.py --n 400 --seeds 40

For each seed (apertures uniform in [(1-λ)a, (1+λ)a], λ = 0.5) it records, at breakthrough,
the drained fraction without trapping, the drained and trapped fractions with trapping, and the
largest accepted entry-pressure quantile. When OpenPNM is importable (see
tests/benchmarks/openpnm_ip.py) the same apertures are invaded by OpenPNM too, its sequence is
cut at its first edge pore, and the script reports how many seeds give identical orders.
Numbers quoted in docs/verification.md come from this script.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

import porenet

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests" / "benchmarks"))
from openpnm_ip import openpnm_available, openpnm_invasion


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--n", type=int, default=400)
    parser.add_argument("--seeds", type=int, default=40)
    parser.add_argument("--disorder", type=float, default=0.5)
    args = parser.parse_args()
    n = args.n
    pnm = openpnm_available()
    rows = {"no-trap drained": [], "trap drained": [], "trap trapped": [], "quantile": []}
    identical = 0
    for seed in range(args.seeds):
        base = {"seed": seed, "lattice": {"n": n, "disorder": args.disorder}}
        a = porenet.run(base | {"fluid": {"trapping": False}})
        b = porenet.run(base | {"fluid": {"trapping": True}})
        rows["no-trap drained"].append(a.summary["drained_fraction"])
        rows["trap drained"].append(b.summary["drained_fraction"])
        rows["trap trapped"].append(b.summary["trapped_fraction"])
        rows["quantile"].append(a.summary["max_entry_pressure_quantile"])
        if pnm:
            r = a.lattice.initial_apertures
            same = True
            for trapping, ours in ((False, a), (True, b)):
                ref = openpnm_invasion(r, n, trapping, outlet_ring=trapping)["order"]
                edge = a.lattice.boundary_pores[ref]
                ref = ref[: int(np.argmax(edge)) + 1]
                same &= bool(np.array_equal(ref, ours.data.order))
            identical += same
    print(f"n = {n}, λ = {args.disorder}, {args.seeds} seeds, at breakthrough:")
    for key, values in rows.items():
        v = np.asarray(values)
        print(
            f"  {key:<16} mean {v.mean():.4f}  sd {v.std(ddof=1):.4f}  "
            f"sem {v.std(ddof=1) / np.sqrt(v.size):.4f}"
        )
    if pnm:
        print(
            f"  OpenPNM gives the identical order (both trapping settings) for "
            f"{identical} / {args.seeds} seeds"
        )
    else:
        print("  OpenPNM not installed: no comparison")


if __name__ == "__main__":
    main()
