"""Snapshots are an observer (docs/architecture.md, rule 8): its trigger ends the fluid
model's calls at the drained counts and model times asked for; any fluid model can have them
(``[[observers]] kind = "snapshots"``); the viscous model's ``snapshot_*`` fields are a
shorthand for one."""

from __future__ import annotations

import math

import numpy as np

from porenet.core.state import State
from porenet.core.triggers import Schedule
from porenet.simulation import Simulation


def _state(n_drained: int, time: float) -> State:
    state = State.initial(100, np.ones(180))
    state.n_drained, state.time = n_drained, time
    return state


def test_schedule_fires_once_per_count_and_time_in_order() -> None:
    trigger = Schedule(counts=[10, 5], times=[2.0, 1.0])
    assert trigger.events_until_due(_state(3, 0.0)) == 2
    assert trigger.next_time(_state(3, 0.0)) == 1.0
    assert not trigger.fires(_state(4, 0.5))
    assert trigger.fires(_state(5, 0.5)) and not trigger.fires(_state(5, 0.5))
    assert trigger.events_until_due(_state(5, 0.5)) == 5
    assert trigger.fires(_state(6, 1.0 - 1e-14))  # the call ended at the time (round-off)
    assert trigger.next_time(_state(6, 1.0)) == 2.0
    trigger.reset()
    assert trigger.events_until_due(_state(0, 0.0)) == 5


def _viscous(**fluid: object) -> dict:
    return {
        "seed": 2,
        "lattice": {"n": 20, "disorder": 0.3, "pore_size": 1e-7},
        "fluid": {"kind": "viscous", "capillary_number": 1e-3, "integrator": "explicit",
                  **fluid},
        "classifier": {"kind": "none"},
    }  # fmt: skip


def test_snapshots_at_saturations_and_times() -> None:
    """A snapshot at each saturation has exactly ceil(s N) drained pores; one at each time is
    taken at that time (the fluid's steps end there)."""
    data = (
        Simulation.from_scene(_viscous(snapshot_saturations=[0.05, 0.1], snapshot_times=[2e-8]))
        .run()
        .data
    )
    assert len(data.snapshots) == 3
    by_time = sorted(data.snapshots, key=lambda s: s.time)
    counts = sorted(int(s.drained.sum()) for s in data.snapshots)
    assert math.ceil(0.05 * 400) in counts and math.ceil(0.1 * 400) in counts
    assert any(abs(s.time - 2e-8) <= 1e-20 for s in by_time)
    for snap in data.snapshots:  # the invader's pressure in drained pores
        assert np.all(snap.pressure[snap.drained] == snap.invading_pressure)


def test_the_shorthand_and_the_observer_give_the_same_snapshots() -> None:
    short = Simulation.from_scene(_viscous(snapshot_saturations=[0.08])).run().data
    scene = _viscous()
    scene["observers"] = [{"kind": "snapshots", "saturations": [0.08]}]
    table = Simulation.from_scene(scene).run().data
    assert len(short.snapshots) == len(table.snapshots) == 1
    a, b = short.snapshots[0], table.snapshots[0]
    assert a.time == b.time and np.array_equal(a.pressure, b.pressure)
    assert np.array_equal(short.order, table.order)


def test_invasion_percolation_has_snapshots_too() -> None:
    """Any fluid model: invasion percolation records the drained pattern at a saturation."""
    scene = {
        "seed": 1,
        "lattice": {"n": 30, "disorder": 0.3},
        "fluid": {"kind": "invasion-percolation"},
        "stop": {"at": "complete"},
        "observers": [{"kind": "snapshots", "saturations": [0.2, 0.5]}],
        "classifier": {"kind": "none"},
    }
    data = Simulation.from_scene(scene).run().data
    assert [int(s.drained.sum()) for s in data.snapshots] == [180, 450]
