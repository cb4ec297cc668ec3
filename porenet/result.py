"""What a run produces: :class:`RunData` (SI arrays, as in the run file) and :class:`RunResult`.

Dynamic fluid models add time series (named as in :data:`TIMESERIES_UNITS`) and pressure
:class:`Snapshot` objects to the :class:`RunData`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from porenet.core.interfaces import Lattice
    from porenet.core.plan import Plan
    from porenet.core.state import State


#: Unit of each known time series of :attr:`RunData.timeseries` (SI; "-" for dimensionless).
#: Series with other names are allowed; their unit is ``""`` (unknown).
TIMESERIES_UNITS: dict[str, str] = {
    # time since the start of injection
    "time": "s",
    # pressure of the invading fluid at the inlet
    "invading_pressure": "Pa",
    # volume delivered by the pump
    "injected": "m^3",
    # defender volume displaced by advancing menisci, i.e. volume of the invader in the medium
    "drained": "m^3",
    # volume held by compressibility: injection reservoir plus defending fluid
    "stored": "m^3",
    # defending fluid through the outlet
    "outflow": "m^3",
    # compressibility storage discarded when a pore drains
    "released": "m^3",
    # measured capillary number Ca = mu v / gamma so far
    "capillary_number": "-",
    # number of drained pores
    "n_drained": "-",
}


@dataclass(frozen=True, eq=False)
class Snapshot:
    """The pore pressure field at one instant of a dynamic run, in SI units.

    Equality is identity (the fields hold arrays); compare fields to compare snapshots.

    Attributes
    ----------
    time : float
        Time of the snapshot (s).
    saturation : float
        Drained fraction of the pores (-).
    invading_pressure : float
        Pressure of the invading fluid at the inlet (Pa).
    pressure : ndarray (N,) float
        Pore pressure (Pa): defender pressure in undrained pores, invader pressure in drained
        pores. Flat (``n_pores``), like the other pore arrays of :class:`RunData`.
    drained : ndarray (N,) bool
        Invader occupancy at ``time``.
    mechanics : dict of str to ndarray
        Deformable media: the solid at ``time`` (as of its last update): ``apertures`` (M,) m,
        ``spring_compression`` (M,) m, ``spring_force`` (M,) N, ``removed_springs`` (M,) bool,
        ``displacement`` (n_particles, 2) m. Empty for a rigid medium.
    """

    time: float
    saturation: float
    invading_pressure: float
    pressure: np.ndarray
    drained: np.ndarray
    mechanics: dict[str, np.ndarray] = field(default_factory=dict)


@dataclass
class RunData:
    """Everything a run file holds, in SI units. Pore arrays are flat (``n_pores``).

    Attributes
    ----------
    porenet_version : str
        Version that produced the run.
    scene : dict
        The validated scene (JSON-compatible).
    pore_size : float
        ``a`` (m).
    grid_shape : tuple of int or None
        (rows, cols) when pores form a grid (pore ``i*cols + j``).
    throat_pores : ndarray (M, 2) int64
    pore_coords : ndarray (N, 2) float, m
    apertures : ndarray (M,) float, m
        Initial apertures, canonical throat order.
    drained, trapped : ndarray (N,) bool
        Final invader occupancy; defending pores cut off from the outlet.
    order : ndarray (K,) int64
        Pores in order of drainage (inlets first).
    throat : ndarray (K,) int64
        Throat through which each pore was entered (-1 for inlets).
    invasion_pressure : ndarray (K,) float, Pa
        Entry pressure overcome at each step (0 for inlets).
    summary : dict
        Scalars of ``/summary`` (SI).
    pressure : ndarray (N,) float, Pa, or None
        Final pore pressure where the fluid model defines one.
    invasion_time : ndarray (K,) float, s, or None
        Drainage times in dynamic models.
    final_apertures : ndarray (M,) float, m, or None
        Apertures at the end, for deformable media.
    burst_sizes : ndarray (B,) int64
        Steps in each burst (runs between record highs of the entry pressure), in order.
    timeseries : dict of str to ndarray (T,) float
        Time series of dynamic models, 1-D arrays of equal length in SI units, named and
        with units as in :data:`TIMESERIES_UNITS`; empty for static models.
    snapshots : list of Snapshot
        Pressure snapshots of dynamic models, in time order; empty for static models.
    mechanics_final : dict of str to ndarray
        Deformable media: ``spring_compression`` (M,) m, ``spring_force`` (M,) N,
        ``removed_springs`` (M,) bool, ``displacement`` (n_particles, 2) m, at the end.
    mechanics_series : dict of str to ndarray (U,)
        Deformable media, one entry per mechanical update: ``time`` (s; 0 in quasi-static
        runs), ``drained`` (pores), ``removed_springs``, ``max_aperture_change`` (m),
        ``balance_residual`` (N).
    observers : dict of str to dict of str to ndarray
        What observers recorded (:meth:`porenet.core.interfaces.Observer.outputs`), SI, by
        observer (``output_name``) and then by name; empty when no observer recorded any.
    observer_units : dict of str to dict of str to str
        The unit of each array of :attr:`observers`, with the same keys.
    """

    porenet_version: str
    scene: dict[str, Any]
    pore_size: float
    grid_shape: tuple[int, int] | None
    throat_pores: np.ndarray
    pore_coords: np.ndarray
    apertures: np.ndarray
    drained: np.ndarray
    trapped: np.ndarray
    order: np.ndarray
    throat: np.ndarray
    invasion_pressure: np.ndarray
    summary: dict[str, Any] = field(default_factory=dict)
    pressure: np.ndarray | None = None
    invasion_time: np.ndarray | None = None
    final_apertures: np.ndarray | None = None
    burst_sizes: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    timeseries: dict[str, np.ndarray] = field(default_factory=dict)
    snapshots: list[Snapshot] = field(default_factory=list)
    mechanics_final: dict[str, np.ndarray] = field(default_factory=dict)
    mechanics_series: dict[str, np.ndarray] = field(default_factory=dict)
    observers: dict[str, dict[str, np.ndarray]] = field(default_factory=dict)
    observer_units: dict[str, dict[str, str]] = field(default_factory=dict)

    @property
    def n_pores(self) -> int:
        return int(self.drained.shape[0])

    def as_grid(self, values: np.ndarray) -> np.ndarray:
        """Reshape a pore array to ``grid_shape`` (ValueError for non-grid lattices)."""
        if self.grid_shape is None:
            raise ValueError("this lattice has no grid layout")
        return np.asarray(values).reshape(self.grid_shape)

    def drainage_step(self) -> np.ndarray:
        """(N,) int64: step at which each pore drained, -1 if never."""
        return drainage_step(self.order, self.n_pores)

    def overview(self) -> list[tuple[str, str]]:
        """What the run was and what came out, as (label, text) rows: the lattice, the
        models, the pores drained and trapped, why it stopped, the regime, the wall time
        (the ``repr`` and a notebook's HTML view show these)."""
        s, scene = self.summary, self.scene
        shape = " x ".join(str(k) for k in self.grid_shape) if self.grid_shape else "not a grid"
        kinds = [str(scene.get(part, {}).get("kind", "")) for part in ("fluid", "solid")]
        drained = int(np.count_nonzero(self.drained))
        rows = [
            ("lattice", f"{scene.get('lattice', {}).get('kind', '?')} ({shape}), "
                        f"{self.n_pores} pores, {len(self.throat_pores)} throats, "
                        f"a = {self.pore_size:g} m"),
            ("models", ", ".join(k for k in kinds if k) or "?"),
            ("drained", f"{drained} pores ({drained / max(self.n_pores, 1):.1%})"),
            ("trapped", f"{int(np.count_nonzero(self.trapped))} pores"),
        ]  # fmt: skip
        for label, key, unit in (("stopped", "stop_reason", ""), ("regime", "regime", ""),
                                 ("wall time", "wall_time_s", " s")):  # fmt: skip
            if key in s:
                value = s[key]
                text = f"{value:.3g}" if isinstance(value, float) else str(value)
                rows.append((label, text + unit))
        rows.append(("porenet", self.porenet_version))
        return rows

    def __repr__(self) -> str:
        return _repr(type(self).__name__, self.overview())

    def _repr_html_(self) -> str:
        return _html(type(self).__name__, self.overview())


def _repr(name: str, rows: list[tuple[str, str]]) -> str:
    """``Name(``, then ``label: text`` a line for each row, then ``)``."""
    return name + "(\n" + "".join(f"  {label}: {text}\n" for label, text in rows) + ")"


def _html(name: str, rows: list[tuple[str, str]]) -> str:
    """A two-column HTML table of the rows, headed by ``name``."""
    from html import escape

    body = "".join(
        f"<tr><th style='text-align:left'>{escape(label)}</th><td style='text-align:left'>"
        f"{escape(text)}</td></tr>"
        for label, text in rows
    )
    return f"<table><caption style='text-align:left'><b>{escape(name)}</b></caption>{body}</table>"


def drainage_step(order: np.ndarray, n_pores: int) -> np.ndarray:
    """(N,) int64: the step at which each pore drained (its place in ``order``, the pores in
    order of drainage, inlets first), -1 for a pore that never drained."""
    step = np.full(n_pores, -1, dtype=np.int64)
    step[np.asarray(order)] = np.arange(len(order))
    return step


@dataclass
class RunResult:
    """A finished run: its data (SI) and the live objects that produced it.

    Attributes
    ----------
    data : RunData
        Arrays and summary, exactly as written to the run file.
    state : State
        The final State (scaled units).
    lattice : Lattice
        The lattice the run used.
    plan : Plan
        The plan the simulation was built from.
    path : Path or None
        The run file, if one was written.
    """

    data: RunData
    state: State
    lattice: Lattice
    plan: Plan
    path: Path | None = None

    @property
    def summary(self) -> dict[str, Any]:
        return self.data.summary

    def overview(self) -> list[tuple[str, str]]:
        """The data's :meth:`RunData.overview` and where the run file is."""
        where = str(self.path) if self.path is not None else "not written"
        return [*self.data.overview(), ("run file", where)]

    def __repr__(self) -> str:
        return _repr(type(self).__name__, self.overview())

    def _repr_html_(self) -> str:
        return _html(type(self).__name__, self.overview())

    @property
    def drained(self) -> np.ndarray:
        """Final drained mask, as a grid when the lattice has one."""
        d = self.data
        return d.as_grid(d.drained) if d.grid_shape else d.drained
