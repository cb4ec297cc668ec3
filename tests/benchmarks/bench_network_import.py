"""Benchmark: importing a million-pore network with the ``network`` lattice.

Not a test (no timing assertions): run it directly and read the medians.

    python tests/benchmarks/bench_network_import.py            # 100^3 = 1 M pores
    python tests/benchmarks/bench_network_import.py --side 50 --repeat 5

It writes, in a temporary directory, a ``side^3`` cubic network with jittered pore centres
and random sizes (2.97 M throats at side 100) as an OpenPNM-style ``.npz`` (``numpy.savez``,
and ``numpy.savez_compressed``) and as Statoil files (the x faces linked to the inlet and
outlet reservoirs, numbers with 7 significant digits as pnextract writes them), then times
building ``NetworkLattice`` from each (reading, checking, scaling; median of ``--repeat``),
and, separately, its adjacency lists (built on first use by the fluid models). The first
Statoil read of a fresh install also compiles the text parser (~2 s, then cached on disk):
the script reads a small file once before timing.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(
    0, str(Path(__file__).resolve().parents[2] / "porenet" / "kinds" / "network" / "tests")
)

from network_helpers import jittered_cubic

from porenet.kinds.network.config import NetworkLatticeConfig
from porenet.kinds.network.model import NetworkLattice


def _text(rows: np.ndarray, fmt: str) -> str:
    """Rows of numbers as text lines (a format per column)."""
    return "\n".join(fmt % tuple(row) for row in rows.tolist()) + "\n"


def write_statoil(prefix: Path, net: dict[str, np.ndarray]) -> Path:
    """The network of ``jittered_cubic`` as Statoil files; ``pore.left`` / ``pore.right``
    linked to the inlet (-1) and outlet (0) reservoirs (appended after the throats)."""
    xyz, conns = net["pore.coords"], net["throat.conns"]
    n, m = len(xyz), len(conns)
    inlets, outlets = np.flatnonzero(net["pore.left"]), np.flatnonzero(net["pore.right"])
    ends = np.concatenate(
        [conns + 1, np.column_stack([inlets + 1, np.full(len(inlets), -1)]),
         np.column_stack([outlets + 1, np.zeros(len(outlets), dtype=np.int64)])]
    )  # fmt: skip
    k = len(ends)
    r = np.concatenate([net["throat.inscribed_diameter"] / 2, np.full(k - m, 1e-5)])
    g = np.concatenate([net["throat.shape_factor"], np.full(k - m, 0.05)])
    length = np.concatenate([net["throat.total_length"], np.full(k - m, 1e-4)])
    index = np.arange(1, k + 1)
    link1 = np.column_stack([index, ends, r, g, length])
    link2 = np.column_stack(
        [index, ends, 0.25 * length, 0.25 * length, 0.5 * length, np.zeros(k), np.zeros(k)]
    )
    Path(f"{prefix}_link1.dat").write_text(f"{k}\n" + _text(link1, "%d %d %d %.6e %.6e %.6e"))
    Path(f"{prefix}_link2.dat").write_text(_text(link2, "%d %d %d %.6e %.6e %.6e %.6e %.6e"))
    node2 = np.column_stack([np.arange(1, n + 1), net["pore.volume"], np.full((n, 3), 0.01)])
    Path(f"{prefix}_node2.dat").write_text(_text(node2, "%d %.6e %.6e %.6e %.6e"))
    # node1: index x y z n, neighbours, is_inlet is_outlet, throats; grouped by degree
    order = np.argsort(np.concatenate([ends[:, 0], ends[:, 1]]), kind="stable")
    pore = np.concatenate([ends[:, 0], ends[:, 1]])[order]
    other = np.concatenate([ends[:, 1], ends[:, 0]])[order]
    link = np.concatenate([index, index])[order]
    keep = pore > 0
    pore, other, link = pore[keep] - 1, other[keep], link[keep]
    degree = np.bincount(pore, minlength=n)
    start = np.concatenate([[0], np.cumsum(degree)[:-1]])
    lines = np.empty(n, dtype=object)
    for d in np.unique(degree):
        group = np.flatnonzero(degree == d)
        slots = start[group][:, None] + np.arange(d)
        rows = np.column_stack(
            [group + 1, xyz[group], np.full(len(group), d), other[slots],
             net["pore.left"][group], net["pore.right"][group], link[slots]]
        )  # fmt: skip
        fmt = "%d %.6e %.6e %.6e %d" + " %d" * d + " %d %d" + " %d" * d
        lines[group] = _text(rows, fmt).splitlines()
    extent = " ".join(f"{v:.6e}" for v in xyz.max(axis=0))
    Path(f"{prefix}_node1.dat").write_text(f"{n} {extent}\n" + "\n".join(lines) + "\n")
    return Path(f"{prefix}_node1.dat")


def build(path: Path) -> NetworkLattice:
    config = NetworkLatticeConfig(file=path, pore_size=1e-5)
    lattice = NetworkLattice(config, np.random.default_rng(0))
    _ = lattice.boundary_pores, lattice.throat_factors
    return lattice


def median_time(fn, repeat: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), out


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--side", type=int, default=100)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp_path = Path(tmp)
        small = write_statoil(tmp_path / "warm", jittered_cubic((3, 3, 3)))
        build(small)  # compile (or load) the text parser
        t0 = time.perf_counter()
        net = jittered_cubic((args.side,) * 3)
        npz = tmp_path / "net.npz"
        np.savez(npz, **net)
        packed = tmp_path / "packed.npz"
        np.savez_compressed(packed, **net)
        node1 = write_statoil(tmp_path / "net", net)
        sizes = {
            "npz": npz.stat().st_size,
            "npz (compressed)": packed.stat().st_size,
            "statoil": sum(p.stat().st_size for p in tmp_path.glob("net_*.dat")),
        }
        n, m = len(net["pore.coords"]), len(net["throat.conns"])
        print(f"{n:,} pores, {m:,} throats; files written in {time.perf_counter() - t0:.0f} s")
        print("| file | size (MB) | NetworkLattice (s) | with adjacency (s) |")
        print("|---|---|---|---|")
        for name, path in (("npz", npz), ("npz (compressed)", packed), ("statoil", node1)):
            seconds, lattice = median_time(lambda p=path: build(p), args.repeat)
            assert lattice.n_pores == n and lattice.n_throats == m
            adjacency, _ = median_time(
                lambda p=path: build(p).adjacency, 1 if args.repeat < 3 else args.repeat
            )
            print(f"| {name} | {sizes[name] / 1e6:.0f} | {seconds:.2f} | {adjacency:.2f} |")


if __name__ == "__main__":
    main()
