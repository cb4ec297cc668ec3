"""The frictional solid (kind hertz-mindlin) end to end: its frictionless limit is the Hertzian
solid to the bit, its solvers agree and balance forces to round-off, its stiff limit is the
rigid pattern, hard cases stay finite, and its records and errors (docs/model.md, "Frictional
solid (kind hertz-mindlin)")."""

from __future__ import annotations

import numpy as np
import pytest

import porenet
from porenet.core.errors import ConfigError, NumericalError
from porenet.core.plan import make_plan
from porenet.hooks import get_registry
from porenet.io.runfile import read_run
from porenet.kinds.mindlin.config import HertzMindlinConfig

GAMMA, A, LAM = 0.07, 1e-7, 0.1
VISCOUS = {"kind": "viscous", "capillary_number": 1e-2, "integrator": "explicit"}
RATE = {"capillary_number": 10 * LAM / (1 - LAM**2) / 20}  # Ca* = 10 on n = 20


def scene(n=20, fluid=None, seed=1, kind="hertz-mindlin", **solid):
    solid = {"kind": kind, **solid} if solid else {"kind": "rigid"}
    return {
        "seed": seed,
        "lattice": {"n": n, "disorder": LAM, "pore_size": A},
        "fluid": fluid or {"kind": "invasion-percolation"},
        "solid": solid,
    }


def same_run(a, b) -> None:
    """Two runs drained the same pores in the same order at the same times, to the bit, and
    ended with the same solid."""
    np.testing.assert_array_equal(a.data.order, b.data.order)
    np.testing.assert_array_equal(a.data.final_apertures, b.data.final_apertures)
    if a.data.invasion_time is not None:
        np.testing.assert_array_equal(a.data.invasion_time, b.data.invasion_time)
    for key, value in a.data.mechanics_final.items():
        np.testing.assert_array_equal(b.data.mechanics_final[key], value, err_msg=key)


@pytest.mark.parametrize("fluid", [None, VISCOUS], ids=["ip", "viscous"])
@pytest.mark.parametrize("solver", ["auto", "sparse-direct"])
def test_zero_shear_stiffness_is_the_hertz_solid_to_the_bit(fluid, solver):
    hertz = porenet.run(scene(fluid=fluid, kind="hertz", fracturing_number=3.0, solver=solver))
    frictionless = porenet.run(scene(fluid=fluid, fracturing_number=3.0, solver=solver,
                                     shear_stiffness_ratio=0.0, friction=0.3))  # fmt: skip
    assert hertz.summary["springs_removed"] > 0
    same_run(hertz, frictionless)
    assert frictionless.summary["mechanics_solver"] == hertz.summary["mechanics_solver"]


@pytest.mark.parametrize("fluid", [None, {**VISCOUS, **RATE}], ids=["ip", "viscous"])
def test_multigrid_and_sparse_direct_give_the_same_run(fluid):
    """Solved to round-off, the two solvers drain the same pores in the same order and agree
    on the solid to round-off (the fluid's times too)."""
    runs = {
        solver: porenet.run(
            scene(
                fluid=fluid,
                fracturing_number=3.0,
                shear_stiffness_ratio=0.5,
                solver=solver,
                solver_tolerance=0.0,
            )
        )
        for solver in ("multigrid", "sparse-direct")
    }
    mg, direct = runs["multigrid"], runs["sparse-direct"]
    assert mg.summary["mechanics_solver"] == "multigrid"
    assert direct.summary["mechanics_solver"] == "sparse-direct"
    np.testing.assert_array_equal(mg.data.order, direct.data.order)
    np.testing.assert_allclose(mg.data.final_apertures, direct.data.final_apertures, rtol=1e-9)
    if fluid is not None:
        np.testing.assert_allclose(mg.data.invasion_time, direct.data.invasion_time, rtol=1e-9)
    assert direct.summary["springs_removed"] > 0


