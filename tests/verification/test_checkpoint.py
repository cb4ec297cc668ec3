"""A run resumed from a checkpoint gives the uninterrupted run's result, to the bit.

Every fluid model, integrator and solid: each scene runs once straight through, and once with
a checkpoint written after a third of its drained pores and the process "crashing" right
after writing it; the checkpoint is loaded and the run finished. Drainage order, throats,
times, invading pressures, final pressures, trapped set, apertures, time series, snapshots and
the summary (wall time aside) must be equal (docs/run-file.md, "Checkpoints"). The real
``kill -9`` of a ``porenet run`` is in tests/unit/test_checkpoint_cli.py.
"""

from __future__ import annotations

import numpy as np
import pytest

from porenet.io.checkpoint import CheckpointSchedule
from porenet.simulation import Simulation
from porenet.testing.runs import Killed, KilledAfterCheckpoint


def scene(fluid: dict, n: int = 24, seed: int = 3, **sections: object) -> dict:
    out = {
        "seed": seed,
        "lattice": {"n": n, "disorder": 0.3, "pore_size": 1e-7},
        "fluid": fluid,
        "stop": {"at": "breakthrough"},
    }
    out.update(sections)
    return out


VISCOUS = {"kind": "viscous", "capillary_number": 1e-4}
IP = {"kind": "invasion-percolation"}
HERTZ = {"kind": "hertz", "fracturing_number": 1.0}
MINDLIN = {"kind": "hertz-mindlin", "fracturing_number": 1.0, "shear_stiffness_ratio": 0.5}

CASES = {
    "viscous, explicit": scene(VISCOUS | {"integrator": "explicit"}),
    "viscous, rkc": scene(VISCOUS | {"integrator": "rkc", "local_steps": "off"}),
    "viscous, rkc, local time steps": scene(
        VISCOUS | {"integrator": "rkc", "local_steps": "on", "capillary_number": 1e-5}, n=32
    ),
    "viscous, implicit": scene(VISCOUS | {"integrator": "implicit"}, n=16),
    "viscous, pressure control, snapshots": scene(
        VISCOUS
        | {
            "control": "pressure",
            "capillary_number": None,
            "injection_pressure": 1.6e6,
            "max_time": 2e-6,
            "snapshot_saturations": [0.05, 0.1],
        }
    ),
    "viscous in a Hertz solid": scene(VISCOUS, solid=HERTZ),
    "invasion percolation in a Hertz solid": scene(IP, solid=HERTZ),
    # the frictional solid keeps its contacts' shear forces, slips and modes and its
    # multigrid hierarchies (reused across updates) in the checkpoint
    "viscous in a frictional solid": scene(VISCOUS, solid=MINDLIN),
    "viscous in a frictional solid with sliding": scene(
        VISCOUS, solid=MINDLIN | {"friction": 0.3, "fracturing_number": 3.0}
    ),
}


def _same(a, b) -> None:  # type: ignore[no-untyped-def]
    """Every field of two runs' data equal (wall and compile time aside)."""
    for name in ("order", "throat", "invasion_pressure", "invasion_time", "pressure",
                 "drained", "trapped", "final_apertures", "burst_sizes"):  # fmt: skip
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None) == (y is None), name
        if x is not None:
            assert np.array_equal(x, y, equal_nan=True), name
    for key, series in (a.timeseries or {}).items():
        assert np.array_equal(series, b.timeseries[key], equal_nan=True), key
    assert len(a.snapshots or []) == len(b.snapshots or [])
    for s, t in zip(a.snapshots or [], b.snapshots or [], strict=True):
        assert s.time == t.time and np.array_equal(s.pressure, t.pressure)
        assert np.array_equal(s.drained, t.drained)
    for key in a.mechanics_series or {}:
        assert np.array_equal(a.mechanics_series[key], b.mechanics_series[key]), key
    skip = {"wall_time_s", "compile_time_s", "threaded_seconds_most", "thread_switches",
            "threads_most", "threaded_calls", "mechanics_time_s"}  # fmt: skip
    for key, value in a.summary.items():
        if key not in skip and not key.startswith("thread"):
            other = b.summary[key]
            assert other == value or (value != value and other != other), key


@pytest.mark.parametrize("name", list(CASES))
def test_resumed_run_equals_uninterrupted(name: str, tmp_path) -> None:  # type: ignore[no-untyped-def]
    config = CASES[name]
    reference = Simulation.from_scene(config).run()
    drained = reference.summary["n_drained"]
    path = tmp_path / "run.h5.checkpoint"
    with pytest.raises(Killed):
        Simulation.from_scene(config).run(
            KilledAfterCheckpoint(path, every_drained=max(drained // 3, 1))
        )
    resumed = Simulation.resume(path)
    assert 0 < resumed.state.n_drained < drained
    _same(reference.data, resumed.run().data)


def test_a_run_in_one_call_writes_no_checkpoint(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """Invasion percolation in a rigid medium drains every pore in one kernel call: a
    checkpoint would come only after the run, so none is written, and the run is unchanged."""
    config = scene(IP, n=30)
    path = tmp_path / "ip.h5.checkpoint"
    schedule = CheckpointSchedule(path, every_drained=1)
    result = Simulation.from_scene(config).run(schedule)
    assert schedule.written == 0 and not path.exists()
    assert np.array_equal(result.data.order, Simulation.from_scene(config).run().data.order)


def test_checkpoints_are_removed_when_the_run_ends(tmp_path) -> None:  # type: ignore[no-untyped-def]
    path = tmp_path / "run.h5.checkpoint"
    schedule = CheckpointSchedule(path, every_drained=20)
    Simulation.from_scene(CASES["viscous, explicit"]).run(schedule)
    assert schedule.written >= 2 and not path.exists()
