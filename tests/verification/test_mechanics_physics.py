"""Deformable media end to end: limits, Eq. 2, fracturing, cohesion, hard cases, records."""

from __future__ import annotations

import math

import numpy as np
import pytest

import porenet
from porenet.analysis.features import longest_straight_run
from porenet.analysis.fractal import mass_radius_dimension
from porenet.analysis.numbers import capillary_number_at
from porenet.core.errors import ConfigError
from porenet.core.plan import make_plan
from porenet.hooks import get_registry
from porenet.io.runfile import read_run

GAMMA, A, LAM, EPS0 = 0.07, 1e-7, 0.1, 0.05


def scene(n=30, fluid=None, seed=1, **solid):
    solid = {"kind": "hertz", **solid} if solid else {"kind": "rigid"}
    return {
        "seed": seed,
        "lattice": {"n": n, "disorder": LAM, "pore_size": A},
        "fluid": fluid or {"kind": "invasion-percolation"},
        "solid": solid,
    }


VISCOUS = {"kind": "viscous", "capillary_number": 1e-2, "integrator": "explicit"}


def test_fracturing_number_from_modulus_matches_eq2():
    modulus = 3e9
    res = porenet.run(scene(n=12, modulus=modulus))
    expected = GAMMA / (LAM * A * modulus * math.sqrt(EPS0))
    assert res.summary["fracturing_number"] == pytest.approx(expected, rel=1e-12)
    assert res.summary["modulus"] == pytest.approx(modulus, rel=1e-12)


def test_modulus_from_fracturing_number_inverts_eq2():
    res = porenet.run(scene(n=12, fracturing_number=0.5))
    expected = GAMMA / (LAM * A * 0.5 * math.sqrt(EPS0))
    assert res.summary["modulus"] == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("fluid", [None, VISCOUS], ids=["ip", "viscous"])
def test_infinite_stiffness_reproduces_the_rigid_run(fluid):
    rigid = porenet.run(scene(n=24, fluid=fluid))
    stiff = porenet.run(scene(n=24, fluid=fluid, fracturing_number=1e-9))
    np.testing.assert_array_equal(stiff.data.order, rigid.data.order)
    np.testing.assert_array_equal(stiff.data.throat, rigid.data.throat)
    assert stiff.summary["springs_removed"] == 0
    np.testing.assert_allclose(stiff.data.final_apertures, rigid.data.apertures, rtol=1e-9)
    if fluid is not None:
        np.testing.assert_allclose(stiff.data.invasion_time, rigid.data.invasion_time, rtol=1e-7)


@pytest.mark.parametrize("fluid", [None, VISCOUS], ids=["ip", "viscous"])
def test_low_fracturing_number_matches_the_rigid_pattern(fluid):
    rigid = porenet.run(scene(n=24, fluid=fluid))
    soft = porenet.run(scene(n=24, fluid=fluid, fracturing_number=0.01))
    overlap = np.count_nonzero(soft.data.drained & rigid.data.drained) / np.count_nonzero(
        soft.data.drained | rigid.data.drained
    )
    assert overlap >= 0.95, overlap


@pytest.mark.parametrize("fluid", [None, VISCOUS], ids=["ip", "viscous"])
def test_high_fracturing_number_opens_straight_segments(fluid):
    n = 30
    rigid = porenet.run(scene(n=n, fluid=fluid))
    frac = porenet.run(scene(n=n, fluid=fluid, fracturing_number=3.0))
    assert frac.summary["springs_removed"] >= 10
    # a straight open segment across two thirds of the lattice, longer than any of the rigid
    # pattern (seeds 1-3 at n = 30: 20-29 pores against 9-19 for the rigid medium)
    straight = longest_straight_run(frac.data.as_grid(frac.data.drained))
    assert straight >= 2 * n // 3
    assert straight > longest_straight_run(rigid.data.as_grid(rigid.data.drained))
    removed = frac.data.mechanics_final["removed_springs"]
    assert removed.sum() == frac.summary["springs_removed"]


def fig5_shape(n, seed, nf, foundation):
    """Fig. 5's conditions (Ca* = 10, lambda = 0.1, viscous) at n: the run's summary, its
    mass-radius D_f (radii 2a to 0.35 L, as examples/scripts/fig5.py) and its longest straight
    drained run."""
    fluid = {"kind": "viscous", "capillary_number": capillary_number_at(10.0, n, LAM)}
    res = porenet.run(
        scene(n=n, fluid=fluid, seed=seed, fracturing_number=nf, foundation=foundation)
    )
    data = res.data
    xy = data.pore_coords / data.pore_size
    d_f, _, _ = mass_radius_dimension(data.drained, xy, xy[data.order[0]], 4.0, 0.35 * 2 * n)
    return res.summary, d_f, longest_straight_run(data.as_grid(data.drained))


