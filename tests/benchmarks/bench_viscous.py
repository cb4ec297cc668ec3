"""Benchmark: the viscous model on the paper's 400 x 400 lattice (not a test; no assertions).

    python tests/benchmarks/bench_viscous.py                 # Fig. 1b to breakthrough, and
                                                             # a Ca = 1e-5 sample
    python tests/benchmarks/bench_viscous.py --skip-fig1b    # only the Ca = 1e-5 sample
    python tests/benchmarks/bench_viscous.py --skip-fig1b --low-ca-full   # Ca = 1e-5 to
                                                             # breakthrough (default: rkc)
    python tests/benchmarks/bench_viscous.py --skip-fig1b --low-ca-full \
        --set fluid.local_steps=off                          # without local time steps
    python tests/benchmarks/bench_viscous.py --skip-fig1b --high-ca       # Ca = 0.1,
                                                             # lambda = 0.55 to breakthrough

* Fig. 1b (`examples/scenes/fig1b.toml`: n = 400, Ca = 9e-4, lambda = 0.3, default
  settings) to breakthrough: wall time, time steps, time per step, steps per drained pore.
* Ca = 1e-5 on the same lattice: a full run is out of reach of the explicit integrator, so
  the script runs about ``--sample-steps`` steps (a ``max_time``), measures the time per
  step, and
  multiplies it by the number of steps to breakthrough extrapolated from the injection rate:
  ``t_breakthrough = V_breakthrough / Q`` with ``V_breakthrough`` the displaced volume at
  breakthrough measured at Ca = 9e-4 (a lower bound at smaller Ca, where more of the lattice
  drains before breakthrough), divided by the mean step of the sample.
* ``--high-ca``: Ca = 0.1, lambda = 0.55 on the same lattice to breakthrough (Fig. 2's
  dearest corner for the explicit integrator: a long front, every step ends on a landing):
  wall time, steps, time per step.
* ``--low-ca-full``: Ca = 1e-5 on the same lattice to breakthrough with the default
  integrator (``auto``, which picks ``rkc`` there, with local time steps; ``--integrator``
  to choose, ``--set`` for other overrides): wall time, steps, stage sweeps and explicit
  steps, per drained pore, and the local time steps' counters.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from porenet.jit.threads import configure_threads
from porenet.simulation import Simulation

SCENE = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "fig1b.toml"


def fig1b() -> dict:
    sim = Simulation.from_scene(SCENE)
    t0 = time.perf_counter()
    result = sim.run()
    wall = time.perf_counter() - t0
    steps = result.summary["time_steps"]
    drained = result.summary["n_drained"]
    return {
        "wall_s": wall,
        "steps": steps,
        "us_per_step": 1e6 * wall / steps,
        "steps_per_drained_pore": steps / drained,
        "n_drained": drained,
        "displaced_volume": sim.fluid.volumes()["drained"],
    }


def low_ca_sample(sample_steps: int, displaced_volume: float) -> dict:
    tau = 1e-3 * 1e-7 / 0.07  # mu a / gamma of the scene (s)
    max_time = sample_steps * 0.15 * tau  # about sample_steps stable steps
    sim = Simulation.from_scene(
        SCENE,
        [
            "fluid.capillary_number=1e-5",
            f"fluid.max_time={max_time!r}",
            "fluid.integrator=explicit",  # what the extrapolation is about (auto picks rkc)
        ],
    )
    t0 = time.perf_counter()
    result = sim.run()
    wall = time.perf_counter() - t0
    steps = result.summary["time_steps"]
    mean_step = sim.state.time / steps
    t_breakthrough = displaced_volume / sim.fluid.injection_rate
    total_steps = t_breakthrough / mean_step
    return {
        "steps": steps,
        "sample_wall_s": wall,
        "us_per_step": 1e6 * wall / steps,
        "estimated_steps": total_steps,
        "estimated_wall_s": total_steps * wall / steps,
    }


def high_ca() -> dict:
    sim = Simulation.from_scene(SCENE, ["fluid.capillary_number=0.1", "lattice.disorder=0.55"])
    t0 = time.perf_counter()
    result = sim.run()
    wall = time.perf_counter() - t0
    steps = result.summary["time_steps"]
    return {"wall_s": wall, "steps": steps, "us_per_step": 1e6 * wall / steps,
            "n_drained": result.summary["n_drained"]}  # fmt: skip


def low_ca_full(integrator: str, overrides: list[str]) -> dict:
    sim = Simulation.from_scene(
        SCENE, ["fluid.capillary_number=1e-5", f"fluid.integrator={integrator}", *overrides]
    )
    t0 = time.perf_counter()
    result = sim.run()
    wall = time.perf_counter() - t0
    s = result.summary
    return {
        "wall_s": wall,
        **{
            k: s.get(k)
            for k in (
                "integrator",
                "n_drained",
                "time_steps",
                "stage_sweeps",
                "explicit_steps",
                "rkc_steps",
                "rejected_steps",
                "rejected_for_events",
                "rejected_stage_sweeps",
                "volume_balance_error",
                "capillary_number_measured",
                "local_steps",
                "macro_steps",
                "macro_cuts",
                "single_rate_pores",
                "coarse_stage_sweeps",
                "coarse_rejected_steps",
                "window_pore_stages",
                "coarse_pore_stages",
            )
        },
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip-fig1b", action="store_true")
    parser.add_argument("--sample-steps", type=int, default=20000)
    parser.add_argument(
        "--displaced-volume",
        type=float,
        default=None,
        help="displaced volume at breakthrough (a^3) if Fig. 1b is skipped",
    )
    parser.add_argument("--low-ca-full", action="store_true")
    parser.add_argument("--high-ca", action="store_true")
    parser.add_argument("--integrator", default="auto")
    parser.add_argument(
        "--threads",
        default="auto",
        help="threads of the parallel kernels: N, or auto (the default: measured per run)",
    )
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="scene override for --low-ca-full, e.g. fluid.local_steps=off (repeatable)",
    )
    args = parser.parse_args()
    threads = args.threads if args.threads == "auto" else int(args.threads)
    print(f"threads: {configure_threads(threads).describe()}")
    Simulation.from_scene(SCENE, ["lattice.n=20"]).run()  # load the numba cache
    Simulation.from_scene(SCENE, ["lattice.n=20", "fluid.capillary_number=1e-5"]).run()
    volume = args.displaced_volume
    if not args.skip_fig1b:
        r = fig1b()
        volume = r["displaced_volume"]
        print(
            f"Fig. 1b (n=400, Ca=9e-4): {r['wall_s']:.1f} s, {r['steps']} steps, "
            f"{r['us_per_step']:.0f} us/step, {r['steps_per_drained_pore']:.1f} steps per "
            f"drained pore ({r['n_drained']} drained, displaced volume {volume:.4g} a^3)"
        )
    if args.high_ca:
        r = high_ca()
        print(
            f"Ca=0.1, lambda=0.55, n=400 to breakthrough: {r['wall_s']:.1f} s, {r['steps']} "
            f"steps, {r['us_per_step']:.0f} us/step, {r['n_drained']} drained"
        )
    if args.low_ca_full:
        r = low_ca_full(args.integrator, args.set)
        d = max(r["n_drained"] - 1, 1)
        per = {k: round(r[k] / d, 1) for k in ("time_steps", "stage_sweeps", "explicit_steps")
               if r[k] is not None}  # fmt: skip
        print(f"Ca=1e-5, n=400 to breakthrough: {r['wall_s']:.1f} s; {r}; per drained pore {per}")
    if volume is not None:
        r = low_ca_sample(args.sample_steps, volume)
        print(
            f"Ca=1e-5, n=400: first {r['steps']} steps in {r['sample_wall_s']:.1f} s "
            f"({r['us_per_step']:.0f} us/step); estimated {r['estimated_steps']:.3g} steps and "
            f"{r['estimated_wall_s'] / 3600:.1f} h to breakthrough"
        )


if __name__ == "__main__":
    main()
