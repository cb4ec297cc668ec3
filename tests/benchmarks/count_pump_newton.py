"""Count Newton iterations per solve of the pump equation (not a test; no assertions).

    python tests/benchmarks/count_pump_newton.py            # Ca = 0.1, lambda = 0.55, n = 60

Runs the viscous model with numba disabled (pure Python, ~1-2 min) and wraps
:func:`porenet.kinds.viscous.kernels.menisci.invader_pressure` to count the residual evaluations of
each solve: the number behind docs/performance.md's "~7 iterations per solve, ~40 before" (run it at
a commit before the fix, e.g. in a git worktree, for the second number).
"""

from __future__ import annotations

import argparse
import collections
import os

os.environ["NUMBA_DISABLE_JIT"] = "1"  # before numba is imported

import numpy as np

import porenet.kinds.viscous.kernels.explicit as viscous
import porenet.kinds.viscous.kernels.menisci as menisci
from porenet.simulation import run

SCENE = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "scenes", "fig1b.toml")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=60)
    parser.add_argument("--ca", type=float, default=0.1)
    parser.add_argument("--disorder", type=float, default=0.55)
    args = parser.parse_args()
    residual, solve = menisci._pump_residual, menisci.invader_pressure
    counts: list[int] = []

    def counted_residual(*a):  # type: ignore[no-untyped-def]
        counts[-1] += 1
        return residual(*a)

    def counted_solve(*a):  # type: ignore[no-untyped-def]
        counts.append(0)
        return solve(*a)

    menisci._pump_residual = counted_residual
    menisci.invader_pressure = counted_solve
    viscous.invader_pressure = counted_solve
    overrides = [f"lattice.n={args.n}", f"fluid.capillary_number={args.ca}",
                 f"lattice.disorder={args.disorder}", "fluid.integrator=explicit"]  # fmt: skip
    run(SCENE, overrides)
    its = np.array(counts)
    print(f"{len(its)} solves: {its.mean():.2f} iterations per solve (max {its.max()})")
    print("histogram:", sorted(collections.Counter(its.tolist()).items()))


if __name__ == "__main__":
    main()
