"""What accuracy costs in time for the fluid-solid coupling: error against updating the solid
after every fluid step, versus wall time, for each coupling schedule and solver.

    python examples/scripts/accuracy_mechanics.py                  # n = 100, N_f = 1, Ca* = 10
    python examples/scripts/accuracy_mechanics.py --n 60 --quick
    python examples/scripts/accuracy_mechanics.py --n 100 --seeds 4 --no-sparse \\
        --out docs/figures/accuracy-mechanics-n100.png --table docs/accuracy-mechanics-n100.md
    python examples/scripts/accuracy_mechanics.py --solid hertz-mindlin --n 100 --seeds 2 \\
        --out docs/figures/accuracy-mindlin-n100.png --table docs/accuracy-mindlin-n100.md
    python examples/scripts/accuracy_mechanics.py --solid hertz-mindlin --friction 0.3 --n 50 \\
        --seeds 2 --out docs/figures/accuracy-mindlin-sliding-n50.png \\
        --table docs/accuracy-mindlin-sliding-n50.md

Scenes: n x n, centre injection, lambda = 0.1, the viscous model at Ca* = Ca (L/a) /
[lambda/(1-lambda^2)] = 10 as in the paper's Fig. 5, a Hertzian solid at fracturing number
N_f (``--solid hertz``, or ``hertz-mindlin`` with K_t / K_n = ``--shear-ratio``, rotations held
or ``--rotation free``, Coulomb sliding with ``--friction MU``, none without), seeds 1..K
(``--seeds``), to breakthrough. Near N_f = 1 a single pattern is chaotic (a one-pore
difference early on can decide which fracture wins), so errors are means over seeds. The
reference updates the solid after every fluid time step, passing on every pressure change
(``coupling = "every-step"``); each other run changes one knob:

* ``coupling = "adaptive"`` with ``coupling_tolerance`` (a deformation, units of a) swept:
  pressure changes smaller than ``tolerance K_0 / A_p`` may go unseen (docs/model.md);
* ``coupling = "interval"`` with ``coupling_interval`` (fluid steps) swept;
* ``solver = "sparse-direct"`` instead of the chains (same equations, general lattices; it
  solves everything at every update, so it ignores the adaptive tolerance's second half);
* hertz-mindlin only: ``solver_tolerance`` (the multigrid-preconditioned conjugate gradient's
  relative residual) swept, and ``solver = "sparse-direct"`` instead of the multigrid. Its
  reference also solves to ``solver_tolerance = 1e-9``. With ``--rotation free`` (which only
  the sparse direct solver takes) the solver rows are left out. With ``--friction``,
  ``slip_tolerance`` is swept too (the reference solves again after every change of sliding
  mode, ``slip_tolerance = 0``).

Errors against the reference:

* pattern: 1 - |A & B| / |A | B| of the drained sets at breakthrough;
* breakthrough time: relative error;
* deformation: relative L2 norm of the difference of the final aperture changes
  ``r_final - r_initial``.

Wall times are single runs after a warm-up (numba cache loaded), on this machine.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from porenet.analysis.numbers import capillary_number_at
from porenet.simulation import Simulation
from porenet.testing.runs import pattern_overlap

LAMBDA = 0.1

#: knob -> (values swept, extra settings that make the knob active)
KNOBS = {
    "coupling_tolerance": ([1e-1, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4], {"coupling": "adaptive"}),
    "coupling_interval": ([128, 32, 8, 2], {"coupling": "interval"}),
    "solver": (["chains", "sparse-direct"], {"coupling": "adaptive"}),
}

#: The knobs of the hertz-mindlin solid, and the fields of its reference run.
#: The coupling's and the solvers' rows at solver_tolerance 1e-3, the default when
#: docs/accuracy-mindlin-n100.md was measured (docs/accuracy.md, "Frictional solid").
_AT_1E3 = {"solver_tolerance": 1e-3}
MINDLIN_KNOBS = {
    knob: (KNOBS[knob][0], KNOBS[knob][1] | _AT_1E3)
    for knob in ("coupling_tolerance", "coupling_interval")
} | {
    "solver_tolerance": ([1e-1, 1e-2, 1e-3, 1e-4, 1e-6], {"coupling": "adaptive"}),
    "solver": (["multigrid", "sparse-direct"], {"coupling": "adaptive"} | _AT_1E3),
}
MINDLIN_REFERENCE = {"coupling": "every-step", "solver_tolerance": 1e-9}
#: With sliding: the slip tolerance too (0: every change of sliding mode solved again).
SLIP_KNOB = {"slip_tolerance": ([1e-1, 1e-2, 1e-3, 0.0], {"coupling": "adaptive"})}


def scene(n: int, ca_star: float, nf: float, seed: int = 1, **solid: object) -> dict:
    solid = {"kind": "hertz", **solid}
    return {
        "seed": seed,
        "lattice": {"n": n, "disorder": LAMBDA, "pore_size": 1e-7},
        "fluid": {"kind": "viscous", "capillary_number": capillary_number_at(ca_star, n, LAMBDA)},
        "solid": {"fracturing_number": nf, **solid},
    }


def describe(fields: dict) -> str:
    """``key = value`` pairs of some solid fields, for a table's caption."""
    return ", ".join(f"{k} = {v}" for k, v in fields.items())


