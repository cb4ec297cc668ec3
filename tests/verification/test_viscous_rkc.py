"""The stabilised integrator of the viscous model (``integrator = "rkc"``): conservation, exact
landings, agreement with a tight explicit run, the invasion-percolation limit, a cost that
grows far slower than 1/Ca, hard corners, generic lattices, determinism.

IMEX Runge-Kutta-Chebyshev steps with the explicit integrator near landings
(:mod:`porenet.kernels.viscous.rkc`). Scenes are small (n <= 30) so that the file runs in well
under a minute; the helpers mirror ``test_viscous_implicit.py``.
"""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Literal

import numpy as np
import pytest

from porenet.builtin.lattices.square import SquareLattice, SquareLatticeConfig
from porenet.hooks import build_registry, hookimpl
from porenet.simulation import Simulation
from porenet.testing.runs import (
    assert_tiny_lattice_outcome,
    assert_viscous_run_sane,
    cached_run,
    frontier_menisci,
    pattern_overlap,
    simulate,
    tiny_lattice_cases,
)

GAMMA = 0.07  # N/m
MU = 1e-3  # Pa s
A = 1e-7  # m
P_SCALE = GAMMA / A  # gamma / a (Pa)
T_SCALE = MU * A / GAMMA  # mu a / gamma (s)
ELL0 = 2.0  # length of a new meniscus (units of a)


def scene(n=20, seed=1, disorder=0.3, at="breakthrough", integrator="rkc", **fluid):
    return {
        "seed": seed,
        "lattice": {"n": n, "disorder": disorder, "pore_size": A},
        "fluid": {"kind": "viscous", "integrator": integrator, **fluid},
        "stop": {"at": at},
        "classifier": {"kind": "none"},
    }


# -- 1. volume balances ---------------------------------------------------------------------------

BALANCE_CASES = {
    "rate-pore": {"capillary_number": 1e-3},
    "rate-drained": {"capillary_number": 1e-3, "reservoir": "drained"},
    "rate-low-ca": {"capillary_number": 1e-5},
    "pressure": {"control": "pressure", "injection_pressure": 2.2 * P_SCALE},
    "ramp": {"control": "ramp", "ramp_rate": 1e-4 * P_SCALE / T_SCALE},
    "latching-rate": {"capillary_number": 1e-4, "meniscus": "latching"},
}


@pytest.mark.parametrize("case", list(BALANCE_CASES))
def test_volume_balances_close_to_round_off(case):
    """injected = drained + stored in the reservoir, drained = stored + outflow + released, at
    every drainage event. An RKC step is a linear combination of stage fluxes and the volume
    totals follow the same recursion as the pressures, so the balances close to round-off
    (measured 5e-14 to 6e-13 on these runs); 1e-11 catches a lost term (one step is >= 1e-4 of
    the total) and every run takes RKC steps."""
    sim, result = cached_run(scene(**BALANCE_CASES[case]))
    s = result.summary
    assert s["integrator"] == "rkc" and s["rkc_steps"] > 0
    invader, defender = sim.fluid.balance_errors()
    assert invader < 1e-11 and defender < 1e-11
    assert s["volume_balance_error"] < 1e-11
    ts = sim.fluid.timeseries()
    for name in ("time", "injected", "drained", "outflow", "released", "n_drained"):
        assert np.all(np.diff(ts[name]) >= 0), name
    v = sim.fluid.volumes()
    cfg = sim.fluid.config
    if cfg.control == "rate":  # the pump delivers exactly Q t, Q = Ca 4 n
        np.testing.assert_allclose(v["injected"], cfg.capillary_number * 80 * v["time"], rtol=1e-12)
    elif cfg.control == "pressure":
        assert v["stored_reservoir"] == 0.0
        np.testing.assert_allclose(v["injected"], v["drained"], rtol=1e-12)
    else:
        np.testing.assert_allclose(
            v["invading_pressure"], cfg.ramp_rate * T_SCALE / P_SCALE * v["time"], rtol=1e-9
        )


# -- 2. menisci land exactly ----------------------------------------------------------------------


@pytest.mark.parametrize("ca", [1e-3, 1e-5])
def test_menisci_land_exactly_and_never_overshoot(ca):
    """Drain one pore per call of advance(): after every drainage event no meniscus is below 0,
    each drained pore's entry meniscus is exactly 0 (landings are the explicit integrator's,
    located on l = 0), and the volume the menisci swept is the drained volume."""
    sim = Simulation.from_scene(scene(capillary_number=ca))
    state = sim.state
    sim.fluid.setup(state)
    calls = 0
    while not state.breakthrough:
        sim.fluid.advance(state, 1)
        calls += 1
        assert np.all(state.meniscus_length >= 0.0), calls
        assert calls < 2000
    ell = state.meniscus_length
    rec = state.record
    throat = rec.throat[: rec.size]
    via = throat[throat >= 0]
    assert np.all(ell[via] == 0.0)
    c_area, _ = sim.lattice.throat_factors
    area = c_area * (state.apertures / sim.lattice.mean_aperture) ** 2
    swept = float(np.sum(area * (ELL0 - ell)))
    np.testing.assert_allclose(swept, sim.fluid.volumes()["drained"], rtol=1e-10)


