"""Snapshots: the pressure field, and the solid's fields, at given saturations and times.

An observer like any other (docs/architecture.md, rule 8): its trigger
(:class:`porenet.core.triggers.Schedule`) makes the Simulation end the fluid model's calls at
the drained counts and model times asked for, and it records the State then. At the end it
gives what it recorded as the run data's ``snapshots`` (:meth:`Snapshots.run_data`), which the
run-file writer stores under ``/snapshots`` (docs/run-file.md). ``fluid.snapshot_saturations``
and ``fluid.snapshot_times`` of the viscous model are a shorthand for one such observer.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from porenet.core.interfaces import Observer, RunView
from porenet.core.state import State
from porenet.core.triggers import Schedule
from porenet.core.units import Scales
from porenet.kinds.snapshots.config import SnapshotsConfig


class Snapshots(Observer):
    """Records, when its trigger fires: the model time, the saturation, the invading pressure,
    the pore pressures (the invader's in drained pores), the drained mask and, in a
    deformable medium, the solid's fields (:meth:`porenet.core.interfaces.SolidModel.
    snapshot`). Scaled units (the Simulation converts them to SI).

    Attributes
    ----------
    records : list of dict
        One per firing, in time order.
    """

    config: SnapshotsConfig

    def __init__(self, config: SnapshotsConfig | None = None) -> None:
        super().__init__(config or SnapshotsConfig())
        self.records: list[dict[str, Any]] = []
        self._solid_fields: Callable[[State], dict[str, np.ndarray]] | None = None

    def attach(self, run: RunView) -> None:
        n = run.lattice.n_pores
        time_unit = run.scales.time
        times = [t / time_unit for t in self.config.times] if time_unit else []
        self.trigger = Schedule([math.ceil(s * n) for s in self.config.saturations], times)
        self._solid_fields = run.solid_fields

    def observe(self, state: State) -> None:
        none = state.pressure is None  # a model without a pressure field
        pressure = np.zeros(state.n_pores) if none else state.pressure.copy()
        pressure[state.drained] = state.invading_pressure
        self.records.append(
            {
                "time": state.time,
                "saturation": state.n_drained / state.n_pores,
                "invading_pressure": state.invading_pressure,
                "pressure": pressure,
                "drained": state.drained.copy(),
                "mechanics": {} if self._solid_fields is None else self._solid_fields(state),
            }
        )

    def run_data(self, scales: Scales) -> dict[str, Any]:
        """The records as the run data's ``snapshots``, in SI (the run file's
        ``/snapshots``, docs/run-file.md)."""
        from porenet.result import Snapshot

        if not self.records:
            return {}
        time = scales.time or 1.0
        return {
            "snapshots": [
                Snapshot(
                    time=snap["time"] * time,
                    saturation=snap["saturation"],
                    invading_pressure=snap["invading_pressure"] * scales.pressure,
                    pressure=snap["pressure"] * scales.pressure,
                    drained=snap["drained"],
                    mechanics=scales.solid_fields(snap["mechanics"]),
                )
                for snap in self.records
            ]
        }
