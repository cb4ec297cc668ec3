"""Benchmark: where the fixed work of one RKC step goes (not a test; no assertions).

    python tests/benchmarks/bench_rkc_step.py                          # n = 400, Ca = 1e-5
    python tests/benchmarks/bench_rkc_step.py --n 200 --drained 1500

Runs the scene of ``bench_implicit.py`` (seed 1, lambda = 0.3, ``integrator = "rkc"``) until
``--drained`` pores have drained, then times, on that state and with the next step's length,
each piece of work :func:`porenet.kinds.viscous.kernels.rkc.rkc_advance` does per RKC step besides
its stage sweeps: the box check, the candidate listing, the first stage's increment, the
unlisted-meniscus check over the front, the error estimate (a flux sweep and
:func:`porenet.kinds.viscous.kernels.rkc_step.step_error`), ``p += ds``; and, for scale, one flux
sweep, one stage sweep and the whole of :func:`porenet.kinds.viscous.kernels.rkc_step.imex_stages`.
Each is repeated inside one compiled loop (no dispatch cost); medians of 5 rounds.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from porenet.jit.jit import njit
from porenet.kinds.viscous.kernels.chebyshev import stage_count, sweep
from porenet.kinds.viscous.kernels.diffusion import grow_where_reached
from porenet.kinds.viscous.kernels.menisci import meniscus_fluxes, undrained_pore
from porenet.kinds.viscous.kernels.rkc import Slot, _add_active, _list_candidates, _unlist
from porenet.kinds.viscous.kernels.rkc_step import (
    Stages,
    StepStart,
    _scaled_rate,
    imex_stages,
    step_error,
)
from porenet.kinds.viscous.kernels.state import Count, Menisci, Pump, Sweep, Total, new_scratch
from porenet.kinds.viscous.kernels.window import no_window

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_implicit import scene

ZERO = (0.0, 0.0, 0.0, 0.0)


@njit
def _flux_sweeps(reps, field, y, out):
    s = 0.0
    for _ in range(reps):
        s += sweep(field, y, y, out, ZERO, out, True)
    return s


@njit
def _stage_sweeps(reps, field, y1, y2, f0, out):
    s = 0.0
    for _ in range(reps):
        s += sweep(field, y1, y2, f0, (0.9, 0.1, 0.3, 0.2), out, False)
    return s


@njit
def _box_checks(reps, box, n, p, floor, margin):
    c = 0
    for _ in range(reps):
        c += grow_where_reached(box.copy(), n, p, floor, margin)
    return c


@njit
def _listings(reps, h, t, menisci0, pump0, net, cond, flow, front, scratch, latching, win):
    n_on = 0
    for _ in range(reps):
        n_on = _list_candidates(h, t, menisci0, pump0, net, cond, flow, front, scratch,
                                latching, win)  # fmt: skip
        _unlist(n_on, menisci0, scratch.candidate)
    return n_on


@njit
def _scalings(reps, field, f0, out):
    for _ in range(reps):
        _scaled_rate(field, f0, 0.1, out)


@njit
def _stages(reps, h, m, field, start, n_on, menisci0, pump0, stages, win):
    k = 0
    for _ in range(reps):
        k = imex_stages(h, m, field, start, n_on, menisci0, pump0, stages, win)
    return k


@njit
def _front_checks(reps, front, nf, tp, drained, cand, ps, p, ds, pe):
    """The unlisted-meniscus check of :func:`porenet.kinds.viscous.kernels.rkc.rkc_advance`."""
    c = 0
    for _ in range(reps):
        for s in range(nf):
            f = front[s]
            i = undrained_pore(tp, drained, f)
            if not cand[f] and ps - p[i] - ds[i] > pe[f]:
                c += 1
                break
    return c


@njit
def _estimates(reps, h, field, ds, f0, fnew, fi, vol):
    e = 0.0
    for _ in range(reps):
        out_s = sweep(field, ds, ds, f0, ZERO, fnew, True)
        err, _stored, _largest = step_error(h, field, ds, f0, fnew, fi, vol)
        e += err + out_s
    return e


@njit
def _additions(reps, field, ds, p):
    for _ in range(reps):
        _add_active(field, ds, p)


def timed(name: str, fn, *args, reps: int = 200) -> float:
    fn(1, *args)
    rounds = []
    for _ in range(5):
        t0 = time.perf_counter()
        fn(reps, *args)
        rounds.append((time.perf_counter() - t0) / reps * 1e3)
    ms = float(np.median(rounds))
    print(f"{name:44s} {ms:8.4f} ms")
    return ms


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=400)
    parser.add_argument("--ca", type=float, default=1e-5)
    parser.add_argument("--drained", type=int, default=3000)
    args = parser.parse_args()
    from porenet.simulation import Simulation

    sim = Simulation.from_scene(scene(args.n, args.ca, "rkc", max_drained=args.drained))
    t0 = time.perf_counter()
    sim.run()
    print(f"n = {args.n}, Ca = {args.ca:g}: {args.drained} drained in "
          f"{time.perf_counter() - t0:.1f} s")  # fmt: skip
    fl = sim.fluid
    net, cond, flow, front = fl.network, fl.conductances, fl.flow, fl.front
    counters, totals, drained = flow.counters, flow.totals, flow.drained
    nf, n_thr, n_p = int(counters[Count.N_FRONT]), len(cond.area), len(flow.pressure)
    p, f0, fnew = flow.pressure.copy(), np.zeros(n_p), np.zeros(n_p)
    field = Sweep(net.grid_n, front.box, counters[Count.N_ACTIVE], front.pores,
                  front.pore_slot, net.indptr, net.neighbour, net.throat, cond.between,
                  cond.outlet, net.inverse_volume, fnew, front.box)  # fmt: skip
    h = fl.rkc.memory[Slot.H]
    m = stage_count(h, fl.spectral_radius)
    print(f"front {nf} throats, box {front.box.tolist()}, next step {h:.3g} ({m} stages)")
    out0 = sweep(field, p, p, f0, ZERO, f0, True)
    scratch = new_scratch(n_p, n_thr)
    menisci0 = Menisci(scratch.meniscus_throat, scratch.meniscus_pore, scratch.threshold,
                       scratch.head, scratch.next_candidate, p, f0, net.volume, cond.meniscus,
                       flow.meniscus_length, cond.area)  # fmt: skip
    inj = fl.injection
    capacity = inj.capacity + inj.capacity_per_drained * totals[Total.DRAINED_PORE_VOLUME]
    pump0 = Pump(inj.control, totals[Total.INVADING_PRESSURE], inj.rate, capacity,
                 inj.ramp_rate)  # fmt: skip
    flow_copy = flow._replace(latched=flow.latched.copy())
    listing = (h, totals[Total.TIME], menisci0, pump0, net, cond, flow_copy, front, scratch,
               fl.config.meniscus == "latching", no_window())  # fmt: skip
    sweep_ms = timed("flux sweep (for scale)", _flux_sweeps, field, p, np.zeros(n_p))
    ybuf = np.zeros((3, n_p))
    stage_ms = timed("stage sweep (for scale)", _stage_sweeps, field, ybuf[0], ybuf[1], f0,
                     ybuf[2])  # fmt: skip
    timed("box check (grow_where_reached)", _box_checks, front.box, net.grid_n, p,
          fl.config.pressure_floor, m + 1)  # fmt: skip
    timed("candidate listing (_list_candidates)", _listings, *listing)
    timed("first stage's increment (_scaled_rate)", _scalings, field, f0, ybuf[2])
    n_on = _list_candidates(*listing)
    q0 = np.zeros(n_thr)
    meniscus_fluxes(fl.dt_stable, n_on, menisci0, pump0, q0)
    stages = Stages(ybuf, np.zeros(n_p), np.zeros(n_p), np.zeros((3, n_thr)),
                    np.zeros((3, n_thr)), np.zeros(3), np.zeros((3, 2)), np.zeros(n_thr),
                    np.zeros(n_thr, dtype=np.bool_))  # fmt: skip
    step = (h, m, field, StepStart(p, f0, out0, q0), n_on, menisci0, pump0, stages, no_window())
    all_ms = timed(f"imex_stages ({m} stages, for scale)", _stages, *step, reps=20)
    print(f"{'  of which not stage sweeps':44s} {all_ms - (m - 1) * stage_ms:8.4f} ms")
    k = imex_stages(*step)
    ds = ybuf[k].copy()
    timed("unlisted check over the front", _front_checks, front.throats, nf, net.throat_pores,
          drained, scratch.candidate, stages.invading_pressure[k], p, ds,
          cond.entry_pressure)  # fmt: skip
    timed("error estimate (sweep + step_error)", _estimates, h, field, ds, f0, fnew,
          np.zeros(n_p), net.volume)  # fmt: skip
    timed("p += ds (_add_active)", _additions, field, ds, p.copy())
    print(f"flux sweep {sweep_ms:.4f} ms, stage sweep {stage_ms:.4f} ms")


if __name__ == "__main__":
    main()
