"""Fig. 5 of the paper: fracturing giving way to fingering as the fracturing number falls.

    python examples/scripts/fig5.py                                   # n = 400 (minutes)
    python examples/scripts/fig5.py --n 100 --out /tmp/fig5.png       # a quick look
    python examples/scripts/fig5.py --out docs/figures/fig5.png --table docs/fig5-table.md

Runs ``examples/scenes/fig5.toml`` (lambda = 0.1, Ca* = 10, viscous, Hertzian solid) at each
fracturing number, with the capillary number set so that Ca* = Ca (L/a) / [lambda/(1-lambda^2)]
stays 10 at any n, and the rigid medium for comparison. For each run it reports the drained
pores at breakthrough, the springs removed, the longest straight drained segment and the
mass-radius fractal dimension D_f (``porenet.analysis.fractal``, radii 2a to 0.35 L: one
pattern, so a rough estimate; the paper's FR value is about 1.43, VF 1.64, CF 1.82), and
draws the patterns and D_f against N_f.
"""

from __future__ import annotations

import argparse
import time
import tomllib
from pathlib import Path

from porenet.analysis.features import longest_straight_run
from porenet.analysis.fractal import mass_radius_dimension
from porenet.analysis.numbers import capillary_number_at
from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.result import RunData
from porenet.simulation import Simulation

SCENE = Path(__file__).resolve().parents[1] / "scenes" / "fig5.toml"
LAMBDA = 0.1


def make_scene(
    n: int,
    nf: float | None,
    cap: float | None = None,
    foundation: float | None = None,
    seed: int | None = None,
    solid: dict | None = None,
) -> dict:
    """The scene at n pores per side, Ca* = 10, at fracturing number ``nf`` (None: rigid),
    with the solid's ``aperture_cap`` and ``foundation`` and the scene's seed if given, and
    the other ``[solid]`` fields in ``solid`` (for example ``{"kind": "hertz-mindlin",
    "shear_stiffness_ratio": 0.3}``)."""
    with SCENE.open("rb") as f:
        scene = tomllib.load(f)
    scene["lattice"]["n"] = n
    if seed is not None:
        scene["seed"] = seed
    scene["fluid"]["capillary_number"] = capillary_number_at(10.0, n, LAMBDA)
    if nf is None:
        scene["solid"] = {"kind": "rigid"}
    else:
        scene["solid"]["fracturing_number"] = nf
        if cap is not None:
            scene["solid"]["aperture_cap"] = cap
        if foundation is not None:
            scene["solid"]["foundation"] = foundation
        scene["solid"].update(solid or {})
    return scene


def run(
    n: int,
    nf: float | None,
    output: Path | None,
    cap: float | None = None,
    foundation: float | None = None,
    seed: int | None = None,
    solid: dict | None = None,
) -> tuple[float, object]:
    """Run :func:`make_scene`'s scene (to ``output`` if given); its wall time and result."""
    sim = Simulation.from_scene(make_scene(n, nf, cap, foundation, seed, solid), output=output)
    t0 = time.perf_counter()
    result = sim.run()
    return time.perf_counter() - t0, result


