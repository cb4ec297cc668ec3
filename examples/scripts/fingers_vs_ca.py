"""Finger width and fractal dimension against the capillary number, at fixed disorder.

    python examples/scripts/fingers_vs_ca.py --n 400 --seeds 5 \
        --table docs/fingers-vs-ca.md --figure docs/figures/fingers-vs-ca.png

Viscous drainage (kind ``viscous``, default settings) to breakthrough on n x n lattices at
λ = 0.3, over modified capillary numbers Ca* = Ca (L/a) / [λ/(1-λ²)] (Ca* = 1 is the CF/VF
line of docs/model.md section 6), and invasion percolation with trapping as the Ca -> 0 limit, on
the same seeds. Per Ca*: the mean finger width (pores, porenet.analysis.features), D_f by mass
against distance and by box counting (porenet.analysis.fractal, automatic range; raw, and
with the invasion-percolation finite-size bias removed), and the drained fraction; means and
standard errors over seeds. docs/paper.md quotes the table (issue 3: "higher Ca gives thinner
fingers and a lower fractal dimension at fixed λ").
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import porenet
from porenet.analysis.features import pattern_features
from porenet.analysis.fractal import pattern_dimension
from porenet.analysis.numbers import capillary_number_at

MEASURES = {
    "finger width (pores)": "width",
    "D_f mass-radius": "mr",
    "D_f box counting": "box",
    "D_f box, bias removed": "box_corrected",
    "drained fraction": "drained",
}


def measure(data) -> dict[str, float]:
    mr = pattern_dimension(data)
    box = pattern_dimension(data, "box-counting")
    features = pattern_features(data)
    return {
        "width": features["finger_width_mean"],
        "mr": mr.dimension,
        "box": box.dimension,
        "box_corrected": box.dimension - box.bias,
        "drained": features["drained_fraction"],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=400)
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--disorder", type=float, default=0.3)
    parser.add_argument("--ca-star", type=float, nargs="+", default=[1.0, 3.0, 10.0, 30.0, 100.0])
    parser.add_argument("--table", type=Path)
    parser.add_argument("--figure", type=Path)
    args = parser.parse_args()
    n, lam = args.n, args.disorder
    cases: list[tuple[str, float, dict]] = [
        ("IP (Ca -> 0)", 0.0, {"kind": "invasion-percolation", "trapping": True})
    ]
    for cs in args.ca_star:
        ca = capillary_number_at(cs, n, lam)
        cases.append((f"{cs:g} (Ca = {ca:.3g})", cs, {"kind": "viscous", "capillary_number": ca}))
    head = ["Ca*", *MEASURES, "wall per run (s)"]
    lines = [
        f"n = {n}, λ = {lam}, seeds 0-{args.seeds - 1}, to breakthrough; mean ± standard "
        f"error over seeds (`python examples/scripts/fingers_vs_ca.py --n {n} "
        f"--seeds {args.seeds}`).",
        "",
        "| " + " | ".join(head) + " |",
        "|" + "---|" * len(head),
    ]
    results: list[tuple[float, dict[str, np.ndarray]]] = []
    for label, cs, fluid in cases:
        rows, t0 = [], time.perf_counter()
        for seed in range(args.seeds):
            scene = {
                "seed": seed,
                "lattice": {"n": n, "disorder": lam},
                "fluid": fluid,
                "classifier": {"kind": "none"},
            }
            rows.append(measure(porenet.run(scene).data))
        wall = (time.perf_counter() - t0) / args.seeds
        values = {k: np.array([r[k] for r in rows]) for k in rows[0]}
        results.append((cs, values))
        sem = {k: v.std(ddof=1) / np.sqrt(v.size) if v.size > 1 else np.nan
               for k, v in values.items()}  # fmt: skip
        cells = [label] + [f"{values[k].mean():.3f} ± {sem[k]:.3f}" for k in MEASURES.values()]
        lines.append("| " + " | ".join([*cells, f"{wall:.1f}"]) + " |")
        print(lines[-1], flush=True)
    if args.table:
        args.table.write_text("\n".join(lines) + "\n")
        print(f"table: {args.table}")
    if args.figure:
        plot(results, n, lam, args.figure)
        print(f"figure: {args.figure}")


def plot(results, n: int, lam: float, path: Path) -> None:
    from matplotlib.figure import Figure

    from porenet.viz.pattern import save_figure

    fig = Figure(figsize=(8.0, 3.2), dpi=150, layout="constrained")
    axes = fig.subplots(1, 2)
    ip = results[0][1]
    dyn = results[1:]
    x = np.array([cs for cs, _ in dyn])
    for ax, keys, ylabel in (
        (axes[0], ("width",), "mean finger width (pores)"),
        (axes[1], ("mr", "box", "box_corrected"), "D_f"),
    ):
        for key, marker in zip(keys, "osD", strict=False):
            name = next(k for k, v in MEASURES.items() if v == key)
            mean = np.array([v[key].mean() for _, v in dyn])
            err = np.array([v[key].std(ddof=1) / np.sqrt(v[key].size) for _, v in dyn])
            line = ax.errorbar(x, mean, yerr=err, marker=marker, capsize=3, label=name)
            ax.axhline(ip[key].mean(), ls=":", color=line[0].get_color())
        ax.set_xscale("log")
        ax.set_xlabel("Ca* = Ca (L/a) / [λ/(1-λ²)]")
        ax.set_ylabel(ylabel)
        ax.axvline(1.0, color="0.6", lw=0.8)
    axes[1].axhline(1.82, color="k", lw=0.6, ls="--")
    axes[1].axhline(1.64, color="k", lw=0.6, ls="-.")
    axes[1].legend(fontsize=7)
    fig.suptitle(
        f"n = {n}, λ = {lam}: dotted lines are invasion percolation (Ca -> 0); "
        "dashed 1.82 (CF), dash-dot 1.64 (VF, paper)",
        fontsize=8,
    )
    save_figure(fig, path)


if __name__ == "__main__":
    main()
