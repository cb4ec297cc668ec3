"""The one-way coupler, kind ``oneway.pressure``.

One-way (or sequential, "staggered without feedback") coupling is the usual first
approximation of poromechanics when the solid is stiff: the fluid's pressures load the solid,
and the solid's deformation is computed and recorded, but it is not fed back into the flow
(the permeability, here the apertures, stays that of the undeformed medium). So the invasion
is exactly the rigid medium's, while the solid's stresses, displacements and the apertures it
would give follow the fluid. Comparing a run with porenet's two-way ``pressure-aperture``
coupler shows where the feedback matters (the fracturing regime of docs/model.md section 6).

What the coupler does after each fluid advance, when the solid's schedule says so:

1. hands the solid every pore's pressure (:func:`pore_pressures`: the invader's in drained
   pores, the defender's elsewhere, in ``gamma / a``);
2. lets the solid balance its forces (:meth:`porenet.core.interfaces.SolidModel.update`),
   which writes ``spring_compression``, ``spring_force``, ``displacement`` and, in place,
   ``apertures``;
3. writes the apertures the fluid saw before back into ``state.apertures`` and reports no
   change, so the fluid model is never told of one.
"""

from __future__ import annotations

import numpy as np

from porenet.config.base import ModelConfig
from porenet.core.interfaces import Coupler, RunContext, SolidModel
from porenet.core.state import State


def pore_pressures(
    drained: np.ndarray, invading_pressure: float, defender: np.ndarray | None
) -> np.ndarray:
    """(n_pores,) float: the pressure of each pore's fluid in ``gamma / a``: the invader's,
    ``invading_pressure``, in ``drained`` pores; elsewhere the defender's, ``defender`` (the
    fluid model's pressure field), or 0 for a model that solves none (quasi-static)."""
    outside = 0.0 if defender is None else np.asarray(defender, dtype=np.float64)
    return np.where(np.asarray(drained, dtype=bool), float(invading_pressure), outside)


class OneWayCoupler(Coupler):
    """Loads the solid with the fluid's pore pressures on the solid config's schedule and
    keeps the apertures the fluid sees (module docstring).

    ``config`` is the solid's config: ``coupling`` (``every-step``, ``interval``,
    ``adaptive``), ``coupling_interval`` and ``coupling_tolerance``, read as porenet's
    ``pressure-aperture`` coupler reads them.
    """

    def __init__(self, config: ModelConfig, context: RunContext) -> None:
        super().__init__(config, context)
        self.schedule = str(getattr(config, "coupling", "every-step"))
        self.interval = int(getattr(config, "coupling_interval", 1))
        self.tolerance = float(getattr(config, "coupling_tolerance", 0.0))
        self.changed_throats = np.zeros(0, dtype=np.int64)
        self.last_pressure: np.ndarray | None = None  # handed to the solid at its last update
        self.last_step = 0
        self.updates = 0

    def max_events(self) -> int | None:
        """One drained pore between exchanges: the solid sees every drainage event."""
        return 1

    def max_steps(self) -> int | None:
        """The fluid's time steps between exchanges: the interval, else one."""
        return self.interval if self.schedule == "interval" else 1

    def due(self, state: State, pressure: np.ndarray, compliance: float) -> bool:
        """Whether the schedule updates the solid now: after every step, every
        ``coupling_interval`` steps, or (adaptive) when the largest pore-pressure change since
        the last update (since the start: the prestressed solid balances zero pressure) could
        deform the solid by more than half ``coupling_tolerance``."""
        if self.schedule == "interval":
            return state.step - self.last_step >= self.interval
        if self.schedule == "adaptive":
            last = 0.0 if self.last_pressure is None else self.last_pressure
            change = float(np.abs(pressure - last).max(initial=0.0))
            return change * compliance > 0.5 * self.tolerance
        return True

    def exchange(self, state: State, solid: SolidModel, events: int) -> bool:
        """Update the solid if due; the fluid's apertures stay as they were. Returns False:
        the apertures never change."""
        pressure = pore_pressures(state.drained, state.invading_pressure, state.pressure)
        if not self.due(state, pressure, solid.compliance):
            return False
        seen = state.apertures.copy()  # what the fluid sees, and keeps seeing
        solid.update(state, pressure, 0.5 * self.tolerance if self.schedule == "adaptive" else 0.0)
        state.apertures[:] = seen
        self.last_pressure, self.last_step = pressure, state.step
        self.updates += 1
        return False
