"""Generate the small irregular 2-D network of examples/networks/ and its scene.

    python examples/scripts/make_example_network.py

Writes ``examples/networks/delaunay-2d.npz``, an OpenPNM-style network dict (the keys of
docs/lattices.md, "Imported networks (kind `network`)"), and ``examples/scenes/network.toml``,
a viscous drainage from the left face to the right one.

The network: 20 x 20 pores on a jittered grid of spacing 50 µm (the pores of the left and
right columns on x = 0 and x = L exactly, those of the bottom and top rows on y = 0 and
y = L), joined by the edges of their Delaunay triangulation, of which 15 % are removed at
random (so the coordination varies and a few pores may end up isolated). Sizes, from one
seeded generator: pore inscribed radii uniform in [12, 20] µm, pore volumes those of the
spheres; throat radii 30-80 % of the smaller of their two pores'; shape factors uniform in
[0.03, 0.08] (triangles, squares and circles by pnflow's thresholds); total length the
distance between the pore centres, the throat's own length that less the two pore radii (at
least 1 µm). Labels in OpenPNM 3's naming: ``pore.left`` (x = 0), ``pore.right`` (x = L),
``pore.front`` (y = 0), ``pore.back`` (y = L) and ``pore.surface`` (any of them).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.spatial import Delaunay

ROOT = Path(__file__).resolve().parents[2]
SIDE = 20
SPACING = 50e-6  # m
REMOVED = 0.15

SCENE = """\
# Viscous drainage (Ca = 1e-3) across an irregular 2-D network imported from an OpenPNM-style
# .npz (docs/lattices.md, "Imported networks (kind `network`)"), from the left face to the
# right one. Generated, with the network, by examples/scripts/make_example_network.py.
#   porenet run examples/scenes/network.toml -o network.h5
name = "network"
seed = 0

[lattice]
kind = "network"
file = "../networks/delaunay-2d.npz"
pore_size = {pore_size:.6g}   # a (m): the mean throat radius of the file
outlet = "pore.right"

[injection]
at = "pore.left"

[fluid]
kind = "viscous"
capillary_number = 1e-3
viscosity = 1e-3            # mu (Pa s)
interfacial_tension = 0.07  # gamma (N/m)

[stop]
at = "breakthrough"
"""


def grid_points(rng: np.random.Generator) -> np.ndarray:
    """(SIDE^2, 2) jittered grid points in [0, L]^2, the outer rows and columns on the box."""
    length = (SIDE - 1) * SPACING
    j, i = np.meshgrid(np.arange(SIDE), np.arange(SIDE))
    xy = np.stack([j.ravel(), i.ravel()], axis=1) * SPACING
    xy = xy + rng.uniform(-0.3, 0.3, size=xy.shape) * SPACING
    for axis in (0, 1):
        index = (j, i)[axis].ravel()
        xy[index == 0, axis] = 0.0
        xy[index == SIDE - 1, axis] = length
    return np.clip(xy, 0.0, length)


def delaunay_edges(xy: np.ndarray) -> np.ndarray:
    """(M, 2) sorted pore pairs: the edges of the Delaunay triangulation of ``xy``."""
    simplices = Delaunay(xy).simplices
    pairs = np.concatenate([simplices[:, [0, 1]], simplices[:, [1, 2]], simplices[:, [0, 2]]])
    return np.unique(np.sort(pairs, axis=1), axis=0)


def make_network(seed: int = 2024) -> dict[str, np.ndarray]:
    """The network dict (OpenPNM keys, SI units)."""
    rng = np.random.default_rng(seed)
    xy = grid_points(rng)
    edges = delaunay_edges(xy)
    edges = edges[rng.random(len(edges)) >= REMOVED]
    n = len(xy)
    pore_r = rng.uniform(12e-6, 20e-6, size=n)
    smaller = np.minimum(pore_r[edges[:, 0]], pore_r[edges[:, 1]])
    throat_r = smaller * rng.uniform(0.3, 0.8, size=len(edges))
    total = np.linalg.norm(xy[edges[:, 1]] - xy[edges[:, 0]], axis=1)
    own = np.maximum(total - pore_r[edges[:, 0]] - pore_r[edges[:, 1]], 1e-6)
    length = xy.max(axis=0)
    on = {
        "pore.left": xy[:, 0] == 0.0,
        "pore.right": xy[:, 0] == length[0],
        "pore.front": xy[:, 1] == 0.0,
        "pore.back": xy[:, 1] == length[1],
    }
    on["pore.surface"] = np.logical_or.reduce(list(on.values()))
    return {
        "pore.coords": np.column_stack([xy, np.zeros(n)]),
        "throat.conns": edges.astype(np.int64),
        "pore.inscribed_diameter": 2.0 * pore_r,
        "pore.volume": 4.0 / 3.0 * np.pi * pore_r**3,
        "throat.inscribed_diameter": 2.0 * throat_r,
        "throat.shape_factor": rng.uniform(0.03, 0.08, size=len(edges)),
        "throat.total_length": total,
        "throat.length": own,
        **on,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--network", type=Path, default=ROOT / "examples/networks/delaunay-2d.npz")
    parser.add_argument("--scene", type=Path, default=ROOT / "examples/scenes/network.toml")
    args = parser.parse_args()
    net = make_network()
    args.network.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(args.network, **net)
    pore_size = float(np.mean(net["throat.inscribed_diameter"])) / 2.0
    args.scene.write_text(SCENE.format(pore_size=pore_size))
    degree = np.bincount(net["throat.conns"].ravel(), minlength=len(net["pore.coords"]))
    print(
        f"wrote {args.network} ({args.network.stat().st_size / 1e3:.0f} kB): "
        f"{len(net['pore.coords'])} pores, {len(net['throat.conns'])} throats, "
        f"{int(np.sum(degree == 0))} isolated, mean throat radius {pore_size:.3g} m"
    )
    print(f"wrote {args.scene}")


if __name__ == "__main__":
    main()
