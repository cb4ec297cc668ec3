"""The ``front.interface`` observer in real runs: its records are the front of the drained set
at each scheduled count and at the end (its contract, with the run file, determinism and
checkpoints: test_front_contract.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from porenet_front.config import KIND
from porenet_front.front import front_geometry, measure

from porenet.simulation import Simulation

N, PORE_SIZE = 24, 1e-4


def scene(seed: int = 7, at: str = "left-edge", **observer) -> dict:
    return {
        "seed": seed,
        "lattice": {"kind": "square", "n": N, "disorder": 0.3, "pore_size": PORE_SIZE},
        "injection": {"at": at},
        "fluid": {"kind": "invasion-percolation"},
        "observers": [{"kind": KIND, "every": 0.04, **observer}],
        "stop": {"at": "breakthrough"},
        "classifier": {"kind": "none"},
    }


@pytest.fixture(scope="module")
def run(reg):
    sim = Simulation.from_scene(scene(), registry=reg)
    return sim, sim.run()


def test_records_are_the_front_of_the_drained_set_at_each_count(run):
    """Rebuild the drained set at each recorded count from the run's drainage order and
    measure it again: the observer saw exactly those states."""
    sim, result = run
    records = result.data.observers[KIND]
    geometry = front_geometry(sim.lattice, "left-edge")
    order = result.data.order
    assert len(records["n_drained"]) >= 5
    for k, count in enumerate(records["n_drained"]):
        drained = np.zeros(sim.lattice.n_pores, dtype=bool)
        drained[order[:count]] = True
        front = measure(geometry, drained)
        assert records["menisci"][k] == front.menisci
        assert records["front_menisci"][k] == front.front_menisci
        assert records["front_position"][k] == front.position * PORE_SIZE
        assert records["front_width"][k] == front.width * PORE_SIZE
        assert records["extent"][k] == front.extent * PORE_SIZE
        # IP: the pressure at count k is the threshold of the step that drained pore k
        assert records["invading_pressure"][k] == result.data.invasion_pressure[count - 1]


def test_records_follow_the_schedule_and_grow(run):
    _, result = run
    records = result.data.observers[KIND]
    counts = records["n_drained"]
    step = math.ceil(0.04 * N * N)
    assert np.all(np.diff(counts) > 0)
    assert np.all(counts[:-1] % step == 0)  # scheduled records, then the final state
    assert step == N  # ceil(23.04): the N inlets reach the first count, recorded at the start
    assert counts[0] == step
    assert np.all(np.diff(records["extent"]) >= 0)  # the drained set only grows
    assert np.all(records["time"] == 0)  # quasi-static
    # the front is among the menisci, and lies between the inlet and the tip
    assert np.all(records["front_menisci"] <= records["menisci"])
    assert np.all(records["front_position"] <= records["extent"] + PORE_SIZE)


def test_final_record_is_the_final_state(run):
    sim, result = run
    records, state = result.data.observers[KIND], sim.state
    front = measure(front_geometry(sim.lattice, "left-edge"), state.drained)
    assert records["n_drained"][-1] == state.n_drained == result.data.summary["n_drained"]
    assert records["invading_pressure"][-1] == state.invading_pressure * sim.scales.pressure
    assert records["menisci"][-1] == front.menisci
    assert records["front_menisci"][-1] == front.front_menisci
    assert records["front_position"][-1] == front.position * PORE_SIZE
    # breakthrough: the tip touches the outlet column, 2 (N - 1) pore sizes from the inlets
    assert result.data.summary["stop_reason"] == "breakthrough"
    assert records["extent"][-1] == pytest.approx(2 * (N - 1) * PORE_SIZE, rel=1e-15)


def test_another_seed_gives_other_records(reg, run):
    _, first = run
    other = Simulation.from_scene(scene(seed=8), registry=reg).run().data.observers[KIND]
    assert not np.array_equal(other["front_position"], first.data.observers[KIND]["front_position"])


def test_injection_at_the_centre_measures_radii(reg):
    sim = Simulation.from_scene(scene(at="centre", every=0.1), registry=reg)
    records = sim.run().data.observers[KIND]
    front = measure(front_geometry(sim.lattice, "centre"), sim.state.drained)
    assert records["front_position"][-1] == front.position * PORE_SIZE
    # breakthrough at the outer edge: the tip is at least half the lattice from the centre
    assert records["extent"][-1] >= (N - 1) * PORE_SIZE


def test_a_record_is_not_repeated_when_the_run_ends_on_a_scheduled_count(reg):
    data = scene(every=0.04)
    data["stop"] = {"at": "complete", "max_drained": 3 * math.ceil(0.04 * N * N)}
    records = Simulation.from_scene(data, registry=reg).run().data.observers[KIND]
    step = math.ceil(0.04 * N * N)
    np.testing.assert_array_equal(records["n_drained"], [step, 2 * step, 3 * step])
