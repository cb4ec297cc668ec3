"""Benchmark: one mechanical update of the Hertzian solid (not a test; no assertions).

    python tests/benchmarks/bench_mechanics.py              # n = 400, median of 21 updates
    python tests/benchmarks/bench_mechanics.py --n 200 --repeat 51

Builds the paper's 400 x 400 lattice with a Hertzian solid at N_f = 1 (lambda = 0.1) and times
``HertzSolid.update`` (pressure loads, the solve with its contact iterations, the aperture
update and the force-balance residual) in two cases, each repeat from a fresh copy of the
prestressed state:

* a whole new load at once, the pressure field of a drained cluster (the invader at 2 gamma/a
  in a disc of radius 0.2 L around the centre, the defender at 0 elsewhere): every line of
  springs through the disc is solved and springs at its edge open (the worst case);
* one more pore drained at the edge of that disc (the typical update of a run: only the lines
  through its four particles are solved).

With ``--sparse``, also one general-purpose sparse LU solve of the same 2-D system (scipy
SuperLU with the same contact iteration), the issue's reference point; it takes seconds.
"""

from __future__ import annotations

import argparse
import copy
import statistics
import time

import numpy as np

from porenet.simulation import Simulation


def build(n: int) -> tuple[Simulation, np.ndarray]:
    scene = {
        "lattice": {"n": n, "disorder": 0.1},
        "fluid": {"kind": "invasion-percolation"},
        "solid": {"kind": "hertz", "fracturing_number": 1.0},
    }
    sim = Simulation.from_scene(scene)
    sim.solid.setup(sim.state)
    xy = sim.lattice.pore_coords
    centre = xy.mean(axis=0)
    drained = np.hypot(*(xy - centre).T) < 0.2 * 2 * n  # a disc of radius 0.2 L
    pressure = np.where(drained, 2.0, 0.0)
    sim.state.drained[:] = drained
    return sim, pressure


def timed(fn, repeat: int) -> list[float]:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=400)
    parser.add_argument("--repeat", type=int, default=21)
    parser.add_argument("--sparse", action="store_true", help="also time scipy's sparse LU")
    args = parser.parse_args()
    sim, pressure = build(args.n)
    solid, state0 = sim.solid, sim.state
    mode0 = solid._mode.copy()
    lines = len(solid._chains.chain_axis)

    def reset() -> object:
        state = copy.deepcopy(state0)
        solid._mode[:] = mode0
        solid.geometric_apertures[:] = state0.apertures
        solid._seen[:] = 0.0
        solid._load[:] = 0.0
        solid.n_removed = 0
        solid.chains_solved = 0
        return state

    def disc() -> float:
        state = reset()
        t0 = time.perf_counter()
        solid.update(state, pressure)
        return time.perf_counter() - t0

    # one more pore drains at the edge of the disc: the typical update of a run
    edge = int(np.flatnonzero((pressure == 0) & np.roll(pressure > 0, 1))[0])
    after = pressure.copy()
    after[edge] = 2.0

    def one_pore() -> float:
        state = reset()
        solid.update(state, pressure)
        solved_before = solid.chains_solved
        t0 = time.perf_counter()
        solid.update(state, after)
        elapsed = time.perf_counter() - t0
        one_pore.lines = solid.chains_solved - solved_before  # type: ignore[attr-defined]
        return elapsed

    disc(), one_pore()  # compile
    disc_times = [disc() for _ in range(args.repeat)]
    print(
        f"n = {args.n}: update under a new pressure disc (radius 0.2 L): "
        f"{1e3 * statistics.median(disc_times):.2f} ms median of {args.repeat} "
        f"(min {1e3 * min(disc_times):.2f} ms); {solid.chains_solved} of {lines} lines solved, "
        f"{solid.n_removed} springs open, {solid.contact_iterations} contact iterations at most"
    )
    pore_times = [one_pore() for _ in range(args.repeat)]
    print(
        f"  update after one more drained pore: {1e3 * statistics.median(pore_times):.2f} ms "
        f"median of {args.repeat}; {one_pore.lines} lines solved"  # type: ignore[attr-defined]
    )
    if args.sparse:
        from porenet.kinds.hertz.kernels import springs as mk

        h, force = state0.spring_compression, state0.spring_force
        load = np.zeros_like(solid._xy)
        mk.pressure_loads(pressure, solid._pair_pore, solid._pair_particle, solid._pair_dir,
                          1.0, load)  # fmt: skip
        k_c = solid.config.cohesion * solid.k0

        law = mk.ContactLaw(solid.modulus, k_c, solid.k0, 0.0, True, 50)

        def sparse() -> None:
            mk.solve_sparse(solid._springs, solid._axis, solid._fixed, load,
                            mk.SpringState(h, force, mode0.copy()), law)  # fmt: skip

        sparse_times = timed(sparse, 3)
        print(
            f"  sparse LU (SuperLU, same contact iteration): "
            f"{statistics.median(sparse_times):.2f} s median of 3"
        )


if __name__ == "__main__":
    main()
