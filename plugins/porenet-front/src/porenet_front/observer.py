"""The ``front.interface`` observer: the invasion front (:mod:`porenet_front.front`) recorded
as the run goes on, stored in the run file under ``/observers/front.interface``."""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np

from porenet.core.interfaces import Observer, RunView
from porenet.core.state import State
from porenet.core.triggers import Schedule
from porenet_front.config import FrontConfig
from porenet_front.front import FrontGeometry, front_geometry, measure


class FrontObserver(Observer):
    """Records the front each time the drained pores reach a multiple of
    ``ceil(every x n_pores)``, and once more at the end (the final state, after the fluid
    model's ``finalize``).

    Reads ``state.drained``, ``state.n_drained``, ``state.time`` and
    ``state.invading_pressure``; writes nothing in the State (observers never do). Its
    records, in SI, reach the run file through :meth:`outputs`.

    Attributes
    ----------
    records : dict of str to list
        One list per name of :attr:`output_units`, one entry per record, in SI.
    """

    config: FrontConfig

    #: The records and their units (SI), in the order they are stored.
    output_units: ClassVar[dict[str, str]] = {
        "n_drained": "-",  # drained pores, inlets included
        "time": "s",  # model time (0 for quasi-static models)
        "invading_pressure": "Pa",  # pressure of the invading fluid
        "menisci": "-",  # throats between a drained and an undrained pore
        "front_menisci": "-",  # of those, facing defender connected to the outlet
        "front_position": "m",  # mean distance of the front's menisci from the injection site
        "front_width": "m",  # standard deviation of that distance
        "extent": "m",  # largest distance of a drained pore from the injection site
    }

    def __init__(self, config: FrontConfig | None = None) -> None:
        super().__init__(config or FrontConfig())
        self.records: dict[str, list[Any]] = {name: [] for name in self.output_units}
        self.geometry: FrontGeometry | None = None
        self.units = (1.0, 1.0, 1.0)  # length (m), pressure (Pa), time (s) of the scaled State

    def attach(self, run: RunView) -> None:
        """Fix the schedule (every ``ceil(every x n_pores)`` drained pores), the lattice's
        front geometry for the scene's injection site and the SI units of the run."""
        n = run.lattice.n_pores
        step = math.ceil(self.config.every * n)
        self.trigger = Schedule(list(range(step, n + 1, step)))
        self.geometry = front_geometry(run.lattice, run.injection.at)
        scales = run.scales
        self.units = (scales.length, scales.pressure, scales.time or 0.0)  # no clock: t = 0

    def observe(self, state: State) -> None:
        """Append one record of the front of ``state``."""
        assert self.geometry is not None, "attach() first"
        front = measure(self.geometry, state.drained)
        length, pressure, time = self.units
        values = {
            "n_drained": int(state.n_drained),
            "time": state.time * time,
            "invading_pressure": state.invading_pressure * pressure,
            "menisci": front.menisci,
            "front_menisci": front.front_menisci,
            "front_position": front.position * length,
            "front_width": front.width * length,
            "extent": front.extent * length,
        }
        for name, value in values.items():
            self.records[name].append(value)

    def outputs(self, state: State) -> dict[str, np.ndarray]:
        """The records as arrays (SI), the final state's included: porenet stores them as
        ``/observers/front.interface/<name>`` with their units."""
        drained, times = self.records["n_drained"], self.records["time"]
        if not drained or (drained[-1], times[-1]) != (state.n_drained, state.time * self.units[2]):
            self.observe(state)
        return {name: np.asarray(values) for name, values in self.records.items()}