@pytest.mark.parametrize("seed", [1, 2])
def test_a_local_elastic_response_branches_the_fractures(seed):
    """Fig. 5's conditions at n = 64 (Ca* = 10, lambda = 0.1, N_f = 10): the paper's lattice
    (no foundation) opens four straight cracks from the inlet along the axes, D_f ~ 1.0; with
    a foundation of K_0 the fractures branch, D_f 1.42 +- 0.014 over seeds 1-4 (the paper's FR:
    1.43), and are still fractures (straight open segments across half the lattice)."""
    n = 64
    d_f = {}
    for foundation in (0.0, 1.0):
        summary, d_f[foundation], straight = fig5_shape(n, seed, 10.0, foundation)
        assert straight >= n // 2
        assert summary["foundation"] == foundation
    assert d_f[0.0] < 1.1 and d_f[1.0] > 1.3, d_f


def test_a_weak_foundation_keeps_the_crossover_near_nf_1():
    """Fig. 5's conditions at n = 64 with k_f = 0.02 K_0, the foundation docs/paper.md picks so
    that fracturing still sets in at N_f ~ 1 (it does so at n = 400, between N_f = 1 and 2 on
    two seeds): N_f = 1 fingers (D_f 1.63 here, a few opened throats inside the fingers),
    N_f = 2 opens cracks across the lattice (D_f 1.12). The branching at N_f = 10 needs the
    larger lattice and is not tested here."""
    n = 64
    shape = {nf: fig5_shape(n, 1, nf, 0.02)[1:] for nf in (1.0, 2.0)}
    assert shape[1.0][0] > 1.5 and shape[1.0][1] < n // 2, shape
    assert shape[2.0][0] < 1.3 and shape[2.0][1] >= n // 2, shape


def test_quasi_static_coupling_updates_after_every_drained_pore():
    res = porenet.run(scene(n=20, fracturing_number=1.0, coupling="every-step"))
    assert res.summary["mechanical_updates"] == res.summary["n_drained"] - 1  # inlet excluded
    series = res.data.mechanics_series
    assert np.all(np.diff(series["drained"]) == 1)


@pytest.mark.parametrize("foundation", [0.0, 1.0])
@pytest.mark.parametrize("fluid", [None, VISCOUS], ids=["ip", "viscous"])
def test_results_do_not_depend_on_the_cohesion(fluid, foundation):
    runs = [
        porenet.run(
            scene(n=24, fluid=fluid, fracturing_number=3.0, cohesion=c, foundation=foundation)
        )
        for c in (1e-9, 1e-7, 1e-5)
    ]
    for other in runs[1:]:
        np.testing.assert_array_equal(other.data.order, runs[0].data.order)
        assert other.summary["springs_removed"] == runs[0].summary["springs_removed"]


@pytest.mark.parametrize("foundation", [0.0, 1.0])
@pytest.mark.parametrize("nf", [1e-3, 1e-1, 1e1, 1e3])
def test_hard_fracturing_numbers_stay_finite(nf, foundation):
    for fluid in (None, VISCOUS):
        res = porenet.run(scene(n=16, fluid=fluid, fracturing_number=nf, foundation=foundation))
        assert res.summary["breakthrough"]
        assert np.all(np.isfinite(res.data.final_apertures))
        assert np.all(res.data.final_apertures > 0)
        assert np.all(np.isfinite(res.data.mechanics_final["displacement"]))
        assert res.summary["unsettled_updates"] == 0
        assert res.summary["largest_balance_residual"] < 1e-9 * GAMMA * A


def test_compaction_stops_at_the_aperture_floor_and_is_reported():
    res = porenet.run(scene(n=16, fracturing_number=100.0, aperture_floor=0.9))
    floor = 0.9 * A  # mean aperture = a
    assert res.summary["apertures_at_floor"] > 0
    assert res.data.final_apertures.min() >= floor * (1 - 1e-12)


def test_rigid_plan_builds_no_mechanics_and_hertz_builds_both():
    reg = get_registry()
    rigid = make_plan(porenet.load_scene(scene(n=8)), reg)
    assert not rigid.builds("solid") and not rigid.builds("coupler")
    hertz = make_plan(porenet.load_scene(scene(n=8, fracturing_number=1.0)), reg)
    assert hertz.builds("solid") and hertz.builds("coupler")
    assert hertz.effects["deformation"] and hertz.effects["contact_loss"]
    assert hertz.numbers["fracturing number N_f"] == 1.0
    by_modulus = make_plan(porenet.load_scene(scene(n=8, modulus=3e9)), reg)
    expected = GAMMA / (LAM * A * 3e9 * math.sqrt(EPS0))
    assert by_modulus.numbers["fracturing number N_f"] == pytest.approx(expected, rel=1e-12)
    assert "fracturing number N_f" not in rigid.numbers


