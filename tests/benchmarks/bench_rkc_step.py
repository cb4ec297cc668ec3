"""Benchmark: where the fixed work of one RKC step goes (not a test; no assertions).

    python tests/benchmarks/bench_rkc_step.py                          # n = 400, Ca = 1e-5
    python tests/benchmarks/bench_rkc_step.py --n 200 --drained 1500

Runs the scene of ``bench_implicit.py`` (seed 1, lambda = 0.3, ``integrator = "rkc"``) until
``--drained`` pores have drained, then times, on that state and with the next step's length,
each piece of work :func:`porenet.kernels.viscous.rkc.rkc_advance` does per RKC step besides its
stage sweeps: the box check, the candidate listing, the first stage's increment, the
unlisted-meniscus check over the front, the error estimate (a flux sweep and
:func:`porenet.kernels.viscous.rkc_step.step_error`), ``p += ds``; and, for scale, one flux sweep,
one stage sweep and the whole of :func:`porenet.kernels.viscous.rkc_step.imex_stages`. Each is
repeated inside one compiled loop (no dispatch cost); medians of 5 rounds.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from porenet.kernels._jit import njit
from porenet.kernels.viscous.chebyshev import stage_count, sweep
from porenet.kernels.viscous.diffusion import grow_where_reached
from porenet.kernels.viscous.menisci import meniscus_fluxes, undrained_pore
from porenet.kernels.viscous.rkc import _add_active, _list_candidates, _unlist
from porenet.kernels.viscous.rkc_step import _scaled_rate, imex_stages, step_error
from porenet.kernels.viscous.window import no_window

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
def _listings(reps, h, menisci0, pump0, front, nf, tp, drained, pe, latched, latching, inv_vol,
              cand, near, win, grid_n, t):  # fmt: skip
    n_on = 0
    for _ in range(reps):
        n_on = _list_candidates(h, menisci0, pump0, front, nf, tp, drained, pe, latched,
                                latching, inv_vol, cand, near, win, grid_n, t)  # fmt: skip
        _unlist(n_on, menisci0[0], menisci0[1], menisci0[3], cand)
    return n_on


@njit
def _scalings(reps, field, f0, out):
    for _ in range(reps):
        _scaled_rate(field, f0, 0.1, out)


@njit
def _stages(reps, h, m, field, p, f0, out0, ybuf, rhs, zero, n_on, menisci0, pump0, q0, qst,
            lst, pst, ast, r_ell, moved, win):  # fmt: skip
    k = 0
    for _ in range(reps):
        k = imex_stages(h, m, field, p, f0, out0, ybuf, rhs, zero, n_on, menisci0, pump0, q0,
                        qst, lst, pst, ast, r_ell, moved, win)  # fmt: skip
    return k


@njit
def _front_checks(reps, front, nf, tp, drained, cand, ps, p, ds, pe):
    """The unlisted-meniscus check of :func:`porenet.kernels.viscous.rkc.rkc_advance`."""
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
    cnt, acc, drained = fl._cnt, fl._acc, sim.state.drained
    nf, n_thr, n_p = int(cnt[2]), len(fl._pe), len(fl._p)
    inv_vol = 1.0 / fl._vol
    p, f0, fnew = fl._p.copy(), np.zeros(n_p), np.zeros(n_p)
    field = (fl._grid_n, fl._box, cnt[3], fl._act, fl._apos, *fl._csr, fl._g_eff, fl._g_out,
             inv_vol, fnew, fl._box)  # fmt: skip
    h = fl._ctrl[0]
    m = stage_count(h, fl.spectral_radius)
    print(f"front {nf} throats, box {fl._box.tolist()}, next step {h:.3g} ({m} stages)")
    out0 = sweep(field, p, p, f0, ZERO, f0, True)
    head = np.full(n_p, -1, dtype=np.int64)
    cand = np.zeros(n_thr, dtype=np.bool_)
    near = np.empty(n_thr, dtype=np.int64)
    menisci0 = (fl._on_t, fl._on_p, np.empty(n_thr), head, np.empty(n_thr, dtype=np.int64), p,
                f0, fl._vol, fl._g_num, fl._ell, fl._area)  # fmt: skip
    capacity = fl._capacity + fl._capacity_per_drained * acc[7]
    pump0 = (fl._control, acc[1], fl._q, capacity, fl._ramp)
    latched = fl._latched.copy()
    listing = (h, menisci0, pump0, fl._front, nf, fl._tp, drained, fl._pe, latched,
               fl.config.meniscus == "latching", inv_vol, cand, near, no_window(),
               fl._grid_n, acc[0])  # fmt: skip
    sweep_ms = timed("flux sweep (for scale)", _flux_sweeps, field, p, np.zeros(n_p))
    ybuf = np.zeros((3, n_p))
    stage_ms = timed("stage sweep (for scale)", _stage_sweeps, field, ybuf[0], ybuf[1], f0,
                     ybuf[2])  # fmt: skip
    timed("box check (grow_where_reached)", _box_checks, fl._box, fl._grid_n, p,
          fl.config.pressure_floor, m + 1)  # fmt: skip
    timed("candidate listing (_list_candidates)", _listings, *listing)
    timed("first stage's increment (_scaled_rate)", _scalings, field, f0, ybuf[2])
    n_on = _list_candidates(*listing)
    q0 = np.zeros(n_thr)
    meniscus_fluxes(fl.dt_stable, n_on, menisci0, pump0, q0)
    stages = (h, m, field, p, f0, out0, ybuf, np.zeros(n_p), np.zeros(n_p), n_on, menisci0,
              pump0, q0, np.zeros((3, n_thr)), np.zeros((3, n_thr)), np.zeros(3),
              np.zeros((3, 2)), np.zeros(n_thr), np.zeros(n_thr, dtype=np.bool_),
              no_window())  # fmt: skip
    all_ms = timed(f"imex_stages ({m} stages, for scale)", _stages, *stages, reps=20)
    print(f"{'  of which not stage sweeps':44s} {all_ms - (m - 1) * stage_ms:8.4f} ms")
    k = imex_stages(*stages)
    ds, pst = ybuf[k].copy(), stages[15]
    timed("unlisted check over the front", _front_checks, fl._front, nf, fl._tp, drained,
          cand, pst[k], p, ds, fl._pe)  # fmt: skip
    timed("error estimate (sweep + step_error)", _estimates, h, field, ds, f0, fnew,
          np.zeros(n_p), fl._vol)  # fmt: skip
    timed("p += ds (_add_active)", _additions, field, ds, p.copy())
    print(f"flux sweep {sweep_ms:.4f} ms, stage sweep {stage_ms:.4f} ms")


if __name__ == "__main__":
    main()