# -- 3. the same dynamics as a tight explicit run -------------------------------------------------


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_agrees_with_tight_explicit_run(seed):
    """n = 20, Ca = 1e-4, lambda = 0.3: RKC at its default tolerance against the explicit
    integrator at safety_factor 0.2 and pressure_step 0.01 (the reference of docs/accuracy.md).
    Breakthrough times within 1 % and the same drained set, but for a near-tie reordered."""
    rkc = cached_run(scene(seed=seed, capillary_number=1e-4))[1]
    explicit = cached_run(
        scene(
            seed=seed,
            capillary_number=1e-4,
            integrator="explicit",
            safety_factor=0.2,
            pressure_step=0.01,
        )
    )[1]
    t_r = rkc.data.invasion_time[-1]
    t_e = explicit.data.invasion_time[-1]
    overlap = pattern_overlap(rkc.data.drained, explicit.data.drained)
    print(f"seed {seed}: breakthrough time {t_r / t_e - 1:+.4%}, Jaccard {overlap:.3f}")
    assert abs(t_r / t_e - 1) < 0.01
    assert overlap >= 0.9
    assert rkc.summary["rkc_steps"] > 0
    ca_r = rkc.summary["capillary_number_measured"]
    ca_e = explicit.summary["capillary_number_measured"]
    assert abs(ca_r / ca_e - 1) < 0.01


# -- 4. Ca -> 0 is invasion percolation with trapping ---------------------------------------------


def test_small_ca_is_invasion_percolation_with_trapping():
    """Ca = 1e-6 on 20 x 20 (lambda = 0.3): the drained set at breakthrough is invasion
    percolation's with trapping, pore for pore, for every seed."""
    for s in (0, 1, 2, 3):
        dyn = cached_run(scene(seed=s, capillary_number=1e-6))[1].data
        ip_scene = scene(seed=s)
        ip_scene["fluid"] = {"kind": "invasion-percolation", "trapping": True}
        ip = cached_run(ip_scene)[1].data
        np.testing.assert_array_equal(dyn.drained, ip.drained, err_msg=f"seed {s}")


# -- 5. the cost grows far slower than 1/Ca -------------------------------------------------------


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


# -- 6. hard cases stay finite and finish ---------------------------------------------------------

HARD_CASES = {
    "lambda=0.01": (scene(n=20, disorder=0.01, capillary_number=1e-4), "breakthrough"),
    "lambda=0.95": (scene(n=20, disorder=0.95, capillary_number=1e-4), "breakthrough"),
    "Ca=1": (scene(n=20, capillary_number=1.0), "breakthrough"),
    "Ca=1e-7": (scene(n=20, capillary_number=1e-7), "breakthrough"),
    **tiny_lattice_cases(scene, 1e-4, 3 * P_SCALE),
}


@pytest.mark.parametrize("case", list(HARD_CASES))
def test_hard_cases_stay_finite_and_finish(case):
    sc, reason = copy.deepcopy(HARD_CASES[case])
    sim, result = simulate(sc)
    s = result.summary
    assert s["stop_reason"] == reason
    assert_viscous_run_sane(sim, result)
    # round-off accumulates over the sweeps (as for the explicit integrator, ~1e-16 each)
    sweeps = s["stage_sweeps"] + s["time_steps"]
    assert s["volume_balance_error"] < max(1e-15 * sweeps, 1e-12)
    if sc["lattice"]["n"] == 3:
        assert_tiny_lattice_outcome(result, reason)


def test_trapped_clusters_arrest_under_pressure_control():
    """Fixed p_inv = 2.4 gamma/a on 20 x 20 until nothing moves: trapped defending clusters
    survive, held by their own raised pressure, and every meniscus is at or below its
    threshold (to the step's accuracy)."""
    p_inv = 2.4 * P_SCALE
    sc = scene(n=20, seed=0, at="complete", control="pressure", injection_pressure=p_inv)
    _, result = simulate(sc)
    data = result.data
    assert result.summary["stop_reason"] in ("stationary", "complete")
    p, trapped, drained = data.pressure, data.trapped, data.drained
    assert trapped.sum() > 0 and not (trapped & drained).any()
    assert np.all(p[trapped] > 0) and np.all(p[trapped] < p_inv)
    _, _, excess = frontier_menisci(data, p_inv, P_SCALE)
    assert np.all(excess <= 1e-6)
    assert result.summary["volume_balance_error"] < 1e-11


# -- 7. generic lattices (no canonical grid) ------------------------------------------------------


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


# -- 8. determinism -------------------------------------------------------------------------------


def test_same_scene_same_run():
    sc = scene(n=20, seed=3, capillary_number=1e-4)
    a = simulate(sc)[1]
    b = simulate(sc)[1]
    np.testing.assert_array_equal(a.data.order, b.data.order)
    np.testing.assert_array_equal(a.data.invasion_time, b.data.invasion_time)
    np.testing.assert_array_equal(a.data.pressure, b.data.pressure)
    assert a.summary["time_steps"] == b.summary["time_steps"]


# -- 9. deformable media --------------------------------------------------------------------------


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
