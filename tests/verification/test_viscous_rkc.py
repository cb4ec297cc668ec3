"""The stabilised integrator of the viscous model (``integrator = "rkc"``): what is specific to
it, a cost that grows far slower than 1/Ca, generic lattices (the list sweep) and deformable
media.

IMEX Runge-Kutta-Chebyshev steps with the explicit integrator near landings
(:mod:`porenet.kinds.viscous.kernels.rkc`). The checks every integrator shares (conservation, exact
landings, agreement with a tight explicit run, the invasion-percolation limit, hard corners,
trapped clusters under pressure control, determinism) are in ``test_viscous_integrators.py``,
for this integrator with the ids ``[rkc-...]``; it builds its scenes as ``scene`` below does,
so ``cached_run`` shares the runs both files make. Scenes are small (n <= 40).
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

import numpy as np

from porenet.hooks import build_registry, hookimpl
from porenet.kinds.square.model import SquareLattice, SquareLatticeConfig
from porenet.simulation import Simulation
from porenet.testing.runs import cached_run

A = 1e-7  # m


def scene(n=20, seed=1, disorder=0.3, at="breakthrough", integrator="rkc", **fluid):
    return {
        "seed": seed,
        "lattice": {"n": n, "disorder": disorder, "pore_size": A},
        "fluid": {"kind": "viscous", "integrator": integrator, **fluid},
        "stop": {"at": at},
        "classifier": {"kind": "none"},
    }


# -- 1. the cost grows far slower than 1/Ca -------------------------------------------------------


def test_sweeps_per_drained_pore_grow_far_slower_than_one_over_ca():
    """From Ca = 1e-4 to 1e-6 the explicit integrator needs 100 times more sweeps per drained
    pore (~4/(n Ca)); an RKC step's stages grow like the square root of its length, so RKC
    needs ~10 times more at most (the printout gives the measured ratio). 20 is far below
    100."""
    per_pore = {}
    for ca in (1e-4, 1e-6):
        s = cached_run(scene(capillary_number=ca))[1].summary
        per_pore[ca] = (s["stage_sweeps"] + s["explicit_steps"]) / (s["n_drained"] - 1)
    ratio = per_pore[1e-6] / per_pore[1e-4]
    print(f"sweeps per drained pore {per_pore}, ratio {ratio:.2f}")
    assert ratio < 20


# -- 2. generic lattices (no canonical grid) ------------------------------------------------------


class ListedConfig(SquareLatticeConfig):
    kind: Literal["test.listed"] = "test.listed"  # type: ignore[assignment]


class ListedLattice(SquareLattice):
    """The square lattice without its canonical-grid flag: pores are swept from lists."""

    @property
    def canonical_grid(self) -> bool:
        return False


class ListedPlugin:
    @staticmethod
    @hookimpl
    def porenet_register_lattices(register) -> None:
        register(ListedConfig, ListedLattice)


def test_generic_lattice_runs_and_matches_the_grid():
    """The list sweep of a lattice without a canonical grid against the stencil sweep of the
    same square lattice: same drained set, breakthrough time within 1e-3 (the two activate
    pores differently, so they are not equal to the bit)."""
    registry = build_registry(extra_plugins={"listed": ListedPlugin})
    results = {}
    for kind in ("test.listed", "square"):
        sc = scene(capillary_number=1e-4)
        sc["lattice"]["kind"] = kind
        sim = Simulation.from_scene(sc, registry=registry)
        results[kind] = (sim, sim.run())
    listed, square = results["test.listed"], results["square"]
    assert listed[0].fluid.network.grid_n == 0 and square[0].fluid.network.grid_n > 0
    np.testing.assert_array_equal(listed[1].data.drained, square[1].data.drained)
    t_l, t_s = listed[1].data.invasion_time[-1], square[1].data.invasion_time[-1]
    assert abs(t_l / t_s - 1) < 1e-3
    assert listed[1].summary["volume_balance_error"] < 1e-11


# -- 3. deformable media --------------------------------------------------------------------------


def test_deformable_medium_fractures_as_with_the_explicit_integrator():
    """Fig. 5's scene at n = 40, N_f = 10, Ca* = 0.1 (Ca = 2.5e-4; ~120 explicit steps per
    drained pore, so RKC takes long steps between mechanical updates, which see every RKC
    step's pressures): the same drained pores and removed springs as the explicit integrator,
    and a breakthrough time within 1 %."""
    runs = {}
    for integrator in ("explicit", "rkc"):
        sim = Simulation.from_scene(
            Path(__file__).resolve().parents[2] / "examples" / "scenes" / "fig5.toml",
            ["lattice.n=40", "fluid.capillary_number=2.525e-4", "solid.fracturing_number=10",
             f"fluid.integrator={integrator}", "classifier.kind=none"],
        )  # fmt: skip
        runs[integrator] = sim.run()
    res_e, res_r = runs["explicit"], runs["rkc"]
    assert res_r.summary["rkc_steps"] > 0 and res_r.summary["springs_removed"] > 0
    np.testing.assert_array_equal(res_r.data.drained, res_e.data.drained)
    assert res_r.summary["springs_removed"] == res_e.summary["springs_removed"]
    t_r, t_e = res_r.data.invasion_time[-1], res_e.data.invasion_time[-1]
    assert abs(t_r / t_e - 1) < 0.01
    assert res_r.summary["volume_balance_error"] < 1e-11