def test_run_file_holds_the_solid_records(tmp_path):
    path = tmp_path / "run.h5"
    fluid = {**VISCOUS, "snapshot_saturations": [0.01]}
    porenet.run(scene(n=16, fluid=fluid, fracturing_number=3.0), output=path)
    data = read_run(path)
    m = 2 * 16 * 15
    assert data.final_apertures.shape == (m,)
    assert data.summary["springs_removed"] >= 1
    assert "fracturing_number" in data.summary
    final = data.mechanics_final
    assert final["spring_compression"].shape == (m,) and final["spring_force"].shape == (m,)
    assert final["removed_springs"].dtype == bool
    assert final["displacement"].shape == (17 * 17, 2)
    series = data.mechanics_series
    assert set(series) >= {"time", "removed_springs", "max_aperture_change", "balance_residual"}
    assert np.all(np.diff(series["time"]) >= 0) and series["time"][-1] > 0
    (snap,) = data.snapshots
    assert set(snap.mechanics) == {"apertures", *final}
    assert snap.mechanics["apertures"].shape == (m,)
    assert snap.mechanics["removed_springs"].sum() <= final["removed_springs"].sum()


def test_adaptive_coupling_converges_to_every_step():
    base = {"fracturing_number": 1.0}
    fluid = {**VISCOUS, "capillary_number": 10 * LAM / (1 - LAM**2) / 24}  # Ca* = 10
    ref = porenet.run(scene(n=24, fluid=fluid, coupling="every-step", **base))
    tight = porenet.run(scene(n=24, fluid=fluid, coupling_tolerance=1e-12, **base))
    np.testing.assert_array_equal(tight.data.order, ref.data.order)
    np.testing.assert_allclose(tight.data.invasion_time, ref.data.invasion_time, rtol=1e-9)
    np.testing.assert_allclose(tight.data.final_apertures, ref.data.final_apertures, rtol=1e-9)
    assert ref.summary["springs_removed"] > 0


def test_implicit_integrator_follows_deformation():
    def run(integrator, **solid):
        fluid = {"kind": "viscous", "capillary_number": 1e-4, "integrator": integrator}
        return porenet.run(scene(n=20, fluid=fluid, **solid))

    rigid = run("implicit")
    stiff = run("implicit", fracturing_number=1e-9)
    np.testing.assert_array_equal(stiff.data.order, rigid.data.order)
    np.testing.assert_allclose(stiff.data.invasion_time, rigid.data.invasion_time, rtol=1e-9)
    soft_implicit = run("implicit", fracturing_number=3.0)
    soft_explicit = run("explicit", fracturing_number=3.0)
    assert soft_implicit.summary["springs_removed"] > 0
    np.testing.assert_array_equal(soft_implicit.data.drained, soft_explicit.data.drained)
    t_i, t_e = soft_implicit.data.invasion_time[-1], soft_explicit.data.invasion_time[-1]
    assert t_i == pytest.approx(t_e, rel=0.03)  # both integrators at their default accuracy
    assert soft_implicit.summary["volume_balance_error"] < 1e-12


@pytest.mark.parametrize(
    ("solid", "message"),
    [
        ({"modulus": 1e9, "fracturing_number": 1.0}, "exactly one of 'modulus'"),
        ({}, "exactly one of 'modulus'"),
        ({"fracturing_number": 1.0, "cohesion": 0.5}, "solid.cohesion"),
        ({"fracturing_number": 1.0, "prestrain": 1.5}, "solid.prestrain"),
        ({"fracturing_number": 1.0, "foundation": -1.0}, "solid.foundation"),
    ],
)
def test_bad_solid_configs_name_the_field(solid, message):
    with pytest.raises(ConfigError, match=message):
        porenet.load_scene({**scene(n=8), "solid": {"kind": "hertz", **solid}})


def test_fracturing_number_needs_the_lattice_disorder(tmp_path):
    path = tmp_path / "apertures.npz"
    np.savez(path, apertures=np.full(2 * 8 * 7, A))
    sc = scene(n=8, fracturing_number=1.0)
    sc["lattice"] = {"n": 8, "pore_size": A, "apertures_file": str(path)}
    with pytest.raises(ConfigError, match="needs the lattice's 'disorder'"):
        porenet.run(sc)
