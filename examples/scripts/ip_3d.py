"""Invasion percolation on the 3-D cubic lattice: drained fraction at breakthrough and the
pattern's fractal dimension, over sizes and seeds.

    python examples/scripts/ip_3d.py --sizes 16 24 32 48 64 96 --seeds 16

Centre injection, outlet on the six faces, apertures uniform with λ = 0.5, with and without
trapping. For each size it prints the ensemble mean drained fraction at breakthrough
(geometric mean over seeds, the cost model's ``IP_3D``, docs/cost.md), how many runs had
defender trapped at breakthrough and how much (with trapping), and fits

* ``fraction = a n^-b`` over the sizes (the cost model's law in 3-D);
* the finite-size estimate of the fractal dimension, ``M ~ n^D`` with ``M`` the drained pores
  at breakthrough (weighted least squares on the mean of ``log M``; error from the spread of
  the seeds), and the mass-radius estimate ``<M(R)> ~ R^D`` from the inlet, averaged over
  seeds at the largest size (jackknife error). The 3-D percolation cluster has D ≈ 2.52.

docs/lattices.md ("The cubic lattice") quotes the output. Not a test.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from porenet.simulation import Simulation


def breakthrough(n: int, seed: int, trapping: bool) -> tuple[np.ndarray, int]:
    """The drained pores' coordinates (lattice spacings) in order of drainage, and the number
    of defender pores trapped at breakthrough."""
    scene = {
        "seed": seed,
        "lattice": {"kind": "cubic", "shape": [n, n, n], "disorder": 0.5},
        "fluid": {"kind": "invasion-percolation", "trapping": trapping},
        "classifier": {"kind": "none"},
    }
    data = Simulation.from_scene(scene).run().data
    trapped = 0 if data.trapped is None else int(np.count_nonzero(data.trapped))
    return data.pore_coords[data.order] / (2.0 * data.pore_size), trapped


def weighted_line(x: np.ndarray, y: np.ndarray, err: np.ndarray) -> tuple[float, float, float]:
    """Slope, intercept and the slope's standard error of a weighted least-squares line."""
    a = np.vstack([x, np.ones_like(x)]).T
    w = 1.0 / err**2
    cov = np.linalg.inv(a.T @ (a * w[:, None]))
    slope, intercept = cov @ a.T @ (w * y)
    return float(slope), float(intercept), float(np.sqrt(cov[0, 0]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[16, 24, 32, 48, 64, 96])
    parser.add_argument("--seeds", type=int, default=16)
    parser.add_argument("--trapping", choices=["both", "yes", "no"], default="both")
    args = parser.parse_args()
    sizes = np.array(args.sizes, dtype=float)
    print("| trapping | n | mean drained fraction | log-mass spread | runs with trapped defender "
          "| mean trapped pores | seconds |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    modes = {"both": (True, False), "yes": (True,), "no": (False,)}[args.trapping]
    for trapping in modes:
        log_mass, log_err, last = [], [], []
        for n in args.sizes:
            t0 = time.perf_counter()
            outcomes = [breakthrough(n, s, trapping) for s in range(args.seeds)]
            runs = [coords for coords, _ in outcomes]
            trapped = np.array([count for _, count in outcomes])
            masses = np.log([len(r) for r in runs])
            log_mass.append(masses.mean())
            log_err.append(masses.std(ddof=1) / np.sqrt(args.seeds))
            last = runs
            print(f"| {trapping} | {n} | {np.exp(masses.mean()) / n**3:.4f} | "
                  f"{masses.std(ddof=1):.2f} | {np.count_nonzero(trapped)} / {args.seeds} | "
                  f"{trapped.mean():.1f} | {time.perf_counter() - t0:.1f} |")  # fmt: skip
        y, e = np.array(log_mass), np.array(log_err)
        d, c, d_err = weighted_line(np.log(sizes), y, e)
        b, _, _ = weighted_line(np.log(sizes), y - 3 * np.log(sizes), e)
        print(f"trapping {trapping}: fraction = {np.exp(c):.3f} n^{b:.3f} (i.e. a n^-b, "
              f"b = {-b:.3f}); finite-size D = {d:.3f} ± {d_err:.3f}")  # fmt: skip
        # the effective exponent between consecutive sizes, which should drift towards the
        # percolation cluster's D as the corrections to scaling fade
        for k in range(1, len(sizes)):
            slope = (y[k] - y[k - 1]) / np.log(sizes[k] / sizes[k - 1])
            err = np.hypot(e[k], e[k - 1]) / np.log(sizes[k] / sizes[k - 1])
            print(f"trapping {trapping}: local D between n = {sizes[k - 1]:g} and "
                  f"{sizes[k]:g}: {slope:.3f} ± {err:.3f}")  # fmt: skip
        n = args.sizes[-1]
        radii = np.geomspace(2.0, n / 8.0, 10)
        mass = np.array([
            np.searchsorted(np.sort(np.linalg.norm(r - r[0], axis=1)), radii, side="right")
            for r in last
        ], dtype=float)  # fmt: skip
        slope = np.polyfit(np.log(radii), np.log(mass.mean(axis=0)), 1)[0]
        jack = [np.polyfit(np.log(radii), np.log(np.delete(mass, i, 0).mean(axis=0)), 1)[0]
                for i in range(len(mass))]  # fmt: skip
        jack_err = np.sqrt((len(jack) - 1) / len(jack) * np.sum((jack - np.mean(jack)) ** 2))
        print(f"trapping {trapping}: mass-radius at n = {n}, R in [2, {n / 8:g}] spacings: "
              f"D = {slope:.3f} ± {jack_err:.3f}")  # fmt: skip


if __name__ == "__main__":
    main()
