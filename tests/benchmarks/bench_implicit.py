"""Benchmark: the viscous integrators (explicit, rkc, implicit) across Ca (not a test).

    python tests/benchmarks/bench_implicit.py                       # n = 100, Ca 1e-3 .. 1e-6
    python tests/benchmarks/bench_implicit.py --n 50 --ca 1e-4 1e-6 --integrator implicit rkc
    python tests/benchmarks/bench_implicit.py --n 400 --ca 1e-5 --integrator rkc --max-drained 1500
    python tests/benchmarks/bench_implicit.py --profile --ca 1e-5 --integrator implicit
    python tests/benchmarks/bench_implicit.py --n 400 --ca 1e-5 --integrator rkc --max-drained 300 \
        --tolerance 0.3 1e-2 1e-3

Each run is the scene ``{"seed": 1, "lattice": {"n": n, "disorder": 0.3, "pore_size": 1e-7},
"fluid": {"kind": "viscous", "capillary_number": Ca, "integrator": ...}, "stop": {"at":
"breakthrough"}}`` (default settings otherwise), run in a child process so that a run longer
than ``--max-wall`` seconds is stopped and reported as such (the explicit integrator needs
~4/(n Ca) steps per drained pore). Reported: wall time of ``run()`` (the numba cache is
warmed first, on a 10 x 10 scene), time steps, drained pores, steps per drained pore, and
for the implicit integrator the linear solves and factorisations per drained pore and the
rejected steps, for RKC the stage sweeps per drained pore (with the explicit steps it takes
near landings: "sweeps/pore"). ``--max-drained`` stops each run after that many drained pores
(a sample of a long run); ``--tolerance`` runs each scene at each ``fluid.tolerance`` given
(rkc and implicit). ``--profile`` prints where an integrator spends its time.
"""

from __future__ import annotations

import argparse
import itertools
import json
import multiprocessing as mp
import time
from typing import Any


def scene(
    n: int,
    ca: float,
    integrator: str,
    seed: int = 1,
    max_drained: int | None = None,
    tolerance: float | None = None,
) -> dict[str, Any]:
    stop: dict[str, Any] = {"at": "breakthrough"}
    if max_drained:
        stop["max_drained"] = max_drained
    fluid: dict[str, Any] = {"kind": "viscous", "capillary_number": ca, "integrator": integrator}
    if tolerance is not None:
        fluid["tolerance"] = tolerance
    return {
        "seed": seed,
        "lattice": {"n": n, "disorder": 0.3, "pore_size": 1e-7},
        "fluid": fluid,
        "stop": stop,
        "classifier": {"kind": "none"},
    }


def _run(sc: dict[str, Any], profile: bool, out: Any) -> None:
    from porenet.simulation import Simulation

    small = json.loads(json.dumps(sc))
    small["lattice"]["n"] = 10
    Simulation.from_scene(small).run()  # load or compile the numba cache
    sim = Simulation.from_scene(sc)
    if profile:
        import cProfile
        import pstats

        prof = cProfile.Profile()
        t0 = time.perf_counter()
        prof.enable()
        result = sim.run()
        prof.disable()
        wall = time.perf_counter() - t0
        pstats.Stats(prof).sort_stats("tottime").print_stats(12)
    else:
        t0 = time.perf_counter()
        result = sim.run()
        wall = time.perf_counter() - t0
    s = result.summary
    out.put(
        {
            "wall_s": wall,
            "steps": s["time_steps"],
            "n_drained": s["n_drained"],
            "time": sim.state.time,
            "solves": s.get("linear_solves"),
            "factorizations": s.get("factorizations"),
            "rejected": s.get("rejected_steps"),
            "sweeps": s.get("stage_sweeps", 0) + s.get("explicit_steps", 0)
            if s.get("stage_sweeps") is not None
            else None,
            "balance": s["volume_balance_error"],
        }
    )


def run(sc: dict[str, Any], max_wall: float, profile: bool = False) -> dict[str, Any] | None:
    """One run in a child process; None if it takes longer than ``max_wall`` seconds."""
    ctx = mp.get_context("spawn")
    out = ctx.Queue()
    proc = ctx.Process(target=_run, args=(sc, profile, out))
    proc.start()
    try:
        return out.get(timeout=max_wall + 60)  # + compile / cache warm-up
    except Exception:
        return None
    finally:
        proc.terminate()
        proc.join()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100)
    parser.add_argument("--ca", type=float, nargs="+", default=[1e-3, 1e-4, 1e-5, 1e-6])
    parser.add_argument(
        "--integrator",
        nargs="+",
        default=["implicit", "rkc", "explicit"],
        choices=["implicit", "rkc", "explicit"],
    )
    parser.add_argument("--max-drained", type=int, default=None)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--tolerance", type=float, nargs="+", default=[None])
    parser.add_argument("--max-wall", type=float, default=300.0)
    parser.add_argument("--profile", action="store_true")
    args = parser.parse_args()
    from porenet.config.loading import load_scene
    from porenet.core.errors import ConfigError

    for ca, integrator, tol in itertools.product(args.ca, args.integrator, args.tolerance):
        try:  # a bad value is reported here, not as a child process that never answers
            load_scene(scene(args.n, ca, integrator, args.seed, args.max_drained, tol))
        except ConfigError as exc:
            parser.error(str(exc))
    print(f"n = {args.n}, seed {args.seed}, lambda = 0.3, to breakthrough")
    print(
        "integrator  Ca      tolerance  wall(s)  steps    drained  steps/pore  solves/pore  "
        "fact/pore  sweeps/pore  rejected  time"
    )
    for ca, integrator, tol in itertools.product(args.ca, args.integrator, args.tolerance):
        sc = scene(args.n, ca, integrator, args.seed, args.max_drained, tol)
        label = f"{integrator:10s}  {ca:<6.0e}  {'default' if tol is None else f'{tol:g}':9s}"
        r = run(sc, args.max_wall, args.profile)
        if r is None:
            print(f"{label}  > {args.max_wall:.0f} s (stopped)")
            continue
        d = max(r["n_drained"] - 1, 1)  # the inlet drains at t = 0
        solves = f"{r['solves'] / d:11.1f}" if r["solves"] is not None else " " * 11
        fact = f"{r['factorizations'] / d:9.1f}" if r["factorizations"] is not None else " " * 9
        rej = f"{r['rejected']:8d}" if r["rejected"] is not None else " " * 8
        sweeps = f"{r['sweeps'] / d:11.1f}" if r["sweeps"] is not None else " " * 11
        print(
            f"{label}  {r['wall_s']:7.1f}  {r['steps']:7d}  {r['n_drained']:7d}  "
            f"{r['steps'] / d:10.1f}  {solves}  {fact}  {sweeps}  {rej}  {r['time']:.4g}",
            flush=True,
        )


if __name__ == "__main__":
    main()