def shape(data: RunData, n: int) -> tuple[float, int]:
    """A pattern's mass-radius D_f (radii 2a to 0.35 L about the inlet) and its longest
    straight drained run (pores)."""
    xy = data.pore_coords / data.pore_size
    d_f, _, _ = mass_radius_dimension(data.drained, xy, xy[data.order[0]], 4.0, 0.35 * 2 * n)
    return d_f, longest_straight_run(data.as_grid(data.drained))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=400)
    parser.add_argument("--nf", type=float, nargs="+", default=[10.0, 3.0, 1.0, 0.3, 0.1, 0.01])
    parser.add_argument("--aperture-cap", type=float, help="solid.aperture_cap (default 2)")
    parser.add_argument(
        "--foundation", type=float, help="solid.foundation, k_f / K_0 (default 0: the paper's)"
    )
    parser.add_argument("--seed", type=int, help="the scene's seed (default 1)")
    parser.add_argument("--no-rigid", action="store_true", help="skip the rigid run")
    parser.add_argument("--runs", type=Path, help="directory for the run files")
    parser.add_argument("--out", type=Path, help="figure (PNG)")
    parser.add_argument("--table", type=Path, help="markdown table")
    args = parser.parse_args()
    media = [*args.nf] + ([] if args.no_rigid else [None])
    for nf in media:  # every scene is checked before the first run starts
        try:
            load_scene(make_scene(args.n, nf, args.aperture_cap, args.foundation, args.seed))
        except ConfigError as exc:
            parser.error(str(exc))
    if args.runs:
        args.runs.mkdir(parents=True, exist_ok=True)
    rows = []
    for nf in media:
        label = "rigid" if nf is None else f"N_f = {nf:g}"
        out = None if args.runs is None else args.runs / f"fig5-{label.replace(' ', '')}.h5"
        wall, res = run(args.n, nf, out, args.aperture_cap, args.foundation, args.seed)
        data = res.data
        d_f, straight = shape(data, args.n)
        row = {
            "label": label,
            "nf": nf,
            "wall": wall,
            "drained": res.summary["n_drained"],
            "removed": res.summary.get("springs_removed", 0),
            "steps": res.summary["time_steps"],
            "updates": res.summary.get("mechanical_updates", 0),
            "straight": straight,
            "d_f": d_f,
            "data": data,
        }
        rows.append(row)
        print(
            f"{label:<12} {wall:7.1f} s  steps {row['steps']:>7}  updates {row['updates']:>6}  "
            f"drained {row['drained']:>6}  springs removed {row['removed']:>6}  longest "
            f"straight run {row['straight']:>4}  D_f {d_f:.3f}",
            flush=True,
        )
    if args.table:
        seed = 1 if args.seed is None else args.seed
        lines = [
            f"n = {args.n}, lambda = {LAMBDA}, Ca* = 10 (Ca = "
            f"{capillary_number_at(10.0, args.n, LAMBDA):.4g}), seed {seed}, "
            f"foundation {args.foundation or 0.0:g}, to breakthrough "
            "(`python examples/scripts/fig5.py`).",
            "",
            "| medium | wall (s) | fluid steps | mechanical updates | drained pores | springs "
            "removed | longest straight run (pores) | D_f (mass-radius) |",
            "|---|---|---|---|---|---|---|---|",
        ]
        lines += [
            f"| {r['label']} | {r['wall']:.1f} | {r['steps']} | {r['updates']} | "
            f"{r['drained']} | {r['removed']} | {r['straight']} | {r['d_f']:.3f} |"
            for r in rows
        ]
        args.table.write_text("\n".join(lines) + "\n")
        print(f"table: {args.table}")
    if args.out:
        from matplotlib.figure import Figure

        from porenet.viz.pattern import plot_pattern, save_figure

        k = len(rows)
        cols = 4
        n_rows = -(-(k + 1) // cols)
        fig = Figure(figsize=(3.6 * cols, 3.2 * n_rows), dpi=130, layout="constrained")
        axes = fig.subplots(n_rows, cols).ravel()
        for ax, r in zip(axes, rows, strict=False):
            plot_pattern(r["data"], ax=ax, title=f"{r['label']}, D_f = {r['d_f']:.2f}")
        for ax in axes[k + 1 :]:
            ax.set_axis_off()
        ax = axes[k]
        pts = [(r["nf"], r["d_f"]) for r in rows if r["nf"] is not None]
        ax.semilogx([p[0] for p in pts], [p[1] for p in pts], "o-", label="deformable")
        rigid = [r["d_f"] for r in rows if r["nf"] is None]
        if rigid:
            ax.axhline(rigid[0], color="0.5", ls="--", label="rigid")
        for value, name in ((1.43, "FR (paper)"), (1.64, "VF (paper)")):
            ax.axhline(value, color="k", lw=0.6, ls=":")
            ax.annotate(name, (pts[0][0], value), fontsize=7, xytext=(2, 2),
                        textcoords="offset points")  # fmt: skip
        ax.set_xlabel("fracturing number N_f")
        ax.set_ylabel("D_f (mass-radius)")
        ax.legend(fontsize=8)
        fig.suptitle(f"Fig. 5: n = {args.n}, λ = {LAMBDA}, Ca* = 10", fontsize=10)
        save_figure(fig, args.out)
        print(f"figure: {args.out}")


if __name__ == "__main__":
    main()
