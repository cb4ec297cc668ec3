"""Dynamic viscous drainage (kind "viscous") with the explicit integrator: the imposed rate is
achieved, higher Ca gives thinner fingers, units scale out, the run file, and latching menisci
under rate control.

The checks every integrator shares (volume balances, exact landings and the swept volume, the
invasion-percolation limit, hard parameter corners, trapped clusters under pressure control,
determinism) are in ``test_viscous_integrators.py``, for this integrator with the ids
``[explicit-...]``. Runs are small (n <= 30, n = 128 for the slow finger test); the physics
claims are those of docs/model.md ("Dynamic viscous drainage") and docs/model.md section 4.
"""

from __future__ import annotations

import numpy as np
import pytest

import porenet
from porenet.simulation import Simulation
from porenet.testing.runs import assert_viscous_run_sane, cached_run, simulate

GAMMA = 0.07  # N/m, the default interfacial tension
MU = 1e-3  # Pa s, the default viscosity
A = 1e-7  # m, pore size of the scenes below


def scene(n=30, seed=1, disorder=0.3, at="breakthrough", pore_size=A, **fluid):
    return {
        "seed": seed,
        "lattice": {"n": n, "disorder": disorder, "pore_size": pore_size},
        "fluid": {"kind": "viscous", "integrator": "explicit", **fluid},
        "stop": {"at": at},
    }


# -- 1. the imposed capillary number is achieved --------------------------------------------------


@pytest.mark.parametrize("ca", [1e-2, 1e-3])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_measured_capillary_number_matches_requested(ca, seed):
    """Ca_measured = mu v / gamma, v = V_drained / (t A_b), within 5 % of the requested Ca.

    The pump delivers Q t exactly; the displaced volume falls short of it only by what the
    one-pore injection reservoir holds, C p_inv ~ 2 a^3, against Q t ~ 1e2 a^3 delivered
    before breakthrough here: a shortfall of ~1 %, measured 0.3-1.1 %. So 5 % is a loose bound
    and the identity below pins the shortfall exactly.
    """
    n = 30
    sim, result = cached_run(scene(n=n, seed=seed, capillary_number=ca))
    s, data = result.summary, result.data
    measured = s["capillary_number_measured"]
    print(f"Ca = {ca:g} seed {seed}: measured {measured:.5g} ({measured / ca - 1:+.2%})")
    assert s["capillary_number"] == ca
    assert abs(measured / ca - 1) < 0.05

    # recomputed from the SI outputs: v = V_drained / (t * 4 L a), L = n a
    ts = data.timeseries
    v = ts["drained"][-1] / (ts["time"][-1] * 4 * n * A * A)
    np.testing.assert_allclose(MU * v / GAMMA, measured, rtol=1e-9)
    np.testing.assert_allclose(ts["capillary_number"][-1], measured, rtol=1e-12)

    # the shortfall is exactly the reservoir's storage: Ca_m / Ca - 1 = -C p_inv / (Q t)
    vol = sim.fluid.volumes()
    np.testing.assert_allclose(
        measured / ca - 1, -vol["stored_reservoir"] / vol["injected"], rtol=1e-9, atol=1e-14
    )


# -- 2. higher Ca, thinner fingers ----------------------------------------------------------------


FINGER_N, FINGER_SEEDS = 128, (0, 1, 2, 3)


def finger_measures(ca_star):
    """Mean finger width and box-counting D_f at breakthrough, per seed (λ = 0.3, n = 128);
    ``ca_star = 0`` is invasion percolation with trapping, the Ca -> 0 limit."""
    from porenet.analysis.features import pattern_features
    from porenet.analysis.fractal import pattern_dimension
    from porenet.analysis.numbers import capillary_number_at

    widths, dims = [], []
    for seed in FINGER_SEEDS:
        sc = scene(n=FINGER_N, seed=seed, disorder=0.3)
        if ca_star == 0:
            sc["fluid"] = {"kind": "invasion-percolation", "trapping": True}
        else:
            sc["fluid"] = {
                "kind": "viscous",
                "capillary_number": capillary_number_at(ca_star, FINGER_N, 0.3),
            }
        data = cached_run(sc)[1].data
        widths.append(pattern_features(data)["finger_width_mean"])
        dims.append(pattern_dimension(data, "box-counting").dimension)
    return np.array(widths), np.array(dims)


