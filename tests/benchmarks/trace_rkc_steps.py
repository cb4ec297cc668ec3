"""Diagnostic: the RKC integrator's steps one by one on a low-Ca run (not a test; no assertions).

    python tests/benchmarks/trace_rkc_steps.py                      # n = 400, Ca = 1e-5, 300 pores
    python tests/benchmarks/trace_rkc_steps.py --tolerance 0.3 --show 40

Runs the scene of ``bench_implicit.py`` (seed 1, lambda = 0.3, ``integrator = "rkc"``) until
``--drained`` pores have drained, one kernel call per step (``step_limit = 1``, which ends
the explicit integrator's runs near landings after each step too, so the counts differ a
little from an ordinary run), and records for each step its length, stage sweeps, whether the
explicit integrator took it, rejected steps, the error estimate of the accepted step (as a
fraction of the tolerance) and the menisci that have advanced part of their throat. Prints
how the stage sweeps divide over step lengths (after the first ``--skip`` drained pores) and,
with ``--show``, the first steps after the pore numbered ``--skip``.
"""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_implicit import scene

from porenet.core.errors import ConfigError
from porenet.kinds.viscous.kernels.rkc import Slot
from porenet.kinds.viscous.kernels.state import Count, Total
from porenet.kinds.viscous.model import MENISCUS_LENGTH
from porenet.simulation import Simulation


def trace(n: int, ca: float, drained: int, tolerance: float | None) -> np.ndarray:
    """Rows (start time, end time, stage sweeps, explicit steps, rejected, error / tolerance,
    partly advanced menisci, drained pores) per kernel call."""
    sim = Simulation.from_scene(scene(n, ca, "rkc", 1, drained, tolerance))
    fluid = sim.fluid
    fluid.step_limit = 1
    rows = []
    advance = fluid.rkc_steps

    def one_step(budget, t_end, *args, **kwargs):
        memory, totals = fluid.rkc.memory, fluid.flow.totals
        before, t0 = memory.copy(), totals[Total.TIME]
        ell = fluid.flow.meniscus_length
        partial = int(np.count_nonzero(ell < MENISCUS_LENGTH * (1 - 1e-12)))
        status = advance(budget, t_end, *args, **kwargs)
        rows.append((t0, totals[Total.TIME], memory[Slot.STAGES] - before[Slot.STAGES],
                     memory[Slot.EXPLICIT_STEPS] - before[Slot.EXPLICIT_STEPS],
                     memory[Slot.REJECTED] - before[Slot.REJECTED], memory[Slot.LAST_ERROR],
                     partial, fluid.flow.counters[Count.EVENTS]))  # fmt: skip
        return status

    fluid.rkc_steps = one_step
    sim.run()
    return np.array(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=400)
    parser.add_argument("--ca", type=float, default=1e-5)
    parser.add_argument("--drained", type=int, default=300)
    parser.add_argument("--tolerance", type=float, default=None)
    parser.add_argument("--skip", type=int, default=50, help="drained pores left out (start)")
    parser.add_argument("--show", type=int, default=0, help="steps to print one by one")
    args = parser.parse_args()
    if not 0 <= args.skip < args.drained - 1:
        parser.error("--skip must be at least 0 and below --drained - 1")
    try:
        a = trace(args.n, args.ca, args.drained, args.tolerance)
    except ConfigError as exc:
        parser.error(str(exc))
    a = a[a[:, 7] >= args.skip]
    h, m, explicit = a[:, 1] - a[:, 0], a[:, 2], a[:, 3] > 0
    pores = a[-1, 7] - a[0, 7]
    print(f"n = {args.n}, Ca = {args.ca:g}, tolerance {args.tolerance or 'default'}; "
          f"pores {args.skip} to {int(a[-1, 7])}")  # fmt: skip
    print(f"per drained pore: {m.sum() / pores:.1f} stage sweeps, {(~explicit).sum() / pores:.1f} "
          f"RKC calls, {explicit.sum() / pores:.1f} explicit steps, {a[:, 4].sum() / pores:.2f} "
          f"rejected; partly advanced menisci: median {np.median(a[:, 6]):.0f}")  # fmt: skip
    edges = [0, 2, 4, 8, 16, 32, 64, 128, np.inf]
    print("RKC step length   steps   stage sweeps   share")
    for lo, hi in itertools.pairwise(edges):
        s = ~explicit & (h >= lo) & (h < hi)
        print(f"[{lo:g}, {hi:g})".ljust(17) + f"{s.sum():6d}   {m[s].sum():12.0f}   "
              f"{m[s].sum() / m.sum():5.0%}")  # fmt: skip
    for r in a[: args.show]:
        print(f"t {r[0]:10.2f}  h {r[1] - r[0]:8.3f}  stages {r[2]:3.0f}  explicit {r[3]:2.0f}  "
              f"rejected {r[4]:1.0f}  error/tol {r[5]:.3g}  drained {r[7]:.0f}")  # fmt: skip


if __name__ == "__main__":
    main()
