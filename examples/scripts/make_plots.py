"""Regenerate the figures of docs/plots.md: one small run per model, every plot kind.

    python examples/scripts/make_plots.py            # docs/figures/plots-RUN-KIND.png (~30 s)
    python examples/scripts/make_plots.py --out /tmp/plots --n 40   # quicker, smaller

Runs (seed 1, a = 0.1 µm, γ = 0.07 N/m, µ = 1e-3 Pa s, stop at breakthrough):

* ``ip``: invasion percolation with trapping, n = 2N, λ = 0.3: ``pattern``, ``fractal``,
  ``timeseries`` (the entry-pressure signal).
* ``viscous``: rigid medium, n = N, λ = 0.3, Ca = 1e-3: ``time``, ``pressure``, ``timeseries``.
* ``fracturing``: deformable (Hertz) medium, n = N, λ = 0.1, N_f = 10, Ca* = 10 as in Fig. 5:
  ``mechanics``.

The lattice sizes are far below the paper's n = 400, to keep the script short: the pictures
show what each plot kind draws, not the paper's measurements.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import porenet
from porenet.viz import make_figure, save_figure

ROOT = Path(__file__).resolve().parents[2]


def scenes(n: int) -> dict[str, tuple[dict, list[str]]]:
    lattice = {"disorder": 0.3, "pore_size": 1e-7}
    ca_star, lam = 10.0, 0.1
    ca = ca_star * (lam / (1 - lam**2)) / n  # Ca* = Ca (L/a) / [λ/(1-λ²)], L = n a
    return {
        "ip": (
            {"seed": 1, "lattice": {"n": 2 * n, **lattice},
             "fluid": {"kind": "invasion-percolation", "trapping": True}},
            ["pattern", "fractal", "timeseries"],
        ),
        "viscous": (
            {"seed": 1, "lattice": {"n": n, **lattice},
             "fluid": {"kind": "viscous", "capillary_number": 1e-3}},
            ["time", "pressure", "timeseries"],
        ),
        "fracturing": (
            {"seed": 1, "lattice": {"n": n, "disorder": lam, "pore_size": 1e-7},
             "fluid": {"kind": "viscous", "capillary_number": ca},
             "solid": {"kind": "hertz", "fracturing_number": 10.0}},
            ["mechanics"],
        ),
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "figures")
    parser.add_argument("--n", type=int, default=100, help="lattice size N (default 100)")
    parser.add_argument("--dpi", type=float, default=110.0)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for name, (scene, kinds) in scenes(args.n).items():
        start = time.perf_counter()
        data = porenet.run({**scene, "name": name}).data
        print(f"{name}: n = {scene['lattice']['n']}, {time.perf_counter() - start:.1f} s")
        for kind in kinds:
            path = args.out / f"plots-{name}-{kind}.png"
            save_figure(make_figure(data, kind), path, dpi=args.dpi)
            print(f"  {kind}: {path}")


if __name__ == "__main__":
    main()
