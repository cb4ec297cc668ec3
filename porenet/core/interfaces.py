"""The abstract interfaces every model implements.

A run is built from one :class:`Lattice`, one :class:`FluidModel`, an optional
:class:`SolidModel` and :class:`Coupler` (absent for a rigid medium), and any number of
:class:`Observer` objects. They share one :class:`~porenet.core.state.State` and never call each
other directly: the :class:`~porenet.simulation.Simulation` calls them in this order::

    fluid.setup(state); solid.setup(state); observer.attach(view)  for each observer
    loop:
        fluid.advance(state, max_events)        # drains pores, updates pressures and time
        coupler.exchange(state, solid)          # only for a deformable solid
        observer.observe(state)                 # only observers whose trigger fires
    fluid.finalize(state)
    observer.outputs(state)                     # every observer, once: its run file records
    observer.close(state, result)               # every observer, once

Length (over the ~500 lines of docs/architecture.md's rule): by design: the five interfaces
a plugin implements, with every method's contract, in one place to read.

Units: every array in the State is scaled (lengths by a, pressures by gamma/a, times by
mu a/gamma, see :mod:`porenet.core.units`); configs are SI; conversions happen at the edges.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from porenet.core.sites import FACES, OPPOSITE_FACE, face_of
from porenet.core.state import State
from porenet.core.triggers import Never, Trigger
from porenet.core.units import Scales

if TYPE_CHECKING:  # pragma: no cover
    from porenet.config.base import ModelConfig


@dataclass(frozen=True)
class RunContext:
    """What every model may know about the run besides its own config.

    Attributes
    ----------
    scales : Scales
        SI scales of the scene.
    injection : Any
        The validated ``[injection]`` section.
    stop : Any
        The validated ``[stop]`` section (a hint: models may stop computing early).
    rng : numpy.random.Generator
        The run's generator, seeded from the scene's seed (the only source of randomness).
    deformable : bool
        True when a solid model will change ``state.apertures`` during the run (the plan's
        effect ``aperture_feedback``: a solid coupled back; the fluid model must then not
        precompute anything from the initial apertures, and is told of each change through
        :meth:`FluidModel.apertures_changed`). False in a rigid medium and under one-way
        coupling.
    """

    scales: Scales
    injection: Any
    stop: Any
    rng: np.random.Generator = field(repr=False)
    deformable: bool = False


class Lattice(ABC):
    """Geometry and topology of the pore network and, for mechanics, of the solid particles.

    A lattice is built once from its config and the run's generator and is read-only afterwards.
    Pores are numbered ``0 .. n_pores-1``, throats ``0 .. n_throats-1`` in the lattice's canonical
    order; lengths are in units of the pore size ``a``, in 2 or 3 dimensions.

    The contract for any network (docs/lattices.md, "The lattice contract"): pore centres
    ``(n_pores, d)``; per throat its two pores, aperture ``r``, length, area and permeability
    factors and entry pressure; per pore its volume; named pore sets (:attr:`labels`) and the
    injection sites and outlet they define (:meth:`sites`). The square lattice's values are one
    case of it. Subclasses implement the abstract properties; the particle/spring description
    is needed only by deformable solids and may raise :class:`NotImplementedError` otherwise.
    """

    def __init__(self, config: ModelConfig, rng: np.random.Generator) -> None:
        self.config = config

    # -- pore network ---------------------------------------------------------------------
    @property
    @abstractmethod
    def n_pores(self) -> int:
        """Number of pore bodies."""

    @property
    @abstractmethod
    def throat_pores(self) -> np.ndarray:
        """(n_throats, 2) int64: the two pores each throat joins."""

    @property
    @abstractmethod
    def pore_coords(self) -> np.ndarray:
        """(n_pores, d) float, d = 2 or 3: pore centres (x, y[, z]) in units of ``a``."""

    @property
    def dimension(self) -> int:
        """2 or 3: the number of columns of :attr:`pore_coords`."""
        return int(np.shape(self.pore_coords)[1])

    @property
    @abstractmethod
    def boundary_pores(self) -> np.ndarray:
        """(n_pores,) bool: pores on the outer edge, which drain to the outlet reservoir."""

    @property
    @abstractmethod
    def initial_apertures(self) -> np.ndarray:
        """(n_throats,) float: throat apertures ``r / a`` before any deformation."""

    @property
    def n_throats(self) -> int:
        """Number of throats (equal to the number of springs)."""
        return int(self.throat_pores.shape[0])

    @property
    def grid_shape(self) -> tuple[int, int] | None:
        """(rows, cols) when pore ``i*cols + j`` sits at row i, column j; None otherwise."""
        return None

    @property
    def pore_volumes(self) -> np.ndarray:
        """(n_pores,) float: pore volumes in units of ``a**3`` (default 1)."""
        return np.ones(self.n_pores)

    @property
    def canonical_grid(self) -> bool:
        """True when the pores form an ``n x n`` grid (pore ``i*n + j``) whose throats are the
        4-neighbour pairs in canonical order: horizontal ``(i,j)-(i,j+1)`` row-major, then
        vertical ``(i,j)-(i+1,j)`` row-major. Kernels may then use stencils instead of the
        adjacency lists. Default False."""
        return False

    @property
    def throat_factors(self) -> tuple[float | np.ndarray, float | np.ndarray]:
        """``(c_A, c_k)``: throat area ``A = c_A r**2`` and permeability ``k = c_k r**2``
        (docs/model.md section 1; default 1, 1). Each is one number for every throat or an
        ``(n_throats,)`` array (a network whose throats have different cross-sections)."""
        return 1.0, 1.0

    @property
    def throat_lengths(self) -> np.ndarray:
        """(n_throats,) float: the length ``l`` of each throat in units of ``a``, over which
        it conducts (``g = A k / l``) and a meniscus crosses it. Default ``2`` (the square
        lattice's node spacing ``2a``, docs/model.md section 1)."""
        return np.full(self.n_throats, 2.0)

    def entry_pressures(
        self, apertures: np.ndarray, throats: np.ndarray | None = None
    ) -> np.ndarray:
        """Capillary entry pressure of each throat in units of ``gamma / a``, from apertures
        ``r / a`` (of the throats ``throats``, default all): ``2 / r`` (a cylinder, zero
        contact angle; docs/model.md section 1). A lattice with shaped throats overrides it."""
        return 2.0 / np.asarray(apertures, dtype=np.float64)

    @property
    def labels(self) -> dict[str, np.ndarray]:
        """Named sets of pores, ``name -> (n_pores,) bool`` (for example an imported network's
        ``pore.inlet``), usable as an injection site or outlet (:meth:`sites`). Default none."""
        return {}

    @property
    def mean_aperture(self) -> float:
        """Mean aperture ``r_mean / a``; also the aperture of the half throats that join the
        boundary pores to the outlet reservoir (default: mean of the initial apertures)."""
        return float(np.mean(self.initial_apertures))

    def outlet_links(self, at: str) -> np.ndarray:
        """(n_pores,) float: number of half throats (length ``a``) joining each pore to the
        outlet reservoir, for an injection site (see :meth:`outlet_mask`). Default: one per
        outlet pore."""
        return self.outlet_mask(at).astype(np.float64)

    # -- solid network (deformable media) ---------------------------------------------------
    @property
    def spring_particles(self) -> np.ndarray:
        """(n_throats, 2) int64: the two particles joined by the spring that crosses throat t."""
        raise NotImplementedError(f"{type(self).__name__} does not describe its particles")

    @property
    def particle_coords(self) -> np.ndarray:
        """(n_particles, 2) float: particle centres in units of ``a``."""
        raise NotImplementedError(f"{type(self).__name__} does not describe its particles")

    @cached_property
    def pore_particle_pairs(self) -> tuple[np.ndarray, np.ndarray]:
        """``(pores, particles)``, int64 arrays of equal length: which particles each pore's
        fluid pushes on (docs/model.md section 5).

        Default: a pore touches the two particles of the spring across each of its throats
        (on the square lattice, the pore's four corners; a corner pore misses its outer corner,
        which is fixed anyway). Sorted by pore, then particle."""
        tp = np.asarray(self.throat_pores, dtype=np.int64)
        sp = np.asarray(self.spring_particles, dtype=np.int64)
        pores = np.concatenate([tp[:, 0], tp[:, 0], tp[:, 1], tp[:, 1]])
        particles = np.concatenate([sp[:, 0], sp[:, 1], sp[:, 0], sp[:, 1]])
        n_particles = int(np.asarray(self.particle_coords).shape[0])
        unique = np.unique(pores * n_particles + particles)
        return unique // n_particles, unique % n_particles

    @cached_property
    def fixed_particles(self) -> np.ndarray:
        """(n_particles,) bool: particles held fixed (the confining boundary).

        Default: the particles on the bounding box of all particles (the outer ring of a
        rectangular lattice)."""
        xy = np.asarray(self.particle_coords, dtype=np.float64)
        span = float(np.ptp(xy, axis=0).max()) or 1.0
        tol = 1e-9 * span
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        return np.any((xy <= lo + tol) | (xy >= hi - tol), axis=1)

    # -- derived --------------------------------------------------------------------------
    @cached_property
    def adjacency(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """CSR neighbour lists ``(indptr, neighbours, throats)``.

        The neighbours of pore ``p`` are ``neighbours[indptr[p]:indptr[p+1]]`` and the throats
        that lead to them ``throats[indptr[p]:indptr[p+1]]``, sorted by throat index.
        """
        from porenet.kernels.graph import csr_adjacency

        return csr_adjacency(self.throat_pores, self.n_pores)

    def sites(self, spec: str | list[int] | tuple[int, ...]) -> np.ndarray:
        """(n_pores,) bool: the pores a site names. ``spec`` is ``"centre"`` (the pore nearest
        the centroid of the pores), a face of the bounding box (``"x-"``, ``"x+"``, ``"y-"``,
        ``"y+"``, ``"z-"``, ``"z+"``; ``"left-edge"`` is ``"x-"``), a label of
        :attr:`labels`, or a list of pore indices. Raises ValueError naming what is known."""
        mask = np.zeros(self.n_pores, dtype=bool)
        if isinstance(spec, (list, tuple)):
            index = np.asarray(spec, dtype=np.int64)
            if index.size == 0 or index.min() < 0 or index.max() >= self.n_pores:
                raise ValueError(f"pore indices must be in [0, {self.n_pores}): got {list(spec)}")
            mask[index] = True
            return mask
        if spec == "centre":
            dx = np.asarray(self.pore_coords, dtype=np.float64)
            dx = dx - dx.mean(axis=0)
            d = np.hypot(dx[:, 0], dx[:, 1]) if dx.shape[1] == 2 else np.linalg.norm(dx, axis=1)
            mask[int(np.argmin(d))] = True
            return mask
        face = face_of(spec)
        if face is not None:
            axis, side = FACES[face]
            if axis >= self.dimension:
                raise ValueError(f"face {spec!r} needs a 3-D lattice; this one is 2-D")
            x = np.asarray(self.pore_coords, dtype=np.float64)[:, axis]
            return np.isclose(x, x.max() if side > 0 else x.min())
        if spec in self.labels:
            return np.asarray(self.labels[spec], dtype=bool).copy()
        known = ", ".join(["centre", *FACES, *sorted(self.labels)])
        raise ValueError(f"unknown site {spec!r}: expected one of {known}, or a list of pores")

    def inlet_pores(self, at: str | list[int]) -> np.ndarray:
        """Pores the invading fluid occupies at the start (:meth:`sites`), sorted."""
        return np.flatnonzero(self.sites(at)).astype(np.int64)

    def outlet_mask(self, at: str | list[int]) -> np.ndarray:
        """(n_pores,) bool: pores connected to the outlet reservoir for an injection site.

        Injection at a face drains through the opposite face (the other faces are closed);
        anywhere else (the centre, a label, a list of pores) through :attr:`boundary_pores`.
        """
        face = face_of(at)
        if face is not None:
            return self.sites(OPPOSITE_FACE[face])
        return np.asarray(self.boundary_pores, dtype=bool)


class FluidModel(ABC):
    """Moves the fluid-fluid interface.

    Reads ``state.apertures``. Writes ``drained``, ``trapped``, ``pressure``,
    ``invading_pressure``, ``time``, ``step``, ``n_drained``, ``breakthrough`` and ``record``.

    Class attributes
    ----------------
    solves_pressure : bool
        True if the model solves for a defending-fluid pressure field (the Plan reports it).
    """

    solves_pressure: ClassVar[bool] = False

    #: Most time steps one :meth:`advance` may take (None: the model's own chunk). The
    #: Simulation sets it from :meth:`Coupler.max_steps` so that a deformable solid can be
    #: updated between fluid steps; models whose steps each drain one pore may ignore it.
    step_limit: int | None = None

    #: Wall time (s) one :meth:`advance` should aim at, where it can return without changing
    #: the run (None: no aim, the model's own chunks). The Simulation sets it before each
    #: call, so that it regains control this often (progress, observers, the choice of
    #: threads: :mod:`porenet.jit.threads`). A model must give the same results whatever it is.
    call_seconds: float | None = None

    #: Model time (scaled) at which one :meth:`advance` must end, if the model has a time
    #: (None: none). The Simulation sets it before each call from the observers' triggers
    #: (:meth:`porenet.core.triggers.Trigger.next_time`: snapshots at given times); a model
    #: that has no time ignores it.
    stop_time: float | None = None

    def __init__(self, config: ModelConfig, lattice: Lattice, context: RunContext) -> None:
        self.config = config
        self.lattice = lattice
        self.context = context

    def setup(self, state: State) -> None:  # noqa: B027 - optional hook
        """Called once before the loop; may drain the inlet pores and precompute."""

    def parallel_work(self) -> float | None:
        """Work done so far by kernels that run on several threads, in units of the model's
        choice that cost about the same wall time each (the viscous model: pore sweeps of
        boxes large enough for threads); None (the default) when the model's kernels never
        use threads. The Simulation measures time per unit of it on 1 and on several
        threads and keeps the faster (:class:`porenet.jit.threads.ThreadGovernor`)."""
        return None

    @abstractmethod
    def advance(self, state: State, max_events: int) -> int:
        """Advance until at most ``max_events`` pores have been drained; return how many were.

        Returning 0 with :attr:`exhausted` True ends the run.
        """

    @property
    @abstractmethod
    def exhausted(self) -> bool:
        """True when nothing more can be invaded."""

    @property
    def stop_reason(self) -> str | None:
        """Why the model is :attr:`exhausted` (e.g. ``"max_time"``); None means "complete"."""
        return None

    def finalize(self, state: State) -> None:  # noqa: B027 - optional hook
        """Called once after the loop (e.g. to settle the final trapped set)."""

    def apertures_changed(self, state: State, throats: np.ndarray | None = None) -> None:
        """Called after the Coupler changed ``state.apertures`` (deformable media only):
        recompute whatever depends on them, for the given ``throats`` (None: any may have
        changed). Models that cannot follow changing apertures keep this default, which
        refuses."""
        raise NotImplementedError(
            f"fluid model {type(self).__name__} does not support deformable media"
        )

    def summary(self, state: State) -> dict[str, Any]:
        """Scalar results (SI) for the run file's ``/summary`` group."""
        return {}

    def outputs(self, state: State) -> dict[str, Any]:
        """Further records, in scaled units, after :meth:`finalize`: optional key
        ``"timeseries"`` (dict of 1-D arrays named as in
        :data:`porenet.result.TIMESERIES_UNITS`). The Simulation converts them to SI.
        (Snapshots of the fields are an observer's, :mod:`porenet.kinds.observers.
        snapshots`.)"""
        return {}


class SolidModel(ABC):
    """Mechanics of the solid skeleton.

    Reads the pore pressures handed over by the :class:`Coupler`. Writes
    ``spring_compression``, ``spring_force`` and ``displacement``. A rigid medium has no
    SolidModel object at all: the Plan builds none.
    """

    def __init__(self, config: ModelConfig, lattice: Lattice, context: RunContext) -> None:
        self.config = config
        self.lattice = lattice
        self.context = context

    def setup(self, state: State) -> None:  # noqa: B027 - optional hook
        """Called once before the loop (e.g. to apply the prestress)."""

    @abstractmethod
    def update(
        self, state: State, pore_pressure: np.ndarray, tolerance: float = 0.0
    ) -> np.ndarray | None:
        """Impose force balance under ``pore_pressure`` (gamma / a, every pore) and write the
        new solid fields and ``state.apertures`` (in place: the fluid model keeps reading the
        same array). ``tolerance`` (units of a) is the deformation the solid may leave
        unresolved where that saves work (the adaptive coupler's tolerance); 0 is exact.
        Returns the throats whose aperture changed, or None for "possibly all"."""

    def summary(self, state: State) -> dict[str, Any]:
        """Scalar results (SI) for the run file's ``/summary`` group."""
        return {}

    @property
    def compliance(self) -> float:
        """Deformation a unit pressure change causes, in units of ``a`` per ``gamma / a``: the
        adaptive coupler multiplies pressure changes by it to compare them with its tolerance
        (default 1: the tolerance is then a pressure, in ``gamma / a``)."""
        return 1.0

    @property
    def unresolved_deformation(self) -> float:
        """Deformation, in units of ``a``, that the solid's settings let it leave unresolved
        (a solver's stopping tolerance, a slip tolerance), so that its force balance holds
        only to that deformation at its stiffness (``1 / compliance``); 0 (the default): solved
        to round-off. The contract suite bounds the recorded ``balance_residual`` by it
        (docs/contract.md)."""
        return 0.0

    def snapshot(self, state: State) -> dict[str, np.ndarray]:
        """Copies of the solid fields now, scaled (the keys of :meth:`outputs`' ``"final"``
        plus ``apertures``), stored with the fluid's pressure snapshot taken at this moment."""
        return {}

    def outputs(self, state: State) -> dict[str, Any]:
        """Further records, scaled: optional ``"final"`` (``spring_compression`` (M,),
        ``spring_force`` (M,), ``removed_springs`` (M,) bool, ``displacement``
        (n_particles, 2)) and ``"series"`` (per update: ``time``, ``drained``,
        ``removed_springs``, ``max_aperture_change``, ``balance_residual``). The Simulation
        converts them to SI."""
        return {}


class Coupler(ABC):
    """Passes pressures from the fluid to the solid and apertures back.

    Reads ``pressure``, ``invading_pressure``, ``drained``; writes ``apertures``.
    """

    def __init__(self, config: ModelConfig, context: RunContext) -> None:
        self.config = config
        self.context = context

    #: The throats whose aperture the last :meth:`exchange` changed (None: possibly all).
    changed_throats: np.ndarray | None = None

    @abstractmethod
    def exchange(self, state: State, solid: SolidModel, events: int) -> bool:
        """Called after every fluid advance that drained ``events`` pores; returns True when
        it changed ``state.apertures`` (the Simulation then calls
        :meth:`FluidModel.apertures_changed` with :attr:`changed_throats`)."""

    def max_events(self) -> int | None:
        """Largest number of drainage events the fluid may take between exchanges."""
        return None

    def summary(self, state: State) -> dict[str, Any]:
        """Scalar results (SI) for the run file's ``/summary`` (default none)."""
        return {}

    def max_steps(self) -> int | None:
        """Largest number of fluid time steps between exchanges (None: no limit)."""
        return None


@dataclass(frozen=True)
class RunView:
    """What an observer sees of the run: read-only, the same for every observer, built-in or
    from a plugin. Handed to :meth:`Observer.attach` and :meth:`Observer.resumed`; the State
    itself comes with every :meth:`Observer.observe`.

    Attributes
    ----------
    scene : SceneConfig
        The validated scene (frozen).
    lattice : Lattice
        The run's lattice (pores, throats, coordinates, labels, :meth:`Lattice.sites`); read
        it, never change it.
    scales : Scales
        The SI scales of the run's scaled units (an observer that records converts with them).
    expected_drained : int or None
        The pores the plan expects the run to drain (its cost estimate, docs/cost.md), None
        where it has no estimate.
    solid_fields : callable or None
        ``solid_fields(state)``: copies of the solid's fields now, scaled
        (:meth:`SolidModel.snapshot`); None in a rigid medium.
    wall_time : callable
        ``wall_time()``: seconds of wall time the run has taken so far (building it, and every
        stretch it ran, across checkpoints).
    """

    scene: Any
    lattice: Lattice
    scales: Scales
    expected_drained: int | None
    solid_fields: Callable[[State], dict[str, np.ndarray]] | None
    wall_time: Callable[[], float]

    @property
    def injection(self) -> Any:
        """The scene's ``[injection]`` section (``injection.at``: the injection site)."""
        return self.scene.injection

    @property
    def stop(self) -> Any:
        """The scene's ``[stop]`` section."""
        return self.scene.stop


class Observer(ABC):  # noqa: B024 - every hook is optional
    """Sees the State when its trigger fires, and once more at the end.

    Observers read the State and never write it. What an observer records reaches the run
    file through :meth:`outputs` (docs/run-file.md, "Observers' records").
    """

    trigger: Trigger = Never()

    #: Unit of each array :meth:`outputs` returns, by name (SI; ``"-"`` for a pure number),
    #: stored as the dataset's ``units`` attribute (``""`` for a name not listed).
    output_units: ClassVar[dict[str, str]] = {}

    def __init__(self, config: ModelConfig | None = None) -> None:
        self.config = config

    @property
    def output_name(self) -> str:
        """Name of the run file group of :meth:`outputs`, ``/observers/<output_name>``: the
        config's kind (the class name for an observer without a config). The Simulation
        appends ``-2``, ``-3``, ... to a name that two observers of a run share."""
        kind = getattr(self.config, "kind", None)
        return str(kind) if kind else type(self).__name__

    def attach(self, run: RunView) -> None:  # noqa: B027 - optional hook
        """Called once before the loop with what the observer may see of the run."""

    def observe(self, state: State) -> None:  # noqa: B027 - optional hook
        """Called after an advance whenever :attr:`trigger` fires."""

    def outputs(self, state: State) -> dict[str, np.ndarray]:
        """What the observer recorded, for the run file: ``{name: array}`` in SI units (the
        observer converts: :meth:`attach` gives it ``run.scales``), any shape and dtype
        numpy can store, units in :attr:`output_units`. Called once at the end, after
        :meth:`FluidModel.finalize` (``state`` is the final State) and before :meth:`close`;
        stored as the datasets ``/observers/<output_name>/<name>`` and read back as
        ``RunData.observers[output_name][name]``. Default: nothing (no group)."""
        return {}

    def run_data(self, scales: Scales) -> dict[str, Any]:
        """Fields of the run's :class:`~porenet.result.RunData` this observer fills, in SI
        (``scales`` converts): the ``snapshots`` observer gives ``{"snapshots": [Snapshot,
        ...]}``, stored as the run file's ``/snapshots`` (docs/run-file.md). Called once at
        the end, like :meth:`outputs`. Default: none (most observers store what they record
        through :meth:`outputs`)."""
        return {}

    def close(self, state: State, result: Any) -> None:  # noqa: B027 - optional hook
        """Called once at the end with the :class:`~porenet.result.RunResult`."""

    def resumed(self, run: RunView) -> None:  # noqa: B027 - optional hook
        """Called instead of :meth:`attach` when a run goes on from a checkpoint, in a new
        process (docs/run-file.md, "Checkpoints"): the observer was pickled with the run, so
        it keeps what it gathered; reopen here what :meth:`observe` writes to. An observer
        that holds an open file or stream drops it in ``__getstate__``."""


@dataclass(frozen=True)
class Classification:
    """A classifier's verdict on a pattern.

    Attributes
    ----------
    regime : str
        One of ``CF``, ``VF``, ``FR``, ``CF/VF``, ``FR/VF``, ``FR/CF``.
    confidence : float
        In [0, 1].
    details : dict
        Features and numbers the verdict rests on.
    """

    regime: str
    confidence: float
    details: dict[str, Any] = field(default_factory=dict)


class Classifier(ABC):
    """Labels an invasion pattern with a regime from a finished run."""

    def __init__(self, config: ModelConfig | None = None) -> None:
        self.config = config

    @abstractmethod
    def classify(self, run: Any) -> Classification:
        """Classify a run (a :class:`~porenet.result.RunResult` or a run file's contents)."""
