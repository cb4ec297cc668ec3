"""The fluid-solid coupler: pore pressures to the solid, apertures back (MODEL.md section 5)."""

from __future__ import annotations

from typing import Literal

import numpy as np

from porenet.config.base import ModelConfig
from porenet.core.interfaces import Coupler, RunContext, SolidModel
from porenet.core.state import State


class PressureApertureConfig(ModelConfig):
    """Names the coupler; its schedule is set in the solid's section (``coupling``,
    ``coupling_interval``, ``coupling_tolerance``)."""

    kind: Literal["pressure-aperture"] = "pressure-aperture"


def pore_pressures(state: State) -> np.ndarray:
    """Pressure in every pore (gamma / a): the invader's in drained pores, the defender's
    elsewhere (0 when the fluid model has no pressure field: the quasi-static defender sits at
    the outlet pressure)."""
    if state.pressure is None:
        p = np.zeros(state.n_pores)
    else:
        p = np.array(state.pressure, dtype=np.float64, copy=True)
    p[state.drained] = state.invading_pressure
    return p


class PressureApertureCoupler(Coupler):
    """Updates the solid on the solid config's schedule and writes the new apertures.

    ``config`` is the solid's config (:class:`~porenet.builtin.solids.hertz.HertzConfig` or
    any config with ``coupling``, ``coupling_interval`` and ``coupling_tolerance``).

    * ``every-step``: after every fluid step (for invasion percolation, every drained pore,
      with the invader at the entry pressure just overcome: the quasi-static rule);
    * ``interval``: every ``coupling_interval`` fluid steps;
    * ``adaptive``: after a fluid step that changed some pore pressure by more than
      ``coupling_tolerance`` (gamma / a) since the last update; a drained pore always does.
    """

    def __init__(self, config: ModelConfig, context: RunContext) -> None:
        super().__init__(config, context)
        self.schedule = str(getattr(config, "coupling", "every-step"))
        self.interval = int(getattr(config, "coupling_interval", 1))
        self.tolerance = float(getattr(config, "coupling_tolerance", 0.0))
        self._last_step = 0
        self._last_pressure: np.ndarray | None = None
        self.updates = 0

    def max_events(self) -> int | None:
        return 1

    def max_steps(self) -> int | None:
        return self.interval if self.schedule == "interval" else 1

    def exchange(self, state: State, solid: SolidModel, events: int) -> bool:
        p = pore_pressures(state)
        if self._last_pressure is None:
            self._last_pressure = np.zeros_like(p)
        if self.schedule == "interval" and state.step - self._last_step < self.interval:
            return False
        if (
            self.schedule == "adaptive"
            and events == 0
            and float(np.max(np.abs(p - self._last_pressure), initial=0.0)) <= self.tolerance
        ):
            return False
        solid.update(state, p)
        self._last_step = state.step
        self._last_pressure = p
        self.updates += 1
        return True