@pytest.mark.parametrize(
    "nf, solid",
    [
        (3.0, {"shear_stiffness_ratio": 0.5}),
        (3.0, {"shear_stiffness_ratio": 0.8, "friction": 0.3}),
        (0.3, {"poisson_ratio": 0.25, "rotation": "free"}),
        (0.3, {"shear_stiffness_ratio": 0.3, "friction": 0.1, "rotation": "free"}),
    ],
    ids=["stick", "slide", "rotate", "rotate-slide"],
)
def test_forces_balance_to_round_off_at_every_update(nf, solid):
    """With the solver at round-off and every change of sliding mode solved again
    (``slip_tolerance = 0``), every update leaves every free particle in force (and,
    where particles rotate, torque) balance to round-off: the largest residual of the run,
    relative to the prestress force F_0, is at the level of the solve's round-off (the
    stiffnesses span 1e6: open contacts keep 1e-6 K_0). Free rotations at N_f = 0.3, where
    contacts stay closed: where they open, a particle held on one side rolls freely (no
    rolling resistance) and the run reflects that mechanism (docs/model.md)."""
    res = porenet.run(scene(fluid={**VISCOUS, **RATE}, fracturing_number=nf,
                            solver_tolerance=0.0, slip_tolerance=0.0, **solid))  # fmt: skip
    f0 = _prestress_force(nf)
    residuals = res.data.mechanics_series["balance_residual"]
    assert len(residuals) == res.summary["mechanical_updates"] > 10
    assert residuals.max() <= 1e-9 * f0, residuals.max() / f0
    assert res.summary["unsettled_updates"] == 0
    if nf > 1:
        assert res.summary["springs_removed"] > 0


@pytest.mark.parametrize("rotation", ["held", "free"])
def test_a_slip_tolerance_bounds_the_imbalance_it_leaves(rotation):
    """With the default slip tolerance delta = 1e-2 a, a change between sticking and sliding
    small enough takes effect without another solve: the run needs fewer solves than with
    every change solved, and the force it leaves out of balance on a particle stays below its
    four contacts' K_t delta (K_t taken at twice the prestress stiffness K_0: no contact is
    compressed to four times its prestress here)."""
    nf, ratio, delta = 3.0, 0.8, 1e-2
    solid = {"shear_stiffness_ratio": ratio, "friction": 0.3, "rotation": rotation,
             "solver": "sparse-direct"}  # fmt: skip
    fluid = {**VISCOUS, **RATE}
    runs = {
        slip: porenet.run(scene(fluid=fluid, fracturing_number=nf, slip_tolerance=slip, **solid))
        for slip in (0.0, delta)
    }
    exact, tolerant = runs[0.0], runs[delta]
    assert tolerant.summary["solver_iterations"] < exact.summary["solver_iterations"]
    residual = tolerant.data.mechanics_series["balance_residual"].max()
    assert residual <= 4 * ratio * 2 * _prestress_stiffness(nf) * delta * A
    assert tolerant.summary["sliding_contacts"] > 0


def _prestress_stiffness(nf: float) -> float:
    """K_0 (N/m) of the prestressed contacts at fracturing number N_f (Eq. 2, eps_0 = 0.05)."""
    eps0 = 0.05
    modulus = GAMMA / (nf * LAM * A * eps0**0.5)
    return 2.0 * modulus * (A / 2 * 2 * A * eps0) ** 0.5


def _prestress_force(nf: float) -> float:
    """F_0 (N) of the prestressed contacts at fracturing number N_f (Eq. 2, eps_0 = 0.05)."""
    eps0 = 0.05
    modulus = GAMMA / (nf * LAM * A * eps0**0.5)
    return 4.0 / 3.0 * modulus * (A / 2) ** 0.5 * (2 * A * eps0) ** 1.5


@pytest.mark.parametrize("fluid", [None, VISCOUS], ids=["ip", "viscous"])
def test_stiff_limit_gives_the_rigid_pattern(fluid):
    rigid = porenet.run(scene(n=24, fluid=fluid))
    stiff = porenet.run(scene(n=24, fluid=fluid, fracturing_number=1e-9,
                              shear_stiffness_ratio=0.5, friction=0.3))  # fmt: skip
    np.testing.assert_array_equal(stiff.data.order, rigid.data.order)
    assert stiff.summary["springs_removed"] == 0
    np.testing.assert_allclose(stiff.data.final_apertures, rigid.data.apertures, rtol=1e-9)
    soft = porenet.run(scene(n=24, fluid=fluid, fracturing_number=0.01, shear_stiffness_ratio=0.5))
    overlap = np.count_nonzero(soft.data.drained & rigid.data.drained) / np.count_nonzero(
        soft.data.drained | rigid.data.drained
    )
    assert overlap >= 0.95, overlap


