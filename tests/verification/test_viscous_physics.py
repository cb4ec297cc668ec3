"""Dynamic viscous drainage (kind "viscous"): conservation, the imposed rate, the quasi-static
(invasion percolation) limit, trapping without special-casing, hard parameter corners, unit
scaling, determinism, the run file and the meniscus bookkeeping.

All runs are small (n <= 30) so that the file runs in seconds; the physics claims are those of
docs/model.md ("Dynamic viscous drainage") and docs/model.md section 4.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

import porenet
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

GAMMA = 0.07  # N/m, the default interfacial tension
MU = 1e-3  # Pa s, the default viscosity
A = 1e-7  # m, pore size of the scenes below
P_SCALE = GAMMA / A  # capillary pressure scale gamma / a (Pa)
T_SCALE = MU * A / GAMMA  # viscous time scale mu a / gamma (s)
ELL0 = 2.0  # length of a new meniscus (units of a)
#: Menisci that land within this length of 0 in the same step drain together (kernel tie rule),
#: so their length is at most this, not exactly 0.
TIE = 1e-12 * ELL0


def scene(n=30, seed=1, disorder=0.3, at="breakthrough", pore_size=A, **fluid):
    return {
        "seed": seed,
        "lattice": {"n": n, "disorder": disorder, "pore_size": pore_size},
        "fluid": {"kind": "viscous", "integrator": "explicit", **fluid},
        "stop": {"at": at},
    }


# -- 1. volume balances ------------------------------------------------------------------------

BALANCE_CASES = {
    "rate-pore": {"capillary_number": 1e-2},
    "rate-drained": {"capillary_number": 1e-2, "reservoir": "drained"},
    "pressure": {"control": "pressure", "injection_pressure": 2.2 * P_SCALE},
    "ramp": {"control": "ramp", "ramp_rate": 1e-2 * P_SCALE / T_SCALE},
    "latching-rate-pore": {"capillary_number": 1e-3, "meniscus": "latching"},
    "latching-rate-drained": {
        "capillary_number": 1e-2,
        "meniscus": "latching",
        "reservoir": "drained",
    },
    "latching-pressure": {
        "control": "pressure",
        "injection_pressure": 2.2 * P_SCALE,
        "meniscus": "latching",
    },
    "latching-ramp": {
        "control": "ramp",
        "ramp_rate": 1e-2 * P_SCALE / T_SCALE,
        "meniscus": "latching",
    },
}


@pytest.mark.parametrize("case", list(BALANCE_CASES))
def test_volume_balances_close_to_round_off(case):
    """injected = drained + stored in the reservoir; drained = stored in the defender +
    outflow + released; so injected = stored + outflow + released at every drainage event.

    Every flux is computed once and booked on both sides, so the residuals are sums of
    O(steps) round-off errors of O(1e-16) relative: ~1e-13 for the ~1e3-1e4 steps here.
    1e-10 leaves three decades of margin and still catches any lost flux term (a single
    missed step is ~1e-3 of the total).
    """
    n = 30
    sim, result = cached_run(scene(n=n, max_steps=10**6, **BALANCE_CASES[case]))
    invader, defender = sim.fluid.balance_errors()
    assert invader < 1e-10 and defender < 1e-10
    assert result.summary["volume_balance_error"] < 1e-10

    ts = sim.fluid.timeseries()
    injected = ts["injected"]
    residual = injected - ts["stored"] - ts["outflow"] - ts["released"]
    assert np.all(np.abs(residual) <= 1e-10 * injected)
    assert len(injected) == result.summary["n_drained"] and injected[-1] > 0

    # signs and monotonicity of the cumulative terms: the defender only leaves through the
    # outlet (p >= 0 there), drainage releases non-negative storage, time runs forward
    for name in ("time", "injected", "outflow", "released", "n_drained"):
        assert np.all(np.diff(ts[name]) >= 0), name
    assert np.all(ts["outflow"] >= 0) and np.all(ts["released"] >= 0)
    np.testing.assert_array_equal(ts["n_drained"], np.arange(1, len(injected) + 1))

    cfg = sim.fluid.config
    if cfg.control == "rate":
        # the pump delivers exactly Q = Ca A_b, with A_b = 4 L a for centre injection
        assert sim.fluid.cross_section == 4 * n
        v = sim.fluid.volumes()
        q = cfg.capillary_number * 4 * n
        np.testing.assert_allclose(v["injected"], q * v["time"], rtol=1e-12)
    elif cfg.control == "pressure":
        # fixed p_inv: the reservoir stores nothing, what is injected is what menisci displace
        v = sim.fluid.volumes()
        assert v["stored_reservoir"] == 0.0
        np.testing.assert_allclose(v["injected"], v["drained"], rtol=1e-12)
    else:
        # ramp: the one-pore reservoir (C = c_t V) is charged along the ramp, C p_inv(t)
        v = sim.fluid.volumes()
        c_inj = float(np.mean(sim.lattice.pore_volumes))
        np.testing.assert_allclose(
            v["stored_reservoir"], c_inj * v["invading_pressure"], rtol=1e-12
        )
        np.testing.assert_allclose(
            v["invading_pressure"], cfg.ramp_rate * T_SCALE / P_SCALE * v["time"], rtol=1e-9
        )


# -- 2. the imposed capillary number is achieved --------------------------------------------------


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


# -- 3. Ca -> 0 is invasion percolation with trapping ---------------------------------------------

LIMIT_SEEDS = (0, 1, 2, 3)
LIMIT_N, LIMIT_DISORDER = 20, 0.3


def limit_runs(ca):
    return [
        cached_run(scene(n=LIMIT_N, seed=s, disorder=LIMIT_DISORDER, capillary_number=ca))[1].data
        for s in LIMIT_SEEDS
    ]


def ip_runs():
    out = []
    for s in LIMIT_SEEDS:
        sc = scene(n=LIMIT_N, seed=s, disorder=LIMIT_DISORDER)
        sc["fluid"] = {"kind": "invasion-percolation", "trapping": True}
        out.append(cached_run(sc)[1].data)
    return out


def test_small_ca_reproduces_invasion_percolation_with_trapping():
    """At Ca = 1e-5 (n = 20, lambda = 0.3) the pattern at breakthrough is IP's.

    Measured Jaccard overlaps |A & B| / |A | B| with IP-with-trapping at breakthrough, default
    settings: Ca = 1e-5, seeds 0-5: 1, 1, 1, 1, 1, 1 (also Ca = 3e-6, seed 0). At Ca = 3e-5
    the converged dynamic pattern already departs from IP by a near-tie or two (seeds 0 and
    3: 0.938 and 0.985, the same at pressure_step 0.1, 0.01 and 0.001 with safety_factor
    0.2): the pressure that a sliding meniscus builds up in the pore it enters lets a
    neighbouring meniscus with a slightly higher entry pressure start. That pressure vanishes
    with Ca. At Ca = 1e-1 the mean overlap is ~0.33. 0.95 per seed and 0.98 on the mean leave
    room for one near-tie and fail well before the crossover regime.
    """
    ip = ip_runs()
    low = limit_runs(1e-5)
    high = limit_runs(1e-1)
    for a, b in zip(low, ip, strict=True):
        np.testing.assert_array_equal(a.apertures, b.apertures)  # same disorder realisation
        assert a.order[0] == b.order[0]  # same inlet
    j_low = [pattern_overlap(a.drained, b.drained) for a, b in zip(low, ip, strict=True)]
    j_high = [pattern_overlap(a.drained, b.drained) for a, b in zip(high, ip, strict=True)]
    print(f"overlap with IP: Ca=1e-5 {np.round(j_low, 3)}, Ca=1e-1 {np.round(j_high, 3)}")
    assert min(j_low) >= 0.95
    assert np.mean(j_low) >= 0.98
    # away from the limit the pattern departs from IP: measured mean 0.33 at Ca = 1e-1
    assert np.mean(j_high) < np.mean(j_low) - 0.3


# -- 4. higher Ca, thinner fingers ----------------------------------------------------------------


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


# -- 5. trapping is not special-cased -------------------------------------------------------------


def test_trapped_clusters_arrest_by_their_own_pressure():
    """Fixed invading pressure 2.4 gamma/a (entry pressures 2/r span 1.54-2.86 gamma/a, so 78 %
    of the throats could open), run until nothing moves. Defending clusters cut off from the
    outlet survive: their pressure rose as menisci pushed fluid into them until
    p_inv - p_i <= p_e on every meniscus around them. Pressures obey the discrete maximum
    principle 0 <= p <= p_inv (the outlet is at 0, the only source is p_inv, and the explicit
    step below the stability limit is a convex combination).
    """
    p_inv = 2.4 * P_SCALE
    sc = scene(
        n=30, seed=0, at="complete", control="pressure", injection_pressure=p_inv, max_steps=10**6
    )
    sim, result = simulate(sc)
    data, s = result.data, result.summary
    assert s["stop_reason"] in ("stationary", "complete")
    assert s["breakthrough"]

    p = data.pressure  # Pa; the invader's pressure in drained pores
    trapped, drained = data.trapped, data.drained
    assert np.all(np.isfinite(p))
    assert trapped.sum() > 0 and not (trapped & drained).any()
    np.testing.assert_allclose(p[drained], p_inv, rtol=1e-12)
    # round-off allowance of 1e-12 relative: the pressures are convex combinations
    assert p.max() <= p_inv * (1 + 1e-12)
    assert p.min() >= -1e-12 * p_inv
    assert np.all(p[trapped] > 0) and np.all(p[trapped] < p_inv)
    np.testing.assert_allclose(sim.state.invading_pressure * P_SCALE, p_inv, rtol=1e-12)
    np.testing.assert_allclose(data.timeseries["invading_pressure"], p_inv, rtol=1e-12)

    # every meniscus is arrested: p_inv - p_i <= p_e = 2 gamma / r (scaled: 2 / r)
    undrained_pore, entry, excess = frontier_menisci(data, p_inv, P_SCALE)
    assert np.all(excess <= 1e-9)  # 1e-9: round-off of the SI <-> scaled conversion
    # and some menisci into trapped clusters are held only by the cluster's raised pressure:
    # at zero defender pressure they would have entered (p_e < p_inv)
    into_trapped = trapped[undrained_pore]
    held = into_trapped & (entry < p_inv / P_SCALE)
    assert held.sum() > 0
    stored = (data.pressure[trapped] / P_SCALE).sum()  # c_V = 1: stored volume (a^3)
    assert stored > 0


# -- 6. hard cases stay finite and finish ---------------------------------------------------------

HARD_CASES = {
    "lambda=0.01": (scene(n=30, disorder=0.01, capillary_number=1e-2), "breakthrough"),
    "lambda=0.95": (scene(n=30, disorder=0.95, capillary_number=1e-2), "breakthrough"),
    "Ca=1e-1": (scene(n=30, capillary_number=1e-1), "breakthrough"),
    "Ca=1": (scene(n=30, capillary_number=1.0), "breakthrough"),
    # the smallest Ca that runs in a few seconds: ~2.2e6 steps at n = 10 (~2 s here)
    "Ca=1e-6": (scene(n=10, capillary_number=1e-6), "breakthrough"),
    # explicit steps grow like 1/Ca: ~1.3e7 steps for one drained pore at n = 3 (~6 s here)
    "Ca=1e-7": (scene(n=3, capillary_number=1e-7, max_steps=5 * 10**7), "breakthrough"),
    **tiny_lattice_cases(scene, 1e-2, 3 * P_SCALE),
}


@pytest.mark.parametrize("case", list(HARD_CASES))
def test_hard_cases_stay_finite_and_finish(case):
    sc, reason = copy.deepcopy(HARD_CASES[case])
    max_steps = sc["fluid"].setdefault("max_steps", 10**7)
    sim, result = simulate(sc)
    assert result.summary["stop_reason"] == reason
    assert_viscous_run_sane(sim, result, max_steps)
    # round-off accumulates with the step count: measured 3.0e-9 after the 1.3e7 steps of
    # Ca = 1e-7 (2e-16 per step: at constant dt the rounding of V/dt * dt/V repeats); a bound
    # of 1e-15 per step (1e-12 at least) still catches any lost flux
    steps = result.summary["time_steps"]
    assert result.summary["volume_balance_error"] < max(1e-15 * steps, 1e-12)
    if sc["lattice"]["n"] == 3:
        assert_tiny_lattice_outcome(result, reason)


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


# -- 7. determinism -------------------------------------------------------------------------------


def test_same_scene_same_run():
    sc = scene(n=30, seed=1, capillary_number=1e-2)
    a = simulate(sc)[1].data
    b = simulate(sc)[1].data
    np.testing.assert_array_equal(a.order, b.order)
    np.testing.assert_array_equal(a.invasion_time, b.invasion_time)
    np.testing.assert_array_equal(a.pressure, b.pressure)
    for name, values in a.timeseries.items():
        np.testing.assert_array_equal(values, b.timeseries[name], err_msg=name)
    c = simulate(scene(n=30, seed=2, capillary_number=1e-2))[1].data
    assert not np.array_equal(a.apertures, c.apertures)


# -- 8. the run file ------------------------------------------------------------------------------


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


# -- 9. menisci never overshoot -------------------------------------------------------------------

MENISCUS_CASES = {
    "rate-1e-2": {"capillary_number": 1e-2},
    "rate-1e-1": {"capillary_number": 1e-1},
    "pressure": {"control": "pressure", "injection_pressure": 2.2 * P_SCALE},
    "latching-1e-3": {"capillary_number": 1e-3, "meniscus": "latching"},
}


@pytest.mark.parametrize("case", list(MENISCUS_CASES))
def test_menisci_land_exactly_on_zero(case):
    """A meniscus starts at 2a and shrinks to exactly 0, never below; the pore it enters drains
    at that instant. The entry throat of a drained pore is never given a new meniscus (both its
    pores are drained), so its final length is the landing value: 0, or within TIE of 0 for
    menisci that landed together in one step."""
    sim, result = cached_run(scene(n=30, max_steps=10**6, **MENISCUS_CASES[case]))
    data, ell = result.data, sim.state.meniscus_length
    assert np.all(ell >= 0) and np.all(ell <= ELL0)

    entered = data.throat >= 0
    assert entered.sum() == len(data.order) - 1  # one inlet
    via = data.throat[entered]
    assert np.all(ell[via] <= TIE)

    # each pore was entered from a pore drained before it
    step = np.full(data.n_pores, -1)
    step[data.order] = np.arange(len(data.order))
    tp = data.throat_pores[via]
    other = np.where(tp[:, 0] == data.order[entered], tp[:, 1], tp[:, 0])
    assert np.all((tp[:, 0] == data.order[entered]) | (tp[:, 1] == data.order[entered]))
    assert np.all((step[other] >= 0) & (step[other] < step[data.order[entered]]))

    # frontier menisci (drained -> undrained) are somewhere in their throat
    drained = data.drained
    frontier = drained[data.throat_pores[:, 0]] != drained[data.throat_pores[:, 1]]
    assert np.all((ell[frontier] > 0) & (ell[frontier] <= ELL0))


def swept_volume(sim, data):
    """Sum over throats of A (2 - l): each throat carries at most one meniscus in a run (it
    appears when the first of its pores drains and is frozen when the second drains), so this
    is the volume all menisci have swept."""
    c_area, _ = sim.lattice.throat_factors
    area = c_area * (data.apertures / A) ** 2
    return float(np.sum(area * (ELL0 - sim.state.meniscus_length)))


SWEPT_CASES = [
    pytest.param({"capillary_number": 1e-3}, 1, id="rate-1e-3"),
    pytest.param({"capillary_number": 1e-2, "reservoir": "drained"}, 1, id="rate-drained"),
    pytest.param({"capillary_number": 1e-2}, 0, id="rate-1e-2-seed0"),
    pytest.param({"control": "pressure", "injection_pressure": 2.2 * P_SCALE}, 1, id="pressure"),
    pytest.param({"control": "ramp", "ramp_rate": 1e-2 * P_SCALE / T_SCALE}, 1, id="ramp"),
    pytest.param(
        {"capillary_number": 1e-2},
        1,
        id="rate-1e-2-seed1",
    ),
    pytest.param(
        {"capillary_number": 1.0},
        0,
        id="rate-1",
    ),
]


@pytest.mark.parametrize(("fluid", "seed"), SWEPT_CASES)
def test_displaced_volume_is_the_volume_swept_by_menisci(fluid, seed):
    """No overshoot in volume terms: the defender volume the menisci displaced (their fluxes
    integrated over time, volumes()["drained"]) equals the throat volume they swept, sum A (2 -
    l), to round-off. A meniscus clamped at l = 0 after its flux carried it further would show
    up here as swept < displaced. rtol 1e-12: both sides are sums of ~1e2-1e4 terms of O(1)."""
    sim, result = cached_run(scene(n=30, seed=seed, max_steps=10**6, **fluid))
    displaced = sim.fluid.volumes()["drained"]
    np.testing.assert_allclose(swept_volume(sim, result.data), displaced, rtol=1e-12)


# -- latching menisci under rate control (once stalled: a meniscus 1 ulp below p_inv) --


def test_latching_rate_control_reaches_breakthrough():
    # the threshold rule needs ~400-600 steps for this run; 5000 makes a stalled run fail fast
    max_steps = 5000
    sc = scene(n=30, seed=0, capillary_number=1e-1, meniscus="latching", max_steps=max_steps)
    sim, result = simulate(sc)
    assert result.summary["stop_reason"] == "breakthrough"
    assert_viscous_run_sane(sim, result, max_steps)
