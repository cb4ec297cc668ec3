"""The fractal dimension of trapping invasion percolation on ``delaunay.random`` networks
against the square lattice of the same side, the numbers behind the tolerance of
``tests/test_delaunay_physics.py`` (README, "The fractal dimension").

Box counting (``porenet.analysis.fractal.pattern_dimension``, automatic range) of the pattern
at breakthrough, centre injection, lambda = 0.5, seeds 1..S; each network of N pores beside
the ``sqrt(N) x sqrt(N)`` square lattice and the square lattice's tabulated mean at that side
(docs/fractal.md: 1.82 plus the finite-size bias)::

    python plugins/porenet-delaunay/examples/fractal_study.py --seeds 40 --pores 1024 4096
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

import porenet_delaunay.plugin

from porenet.analysis.fractal import IP_DIMENSION, finite_size_bias, pattern_dimension
from porenet.testing.contract import plugin_registry
from porenet.testing.runs import simulate


def dimensions(lattice: dict, seeds: range, registry) -> np.ndarray:
    """Box-counting D_f of each seed's pattern."""
    out = []
    for seed in seeds:
        scene = {"seed": seed, "lattice": lattice, "injection": {"at": "centre"},
                 "fluid": {"kind": "invasion-percolation", "trapping": True},
                 "classifier": {"kind": "none"}}  # fmt: skip
        out.append(pattern_dimension(simulate(scene, registry=registry)[1].data, "box-counting"))
    return np.array([fit.dimension for fit in out])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=40)
    parser.add_argument("--pores", type=int, nargs="+", default=[1024, 4096])
    args = parser.parse_args()
    registry = plugin_registry({"delaunay": porenet_delaunay.plugin})
    seeds = range(1, args.seeds + 1)
    print("| lattice | pores | side | D_f mean | sd | sem | table at this side | s/run |")
    print("|---|---|---|---|---|---|---|---|")
    for pores in args.pores:
        side = round(math.sqrt(pores))
        table = IP_DIMENSION[True] + finite_size_bias("box-counting", math.sqrt(pores))[0]
        for name, lattice in (
            ("delaunay.random", {"kind": "delaunay.random", "n_pores": pores, "disorder": 0.5}),
            ("square", {"kind": "square", "n": side, "disorder": 0.5}),
        ):
            t0 = time.perf_counter()
            d = dimensions(lattice, seeds, registry)
            per_run = (time.perf_counter() - t0) / len(d)
            sd = float(d.std(ddof=1))
            print(f"| {name} | {pores if name != 'square' else side * side} | {side} | "
                  f"{d.mean():.3f} | {sd:.3f} | {sd / math.sqrt(len(d)):.3f} | {table:.3f} | "
                  f"{per_run:.2f} |", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