@pytest.mark.parametrize(
    "solid",
    [
        {"fracturing_number": 1e-3, "shear_stiffness_ratio": 0.5},
        {"fracturing_number": 1e3, "shear_stiffness_ratio": 0.5},
        {"fracturing_number": 1e3, "shear_stiffness_ratio": 0.5, "friction": 0.3},
        {"fracturing_number": 10.0, "shear_stiffness_ratio": 1e-3},
        {"fracturing_number": 10.0, "shear_stiffness_ratio": 1.0},
        {"fracturing_number": 10.0, "shear_stiffness_ratio": 0.5, "friction": 1e-6},
        {"fracturing_number": 10.0, "poisson_ratio": 0.25, "rotation": "free", "friction": 1e-6},
        {"fracturing_number": 10.0, "shear_stiffness_ratio": 0.5, "foundation": 0.02},
    ],
    ids=[
        "nf-1e-3",
        "nf-1e3",
        "nf-1e3-slide",
        "ratio-1e-3",
        "ratio-1",
        "mu-1e-6",
        "rotate-mu-1e-6",
        "foundation",
    ],
)
@pytest.mark.parametrize("fluid", [None, VISCOUS], ids=["ip", "viscous"])
def test_hard_cases_stay_finite_and_balanced(solid, fluid):
    """docs/stability.md's hard cases for the frictional solid: extreme N_f, extreme stiffness
    ratios, near-zero friction (almost every contact slides), free rotations: the run reaches
    breakthrough with finite, positive apertures and a balance residual that stays small."""
    res = porenet.run(scene(n=12, fluid=fluid, **solid))
    assert res.summary["breakthrough"]
    apertures = res.data.final_apertures
    assert np.all(np.isfinite(apertures)) and np.all(apertures > 0)
    final = res.data.mechanics_final
    for key in ("displacement", "shear_force", "rotation", "spring_force"):
        assert np.all(np.isfinite(final[key])), key
    # the multigrid's default tolerance (tol = 1e-2 a of deformation) leaves ~K tol out of
    # balance, carried to the next update: the residual stays within 10x that, K the stiffest
    # contact's (at N_f = 1e3 the pressures crush the solid, compressions reach 1e4 a and
    # stiffnesses 100 K_0: a run the summary flags as suspect)
    residual = res.summary["largest_balance_residual"]
    h0 = 2 * 0.05 * A
    squeezed = max(final["spring_compression"].max() / h0, 1.0)
    stiffest = _prestress_stiffness(solid["fracturing_number"]) * squeezed**0.5
    tolerance = HertzMindlinConfig.model_fields["solver_tolerance"].default
    assert residual < 10 * tolerance * A * stiffest
    assert res.summary["unconverged_solves"] == 0


def test_plan_names_the_effects():
    reg = get_registry()
    plan = make_plan(porenet.load_scene(scene(fracturing_number=1.0, poisson_ratio=0.25)), reg)
    assert plan.builds("solid") and plan.builds("coupler")
    assert plan.effects["shear_stiffness"] and not plan.effects["sliding"]
    assert not plan.effects["particle_rotation"]
    sliding = make_plan(porenet.load_scene(scene(fracturing_number=1.0, shear_stiffness_ratio=0.3,
                                                 friction=0.5, rotation="free")), reg)  # fmt: skip
    assert sliding.effects["sliding"] and sliding.effects["particle_rotation"]
    none = make_plan(porenet.load_scene(scene(fracturing_number=1.0, shear_stiffness_ratio=0.0,
                                              friction=0.5)), reg)  # fmt: skip
    assert not none.effects["shear_stiffness"] and not none.effects["sliding"]


def test_run_file_holds_the_frictional_records(tmp_path):
    path = tmp_path / "run.h5"
    porenet.run(scene(n=16, fluid=VISCOUS, fracturing_number=3.0, shear_stiffness_ratio=0.5,
                      friction=0.2), output=path)  # fmt: skip
    data = read_run(path)
    m, particles = 2 * 16 * 15, 17 * 17
    final = data.mechanics_final
    assert final["shear_force"].shape == (m,) and final["slip"].shape == (m,)
    assert final["sliding"].dtype == bool and final["rotation"].shape == (particles,)
    assert np.all(final["rotation"] == 0.0)  # held
    series = data.mechanics_series
    assert {"sliding_contacts", "solver_iterations"} <= set(series)
    summary = data.summary
    assert summary["shear_stiffness_ratio"] == 0.5 and summary["friction"] == 0.2
    assert summary["mechanics_solver"] == "multigrid" and summary["rotation"] == "held"
    assert summary["solver_iterations"] > 0
    # F_0, the scale the carried imbalance is judged by (docs/run-file.md): Eq. 2's contact
    assert summary["prestress_force"] == pytest.approx(_prestress_force(3.0), rel=1e-12)


