"""The one State every model of a run shares (docs/architecture.md, rule 6).

All arrays are in scaled units (see :mod:`porenet.core.units`): lengths in ``a``, pressures in
``gamma / a``, times in ``mu a / gamma``. Pore arrays have length ``n_pores`` and use the lattice's
pore index; throat arrays have length ``n_throats`` in the lattice's canonical throat order.

Which model writes which field
------------------------------
==========================  ===================  ======================================
field                       written by           read by
==========================  ===================  ======================================
``drained``                 FluidModel           observers, Coupler, analysis
``trapped``                 FluidModel           observers, analysis
``pressure``                FluidModel           Coupler, observers
``invading_pressure``       FluidModel           Coupler, observers
``apertures``               Coupler (from solid) FluidModel, observers
``time``, ``step``          FluidModel           everyone
``n_drained``, ``record``   FluidModel           observers, stop criteria
``breakthrough``            FluidModel           stop criteria, observers
solid fields (``None``      SolidModel           Coupler, observers
until a solid exists)
==========================  ===================  ======================================
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class DrainageRecord:
    """Append-only log of drainage events, preallocated to ``n_pores``.

    Attributes
    ----------
    order : ndarray of int64, shape (n_pores,)
        Pore index drained at each step; only the first ``size`` entries are meaningful.
    throat : ndarray of int64, shape (n_pores,)
        Throat through which each pore was entered (-1 for inlet pores).
    pressure : ndarray of float64, shape (n_pores,)
        Entry pressure overcome at each step (scaled by ``gamma / a``; 0 for inlet pores).
    time : ndarray of float64, shape (n_pores,)
        Time of each drainage (scaled; 0 in quasi-static models).
    size : int
        Number of recorded steps.
    """

    order: np.ndarray
    throat: np.ndarray
    pressure: np.ndarray
    time: np.ndarray
    size: int = 0

    @classmethod
    def empty(cls, n_pores: int) -> DrainageRecord:
        return cls(
            order=np.full(n_pores, -1, dtype=np.int64),
            throat=np.full(n_pores, -1, dtype=np.int64),
            pressure=np.zeros(n_pores),
            time=np.zeros(n_pores),
        )

    def extend(
        self, pores: np.ndarray, throats: np.ndarray, pressures: np.ndarray, times: np.ndarray
    ) -> None:
        """Append a batch of events (arrays of equal length)."""
        k = len(pores)
        sl = slice(self.size, self.size + k)
        self.order[sl] = pores
        self.throat[sl] = throats
        self.pressure[sl] = pressures
        self.time[sl] = times
        self.size += k


@dataclass
class State:
    """Arrays describing the system at one instant, shared by all models of a run.

    Attributes
    ----------
    drained : ndarray of bool, shape (n_pores,)
        True where the invading fluid occupies the pore body.
    trapped : ndarray of bool, shape (n_pores,)
        True for defending pores known to be cut off from the outlet.
    apertures : ndarray of float64, shape (n_throats,)
        Current throat apertures ``r / a``.
    pressure : ndarray of float64, shape (n_pores,) or None
        Pore pressure / (gamma / a); invader pressure in drained pores. ``None`` when the fluid
        model defines no pressure field (invasion percolation).
    invading_pressure : float
        Pressure of the invading fluid / (gamma / a).
    time : float
        Elapsed time / (mu a / gamma); stays 0 in quasi-static models.
    step : int
        Number of calls to ``FluidModel.advance`` so far.
    n_drained : int
        Number of drained pores (inlets included).
    breakthrough : bool
        True once a drained pore touches the outlet.
    record : DrainageRecord
        The log of drainage events.
    meniscus_length : ndarray of float64, shape (n_throats,) or None
        Remaining length / a of the meniscus in each throat between a drained and an
        undrained pore (2 when pinned, 0 when it completes); meaningful on the frontier only.
        ``None`` for quasi-static models.
    spring_compression, spring_force, displacement : ndarray or None
        Solid fields, written by a deformable SolidModel; ``None`` for a rigid medium.
    """

    drained: np.ndarray
    trapped: np.ndarray
    apertures: np.ndarray
    record: DrainageRecord
    pressure: np.ndarray | None = None
    invading_pressure: float = 0.0
    time: float = 0.0
    step: int = 0
    n_drained: int = 0
    breakthrough: bool = False
    meniscus_length: np.ndarray | None = None
    spring_compression: np.ndarray | None = None
    spring_force: np.ndarray | None = None
    displacement: np.ndarray | None = None

    @classmethod
    def initial(cls, n_pores: int, apertures: np.ndarray) -> State:
        """A fully saturated medium with the given (scaled) apertures."""
        return cls(
            drained=np.zeros(n_pores, dtype=bool),
            trapped=np.zeros(n_pores, dtype=bool),
            apertures=np.array(apertures, dtype=np.float64, copy=True),
            record=DrainageRecord.empty(n_pores),
        )

    @property
    def n_pores(self) -> int:
        return int(self.drained.shape[0])

    @property
    def n_throats(self) -> int:
        return int(self.apertures.shape[0])
