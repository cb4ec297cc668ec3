"""How much force do the frictional solid's frozen contacts leave out of balance, and does it
change the result? Fig. 5's scene with sliding, at each slip tolerance.

    python examples/scripts/carried_imbalance.py --n 100 --ratio 0.8 --nf 30   # ~8 min
    python examples/scripts/carried_imbalance.py --n 50 --ratio 0.5 --nf 1 --slip 1e-2 0

With sliding, a contact that changes mode :data:`MAX_FLIPS` times in one update keeps its
mode for the rest of it, and one whose change decides a slip of at most ``slip_tolerance``
takes it without another solve (docs/model.md, "Frictional solid (kind hertz-mindlin)",
"Solver"); both leave a force out of balance that is carried to the next update. For each
slip tolerance (``--slip``, in a; 0 solves again after every change of mode) and solver
tolerance (``--solver-tolerance``, a: the multigrid's own error leaves up to ~K times it out
of balance, K a contact's stiffness, carried the same way) this runs Fig. 5's
scene (``examples/scenes/fig5.toml``, lambda = 0.1, Ca* = 10, solid kind hertz-mindlin,
rotations held, Coulomb friction ``--friction``) to breakthrough and reports the contacts
frozen (summed over the updates), the updates left unsettled, the largest force left out of
balance on a particle over the contacts' prestress force F_0 (largest over the run, and the
median and 99th percentile of each update's largest), the drained pores, D_f and, against
the first run's, 1 - |A & B| / |A | B| of the drained sets.
"""

from __future__ import annotations

import argparse
import itertools
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from fig5 import run, shape

from porenet.jit.threads import configure_threads
from porenet.testing.runs import pattern_overlap


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100)
    parser.add_argument("--ratio", type=float, default=0.8, help="K_t / K_n")
    parser.add_argument("--friction", type=float, default=0.3, help="Coulomb coefficient")
    parser.add_argument("--nf", type=float, default=30.0, help="fracturing number N_f")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--slip", type=float, nargs="+", default=[1e-2, 0.0],
                        help="slip tolerances (a); the first is the comparison's")  # fmt: skip
    parser.add_argument("--solver-tolerance", type=float, nargs="+", default=[1e-2],
                        help="solver_tolerance values (a), each with every --slip")  # fmt: skip
    parser.add_argument("--threads", type=int, default=1, help="threads per run (default 1)")
    parser.add_argument("--table", type=Path, help="markdown table")
    args = parser.parse_args()
    if args.n < 8 or args.ratio <= 0 or args.friction < 0 or args.nf <= 0:
        parser.error("--n must be >= 8, --ratio and --nf > 0, --friction >= 0")
    if any(not s >= 0 for s in args.slip) or any(not t > 0 for t in args.solver_tolerance):
        parser.error("--slip values must be >= 0 and --solver-tolerance values > 0")
    configure_threads(args.threads)
    rows, first = [], None
    for tol, slip in itertools.product(args.solver_tolerance, args.slip):
        solid = {"kind": "hertz-mindlin", "shear_stiffness_ratio": args.ratio,
                 "friction": args.friction, "slip_tolerance": slip,
                 "solver_tolerance": tol}  # fmt: skip
        cpu = time.process_time()
        _, res = run(args.n, args.nf, None, seed=args.seed, solid=solid)
        cpu = time.process_time() - cpu
        s = res.summary
        f0 = s["prestress_force"]
        per_update = np.asarray(res.data.mechanics_series["balance_residual"]) / f0
        first = res if first is None else first
        row = {
            "solver": tol, "slip": slip, "cpu": cpu, "updates": s["mechanical_updates"],
            "frozen": s["frozen_contacts"], "unsettled": s["unsettled_updates"],
            "largest": s["largest_balance_residual"] / f0,
            "median": float(np.median(per_update)), "p99": float(np.percentile(per_update, 99)),
            "drained": s["n_drained"], "d_f": shape(res.data, args.n)[0],
            "pattern": 1.0 - pattern_overlap(first.data.drained, res.data.drained),
        }  # fmt: skip
        rows.append(row)
        print(" ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                       for k, v in row.items()), flush=True)  # fmt: skip
    if args.table:
        write_table(rows, args)


def write_table(rows: list[dict], args: argparse.Namespace) -> None:
    columns = ("solver_tolerance (a)", "slip_tolerance (a)", "CPU (s)", "updates", "frozen",
               "unsettled updates", "largest residual / F_0", "median", "99th percentile",
               "drained", "D_f", "pattern vs first")  # fmt: skip
    lines = [
        f"n = {args.n}, K_t/K_n = {args.ratio:g}, mu = {args.friction:g}, N_f = {args.nf:g}, "
        f"seed {args.seed}, rotations held, to breakthrough; residuals over the contacts' "
        "prestress force F_0 (`python examples/scripts/carried_imbalance.py`).",
        "",
        "| " + " | ".join(columns) + " |",
        "|" + "---|" * len(columns),
    ]
    for r in rows:
        cells = (f"{r['solver']:g}", f"{r['slip']:g}", f"{r['cpu']:.1f}", str(r["updates"]),
                 str(r["frozen"]), str(r["unsettled"]), f"{r['largest']:.3g}",
                 f"{r['median']:.2g}", f"{r['p99']:.2g}", str(r["drained"]), f"{r['d_f']:.3f}",
                 f"{r['pattern']:.2g}")  # fmt: skip
        lines.append("| " + " | ".join(cells) + " |")
    args.table.write_text("\n".join(lines) + "\n")
    print(f"table: {args.table}")


if __name__ == "__main__":
    main()
