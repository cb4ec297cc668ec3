"""Benchmark: the cost model of porenet.core.cost against measured runs (not a test).

    python tests/benchmarks/bench_cost.py                 # reduced scenes, ~1 minute
    python tests/benchmarks/bench_cost.py --only fig1b-100 ip-400
    python tests/benchmarks/bench_cost.py --full          # also Fig. 1b and Fig. 5 at n = 400
                                                          # (~1 and ~4 minutes)
    python tests/benchmarks/bench_cost.py --memory        # peak memory, one child per model
    python tests/benchmarks/bench_cost.py --hard          # the hard-case matrix, ~1 minute
    python tests/benchmarks/bench_cost.py --fractions     # IP drained fractions behind the
                                                          # drained-pore model (~2 minutes)

For each scene: the estimate of :func:`porenet.core.cost.estimate_cost` (from the validated
scene alone) and the measured run (``Simulation.run``, numba cache warmed first on tiny
scenes): drained pores, fluid steps, mechanical updates, wall time (build and run, as in the
run's ``wall_time_s``), and the ratio predicted / measured of steps and wall time. One run
per scene: wall times on a shared machine move by ~10-20 %.

``--memory`` runs each model in a child process on an ``--memory-n`` lattice (default 500;
the implicit integrator on n = 150) for 30 drained pores and compares the estimate with the
growth of the peak resident set (``ru_maxrss``) over a warmed-up baseline.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "examples" / "scenes"
FIG1B = str(SCENES / "fig1b.toml")
FIG5 = str(SCENES / "fig5.toml")
IP400 = str(SCENES / "ip-400.toml")


def _ip_hertz(n: int, nf: float) -> dict[str, Any]:
    return {
        "lattice": {"n": n, "disorder": 0.1},
        "fluid": {"kind": "invasion-percolation"},
        "solid": {"kind": "hertz", "fracturing_number": nf},
    }


#: name -> (scene, overrides)
CASES: dict[str, tuple[Any, list[str]]] = {
    "quickstart": (str(ROOT / "porenet" / "examples" / "quickstart.toml"), []),
    "ip-400": (str(SCENES / "ip-400.toml"), []),
    "ip-400 complete": (str(SCENES / "ip-400.toml"), ["stop.at=complete"]),
    "ip-800 no trapping": (str(SCENES / "ip-400.toml"), ["lattice.n=800", "fluid.trapping=false"]),
    "fig1b n=100": (FIG1B, ["lattice.n=100"]),
    "fig1b n=200": (FIG1B, ["lattice.n=200"]),
    "fig1b n=100 left-edge": (FIG1B, ["lattice.n=100", "injection.at=left-edge"]),
    "fig1b n=100 Ca=1e-2": (FIG1B, ["lattice.n=100", "fluid.capillary_number=1e-2"]),
    "fig5 n=100 (N_f=10)": (FIG5, ["lattice.n=100"]),
    "fig5 n=100 N_f=1": (FIG5, ["lattice.n=100", "solid.fracturing_number=1"]),
    "fig5 n=100 N_f=0.1": (FIG5, ["lattice.n=100", "solid.fracturing_number=0.1"]),
    "fig5 n=100 N_f=0.01": (FIG5, ["lattice.n=100", "solid.fracturing_number=0.01"]),
    "fig5 n=200 N_f=0.3": (FIG5, ["lattice.n=200", "solid.fracturing_number=0.3"]),
    "IP + hertz n=100 N_f=1": (_ip_hertz(100, 1.0), []),
    "IP + hertz n=100 N_f=10": (_ip_hertz(100, 10.0), []),
    "auto n=40 Ca=1e-5": (
        {
            "seed": 1,
            "lattice": {"n": 40, "disorder": 0.3},
            "fluid": {"kind": "viscous", "capillary_number": 1e-5},
        },
        [],
    ),
}
#: The hard-case matrix of docs/stability.md, as scenes a user would write (default integrator
#: ``auto``): extreme disorder, Ca from 1e-7 to 1e6, N_f from 1e-6 to 1e6, 3 x 3 lattices and
#: IP on a 3000 x 3000 lattice (``--hard``, ~1 minute; docs/cost.md, "Hard cases").
HARD: dict[str, tuple[Any, list[str]]] = {
    "λ=0.01 n=30 Ca=1e-2": (
        FIG1B,
        ["lattice.n=30", "lattice.disorder=0.01", "fluid.capillary_number=1e-2"],
    ),
    "λ=0.95 n=30 Ca=1e-2": (
        FIG1B,
        ["lattice.n=30", "lattice.disorder=0.95", "fluid.capillary_number=1e-2"],
    ),
    "λ=0.95 n=30 IP": (IP400, ["lattice.n=30", "lattice.disorder=0.95"]),
    **{
        f"n=30 Ca={ca}": (FIG1B, ["lattice.n=30", f"fluid.capillary_number={ca}"])
        for ca in ("1e-1", "1", "1e2", "1e4", "1e6")
    },
    "n=100 Ca=1": (FIG1B, ["lattice.n=100", "fluid.capillary_number=1"]),
    "n=10 Ca=1e-6": (FIG1B, ["lattice.n=10", "fluid.capillary_number=1e-6"]),
    "n=10 Ca=1e-6 explicit": (
        FIG1B,
        ["lattice.n=10", "fluid.capillary_number=1e-6", "fluid.integrator=explicit"],
    ),
    "n=3 Ca=1e-7": (FIG1B, ["lattice.n=3", "fluid.capillary_number=1e-7"]),
    "n=3 breakthrough": (FIG1B, ["lattice.n=3"]),
    "n=3 complete": (FIG1B, ["lattice.n=3", "stop.at=complete"]),
    "n=3 IP complete": (IP400, ["lattice.n=3", "stop.at=complete"]),
    "n=30 N_f=1e-6": (FIG5, ["lattice.n=30", "solid.fracturing_number=1e-6"]),
    "n=30 N_f=1e6": (FIG5, ["lattice.n=30", "solid.fracturing_number=1e6"]),
    "IP + hertz n=30 N_f=1e-6": (_ip_hertz(30, 1e-6), []),
    "IP + hertz n=30 N_f=1e6": (_ip_hertz(30, 1e6), []),
    "IP n=3000": (IP400, ["lattice.n=3000"]),
}
FULL: dict[str, tuple[Any, list[str]]] = {
    "fig1b (n=400)": (FIG1B, []),
    "fig5 (n=400, N_f=10)": (FIG5, []),
}

#: Memory cases: name -> scene sections (30 drained pores on an --memory-n lattice).
MEMORY: dict[str, dict[str, Any]] = {
    "invasion-percolation": {"fluid": {"kind": "invasion-percolation"}},
    "viscous explicit": {"fluid": {"kind": "viscous", "capillary_number": 0.05}},
    "viscous implicit": {
        "fluid": {"kind": "viscous", "capillary_number": 1e-5, "integrator": "implicit"}
    },
    "viscous + hertz": {
        "fluid": {"kind": "viscous", "capillary_number": 0.05},
        "solid": {"kind": "hertz", "fracturing_number": 0.1},
    },
    "IP + hertz": {
        "fluid": {"kind": "invasion-percolation"},
        "solid": {"kind": "hertz", "fracturing_number": 0.1},
    },
}


#: Cases run on a smaller lattice (the implicit integrator factorises the pore matrix ~20
#: times per drained pore).
MEMORY_N = {"viscous implicit": 150}


def warm_up() -> None:
    """Load (or compile) every kernel the cases use, on tiny scenes."""
    import porenet

    for extra in MEMORY.values():
        porenet.run({"lattice": {"n": 12, "disorder": 0.1}, **extra})


def _fmt(value: float | None) -> str:
    return "-" if value is None else f"{value:,.0f}"


def _ratio(pred: float | None, meas: float | None) -> str:
    if pred is None or not meas:
        return "-"
    return f"{pred / meas:.2f}"


def run_cases(cases: dict[str, tuple[Any, list[str]]]) -> None:
    from porenet.config.loading import load_scene
    from porenet.core.cost import estimate_cost
    from porenet.simulation import Simulation

    warm_up()
    print(
        "| scene | drained pred / meas | steps pred / meas | updates pred / meas "
        "| wall pred / meas (s) | steps ratio | wall ratio |"
    )
    print("|---|---|---|---|---|---|---|")
    for name, (source, overrides) in cases.items():
        scene = load_scene(source, overrides)
        est = estimate_cost(scene)
        summary = Simulation.from_scene(scene).run().summary
        drained = summary["n_drained"]
        steps = summary.get("time_steps", drained)
        updates = summary.get("mechanical_updates", 0)
        wall = summary["wall_time_s"]
        pred_wall = "-" if est.wall_seconds is None else f"{est.wall_seconds:.3g}"
        print(
            f"| {name} | {_fmt(est.drained)} / {drained:,} | {_fmt(est.steps)} / {steps:,} "
            f"| {_fmt(est.mechanical_updates)} / {updates:,} | {pred_wall} / {wall:.3g} "
            f"| {_ratio(est.steps, steps)} | {_ratio(est.wall_seconds, wall)} |",
            flush=True,
        )


def memory_child(name: str, n: int) -> None:
    """Print the peak-memory growth of one run (child process)."""
    import porenet
    from porenet.config.loading import load_scene
    from porenet.core.cost import estimate_cost

    warm_up()
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    scene = {"lattice": {"n": n, "disorder": 0.1}, "stop": {"max_drained": 30}, **MEMORY[name]}
    porenet.run(scene)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    est = estimate_cost(load_scene(scene)).memory_bytes
    print(json.dumps({"measured": (peak - base) * 1024, "predicted": est}))


def run_memory(n: int) -> None:
    print("| model (30 drained pores) | n | predicted (MB) | measured (MB) | ratio |")
    print("|---|---|---|---|---|")
    for name in MEMORY:
        size = MEMORY_N.get(name, n)
        out = subprocess.run(
            [sys.executable, __file__, "--memory-child", name, str(size)],
            capture_output=True,
            text=True,
            check=True,
        )
        row = json.loads(out.stdout.strip().splitlines()[-1])
        pred, meas = row["predicted"], row["measured"]
        print(
            f"| {name} | {size} | {pred / 1e6:.0f} | {meas / 1e6:.0f} | {pred / meas:.2f} |",
            flush=True,
        )


def run_fractions(sizes: list[int], seeds: int) -> None:
    """Drained fraction of invasion percolation (λ = 0.3) against n: mean ± sd over seeds at
    breakthrough (with and without trapping) and at completion, centre and left-edge
    injection."""
    import numpy as np

    import porenet

    head = ("breakthrough (mean ± sd)", "no trapping", "complete", "left-edge breakthrough",
            "left-edge complete")  # fmt: skip
    print("| n | " + " | ".join(head) + " |")
    print("|---" * (len(head) + 1) + "|")
    for n in sizes:
        cells = []
        for at, stop, trap in (("centre", "breakthrough", True), ("centre", "breakthrough", False),
                               ("centre", "complete", True), ("left-edge", "breakthrough", True),
                               ("left-edge", "complete", True)):  # fmt: skip
            count = seeds if stop == "breakthrough" else max(2, seeds // 8)
            values = [
                porenet.run(
                    {
                        "seed": s,
                        "lattice": {"n": n, "disorder": 0.3},
                        "fluid": {"trapping": trap},
                        "injection": {"at": at},
                        "stop": {"at": stop},
                        "classifier": {"kind": "none"},
                    }
                ).summary["drained_fraction"]
                for s in range(count)
            ]
            cells.append(f"{np.mean(values):.3f} ± {np.std(values, ddof=1):.3f}")
        print(f"| {n} | " + " | ".join(cells) + " |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="+", help="case names (default: all reduced cases)")
    parser.add_argument("--full", action="store_true", help="add Fig. 1b and Fig. 5 at n = 400")
    parser.add_argument("--hard", action="store_true", help="the hard-case matrix instead")
    parser.add_argument("--memory", action="store_true", help="measure peak memory instead")
    parser.add_argument("--memory-n", type=int, default=500)
    parser.add_argument("--memory-child", nargs=2, help=argparse.SUPPRESS)
    parser.add_argument("--fractions", action="store_true", help="IP drained fractions vs n")
    parser.add_argument("--sizes", type=int, nargs="+", default=[25, 50, 100, 200, 400, 800])
    parser.add_argument("--seeds", type=int, default=32)
    args = parser.parse_args()
    if args.fractions:
        run_fractions(args.sizes, args.seeds)
        return
    if args.memory_child:
        memory_child(args.memory_child[0], int(args.memory_child[1]))
        return
    if args.memory:
        run_memory(args.memory_n)
        return
    cases = dict(CASES)
    if args.full:
        cases.update(FULL)
    if args.hard:
        cases = dict(HARD)
    if args.only:
        every = {**CASES, **FULL, **HARD}
        cases = {k: every[k] for k in args.only}
    run_cases(cases)


if __name__ == "__main__":
    main()