@pytest.mark.slow
def test_higher_ca_gives_thinner_fingers_and_a_lower_fractal_dimension():
    """At fixed λ = 0.3, raising Ca* = Ca (L/a) / [λ/(1-λ²)] through the CF/VF line (Ca* = 1)
    thins the fingers and lowers D_f (docs/model.md section 6-7).

    Measured (n = 128, seeds 0-3, means ± standard errors; `python
    examples/scripts/fingers_vs_ca.py --n 128 --seeds 4 --ca-star 1 30`): finger width IP
    1.759 ± 0.019, Ca* = 1 1.522 ± 0.020, Ca* = 30 1.191 ± 0.009 pores; box-counting D_f IP
    1.619 ± 0.011, Ca* = 1 1.502 ± 0.010. The margins below are ~5 standard errors. D_f is
    compared at Ca* = 1 only: on a lattice this small, Ca* = 30 grows axis-aligned dendrites
    (the lattice anisotropy the paper notes for weak disorder and high Ca) and its box-counting
    D_f (1.575) rises again; the n = 400 trend is in docs/paper.md (fingers-vs-ca table).
    """
    w_ip, d_ip = finger_measures(0)
    w_1, d_1 = finger_measures(1)
    w_30, _ = finger_measures(30)
    print(f"widths {w_ip.mean():.3f} {w_1.mean():.3f} {w_30.mean():.3f}; D_f {d_ip.mean():.3f} "
          f"{d_1.mean():.3f}")  # fmt: skip
    assert w_ip.mean() > w_1.mean() + 0.1 > w_30.mean() + 0.2
    assert d_1.mean() < d_ip.mean() - 0.05


# -- 3. units scale out --------------------------------------------------------------------------


def test_units_scale_out():
    """a = 1e-8 m and a = 1e-3 m are the same scaled run: same drainage order, times equal in
    units of mu a / gamma and pressures in units of gamma / a. rtol 1e-9 allows the round-off
    of the SI conversion (a single multiply and divide, ~1e-16); the runs agree to ~2e-16."""
    runs = {}
    for a in (1e-8, 1e-3):
        runs[a] = simulate(scene(n=20, seed=2, pore_size=a, capillary_number=1e-2))[1].data
    small, large = runs[1e-8], runs[1e-3]
    np.testing.assert_array_equal(small.order, large.order)
    np.testing.assert_array_equal(small.throat, large.throat)
    t_small = small.invasion_time / (MU * 1e-8 / GAMMA)
    t_large = large.invasion_time / (MU * 1e-3 / GAMMA)
    np.testing.assert_allclose(t_small, t_large, rtol=1e-9)
    np.testing.assert_allclose(
        small.pressure / (GAMMA / 1e-8), large.pressure / (GAMMA / 1e-3), rtol=1e-9, atol=1e-12
    )
    np.testing.assert_allclose(
        small.summary["capillary_number_measured"],
        large.summary["capillary_number_measured"],
        rtol=1e-9,
    )


# -- 4. the run file ------------------------------------------------------------------------------


def test_run_file_round_trip(tmp_path):
    path = tmp_path / "v.h5"
    sc = scene(n=30, seed=1, capillary_number=1e-2, snapshot_saturations=[0.05])
    result = Simulation.from_scene(sc, output=path).run()
    data = porenet.read_run(path)
    n_pores = 30 * 30

    # final pressure: the invader's in drained pores, the defender's (finite, below) elsewhere
    p_inv = result.summary["final_invading_pressure"]
    np.testing.assert_allclose(data.pressure[data.drained], p_inv, rtol=1e-12)
    assert np.all(np.isfinite(data.pressure)) and data.pressure.max() <= p_inv * (1 + 1e-12)
    np.testing.assert_array_equal(data.pressure, result.data.pressure)
    np.testing.assert_array_equal(data.order, result.data.order)
    np.testing.assert_array_equal(data.invasion_time, result.data.invasion_time)

    assert {"time", "invading_pressure"} <= set(data.timeseries)
    np.testing.assert_allclose(data.timeseries["invading_pressure"][-1], p_inv, rtol=1e-12)
    np.testing.assert_allclose(data.timeseries["time"], data.invasion_time, rtol=1e-12)
    for key in ("capillary_number", "capillary_number_measured", "volume_balance_error"):
        assert key in data.summary
        assert data.summary[key] == result.summary[key]
    assert data.summary["capillary_number"] == 1e-2
    assert data.summary["volume_balance_error"] < 1e-10

    assert len(data.snapshots) == 1
    snap = data.snapshots[0]
    assert snap.saturation >= 0.05
    # taken at the first drainage event at or past 5 %: ceil(0.05 * 900) = 45 pores
    assert snap.drained.sum() == 45 and snap.saturation == 45 / n_pores
    assert 0 < snap.time < data.invasion_time[-1]
    np.testing.assert_allclose(snap.pressure[snap.drained], snap.invading_pressure, rtol=1e-12)
    assert np.all(np.isfinite(snap.pressure))
    assert not (snap.drained & ~data.drained).any()  # drainage is irreversible


# -- 5. latching menisci under rate control (once stalled: a meniscus 1 ulp below p_inv) ---------


def test_latching_rate_control_reaches_breakthrough():
    # the threshold rule needs ~400-600 steps for this run; 5000 makes a stalled run fail fast
    max_steps = 5000
    sc = scene(n=30, seed=0, capillary_number=1e-1, meniscus="latching", max_steps=max_steps)
    sim, result = simulate(sc)
    assert result.summary["stop_reason"] == "breakthrough"
    assert_viscous_run_sane(sim, result, max_steps)
