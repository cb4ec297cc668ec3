"""What accuracy costs in time for the viscous model: error against a converged reference
versus wall time, for every accuracy knob of each integrator.

    python examples/scripts/accuracy_viscous.py                       # n = 100, Ca = 1e-2
    python examples/scripts/accuracy_viscous.py --n 60 --ca 1e-2 --quick
    python examples/scripts/accuracy_viscous.py --out docs/figures/accuracy-explicit.png \\
        --table accuracy-table.md
    python examples/scripts/accuracy_viscous.py --n 50 --ca 1e-5 --quick \\
        --integrators explicit implicit --reference implicit       # both integrators
    python examples/scripts/accuracy_viscous.py --n 100 --ca 1e-4 --quick \
        --integrators explicit rkc implicit                           # all three
    python examples/scripts/accuracy_viscous.py --from-table docs/accuracy-rkc-n400.md \
        --out docs/figures/accuracy-rkc-n400.png                     # redraw, no runs

For one scene (n x n, centre injection, lambda = 0.3 or --disorder, seed 1, to breakthrough)
it runs a
reference with the tightest settings and then sweeps one knob at a time, the others at their
defaults (what a user changes when tuning a run). Errors against the reference:

* pattern: 1 - |A & B| / |A | B| of the drained sets at breakthrough (Jaccard distance);
* breakthrough time: relative error;
* pressure: relative L2 norm of the difference of the pressure fields at a fixed time (half
  the breakthrough time of a run at default settings), taken from a snapshot; with
  ``--snapshots K`` the median of it at K times from 0.2 to 0.8 of that time.

Wall times are single runs after a warm-up (numba cache loaded), on this machine.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from porenet.kinds.viscous.model import ViscousConfig
from porenet.simulation import Simulation
from porenet.testing.runs import pattern_overlap

#: Per integrator: its accuracy knobs, the values swept, and the value in its reference run.
KNOBS = {
    "explicit": {
        "safety_factor": ([1.0, 0.9, 0.5, 0.25], 0.05),
        "pressure_step": ([None, 1.0, 0.3, 0.1, 0.03], 0.01),
        "pressure_floor": ([1e-2, 1e-4, 1e-6, 1e-9], 0.0),
    },
    "implicit": {
        "tolerance": ([1e-1, 3e-2, 1e-2, 3e-3, 1e-3], 1e-4),
        "event_tolerance": ([1e-4, 1e-6, 1e-10], 1e-12),
    },
    "rkc": {
        "tolerance": ([3e-1, 1e-1, 3e-2, 1e-2, 3e-3, 1e-3], 1e-4),
        # local time steps: on ("auto") or off; the reference takes none
        "local_steps": (["off", "auto"], "off"),
        "window_tolerance": ([0.25, 0.5, 1.0, 2.0, 4.0], None),
    },
}
#: The scenes' lambda (--disorder).
DISORDER = [0.3]
#: Line style of each integrator's curves.
STYLE = {"explicit": "-", "implicit": "--", "rkc": ":"}


def work(summary: dict) -> int:
    """Sweeps of the pore field (explicit: its steps; rkc: stages and explicit steps, with
    local time steps the pore updates in whole-lattice sweeps) or linear solves (implicit):
    the unit of work of each integrator."""
    if summary["integrator"] == "rkc" and summary.get("macro_steps"):
        # local time steps: pore updates of the windows and the coarse steps, in sweeps of
        # the whole lattice
        updates = summary["window_pore_stages"] + summary["coarse_pore_stages"]
        return int(updates / summary["n_pores"] + summary["single_rate_sweeps"])
    if summary["integrator"] == "rkc":
        return int(summary["stage_sweeps"] + summary["explicit_steps"])
    if summary["integrator"] == "implicit":
        return int(summary["linear_solves"])
    return int(summary["time_steps"])


def scene(n: int, ca: float, integrator: str, **fluid: float) -> dict:
    return {
        "seed": 1,
        "lattice": {"n": n, "disorder": DISORDER[0], "pore_size": 1e-7},
        "fluid": {"kind": "viscous", "capillary_number": ca, "integrator": integrator, **fluid},
    }


def run(sc: dict) -> tuple[float, object]:
    sim = Simulation.from_scene(sc)
    t0 = time.perf_counter()
    result = sim.run()
    return time.perf_counter() - t0, result


def errors(ref, res, t_snaps: list[float]) -> dict[str, float]:
    jaccard = 1.0 - pattern_overlap(ref.data.drained, res.data.drained)
    t_ref = ref.data.invasion_time[-1]
    t_bt = res.data.invasion_time[-1]
    out = {"pattern": float(jaccard), "breakthrough_time": abs(t_bt - t_ref) / t_ref}
    diffs = []
    for t_snap in t_snaps:
        pr = [s for s in ref.data.snapshots if abs(s.time - t_snap) <= 1e-9 * t_snap]
        pc = [s for s in res.data.snapshots if abs(s.time - t_snap) <= 1e-9 * t_snap]
        if pr and pc:
            d = np.linalg.norm(pc[0].pressure - pr[0].pressure) / np.linalg.norm(pr[0].pressure)
            diffs.append(float(d))
    # the median over the snapshot times: a single time may fall on an event (a landing a
    # moment earlier in one run than in the other), whose pressure jump dominates the norm
    out["pressure"] = float(np.median(diffs)) if diffs else float("nan")
    return out


def plot(rows: list[dict], integrators: list[str], title: str, out: Path) -> None:
    """The work-precision figure of ``rows`` (one curve per integrator and knob)."""
    from porenet.viz.accuracy import error_vs_wall
    from porenet.viz.pattern import save_figure

    groups = [
        (
            f"{integrator}: {knob}",
            [r for r in rows if r["knob"] == knob and r["integrator"] == integrator],
            STYLE[integrator],
        )
        for integrator in integrators
        for knob in KNOBS[integrator]
    ]
    groups = [g for g in groups if g[1]]  # (a defaults-only integrator has one point)
    fig = error_vs_wall(groups, ("pattern", "breakthrough_time", "pressure"), title)
    save_figure(fig, out)
    print(f"figure: {out}")


def replot(table: Path, out: Path) -> None:
    """Redraw the figure of a table this script wrote (``--table``), without running."""
    try:
        lines = table.read_text().splitlines()
        header = lines[0]  # "Scene: n = N, Ca = CA, lambda = L, ... Reference: I integrator, ..."
        scene_part, reference_part = header.split(" Reference: ")
        fields = dict(f.split(" = ") for f in scene_part.removeprefix("Scene: ").split(", ")[:3])
        reference = reference_part.split(" ")[0]
        wall_ref = float(reference_part.rsplit(", ", 1)[1].removesuffix(" s."))
        missing = {"n", "Ca", "lambda"} - fields.keys()
        if missing:
            raise KeyError(f"header lacks {sorted(missing)}")
    except (OSError, IndexError, KeyError, ValueError) as exc:
        raise SystemExit(f"{table}: not a table written by --table ({exc!r})") from None
    rows = []
    for line in lines[4:]:
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) != 9:
            continue
        integrator, knob, value, wall, _steps, _work, pattern, t_bt, pressure = cells
        rows.append({"integrator": integrator, "knob": knob, "value": value,
                     "wall": float(wall), "pattern": float(pattern),
                     "breakthrough_time": float(t_bt), "pressure": float(pressure)})  # fmt: skip
    if not rows:
        raise SystemExit(f"{table}: no rows of a table written by --table")
    integrators = list(dict.fromkeys(r["integrator"] for r in rows))
    title = (
        f"{', '.join(integrators)}, n = {fields['n']}, Ca = {fields['Ca']}, lambda = "
        f"{fields['lambda']}: error vs wall time (reference: {reference}, {wall_ref:.1f} s)"
    )
    plot(rows, integrators, title, out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100)
    parser.add_argument("--ca", type=float, default=1e-2)
    parser.add_argument("--disorder", type=float, default=0.3, help="lambda")
    parser.add_argument(
        "--quick", action="store_true", help="per knob only the extremes and the default"
    )
    parser.add_argument(
        "--integrators", nargs="+", default=["explicit"], choices=sorted(KNOBS), help="swept"
    )
    parser.add_argument(
        "--defaults-only",
        nargs="*",
        default=[],
        choices=sorted(KNOBS),
        help="integrators run at their default settings only (for comparison)",
    )
    parser.add_argument(
        "--reference", default="explicit", choices=sorted(KNOBS), help="integrator of the reference"
    )
    parser.add_argument(
        "--snapshots",
        type=int,
        default=1,
        help="pressure fields compared at this many times, the median error kept (1: at half "
        "the breakthrough time of a default run; more: evenly from 0.2 to 0.8 of it)",
    )
    parser.add_argument("--out", type=Path, help="figure (PNG)")
    parser.add_argument("--table", type=Path, help="markdown table")
    parser.add_argument(
        "--from-table",
        type=Path,
        help="redraw the figure (--out) of a table written by --table, without running",
    )
    args = parser.parse_args()
    if args.snapshots < 1:
        parser.error(f"--snapshots {args.snapshots}: must be at least 1")
    if args.from_table:
        if not args.out:
            parser.error("--from-table needs --out")
        replot(args.from_table, args.out)
        return
    DISORDER[0] = args.disorder

    for integrator in args.integrators:  # warm-up: load the numba cache
        run(scene(10, args.ca, integrator))
    reference_settings = {
        k: ref for k, (_, ref) in KNOBS[args.reference].items() if ref is not None
    }
    # the pressure fields are compared at half the breakthrough time of a default run
    _, probe = run(scene(args.n, args.ca, args.reference))
    t_bt = probe.data.invasion_time[-1]
    if args.snapshots == 1:
        t_snap = [0.5 * t_bt]
    else:
        t_snap = [t_bt * (0.2 + 0.6 * k / (args.snapshots - 1)) for k in range(args.snapshots)]
    sc_ref = scene(args.n, args.ca, args.reference, **reference_settings, snapshot_times=t_snap)
    wall_ref, ref = run(sc_ref)
    print(
        f"reference ({args.reference}, {reference_settings}): {wall_ref:.2f} s, breakthrough "
        f"at {ref.data.invasion_time[-1]:.4g} s, {ref.summary['time_steps']} steps"
    )
    rows = []
    for integrator in args.integrators:
        for knob, (values, _) in KNOBS[integrator].items():
            default = ViscousConfig.model_fields[knob].default
            if args.quick:
                values = [v for v in values if v in (values[0], default, values[-1])]
            if integrator in args.defaults_only:
                values = [default] if knob == next(iter(KNOBS[integrator])) else []
            for value in values:
                settings = {knob: value}  # the other knobs at their defaults
                sc = scene(args.n, args.ca, integrator, **settings, snapshot_times=t_snap)
                wall, res = run(sc)
                err = errors(ref, res, t_snap)
                rows.append(
                    {
                        "integrator": integrator,
                        "knob": knob,
                        "value": value,
                        "wall": wall,
                        "steps": res.summary["time_steps"],
                        "work": work(res.summary),
                        **err,
                    }
                )
                print(
                    f"  {integrator:>8} {knob:>15} = {value!s:<8} {wall:7.2f} s  steps "
                    f"{rows[-1]['steps']:>8d}  pattern {err['pattern']:.2e}  "
                    f"t_bt {err['breakthrough_time']:.2e}  p {err['pressure']:.2e}",
                    flush=True,
                )
    if args.table:
        lines = [
            f"Scene: n = {args.n}, Ca = {args.ca:g}, lambda = {args.disorder:g}, seed 1, to "
            f"breakthrough, pressure at {len(t_snap)} time(s). "
            f"Reference: {args.reference} integrator, {reference_settings}, {wall_ref:.2f} s.",
            "",
            "| integrator | knob | value | wall (s) | steps | sweeps or solves | pattern error "
            "| breakthrough-time error | pressure error |",
            "|---|---|---|---|---|---|---|---|---|",
        ]
        lines += [
            f"| {r['integrator']} | {r['knob']} | {r['value']} | {r['wall']:.2f} | {r['steps']} "
            f"| {r['work']} | {r['pattern']:.2e} | {r['breakthrough_time']:.2e} "
            f"| {r['pressure']:.2e} |"
            for r in rows
        ]
        args.table.write_text("\n".join(lines) + "\n")
        print(f"table: {args.table}")
    if args.out:
        title = (
            f"{', '.join(args.integrators)}, n = {args.n}, Ca = {args.ca:g}, lambda = "
            f"{args.disorder:g}: error vs wall time (reference: {args.reference}, "
            f"{wall_ref:.1f} s)"
        )
        plot(rows, args.integrators, title, args.out)


if __name__ == "__main__":
    main()
