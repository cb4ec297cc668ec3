"""Diagnostic: how far from the newest landing an RKC step's local error reaches (not a test).

    python tests/benchmarks/error_locality.py                       # n = 400, Ca = 1e-5, 1000
    python tests/benchmarks/error_locality.py --drained 3000 --steps 8 30 100

Runs the scene of ``bench_implicit.py`` (seed 1, lambda = 0.3, ``integrator = "rkc"``) until
``--drained`` pores have drained (the run stops just after a landing), then, from that state,
computes one RKC step of each length in ``--steps`` (:func:`porenet.kinds.viscous.kernels.rkc_step.
imex_stages`, the step's stage count by :func:`porenet.kinds.viscous.kernels.chebyshev.stage_count`)
and the RKC local error estimate of every pore, ``|-0.8 ds + 0.4 h (F(y_n) + F(y_n+1)) / V|`` (as
:func:`porenet.kinds.viscous.kernels.rkc_step.step_error`, without the menisci's implicit part).
Prints, for each step, how many pores exceed the tolerance (``fluid.tolerance`` times the
entry-pressure spread) and 5 % of it, and their largest lattice (Manhattan) distance from the pore
that just drained: the radius a window around the newest landing would need for the rest of the
lattice to take that step within the tolerance. Nothing is written back into the run.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_implicit import scene

from porenet.core.errors import ConfigError
from porenet.kinds.viscous.kernels.chebyshev import stage_count, sweep
from porenet.kinds.viscous.kernels.menisci import meniscus_fluxes
from porenet.kinds.viscous.kernels.rkc import _list_candidates
from porenet.kinds.viscous.kernels.rkc_step import Stages, StepStart, imex_stages
from porenet.kinds.viscous.kernels.state import Count, Menisci, Pump, Sweep, Total, new_scratch
from porenet.kinds.viscous.kernels.window import no_window
from porenet.simulation import Simulation

ZERO = (0.0, 0.0, 0.0, 0.0)


def step_errors(fl, drained: np.ndarray, h: float) -> tuple[np.ndarray, int, int]:
    """Per-pore error estimate of one RKC step of ``h`` from the fluid's state (copies only),
    the stage count and the number of candidate menisci."""
    net, cond, flow, front = fl.network, fl.conductances, fl.flow, fl.front
    counters, totals = flow.counters, flow.totals
    n_thr, n_p = len(cond.area), len(flow.pressure)
    inv_vol = net.inverse_volume
    p, f0, work = flow.pressure.copy(), np.zeros(n_p), np.zeros(n_p)
    field = Sweep(net.grid_n, front.box, counters[Count.N_ACTIVE], front.pores,
                  front.pore_slot, net.indptr, net.neighbour, net.throat, cond.between,
                  cond.outlet, inv_vol, work, front.box)  # fmt: skip
    m = stage_count(h, fl.spectral_radius)
    out0 = sweep(field, p, p, f0, ZERO, f0, True)
    scratch = new_scratch(n_p, n_thr)
    menisci0 = Menisci(scratch.meniscus_throat, scratch.meniscus_pore, scratch.threshold,
                       scratch.head, scratch.next_candidate, p, f0, net.volume, cond.meniscus,
                       flow.meniscus_length.copy(), cond.area)  # fmt: skip
    inj = fl.injection
    capacity = inj.capacity + inj.capacity_per_drained * totals[Total.DRAINED_PORE_VOLUME]
    pump0 = Pump(inj.control, totals[Total.INVADING_PRESSURE], inj.rate, capacity,
                 inj.ramp_rate)  # fmt: skip
    copy = flow._replace(latched=flow.latched.copy(), meniscus_length=menisci0.length)
    n_on = _list_candidates(h, totals[Total.TIME], menisci0, pump0, net, cond, copy, front,
                            scratch, fl.config.meniscus == "latching", no_window())  # fmt: skip
    q0 = np.zeros(n_thr)
    meniscus_fluxes(fl.dt_stable, n_on, menisci0, pump0, q0)
    ybuf = np.zeros((3, n_p))
    stages = Stages(ybuf, np.zeros(n_p), np.zeros(n_p), np.zeros((3, n_thr)),
                    np.zeros((3, n_thr)), np.zeros(3), np.zeros((3, 2)), np.zeros(n_thr),
                    np.zeros(n_thr, dtype=np.bool_))  # fmt: skip
    k = imex_stages(h, m, field, StepStart(p, f0, out0, q0), n_on, menisci0, pump0, stages,
                    no_window())  # fmt: skip
    ds = ybuf[k].copy()
    sweep(field, ds, ds, f0, ZERO, work, True)  # work = L ds
    err = np.abs(-0.8 * ds + 0.4 * h * (2.0 * f0 + work) * inv_vol)
    err[menisci0.pore[:n_on]] = 0.0  # the candidates' pores: implicit, estimated otherwise
    return err, m, n_on


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=400)
    parser.add_argument("--ca", type=float, default=1e-5)
    parser.add_argument("--drained", type=int, default=1000)
    parser.add_argument("--steps", type=float, nargs="+", default=[4, 8, 16, 30, 60, 100, 200])
    args = parser.parse_args()
    if args.drained < 2 or min(args.steps) <= 0:
        parser.error("--drained must be at least 2 and every --steps value positive")
    try:
        sim = Simulation.from_scene(scene(args.n, args.ca, "rkc", max_drained=args.drained))
    except ConfigError as exc:
        parser.error(str(exc))
    sim.run()
    fl = sim.fluid
    n = fl.network.grid_n
    last = int(fl.records.order[int(fl.flow.counters[Count.EVENTS]) - 1])
    tol = fl.config.tolerance * fl.pressure_scale
    t = fl.flow.totals[Total.TIME]
    print(f"n = {args.n}, Ca = {args.ca:g}, {args.drained} drained, t = {t:.6g}; "
          f"distances from pore {last} ({last // n}, {last % n}), tolerance {tol:.3g}")  # fmt: skip
    print(
        "step h  stages  candidates  max err/tol  over tol: pores, farthest  "
        "over 5 %: pores, farthest"
    )
    for h in args.steps:
        err, m, n_on = step_errors(fl, sim.state.drained, h)
        dist = np.abs(np.arange(n * n) // n - last // n) + np.abs(np.arange(n * n) % n - last % n)
        cols = []
        for level in (1.0, 0.05):
            over = err > level * tol
            cols.append(f"{over.sum():7d}, {dist[over].max() if over.any() else 0:4d}")
        print(f"{h:6.1f}  {m:6d}  {n_on:10d}  {err.max() / tol:11.2f}  {cols[0]:>22s}  "
              f"{cols[1]:>22s}")  # fmt: skip


if __name__ == "__main__":
    main()