@pytest.mark.parametrize(
    ("solid", "message"),
    [
        ({"fracturing_number": 1.0}, "exactly one of 'shear_stiffness_ratio'"),
        (
            {"fracturing_number": 1.0, "shear_stiffness_ratio": 0.5, "poisson_ratio": 0.2},
            "both were given",
        ),
        ({"fracturing_number": 1.0, "shear_stiffness_ratio": -0.1}, "solid.shear_stiffness_ratio"),
        ({"fracturing_number": 1.0, "poisson_ratio": 0.7}, "solid.poisson_ratio"),
        (
            {"fracturing_number": 1.0, "shear_stiffness_ratio": 0.5, "friction": -1},
            "solid.friction",
        ),
        (
            {
                "fracturing_number": 1.0,
                "shear_stiffness_ratio": 0.5,
                "rotation": "free",
                "solver": "multigrid",
            },
            "needs rotation = 'held'",
        ),
        (
            {"fracturing_number": 1.0, "shear_stiffness_ratio": 0.5, "solver": "chains"},
            "solid.solver",
        ),
    ],
)
def test_bad_frictional_configs_name_the_field(solid, message):
    with pytest.raises(ConfigError, match=message):
        porenet.load_scene({**scene(n=8), "solid": {"kind": "hertz-mindlin", **solid}})


def test_multigrid_needs_the_square_grid():
    sc = scene(n=8, fracturing_number=1.0, shear_stiffness_ratio=0.5, solver="multigrid")
    sc["lattice"] = {"kind": "network", "file": "tests/data/networks/example.npz"}
    with pytest.raises(ConfigError):
        porenet.run(sc)


def _far_beyond_the_prestress(solver: str) -> dict:
    """Invasion percolation at N_f = 10, lambda = 0.3, sliding, rotations held, n = 40: the
    pressure loads on the inlet's particles are ~30 times the contacts' prestress force."""
    sc = scene(n=40, fracturing_number=10.0, shear_stiffness_ratio=0.5, friction=0.3,
               solver=solver)  # fmt: skip
    sc["lattice"]["disorder"] = 0.3
    sc["stop"] = {"max_drained": 40}
    return sc


@pytest.mark.parametrize("solver", ["multigrid", "sparse-direct"])
def test_contacts_frozen_at_their_kink_keep_particles_apart(solver):
    """Under loads far beyond the prestress, shear makes the contact iteration cycle and
    contacts are frozen for the rest of an update (docs/stability.md, "Frictional contacts").
    Frozen open, as before 2026-12-06, they let particles pass through each other by 1e4 a in
    the second update and the run grew without bound (1e40 a with the sparse direct solver, a
    zero pivot in the multigrid). Frozen re-forming, the run reaches breakthrough with every
    particle within the lattice's width of its place, no open contact left overlapping, and
    the forces balanced."""
    r = porenet.run(_far_beyond_the_prestress(solver))
    assert r.summary["n_drained"] > 3 and r.summary["unsettled_updates"] == 0
    mech = r.data.mechanics_final
    width = 2 * 40  # a
    assert np.abs(mech["displacement"] / A).max() < width
    assert (mech["spring_compression"][mech["removed_springs"]] / A).max() <= 1e-9
    assert r.summary["largest_balance_residual"] <= 1e-9


def test_a_runaway_is_reported_not_returned(monkeypatch):
    """Should an update ever leave a particle a million lattice widths away (injected here
    into the kernel that applies an update), the run stops with a NumericalError naming the
    update, the drained pores and the load against the prestress, never a run file of
    garbage that only looks suspect."""
    from porenet.kinds.mindlin.kernels import frictional as fr

    apply = fr.apply_increments
    calls = []

    def runaway(springs, shear, law, work, du, dtheta, displacement, *rest):
        out = apply(springs, shear, law, work, du, dtheta, displacement, *rest)
        calls.append(1)
        if len(calls) == 3:
            displacement[5, 1] += 1e12
        return out

    monkeypatch.setattr(fr, "apply_increments", runaway)
    with pytest.raises(NumericalError, match=r"runaway displacement .* mechanical update 3 "
                                             r"after \d+ drained pores .* times the contacts' "
                                             r"prestress force"):  # fmt: skip
        porenet.run(_far_beyond_the_prestress("sparse-direct"))
