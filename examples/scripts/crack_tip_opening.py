"""Where a pressurised straight crack opens the throats around it, for each solid.

    python examples/scripts/crack_tip_opening.py --table docs/crack-tip-opening.md   # ~1 min

One mechanical update, no fluid dynamics: on an n x n lattice (lambda = 0.1, seed 1) at
fracturing number N_f, the pores of a straight crack of ``--length`` pores along x from the
centre hold the entry pressure of a mean throat, ``2 gamma / r_mean``, the others none; the
solid balances the forces. Reported per solid and lattice size: the contacts that opened
(springs removed), the throats whose aperture grew by more than half the mean aperture
("opened"), how many of those lie on the crack's line outside the crack itself, and the
farthest of them ahead of the tip (pore spacings). A straight-ahead opening that reaches
beyond the crack is what makes a crack run straight: the next throat to invade is on its
line, whatever the disorder (docs/paper.md, "Frictional contacts").
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from porenet.simulation import Simulation

#: (label, [solid] fields) of the solids compared.
SOLIDS = (
    ("hertz (the paper's model)", {"kind": "hertz"}),
    ("hertz, k_f = 0.02 K_0", {"kind": "hertz", "foundation": 0.02}),
    ("hertz, k_f = 0.5 K_0", {"kind": "hertz", "foundation": 0.5}),
    ("hertz-mindlin, K_t/K_n = 0.1", {"kind": "hertz-mindlin", "shear_stiffness_ratio": 0.1}),
    ("hertz-mindlin, K_t/K_n = 0.8", {"kind": "hertz-mindlin", "shear_stiffness_ratio": 0.8}),
)


def crack_opening(n: int, solid: dict, length: int, nf: float) -> dict[str, int]:
    """One update under a pressurised crack (module docstring); what opened."""
    scene = {"seed": 1, "lattice": {"n": n, "disorder": 0.1},
             "fluid": {"kind": "invasion-percolation"},
             "solid": {"fracturing_number": nf, **solid}}  # fmt: skip
    sim = Simulation.from_scene(scene)
    state = sim.state
    sim.solid.setup(state)
    xy = sim.lattice.pore_coords
    throats = np.asarray(sim.lattice.throat_pores)
    before = state.apertures.copy()
    mean = float(before.mean())
    rows = np.unique(xy[:, 1])
    line = np.flatnonzero(np.isclose(xy[:, 1], rows[n // 2]))
    line = line[np.argsort(xy[line, 0])]
    crack = line[n // 2 : n // 2 + length]
    pressure = np.zeros(xy.shape[0])
    pressure[crack] = 2.0 / mean
    sim.solid.update(state, pressure)
    opened = np.flatnonzero(state.apertures - before > 0.5 * mean)
    spacing = float(np.diff(xy[line, 0]).min())
    on_line = np.isin(throats[opened], line).all(axis=1)
    outside = ~np.isin(throats[opened], crack).all(axis=1)
    beyond = opened[on_line & outside]
    tip_x = xy[crack[-1], 0]
    ahead = xy[throats[beyond]].mean(axis=1)[:, 0] - tip_x if beyond.size else np.zeros(1)
    return {
        "removed": int(sim.solid.n_removed),
        "opened": int(opened.size),
        "on_line": int(beyond.size),
        "ahead": round(max(0.0, float(ahead.max())) / spacing + 0.5) if beyond.size else 0,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, nargs="+", default=[33, 65, 129])
    parser.add_argument("--length", type=int, default=4, help="crack length (pores)")
    parser.add_argument("--nf", type=float, default=10.0, help="fracturing number N_f")
    parser.add_argument("--table", type=Path, help="markdown table")
    args = parser.parse_args()
    if min(args.n) < 2 * args.length + 4 or args.length < 1 or args.nf <= 0:
        parser.error("--length must be >= 1, --nf > 0 and every --n >= 2 --length + 4")
    lines = [
        f"One update: a crack of {args.length} pores from the centre at 2 gamma / r_mean, "
        f"N_f = {args.nf:g}, lambda = 0.1, seed 1 (`python examples/scripts/"
        "crack_tip_opening.py`).",
        "",
        "| solid | n | contacts opened | throats opened (> r_mean / 2) | of them on the crack's "
        "line beyond the crack | farthest ahead of the tip (pores) |",
        "|---|---|---|---|---|---|",
    ]
    for label, solid in SOLIDS:
        for n in args.n:
            r = crack_opening(n, solid, args.length, args.nf)
            lines.append(f"| {label} | {n} | {r['removed']} | {r['opened']} | {r['on_line']} | "
                         f"{r['ahead']} |")  # fmt: skip
            print(lines[-1], flush=True)
    if args.table:
        args.table.write_text("\n".join(lines) + "\n")
        print(f"table: {args.table}")


if __name__ == "__main__":
    main()
