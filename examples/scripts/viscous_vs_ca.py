"""The viscous model across capillary numbers: where it matches invasion percolation, and
how compact the pattern at breakthrough is.

    python examples/scripts/viscous_vs_ca.py overlap    # n = 20, seeds 0-5   (~1 min)
    python examples/scripts/viscous_vs_ca.py fraction   # n = 100, seeds 0-2  (~2 min)
    python examples/scripts/viscous_vs_ca.py df         # n = 150, seed 1     (~1 min)

* ``overlap``: Jaccard overlap ``|A & B| / |A | B|`` of the drained sets at breakthrough with
  invasion percolation with trapping on the same apertures (lambda = 0.3, default settings).
* ``fraction``: drained fraction at breakthrough, mean and standard error over seeds 0-2,
  lambda = 0.3, ``safety_factor = 0.25``, against invasion percolation with trapping.
* ``df``: mass-radius exponent (slope of log mass within radius R of the inlet against
  log R, R from 2 to 0.35 n pores, 12 log-spaced radii) of one pattern at breakthrough, for
  Ca = 1e-2 and 1e-1 (lambda = 0.3, seed 1, ``safety_factor = 0.25``) and for invasion
  percolation with trapping (seed 0). One sample each: an indication, not a measurement of
  D_f (that needs ensembles; issue 5).
"""

from __future__ import annotations

import argparse

import numpy as np

from porenet.simulation import Simulation
from porenet.testing.runs import pattern_overlap


def run(n: int, seed: int, fluid: dict):
    scene = {"seed": seed, "lattice": {"n": n, "disorder": 0.3, "pore_size": 1e-7}}
    return Simulation.from_scene(scene | {"fluid": fluid}).run().data


IP = {"kind": "invasion-percolation", "trapping": True}


def viscous(ca: float, **extra) -> dict:
    return {"kind": "viscous", "capillary_number": ca, **extra}


def overlap() -> None:
    ips = [run(20, s, IP) for s in range(6)]
    for ca in (1e-1, 1e-3, 1e-4, 3e-5, 1e-5):
        j = []
        for s in range(6):
            a, b = run(20, s, viscous(ca)).drained, ips[s].drained
            j.append(pattern_overlap(a, b))
        print(f"Ca = {ca:<7g} overlap with IP {np.round(j, 3)}  mean {np.mean(j):.3f}")


def fraction() -> None:
    for label, fluid in [("IP", IP)] + [
        (f"Ca = {ca:g}", viscous(ca, safety_factor=0.25)) for ca in (1e-3, 3e-3, 1e-2, 3e-2, 1e-1)
    ]:
        f = [run(100, s, fluid).drained.mean() for s in range(3)]
        print(f"{label:<11} drained fraction {np.mean(f):.4f} +- {np.std(f) / np.sqrt(3):.4f}")


def mass_radius(data) -> float:
    n = data.grid_shape[0]
    i, j = np.nonzero(data.as_grid(data.drained))
    r = np.hypot(i - n // 2, j - n // 2)
    radii = np.unique(np.round(np.geomspace(2, 0.35 * n, 12)).astype(int))
    mass = [np.sum(r <= R) for R in radii]
    return float(np.polyfit(np.log(radii), np.log(mass), 1)[0])


def df() -> None:
    print(f"IP (seed 0)  mass-radius exponent {mass_radius(run(150, 0, IP)):.3f}")
    for ca in (1e-2, 1e-1):
        d = run(150, 1, viscous(ca, safety_factor=0.25))
        print(f"Ca = {ca:<5g}   mass-radius exponent {mass_radius(d):.3f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=["overlap", "fraction", "df"])
    {"overlap": overlap, "fraction": fraction, "df": df}[parser.parse_args().what]()


if __name__ == "__main__":
    main()
