"""The implicit integrator of the viscous model (``integrator = "implicit"``): what is specific
to it, a cost that does not grow like 1/Ca, and the ``auto`` choice of integrator named in the
summary.

Backward Euler over all undrained pores with sliding menisci and located events
(:mod:`porenet.kinds.viscous.implicit_steps`). The checks every integrator shares
(conservation, exact landings, agreement with a tight explicit run, the invasion-percolation
limit, hard corners, trapped clusters under pressure control, determinism) are in
``test_viscous_integrators.py``, for this integrator with the ids ``[implicit-...]``; it builds
its scenes as ``scene`` below does, so ``cached_run`` shares the runs both files make. Scenes
are small (n <= 20).
"""

from __future__ import annotations

from porenet.simulation import Simulation
from porenet.testing.runs import cached_run

A = 1e-7  # m


def scene(n=20, seed=1, disorder=0.3, at="breakthrough", integrator="implicit", **fluid):
    return {
        "seed": seed,
        "lattice": {"n": n, "disorder": disorder, "pore_size": A},
        "fluid": {"kind": "viscous", "integrator": integrator, **fluid},
        "stop": {"at": at},
    }


# -- 1. the cost does not grow like 1/Ca ----------------------------------------------------------


def test_steps_per_drained_pore_do_not_grow_like_one_over_ca():
    """From Ca = 1e-4 to 1e-6 the explicit integrator needs 100 times more steps per drained
    pore (~4/(n Ca)); the implicit one follows the events, not the pump. Measured on 20 x 20,
    seed 1: see the printout (the ratio is ~1.5); 5 is far below 100."""
    per_pore = {}
    for ca in (1e-4, 1e-6):
        _, result = cached_run(scene(capillary_number=ca))
        s = result.summary
        per_pore[ca] = (s["time_steps"] / (s["n_drained"] - 1), s["factorizations"])
        per_pore[ca] += (s["factorizations"] / (s["n_drained"] - 1),)
    ratio = per_pore[1e-6][0] / per_pore[1e-4][0]
    ratio_f = per_pore[1e-6][2] / per_pore[1e-4][2]
    print(f"steps, factorisations, factorisations per drained pore: {per_pore}")
    print(f"ratios Ca = 1e-6 / 1e-4: steps {ratio:.2f}, factorisations {ratio_f:.2f}")
    assert ratio < 5
    assert ratio_f < 5


# -- 2. the choice of integrator -----------------------------------------------------------------


def test_auto_choice_and_summary_name_the_integrator():
    """'auto' picks from the explicit integrator's steps per drained pore E ~ 2.8 / (Q dt):
    explicit up to 50, rkc beyond, implicit beyond 50 N. At n = 5, Ca = 1e-1, E ~ 9
    (explicit); at n = 20, Ca = 1e-4, E ~ 2000 < 20 000 (rkc); at n = 10, Ca = 1e-6, E ~ 4e5
    > 5000 (implicit)."""
    result = Simulation.from_scene(scene(n=5, capillary_number=1e-1, integrator="auto")).run()
    assert result.summary["integrator"] == "explicit"
    sim = Simulation.from_scene(scene(n=20, capillary_number=1e-4, integrator="auto"))
    assert sim.run().summary["integrator"] == "rkc"
    sim = Simulation.from_scene(
        scene(n=10, capillary_number=1e-6, integrator="auto", max_time=1e-9)
    )
    assert sim.fluid.integrator == "auto"  # resolved at setup
    result = sim.run()
    assert sim.fluid.integrator == "implicit"
    assert result.summary["integrator"] == "implicit"
    result = Simulation.from_scene(scene(n=5, capillary_number=1e-2)).run()
    assert result.summary["integrator"] == "implicit"
    assert result.summary["linear_solves"] >= result.summary["time_steps"] > 0
