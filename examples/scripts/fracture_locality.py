"""What makes the fractures branch: the range of the elastic response (solid.foundation).

    python examples/scripts/fracture_locality.py --table docs/fracture-locality.md \
        --out docs/figures/fracture-locality.png                          # n = 100, ~4 min
    python examples/scripts/fracture_locality.py --n 200 --foundation 0.3 1 --nf 1 3 10 30 \
        --seeds 1 2 --table /tmp/locality-200.md                         # ~6 min

Runs Fig. 5's scene (``examples/scenes/fig5.toml``: lambda = 0.1, Ca* = 10, viscous drainage,
Hertzian solid, eps_0 = 0.05) at n pores per side for each foundation stiffness k_f / K_0 and
fracturing number, over seeds, to breakthrough, and reports per point the mean and standard
deviation over seeds of the mass-radius fractal dimension (as examples/scripts/fig5.py), the
drained pores, the springs removed and the longest straight drained run. The figure shows D_f
against N_f for each foundation, and against N_f / sqrt(k_f / K_0), the group that sets how
far a throat ahead of a crack tip opens against the disorder (docs/paper.md, Fig. 5).
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from fig5 import LAMBDA, run, shape


def measure(n: int, foundation: float, nf: float, seed: int) -> dict[str, float]:
    """One run of Fig. 5's scene; its D_f, drained pores, removed springs, straight run."""
    wall, res = run(n, nf, None, foundation=foundation, seed=seed)
    d_f, straight = shape(res.data, n)
    return {
        "d_f": d_f,
        "drained": res.summary["n_drained"],
        "removed": res.summary.get("springs_removed", 0),
        "straight": straight,
        "wall": wall,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100)
    parser.add_argument("--foundation", type=float, nargs="+", default=[0.0, 0.1, 0.3, 1.0, 3.0])
    parser.add_argument("--nf", type=float, nargs="+", default=[0.3, 1.0, 3.0, 10.0, 30.0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--table", type=Path, help="markdown table")
    parser.add_argument("--out", type=Path, help="figure (PNG)")
    args = parser.parse_args()
    if any(k < 0 for k in args.foundation) or any(v <= 0 for v in args.nf) or args.n < 8:
        parser.error("--foundation must be >= 0, --nf > 0 and --n >= 8")
    rows = []
    t0 = time.perf_counter()
    for foundation in args.foundation:
        for nf in args.nf:
            runs = [measure(args.n, foundation, nf, s) for s in args.seeds]
            row = {"foundation": foundation, "nf": nf}
            for key in ("d_f", "drained", "removed", "straight"):
                values = [r[key] for r in runs]
                row[key] = statistics.fmean(values)
                row[key + "_sd"] = statistics.pstdev(values) if len(values) > 1 else 0.0
            row["wall"] = statistics.fmean(r["wall"] for r in runs)
            rows.append(row)
            print(
                f"foundation {foundation:<5g} N_f {nf:<5g} D_f {row['d_f']:.3f} +- "
                f"{row['d_f_sd']:.3f}  drained {row['drained']:7.0f}  removed "
                f"{row['removed']:6.0f}  straight {row['straight']:5.0f}  "
                f"{row['wall']:6.1f} s/run",
                flush=True,
            )
    print(f"total {time.perf_counter() - t0:.0f} s")
    if args.table:
        seeds = ", ".join(str(s) for s in args.seeds)
        lines = [
            f"n = {args.n}, lambda = {LAMBDA}, Ca* = 10, seeds {seeds}, to breakthrough; mean "
            "+- standard deviation over the seeds (`python examples/scripts/"
            "fracture_locality.py`).",
            "",
            "| foundation k_f/K_0 | N_f | N_f/sqrt(k_f/K_0) | D_f (mass-radius) | drained pores | "
            "springs removed | longest straight run |",
            "|---|---|---|---|---|---|---|",
        ]
        for r in rows:
            group = f"{r['nf'] / math.sqrt(r['foundation']):.3g}" if r["foundation"] else "-"
            lines.append(
                f"| {r['foundation']:g} | {r['nf']:g} | {group} | {r['d_f']:.3f} +- "
                f"{r['d_f_sd']:.3f} | {r['drained']:.0f} | {r['removed']:.0f} | "
                f"{r['straight']:.0f} |"
            )
        args.table.write_text("\n".join(lines) + "\n")
        print(f"table: {args.table}")
    if args.out:
        draw(rows, args.n, args.out)
        print(f"figure: {args.out}")


def draw(rows: list[dict[str, float]], n: int, out: Path) -> None:
    """D_f against N_f per foundation, and against N_f / sqrt(foundation)."""
    from matplotlib.figure import Figure

    from porenet.viz.pattern import save_figure

    fig = Figure(figsize=(9.0, 3.6), dpi=130, layout="constrained")
    left, right = fig.subplots(1, 2, sharey=True)
    for i, foundation in enumerate(sorted({r["foundation"] for r in rows})):
        label = f"k_f = {foundation:g} K_0" if foundation else "no foundation (paper)"
        style = {"marker": "o", "ms": 4, "capsize": 2, "color": f"C{i}", "label": label}
        mine = [r for r in rows if r["foundation"] == foundation]
        nf = [r["nf"] for r in mine]
        d_f = [r["d_f"] for r in mine]
        sd = [r["d_f_sd"] for r in mine]
        left.errorbar(nf, d_f, yerr=sd, **style)
        if foundation:
            x = [v / math.sqrt(foundation) for v in nf]
            right.errorbar(x, d_f, yerr=sd, **style)
    for ax, xlabel in ((left, "fracturing number N_f"), (right, "N_f / sqrt(k_f / K_0)")):
        ax.set_xscale("log")
        ax.set_xlabel(xlabel)
        for value, name in ((1.43, "FR (paper)"), (1.64, "VF (paper)")):
            ax.axhline(value, color="k", lw=0.6, ls=":")
            ax.annotate(name, (0.02, value), xycoords=("axes fraction", "data"), fontsize=7,
                        xytext=(0, 2), textcoords="offset points")  # fmt: skip
    left.set_ylabel("D_f (mass-radius)")
    left.legend(fontsize=7, loc="lower left")
    fig.suptitle(f"Fig. 5's scene at n = {n} (λ = {LAMBDA}, Ca* = 10): fracture shape", fontsize=10)
    save_figure(fig, out)


if __name__ == "__main__":
    main()
