"""The fluid-solid coupler: pore pressures to the solid, apertures back (docs/model.md §5)."""

from __future__ import annotations

import numpy as np

from porenet.config.base import ModelConfig
from porenet.core.interfaces import Coupler, RunContext, SolidModel
from porenet.core.state import State
from porenet.kinds.pressure_aperture.config import PressureApertureConfig as PressureApertureConfig


class PressureApertureCoupler(Coupler):
    """Updates the solid on the solid config's schedule and writes the new apertures.

    ``config`` is the solid's config (:class:`~porenet.kinds.hertz.model.HertzConfig` or
    any config with ``coupling``, ``coupling_interval`` and ``coupling_tolerance``).

    * ``every-step``: after every fluid step (for invasion percolation, every drained pore,
      with the invader at the entry pressure just overcome: the quasi-static rule);
    * ``interval``: every ``coupling_interval`` fluid steps;
    * ``adaptive``: after a fluid step when the largest pore-pressure change since the last
      update, times the solid's :attr:`~porenet.core.interfaces.SolidModel.compliance`,
      exceeds half of ``coupling_tolerance`` (for the Hertzian solid: a spring-compression
      change in units of a); the solid may leave pores that changed by less than the other
      half out of an update. A stiff solid is thus updated rarely, a soft one often, and the
      pressures the solid works with never lag by more than the tolerance.
    """

    def __init__(self, config: ModelConfig, context: RunContext) -> None:
        super().__init__(config, context)
        self.schedule = str(getattr(config, "coupling", "every-step"))
        self.interval = int(getattr(config, "coupling_interval", 1))
        self.tolerance = float(getattr(config, "coupling_tolerance", 0.0))
        self._last_step = 0
        self._pressure: np.ndarray | None = None  # pore pressures handed to the solid
        self._last = np.zeros(0)  # ... at the last update
        self._no_pressure = np.zeros(0)  # the defender of a pressure-free (quasi-static) model
        self.updates = 0

    def max_events(self) -> int | None:
        return 1

    def max_steps(self) -> int | None:
        return self.interval if self.schedule == "interval" else 1

    def exchange(self, state: State, solid: SolidModel, events: int) -> bool:
        from porenet.kinds.hertz.kernels.springs import fill_pore_pressures

        if self._pressure is None:
            self._pressure = np.zeros(state.n_pores)
            self._last = np.zeros(state.n_pores)
        if self.schedule == "interval" and state.step - self._last_step < self.interval:
            return False
        defender = self._no_pressure if state.pressure is None else state.pressure
        fill_pore_pressures(self._pressure, defender, state.drained, state.invading_pressure)
        # Adaptive: half the tolerance for skipping whole updates here, half for the pores the
        # solid leaves behind within an update, so that the pressures the solid works with
        # never lag the fluid's by more than the tolerance (as a deformation).
        half = 0.5 * self.tolerance if self.schedule == "adaptive" else 0.0
        if half > 0:
            from porenet.kinds.hertz.kernels.springs import largest_pressure_change

            change = largest_pressure_change(
                defender, state.drained, state.invading_pressure, self._last
            )
            if change * solid.compliance <= half:
                return False
        self._last[:] = self._pressure
        self.changed_throats = solid.update(state, self._pressure, half)
        self._last_step = state.step
        self.updates += 1
        return self.changed_throats is None or len(self.changed_throats) > 0
