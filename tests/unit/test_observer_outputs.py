"""Observers' records reach the run file through ``Observer.outputs`` (docs/run-file.md,
"Observers' records"): ``/observers/<name>/<record>`` with a ``units`` attribute, read back as
``RunData.observers``; names shared by two observers are made unique; bad records are refused
before anything is written."""

from __future__ import annotations

from typing import Any, ClassVar

import h5py
import numpy as np
import pytest

from porenet.core.errors import RunFileError
from porenet.core.interfaces import Observer
from porenet.core.state import State
from porenet.core.triggers import Schedule
from porenet.io.runfile import read_run, write_run
from porenet.simulation import Simulation

SCENE = {
    "seed": 4,
    "lattice": {"n": 12, "disorder": 0.3, "pore_size": 1e-6},
    "fluid": {"kind": "invasion-percolation"},
    "stop": {"at": "complete"},
    "classifier": {"kind": "none"},
}


class Counter(Observer):
    """Records the drained pores and the invading pressure (Pa) every 10 drained pores."""

    output_units: ClassVar[dict[str, str]] = {"invading_pressure": "Pa", "drained": "-"}

    def __init__(self) -> None:
        super().__init__(None)
        self.drained: list[int] = []
        self.pressure: list[float] = []
        self.final: State | None = None

    def attach(self, run: Any) -> None:
        self.trigger = Schedule(list(range(10, run.lattice.n_pores + 1, 10)))
        self.pressure_unit = run.scales.pressure

    def observe(self, state: State) -> None:
        self.drained.append(state.n_drained)
        self.pressure.append(state.invading_pressure * self.pressure_unit)

    def outputs(self, state: State) -> dict[str, np.ndarray]:
        self.final = state
        return {
            "drained": np.array(self.drained),
            "invading_pressure": np.array(self.pressure),
            "final_drained": state.drained.copy(),  # a record without a unit
            "count": np.int64(len(self.drained)),  # a scalar
        }


class Silent(Observer):
    """Records nothing: no group."""


def test_records_are_written_under_the_observers_name_with_units(tmp_path):
    counter = Counter()
    sim = Simulation.from_scene(SCENE, output=tmp_path / "r.h5")
    sim.observers[:0] = [counter, Silent(), Counter()]  # before the run-file writer
    result = sim.run()
    assert counter.final is sim.state and sim.state.trapped.any()  # after finalize
    assert counter.output_name == "Counter"
    assert set(result.data.observers) == {"Counter", "Counter-2"}
    with h5py.File(tmp_path / "r.h5") as f:
        group = f["observers/Counter"]
        assert list(group) == ["drained", "invading_pressure", "final_drained", "count"]
        assert group["invading_pressure"].attrs["units"] == "Pa"
        assert group["final_drained"].attrs["units"] == ""
        assert group["count"].shape == ()
        assert "Counter-2" in f["observers"]
    back = read_run(tmp_path / "r.h5")
    assert back.observer_units["Counter"]["drained"] == "-"
    for name, values in result.data.observers["Counter"].items():
        np.testing.assert_array_equal(back.observers["Counter"][name], values)
    np.testing.assert_array_equal(back.observers["Counter"]["final_drained"], back.drained)
    assert back.observers["Counter"]["drained"][0] == 10


def test_no_records_no_group(tmp_path):
    sim = Simulation.from_scene(SCENE, output=tmp_path / "r.h5")
    sim.observers.insert(0, Silent())
    assert sim.run().data.observers == {}
    with h5py.File(tmp_path / "r.h5") as f:
        assert "observers" not in f
    assert read_run(tmp_path / "r.h5").observers == {}


def test_output_name_is_the_kind_of_the_config():
    class Config:
        kind = "mypkg.front"

    assert Silent().output_name == "Silent"  # no config: the class name
    obs = Silent(Config())  # type: ignore[arg-type]
    assert obs.output_name == "mypkg.front"


@pytest.mark.parametrize(
    ("observers", "match"),
    [
        ({"a/b": {"x": np.zeros(2)}}, "observer name 'a/b'"),
        ({"a": {"": np.zeros(2)}}, "record name ''"),
        ({"a": {"x": np.array(["text"])}}, "not numbers or booleans"),
    ],
)
def test_bad_records_are_refused_and_nothing_written(tmp_path, observers, match):
    data = Simulation.from_scene(SCENE).run().data
    data.observers = observers
    with pytest.raises(RunFileError, match=match):
        write_run(tmp_path / "r.h5", data)
    assert list(tmp_path.iterdir()) == []
