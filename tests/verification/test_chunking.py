"""Where the Simulation's calls into the fluid model end, and how many threads each call uses,
changes no result, to the bit.

The viscous model's calls aim at a wall time (:class:`porenet.jit.threads.CallPace`), so where a
call ends depends on the machine's speed; the threads are chosen per call by measuring
(:class:`porenet.jit.threads.ThreadGovernor`). Both are only admissible if a run's drainage
order, times, pressures and volumes do not depend on them. Each integrator is run with the
calls cut after random numbers of steps (1 to 40) and compared with a run cut nowhere.
"""

from __future__ import annotations

import numpy as np
import pytest

from porenet.jit.jit import set_threads
from porenet.jit.threads import CallPace, ThreadGovernor, configure_threads, thread_setting
from porenet.kinds.viscous.local_steps import LocalSteps
from porenet.simulation import Simulation


def scene(n=36, integrator="rkc", seed=4, **fluid):
    fluid = {"kind": "viscous", "capillary_number": 1e-4, "integrator": integrator, **fluid}
    return {
        "seed": seed,
        "lattice": {"n": n, "disorder": 0.3, "pore_size": 1e-7},
        "fluid": fluid,
        "stop": {"at": "breakthrough"},
        "classifier": {"kind": "none"},
    }


CASES = {
    "explicit": scene(integrator="explicit"),
    "rkc": scene(local_steps="off"),
    "rkc, local time steps": scene(capillary_number=1e-5, local_steps="on"),
    "implicit": scene(n=20, integrator="implicit", capillary_number=1e-5),
    # the run stops at the event that drains the last outlet pore, not where a call ends
    "explicit, to completion": {
        **scene(n=12, integrator="explicit"),
        "stop": {"at": "complete"},
    },
    "rkc, pressure control": scene(
        control="pressure", capillary_number=None, injection_pressure=1.6e6, max_time=2e-6
    ),
}


def _run(sc):
    sim = Simulation.from_scene({**sc, "fluid": {k: v for k, v in sc["fluid"].items()
                                                 if v is not None}})  # fmt: skip
    result = sim.run()
    return sim, result


def _same(a, b):
    (sim_a, ra), (sim_b, rb) = a, b
    np.testing.assert_array_equal(ra.data.order, rb.data.order)
    np.testing.assert_array_equal(ra.data.invasion_time, rb.data.invasion_time)
    np.testing.assert_array_equal(sim_a.fluid.flow.pressure, sim_b.fluid.flow.pressure)
    assert sim_a.fluid.volumes() == sim_b.fluid.volumes()
    assert ra.summary["time_steps"] == rb.summary["time_steps"]


@pytest.fixture(autouse=True)
def macro_steps_whatever_they_cost(monkeypatch):
    """Small lattices: take the macro steps of local time steps wherever a window fits."""
    monkeypatch.setattr(LocalSteps, "gain", float("inf"))


@pytest.mark.parametrize("name", list(CASES))
def test_where_calls_end_changes_nothing(name, monkeypatch):
    with monkeypatch.context() as m:  # every call as long as the model allows
        m.setattr(CallPace, "steps", lambda self, seconds, threads=1: self.most)
        uncut = _run(CASES[name])
    rng = np.random.default_rng(11)
    monkeypatch.setattr(
        CallPace, "steps", lambda self, seconds, threads=1: int(rng.integers(1, 41))
    )
    cut = _run(CASES[name])
    assert cut[1].summary["n_drained"] > 10
    _same(uncut, cut)


def test_switching_threads_between_calls_changes_nothing(monkeypatch):
    """A run whose governor alternates 1 and 2 threads call by call (on a box large enough
    for threads) gives the bits of a run on one thread."""
    sc = scene(n=72, capillary_number=1e-4, local_steps="off")
    sc["stop"] = {"at": "breakthrough", "max_drained": 150}
    before = thread_setting()
    try:
        configure_threads(1)
        one = _run(sc)
        configure_threads("auto", most=2)
        calls = []

        def alternate(self):  # the kernels' threads set directly, 1 and 2 in turn
            count = 1 + len(calls) % 2
            calls.append(count)
            set_threads(count)
            return count

        monkeypatch.setattr(ThreadGovernor, "before_call", alternate)
        monkeypatch.setattr(CallPace, "steps", lambda self, seconds, threads=1: 7)
        mixed = _run(sc)
    finally:
        configure_threads("auto" if before.adaptive else before.most, most=before.most)
    assert {1, 2} <= set(calls) and len(calls) > 20
    _same(one, mixed)