def run(sc: dict) -> tuple[float, object]:
    sim = Simulation.from_scene(sc)
    t0 = time.perf_counter()
    result = sim.run()
    return time.perf_counter() - t0, result


def errors(ref, res) -> dict[str, float]:
    t_ref = ref.data.invasion_time[-1]
    dr_ref = ref.data.final_apertures - ref.data.apertures
    dr = res.data.final_apertures - res.data.apertures
    return {
        "pattern": 1.0 - pattern_overlap(ref.data.drained, res.data.drained),
        "breakthrough_time": abs(res.data.invasion_time[-1] - t_ref) / t_ref,
        "deformation": float(np.linalg.norm(dr - dr_ref) / max(np.linalg.norm(dr_ref), 1e-300)),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100)
    parser.add_argument("--nf", type=float, default=1.0, help="fracturing number N_f")
    parser.add_argument("--ca-star", type=float, default=10.0, help="modified Ca*")
    parser.add_argument("--quick", action="store_true", help="extremes and defaults only")
    parser.add_argument(
        "--seeds", type=int, default=1, help="seeds 1..K; errors and times are means over them"
    )
    parser.add_argument("--no-sparse", action="store_true", help="skip the sparse solver")
    parser.add_argument("--solid", choices=["hertz", "hertz-mindlin"], default="hertz")
    parser.add_argument("--shear-ratio", type=float, default=0.5, help="K_t / K_n (mindlin)")
    parser.add_argument(
        "--friction", type=float, help="Coulomb friction coefficient (mindlin; default: none)"
    )
    parser.add_argument(
        "--rotation", choices=["held", "free"], default="held", help="particle rotations (mindlin)"
    )
    parser.add_argument("--out", type=Path, help="figure (PNG)")
    parser.add_argument("--table", type=Path, help="markdown table")
    args = parser.parse_args()

    if args.shear_ratio <= 0:
        parser.error("--shear-ratio must be > 0")
    if args.solid != "hertz-mindlin" and (args.friction is not None or args.rotation != "held"):
        parser.error("--friction and --rotation need --solid hertz-mindlin")
    if args.friction is not None and args.friction < 0:
        parser.error("--friction must be >= 0")
    knobs, reference = KNOBS, {"coupling": "every-step"}
    solid = {"kind": args.solid}
    if args.solid == "hertz-mindlin":
        knobs, reference = MINDLIN_KNOBS, MINDLIN_REFERENCE
        solid["shear_stiffness_ratio"] = args.shear_ratio
        if args.friction is not None:
            solid["friction"] = args.friction
            knobs = knobs | SLIP_KNOB
            reference = reference | {"slip_tolerance": 0.0}
        if args.rotation == "free":
            # free rotations couple x and y: only the sparse direct solver takes them
            solid |= {"rotation": "free", "solver": "sparse-direct"}
            knobs = {k: v for k, v in knobs.items() if k not in ("solver", "solver_tolerance")}
    run(scene(10, args.ca_star, args.nf, **solid))  # warm-up: load the numba cache
    seeds = list(range(1, args.seeds + 1))
    refs, wall_ref, updates_ref, frozen_ref = [], 0.0, 0, 0
    for seed in seeds:
        wall, ref = run(scene(args.n, args.ca_star, args.nf, seed, **solid, **reference))
        refs.append(ref)
        wall_ref += wall / len(seeds)
        updates_ref += ref.summary["mechanical_updates"] // len(seeds)
        frozen_ref += ref.summary.get("frozen_contacts", 0) // len(seeds)
        summary = ref.summary
        print(
            f"reference (every-step, seed {seed}): {wall:.2f} s, "
            f"{summary['mechanical_updates']} updates, {summary['time_steps']} steps, "
            f"{summary['n_drained']} drained, {summary['springs_removed']} springs removed, "
            f"{summary.get('frozen_contacts', 0)} contacts frozen"
        )
    rows = []
    for knob, (values, extra) in knobs.items():
        if args.quick and knob != "solver":
            values = [values[0], values[-1]]
        for value in values:
            if value == "sparse-direct" and args.no_sparse:
                continue
            walls, updates, frozen, errs = [], [], [], []
            for seed, ref in zip(seeds, refs, strict=True):
                sc = scene(args.n, args.ca_star, args.nf, seed, **solid, **extra, **{knob: value})
                wall, res = run(sc)
                walls.append(wall)
                updates.append(res.summary["mechanical_updates"])
                frozen.append(res.summary.get("frozen_contacts", 0))
                errs.append(errors(ref, res))
            err = {key: float(np.mean([e[key] for e in errs])) for key in errs[0]}
            rows.append(
                {
                    "knob": knob,
                    "value": value,
                    "wall": float(np.mean(walls)),
                    "updates": int(np.mean(updates)),
                    "frozen": int(np.mean(frozen)),
                    **err,
                }
            )
            print(
                f"  {knob:>18} = {value!s:<13} {rows[-1]['wall']:7.2f} s  updates "
                f"{rows[-1]['updates']:>7d}  pattern {err['pattern']:.2e}  "
                f"t_bt {err['breakthrough_time']:.2e}  deformation {err['deformation']:.2e}  "
                f"frozen {rows[-1]['frozen']}",
                flush=True,
            )
    if args.table:
        # contacts the iteration froze (summed over updates, mean over seeds): mindlin only
        frozen_col = args.solid == "hertz-mindlin"
        lines = [
            f"Scene: n = {args.n}, lambda = {LAMBDA}, {describe(solid)}, Ca* = {args.ca_star:g} "
            f"(Ca = {capillary_number_at(args.ca_star, args.n, LAMBDA):.3g}), N_f = {args.nf:g}, "
            f"seeds "
            f"1-{args.seeds}, to breakthrough; errors and times are means over the seeds. "
            f"Reference: {describe(reference)}, {wall_ref:.2f} s, {updates_ref} updates"
            + (f", {frozen_ref} contacts frozen" if frozen_col else "")
            + ".",
            "",
            "| knob | value | wall (s) | updates | pattern error | breakthrough-time error "
            "| deformation error |" + (" frozen contacts |" if frozen_col else ""),
            "|---|---|---|---|---|---|---|" + ("---|" if frozen_col else ""),
        ]
        lines += [
            f"| {r['knob']} | {r['value']} | {r['wall']:.2f} | {r['updates']} | "
            f"{r['pattern']:.2e} | {r['breakthrough_time']:.2e} | {r['deformation']:.2e} |"
            + (f" {r['frozen']} |" if frozen_col else "")
            for r in rows
        ]
        args.table.write_text("\n".join(lines) + "\n")
        print(f"table: {args.table}")
    if args.out:
        from porenet.viz.accuracy import error_vs_wall
        from porenet.viz.pattern import save_figure

        groups = [(knob, [r for r in rows if r["knob"] == knob], "-") for knob in knobs]
        fig = error_vs_wall(
            groups,
            ("pattern", "breakthrough_time", "deformation"),
            f"{args.solid}: coupling, n = {args.n}, Ca* = {args.ca_star:g}, N_f = {args.nf:g}, "
            f"{args.seeds} "
            f"seed(s): mean error vs mean wall time (0 drawn at a third of the smallest error)",
            reference_wall=wall_ref,
            reference_label="reference (every step)",
        )
        save_figure(fig, args.out)
        print(f"figure: {args.out}")


if __name__ == "__main__":
    main()
