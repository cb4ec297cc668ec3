"""Finite-size bias of the fractal-dimension estimators on invasion-percolation ensembles.

    python examples/scripts/fractal_bias.py --docs docs    # the study of docs/fractal.md
    python examples/scripts/fractal_bias.py --quick        # a smoke test (seconds)

Invasion percolation on the n x n square lattice (lambda = 0.5; the invasion order does not
depend on lambda), stopped at breakthrough, seeds 0, 1, ...: centre injection with and without
trapping, measured with both estimators of ``porenet.analysis.fractal`` (automatic range,
``pattern_dimension``), and left-edge injection measured by box counting. For each estimator
and size it reports the mean, sd and sem of D_f, the bias against the asymptotic 1.82
(trapping) and 91/48 (no trapping), how the automatic range behaves, the bias with other upper
ends of the range, and the exponent of breakthrough mass against n. With ``--docs DIR`` it
writes DIR/fractal-bias.md, DIR/figures/fractal-bias.png and DIR/figures/fractal-slopes.png.
It prints the ``BIAS_TABLE`` literal of porenet/analysis/fractal.py.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

import porenet
from porenet.analysis.fractal import (
    IP_DIMENSION,
    MIN_RANGE_RATIO,
    RADII_PER_OCTAVE,
    RANGE_FRACTION,
    SCALE_MIN,
    box_counting,
    mass_radius,
    pattern_dimension,
)

#: Upper ends of the range compared with the automatic one (fractions of the median distance).
FRACTIONS = (0.125, 0.25, 0.5, 1.0)
#: Lattice sizes and seeds per size of the study in docs/fractal.md.
SIZES = [100, 200, 400, 800, 1600]
SEEDS = [400, 400, 400, 200, 60]
#: Okabe-Ito colours (colour-blind safe).
COLOURS = ("#0072B2", "#E69F00", "#009E73", "#CC79A7", "#D55E00", "#56B4E9")
#: (label, method, injection, trapping) of each ensemble measured.
SERIES = (
    ("mass-radius", "mass-radius", "centre", True),
    ("mass-radius", "mass-radius", "centre", False),
    ("box-counting", "box-counting", "centre", True),
    ("box-counting", "box-counting", "centre", False),
    ("box-counting", "box-counting", "left-edge", True),
    ("box-counting", "box-counting", "left-edge", False),
)


def median_distance(data, method: str) -> float:
    """``l`` of the automatic range: median distance of the drained pores from the inlet
    (mass-radius) or of the occupied cells from their centroid (box counting), in spacings."""
    if method == "mass-radius":
        xy = data.pore_coords / (2.0 * data.pore_size)
        d = xy[data.drained] - xy[data.order[0]]
        return float(np.median(np.hypot(d[:, 0], d[:, 1])))
    rows, cols = np.nonzero(data.as_grid(data.drained))
    return float(np.median(np.hypot(rows - rows.mean(), cols - cols.mean())))


def measure(data, method: str) -> dict | None:
    """D_f with the automatic range, the range, D_f with other upper ends, the curve."""
    try:
        fit = pattern_dimension(data, method)
    except ValueError:
        return None
    ell = median_distance(data, method)
    alt = {}
    for c in FRACTIONS:
        hi = max(c * ell, MIN_RANGE_RATIO * SCALE_MIN)
        try:
            if method == "mass-radius":
                xy = data.pore_coords / (2.0 * data.pore_size)
                f = mass_radius(data.drained, xy, xy[data.order[0]], r_min=SCALE_MIN, r_max=hi)
            else:
                f = box_counting(data.as_grid(data.drained), s_min=SCALE_MIN, s_max=hi)
            alt[c] = f.dimension
        except ValueError:
            alt[c] = math.nan
    top = float(fit.scales[fit.fitted].max())
    return {
        "d": fit.dimension,
        "stderr": fit.stderr,
        "r_max": top,
        "points": int(fit.fitted.sum()),
        "clamped": bool(RANGE_FRACTION * ell < MIN_RANGE_RATIO * SCALE_MIN),
        "alt": alt,
        "scales": fit.scales,
        "counts": fit.counts,
    }


def run_ensembles(sizes, seeds, edge_seeds, disorder) -> dict:
    """Every run of the study; returns {(label, injection, trapping, n): [measurement, ...]}
    and {(trapping, n): [breakthrough mass, ...]} for centre injection."""
    results: dict = {}
    masses: dict = {}
    for n, n_seeds in zip(sizes, seeds, strict=True):
        t0 = time.perf_counter()
        for injection in ("centre", "left-edge"):
            count = n_seeds if injection == "centre" else min(n_seeds, edge_seeds)
            for trapping in (True, False):
                methods = [s[1] for s in SERIES if s[2] == injection and s[3] == trapping]
                for seed in range(count):
                    scene = {
                        "seed": seed,
                        "lattice": {"n": n, "disorder": disorder},
                        "fluid": {"trapping": trapping},
                        "injection": {"at": injection},
                    }
                    data = porenet.run(scene).data
                    if injection == "centre":
                        masses.setdefault((trapping, n), []).append(int(data.drained.sum()))
                    for method in methods:
                        key = (method, injection, trapping, n)
                        results.setdefault(key, []).append(measure(data, method))
        print(f"n = {n}: {n_seeds} seeds, {time.perf_counter() - t0:.1f} s", flush=True)
    return {"fits": results, "masses": masses}


def summarise(study: dict, sizes) -> list[dict]:
    """One row per (series, n)."""
    rows = []
    for label, method, injection, trapping in SERIES:
        for n in sizes:
            runs = study["fits"].get((method, injection, trapping, n), [])
            ok = [r for r in runs if r is not None]
            if len(ok) < 2:
                continue
            d = np.array([r["d"] for r in ok])
            asym = IP_DIMENSION[trapping]
            rows.append(
                {
                    "label": label,
                    "method": method,
                    "injection": injection,
                    "trapping": trapping,
                    "n": n,
                    "runs": len(runs),
                    "measured": len(ok),
                    "mean": d.mean(),
                    "sd": d.std(ddof=1),
                    "sem": d.std(ddof=1) / math.sqrt(d.size),
                    "bias": d.mean() - asym,
                    "stderr": float(np.mean([r["stderr"] for r in ok])),
                    "r_max": float(np.mean([r["r_max"] for r in ok])),
                    "points": float(np.mean([r["points"] for r in ok])),
                    "clamped": float(np.mean([r["clamped"] for r in ok])),
                    "alt": {
                        c: float(np.nanmean([r["alt"][c] for r in ok])) - asym for c in FRACTIONS
                    },
                }
            )
    return rows


def bias_literal(rows: list[dict]) -> str:
    """The ``BIAS_TABLE`` literal of porenet/analysis/fractal.py (formatted as ruff would)."""
    lines = [
        "BIAS_TABLE: dict[tuple[str, str, bool], tuple[tuple[int, float, float, int], ...]] = {"
    ]
    keys = list(dict.fromkeys((r["method"], r["injection"], r["trapping"]) for r in rows))
    for method, injection, trapping in keys:
        lines.append(f'    ("{method}", "{injection}", {trapping}): (')
        for r in rows:
            if (r["method"], r["injection"], r["trapping"]) == (method, injection, trapping):
                row = f"({r['n']}, {r['bias']:.3f}, {r['sd']:.3f}, {r['measured']}),"
                lines.append(f"        {row}")
        lines.append("    ),")
    lines.append("}")
    return "\n".join(lines)


def markdown(rows: list[dict], study: dict, sizes, command: str, wall: float) -> str:
    """The generated tables of docs/fractal-bias.md."""
    out = [
        "# Fractal-dimension estimators on invasion percolation: generated tables",
        "",
        f"Generated by `{command}` ({wall / 60:.1f} min). Invasion percolation at breakthrough, "
        "square lattice n x n, λ = 0.5, seeds 0, 1, ...; D_f with the automatic range of "
        "`porenet.analysis.fractal` (docs/fractal.md). Bias = mean − asymptote (1.82 with "
        "trapping, 91/48 = 1.896 without); sem = sd / √runs is the uncertainty of the mean and "
        "of the bias. `r_max` is the upper end of the fitted range (radius or largest box, "
        "lattice spacings), `points` the fitted points, `clamped` the fraction of patterns "
        "whose range was widened to the minimum factor 4.",
        "",
        "| estimator | injection | trapping | n | runs | mean D_f | sd | sem | bias | "
        "fit stderr | r_max | r_max / n | points | clamped |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        runs = f"{r['measured']}" + ("" if r["measured"] == r["runs"] else f" of {r['runs']}")
        out.append(
            f"| {r['label']} | {r['injection']} | {'yes' if r['trapping'] else 'no'} | {r['n']} "
            f"| {runs} | {r['mean']:.3f} | {r['sd']:.3f} | {r['sem']:.3f} | {r['bias']:+.3f} | "
            f"{r['stderr']:.3f} | {r['r_max']:.1f} | {r['r_max'] / r['n']:.3f} | "
            f"{r['points']:.1f} | {r['clamped']:.2f} |"
        )
    out += [
        "",
        "## Bias against the upper end of the range",
        "",
        "Upper end `max(c l, 8)` spacings, lower end 2 (c = 1/4 is the automatic range; `l` the "
        "median distance of the pattern, docs/fractal.md), centre injection.",
        "",
        "| estimator | trapping | n | " + " | ".join(f"c = {c:g}" for c in FRACTIONS) + " |",
        "|---|---|---|" + "---|" * len(FRACTIONS),
    ]
    for r in rows:
        if r["injection"] != "centre":
            continue
        cells = " | ".join(f"{r['alt'][c]:+.3f}" for c in FRACTIONS)
        trap = "yes" if r["trapping"] else "no"
        out.append(f"| {r['label']} | {trap} | {r['n']} | {cells} |")
    out += [
        "",
        "## Breakthrough mass against lattice size",
        "",
        "Mean drained pores at breakthrough (centre injection, ± sem) and the exponent between "
        "consecutive sizes, log(M2 / M1) / log(n2 / n1), ± its sem from those of the means.",
        "",
        "| trapping | n | runs | mean mass | exponent from the previous size |",
        "|---|---|---|---|---|",
    ]
    for trapping in (True, False):
        previous = None
        for n in sizes:
            m = np.asarray(study["masses"].get((trapping, n), []), dtype=float)
            if m.size < 2:
                continue
            mean, rel = m.mean(), m.std(ddof=1) / math.sqrt(m.size) / m.mean()
            slope = ""
            if previous is not None:
                span = math.log(n / previous[0])
                value = math.log(mean / previous[1]) / span
                slope = f"{value:.3f} ± {math.hypot(rel, previous[2]) / span:.3f}"
            out.append(
                f"| {'yes' if trapping else 'no'} | {n} | {m.size} | {mean:.0f} ± "
                f"{rel * mean:.0f} | {slope} |"
            )
            previous = (n, mean, rel)
    return "\n".join(out) + "\n"


def mean_curve(runs: list[dict]) -> tuple[np.ndarray, np.ndarray]:
    """Ensemble mean of log counts on the common ladder (curves padded with their total)."""
    longest = max(runs, key=lambda r: r["scales"].size)
    scales = longest["scales"]
    logs = np.empty((len(runs), scales.size))
    for i, r in enumerate(runs):
        c = np.log(np.maximum(r["counts"], 1.0))
        logs[i, : c.size] = c
        logs[i, c.size :] = c[-1] if r["scales"][0] == scales[0] else 0.0
    return scales, logs.mean(axis=0)


def figures(rows: list[dict], study: dict, sizes, folder: Path) -> list[Path]:
    """D_f against n per estimator, and the ensemble-mean local slopes against scale / n."""
    from matplotlib.figure import Figure

    from porenet.viz.pattern import save_figure

    folder.mkdir(parents=True, exist_ok=True)
    fig = Figure(figsize=(9.0, 3.8), dpi=150, layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    for ax, method in zip(axes, ("mass-radius", "box-counting"), strict=True):
        for trapping, colour in ((True, COLOURS[0]), (False, COLOURS[1])):
            ax.axhline(IP_DIMENSION[trapping], color=colour, lw=0.8, ls=":")
            for injection, marker, ls in (("centre", "o", "-"), ("left-edge", "s", "--")):
                sel = [
                    r for r in rows
                    if r["method"] == method and r["trapping"] == trapping
                    and r["injection"] == injection
                ]  # fmt: skip
                if not sel:
                    continue
                n = np.array([r["n"] for r in sel], dtype=float)
                mean = np.array([r["mean"] for r in sel])
                sd = np.array([r["sd"] for r in sel])
                sem = np.array([r["sem"] for r in sel])
                label = f"{'trapping' if trapping else 'no trapping'}, {injection}"
                ax.fill_between(n, mean - sd, mean + sd, color=colour, alpha=0.12, lw=0)
                ax.errorbar(n, mean, yerr=sem, color=colour, marker=marker, ls=ls, ms=4,
                            capsize=2, label=label)  # fmt: skip
        ax.set_xscale("log")
        ax.set_xticks(sizes, [str(s) for s in sizes])
        ax.minorticks_off()
        ax.set_xlabel("lattice size n (pores per side)")
        ax.set_title(f"{method} (automatic range)", fontsize=10)
        ax.grid(True, alpha=0.25, lw=0.5)
    axes[0].set_ylabel("D_f: mean ± sem, band ± sd")
    axes[1].legend(fontsize=7, loc="lower right")
    axes[1].annotate("1.82 (IP, trapping)", (sizes[0], IP_DIMENSION[True]), fontsize=7,
                     xytext=(0, -9), textcoords="offset points")  # fmt: skip
    axes[1].annotate("91/48 (no trapping)", (sizes[0], IP_DIMENSION[False]), fontsize=7,
                     xytext=(0, 3), textcoords="offset points")  # fmt: skip
    bias_path = folder / "fractal-bias.png"
    save_figure(fig, bias_path)

    fig = Figure(figsize=(9.0, 3.8), dpi=150, layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    for ax, method in zip(axes, ("mass-radius", "box-counting"), strict=True):
        for i, n in enumerate(sizes):
            runs = [r for r in study["fits"].get((method, "centre", True, n), []) if r]
            if not runs:
                continue
            scales, logs = mean_curve(runs)
            # slope over one factor of 2: the radii ladder has RADII_PER_OCTAVE steps per octave
            k = RADII_PER_OCTAVE if method == "mass-radius" else 1
            mid = np.sqrt(scales[k:] * scales[:-k])
            slope = (logs[k:] - logs[:-k]) / np.log(scales[k:] / scales[:-k])
            slope = slope if method == "mass-radius" else -slope
            colour = COLOURS[i % len(COLOURS)]
            keep = (mid <= 0.7 * n) & (mid >= 1.0)
            ax.semilogx(mid[keep] / n, slope[keep], "-", color=colour, lw=1, label=f"n = {n}")
            top = np.mean([r["r_max"] for r in runs]) / n
            ax.axvline(top, color=colour, lw=0.6, ls="--")
        ax.axhline(IP_DIMENSION[True], color="k", lw=0.8, ls=":")
        ax.set_xlabel("R / n" if method == "mass-radius" else "s / n")
        ax.set_title(f"{method}: local slope, trapping (dashed: mean r_max)", fontsize=10)
        ax.grid(True, alpha=0.25, lw=0.5)
        ax.set_ylim(0.8, 2.3)
    axes[0].set_ylabel("local slope over a factor 2 of scale")
    axes[0].legend(fontsize=7, loc="lower left")
    slopes_path = folder / "fractal-slopes.png"
    save_figure(fig, slopes_path)
    return [bias_path, slopes_path]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", help=f"default {SIZES}")
    parser.add_argument(
        "--seeds", type=int, nargs="+", help=f"seeds per size, or one for all (default {SEEDS})"
    )
    parser.add_argument("--edge-seeds", type=int, default=40, help="left-edge seeds per size")
    parser.add_argument("--disorder", type=float, default=0.5)
    parser.add_argument("--quick", action="store_true", help="n = 32, 64, 4 seeds (a smoke test)")
    parser.add_argument("--docs", type=Path, help="write the tables and figures under this folder")
    args = parser.parse_args()
    given = {"--sizes": args.sizes, "--seeds": args.seeds}
    if args.quick:
        args.sizes, args.seeds = args.sizes or [32, 64], args.seeds or [4]
        args.edge_seeds = min(args.edge_seeds, max(args.seeds))
    args.sizes, args.seeds = args.sizes or SIZES, args.seeds or SEEDS
    seeds = args.seeds * len(args.sizes) if len(args.seeds) == 1 else args.seeds
    if len(seeds) != len(args.sizes):
        parser.error("give one --seeds value, or one per size")
    t0 = time.perf_counter()
    study = run_ensembles(args.sizes, seeds, args.edge_seeds, args.disorder)
    rows = summarise(study, args.sizes)
    wall = time.perf_counter() - t0
    print(f"study: {wall:.1f} s")
    for r in rows:
        print(
            f"{r['label']:<13} {r['injection']:<9} trap={r['trapping']!s:<5} n={r['n']:<5} "
            f"runs {r['measured']:>3}/{r['runs']:<3} D_f {r['mean']:.3f} sd {r['sd']:.3f} "
            f"sem {r['sem']:.3f} bias {r['bias']:+.3f} r_max/n {r['r_max'] / r['n']:.3f} "
            f"points {r['points']:.1f}"
        )
    print(bias_literal(rows))
    if args.docs:
        words = ["python", "examples/scripts/fractal_bias.py", "--docs", "docs"]
        if args.quick:
            words.append("--quick")
        for option, values in given.items():
            if values:
                words += [option, *map(str, values)]
        table = args.docs / "fractal-bias.md"
        table.parent.mkdir(parents=True, exist_ok=True)
        table.write_text(markdown(rows, study, args.sizes, " ".join(words), wall))
        print(f"table: {table}")
        for path in figures(rows, study, args.sizes, args.docs / "figures"):
            print(f"figure: {path}")


if __name__ == "__main__":
    main()
