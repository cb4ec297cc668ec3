"""Local time steps of the RKC integrator (``local_steps``): fine steps in a window around the
moving menisci, one long coarse step elsewhere (:mod:`porenet.kinds.viscous.kernels.multirate`).

The scheme must keep every property of the single-rate integrator it speeds up. What is
specific to it is here: the pattern and the times are the single-rate run's, ``auto`` takes
local steps only where they pay, and results do not depend on the threads. The checks every
integrator shares (volumes balance to round-off, menisci land exactly, the
invasion-percolation limit, hard cases finish, runs are deterministic) are in
``test_viscous_integrators.py``, for local steps with the ids ``[rkc-local-...]``; it builds
its scenes as ``scene`` below does and takes macro steps under the same rule, so
``cached_run`` shares the runs both files make. The scenes are small (n <= 64) with
``local_steps = "on"`` (``"auto"`` takes local steps only on active boxes of at least
200 x 200 pores, where they pay), so that the file runs in seconds.
"""

from __future__ import annotations

import numpy as np
import pytest

from porenet.kinds.viscous.local_steps import LocalSteps
from porenet.testing.runs import cached_run, pattern_overlap, simulate

A = 1e-7  # m


@pytest.fixture(autouse=True)
def macro_steps_whatever_they_cost(monkeypatch):
    """On these small lattices the cost model (rightly) prefers single-rate steps; the tests
    are about the macro steps, so they are taken wherever a window fits (at Ca <= 1e-6 this is
    many times slower than single-rate steps here, so those scenes are the smallest)."""
    monkeypatch.setattr(LocalSteps, "gain", float("inf"))


def scene(n=40, seed=1, disorder=0.3, at="breakthrough", max_drained=None, **fluid):
    stop = {"at": at}
    if max_drained is not None:
        stop["max_drained"] = max_drained
    return {
        "seed": seed,
        "lattice": {"n": n, "disorder": disorder, "pore_size": A},
        "fluid": {"kind": "viscous", "integrator": "rkc", "local_steps": "on", **fluid},
        "stop": stop,
        "classifier": {"kind": "none"},
    }


def single_rate(sc: dict) -> dict:
    out = {**sc, "fluid": {**sc["fluid"], "local_steps": "off"}}
    return out


#: The scenes compared with single-rate steps (the first two balance cases of
#: test_viscous_integrators.py, so the runs are shared). The meniscus rule "latching" (its
#: third balance case) is left out: with it a single-rate run at tolerance 1e-2 and one at
#: 1e-4 already differ by 22 % in pattern (n = 40, Ca = 1e-5, seed 3), so no pore-for-pore
#: agreement is to be expected.
CASES = {
    "Ca=1e-5": scene(capillary_number=1e-5),
    "Ca=1e-4": scene(capillary_number=1e-4, seed=2),
}


@pytest.mark.parametrize("case", list(CASES))
def test_same_pattern_and_times_as_single_rate_steps(case):
    """The pattern at breakthrough is the single-rate run's, pore for pore, and so is the order
    of drainage; every drainage time agrees to 1e-3 of the breakthrough time and the final
    pressures to the tolerance (0.01 of the entry-pressure spread). Measured: identical
    orders, times within 2e-5, pressures within 0.2 of the tolerance."""
    sim, result = cached_run(CASES[case])
    ref_sim, ref = cached_run(single_rate(CASES[case]))
    assert pattern_overlap(result.data.drained, ref.data.drained) == 1.0
    np.testing.assert_array_equal(result.data.order, ref.data.order)
    t, t_ref = result.data.invasion_time, ref.data.invasion_time
    np.testing.assert_allclose(t, t_ref, rtol=0, atol=1e-3 * t_ref[-1])
    undrained = ~(result.data.drained | ref.data.drained)
    scale = sim.fluid.pressure_scale * sim.fluid.config.tolerance
    dp = np.abs(sim.fluid.flow.pressure - ref_sim.fluid.flow.pressure)[undrained].max()
    assert dp < scale


def test_auto_takes_local_steps_only_where_they_pay(monkeypatch):
    """``auto`` keeps single-rate steps on small active boxes (below 200 x 200 pores), and so
    does ``on`` where the cost model predicts no gain; ``off`` never takes local steps."""
    monkeypatch.setattr(LocalSteps, "gain", 0.8)
    for mode in ("auto", "on"):
        _, run = simulate(scene(n=24, capillary_number=1e-5, local_steps=mode))
        assert run.summary["macro_steps"] == 0 and run.summary["single_rate_pores"] > 0, mode
    _, off = simulate(scene(n=24, capillary_number=1e-5, local_steps="off"))
    assert off.summary["local_steps"] is False and "macro_steps" not in off.summary


def test_results_do_not_depend_on_the_threads():
    """The large sweeps run on several threads and take their sums per row, then over the
    rows in order: a run on one thread and on two gives the same drainage order, times,
    pressures and volumes, to the bit (64 x 64, so that the boxes are swept in parallel)."""
    from porenet.jit.threads import configure_threads, thread_setting

    sc = scene(n=64, capillary_number=1e-4, seed=6, max_drained=120)
    before = thread_setting()
    try:
        configure_threads(1)
        sim_1, one = simulate(sc)
        configure_threads(2)
        sim_2, two = simulate(sc)
    finally:
        configure_threads("auto" if before.adaptive else before.most, most=before.most)
    np.testing.assert_array_equal(one.data.order, two.data.order)
    np.testing.assert_array_equal(one.data.invasion_time, two.data.invasion_time)
    np.testing.assert_array_equal(sim_1.fluid.flow.pressure, sim_2.fluid.flow.pressure)
    assert sim_1.fluid.volumes() == sim_2.fluid.volumes()
