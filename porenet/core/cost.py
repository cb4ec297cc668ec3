"""Estimated cost of a run, from its validated scene alone (the model of docs/cost.md).

Nothing is built or imported beyond the scene's config: the estimate is arithmetic on the
lattice size, the stop condition and the models' settings, with per-unit costs measured on
the project's 2-core machine (``python tests/benchmarks/bench_cost.py`` prints predicted
against measured). It aims at a factor ~2-3 on steps and wall time for the built-in kinds;
kinds it has no model for give ``None`` ("unknown") rather than an error.

The model, in short (docs/cost.md gives the measurements behind each constant; N = n^2
pores):

* **Drained pores.** Invasion percolation from the centre drains a fraction
  ``0.21 n^-0.14`` of an ``n x n`` lattice by breakthrough (ensemble mean with trapping, x1.2
  without), ``1.37 n^-0.167`` at completion with trapping, all of it without; left-edge
  injection has its own fits. The viscous model is taken to drain as much (measured within
  ~1.3x from Ca* = 0.3 to 10). A deformable medium that fractures drains few pores
  (viscous: ~``2 n`` for ``N_f >= 1.5``; invasion percolation: ~``n / 2`` for
  ``N_f >= 5``), interpolated geometrically from the rigid count over the ranges of
  :data:`FRACTURE`. ``stop.max_drained`` caps it.
* **Steps.** Invasion percolation: one per drained pore. Viscous, explicit integrator: the
  pump delivers ``q = Ca A_b / a^2`` volumes ``a^3`` per unit scaled time (``A_b = 4 L a``
  for centre injection, ``L a`` for left-edge), a drained pore takes ~2.8 mean pore volumes
  (counting what the compressible defender stores), the step is the stability limit with
  the widest throats, ``c_V / (2 c_A c_k r_max^4)`` with ``r_max = (1 + lambda) r_mean``, and
  each landing adds a step: ``1 + 2.8 c_V / (q dt)`` steps per drained pore, counted on the
  pores a rigid medium would drain (fracturing changes the time to breakthrough far less
  than the drained count); the accuracy limit ``pressure_step`` adds ~``20 n sqrt(Ca)``
  steps (more for weak disorder), which dominate fast injection (Ca >~ 1), where more pores
  drain too (up to ~``0.3 n^0.12`` of the lattice from Ca = 1e2). Implicit integrator: 13
  steps per drained pore.
  ``integrator = "auto"`` is resolved by the model's own rule.
* **Mechanical updates** (solid kinds ``hertz`` and ``hertz-mindlin``): one per fluid step
  (``every-step``), one per ``coupling_interval`` steps, or, adaptive, a fraction ~0.3 of
  the steps for ``N_f >= 0.1`` falling to 0 at ``N_f = 0.01`` (a stiff solid is never updated). With
  invasion percolation, one per drained pore (adaptive: falling to none the same way).
  Above ``N_f = 10`` (viscous) the estimate notes that it is outside its calibration.
* **Memory**: bytes per pore (lattice, state, records and the run data 240; the viscous
  model +250; its implicit integrator +2000; the Hertzian solid +600, the frictional one
  +1200), peak resident memory.
* **Wall time** (build and run, seconds): invasion percolation ``3e-3 + 2.3e-7 N`` (times
  ``(N / 640 000)^0.3`` above 640 000 pores); explicit
  ``steps (1.5e-7 n + 1.8e-9 N) + drained 2.9e-6 n``; implicit ``drained 0.039
  (N / 2500)^1.41``; a deformable medium adds ``steps (3e-5 + 1.8e-9 N)`` (one step per
  call and the coupler's check) and ``updates (2.3e-9 + 7e-9 w) N^1.15`` (``w`` = 1 when
  fracturing), ``updates 1.9e-7 N`` for ``hertz-mindlin``, times ``1 + 1.7 sqrt(r_t) w``
  with sliding (``r_t = K_t / K_n``); RKC with local time steps on large lattices ~1/3 of its
  time without (:data:`LOCAL_STEPS_FACTOR`). Python start-up, imports and the first-run numba
  compilation (7-55 s, once per machine: docs/performance.md, "First run") are not
  included.

Length (over the ~500 lines of docs/architecture.md's rule): one estimate (``estimate_cost``)
and the per-unit terms it adds up, each with its measured constant and its provenance in
docs/cost.md; kept together so that a constant and the term using it are read side by side.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from porenet.analysis.numbers import fracturing_number
from porenet.core.extent import lattice_extent
from porenet.core.sites import site_geometry
from porenet.kinds.viscous.config import auto_integrator

#: Invasion percolation, centre injection, ensemble mean drained fraction at breakthrough
#: ``a n^-b`` with trapping (n = 25-800, 12-32 seeds each; docs/cost.md).
IP_BREAKTHROUGH_CENTRE = (0.21, 0.14)
#: The same for left-edge injection (n = 25-400).
IP_BREAKTHROUGH_EDGE = (0.96, 0.24)
#: Drained fraction at completion with trapping, centre and left-edge injection.
IP_COMPLETE_CENTRE = (1.37, 0.167)
IP_COMPLETE_EDGE = (1.17, 0.183)
#: Without trapping more is drained by breakthrough (ensemble medians, n = 25-800).
IP_NO_TRAPPING_FACTOR = 1.2
#: 3-D cubic lattice, centre injection, drained fraction at breakthrough ``a n^-b`` (the same
#: with and without trapping; ``python examples/scripts/ip_3d.py --sizes 24 48 96 192 --seeds
#: 48 --trapping no``; docs/cost.md). ``3 - b`` is the cluster's fractal dimension.
IP_3D = (0.073, 0.47)
#: ... and from a face (with trapping, z- face, lambda = 0.5, 8 seeds at each of n = 12, 16,
#: 24, 32, 48, 64: 0.29 to 0.13, the fit within 18 % of each; docs/cost.md, "Other lattices").
IP_3D_FACE = (1.18, 0.53)
#: Injected mean pore volumes per drained pore (docs/model.md, "Dynamic viscous drainage").
VOLUME_PER_DRAINED = 2.8
#: Implicit integrator: steps per drained pore (~13 for Ca = 1e-4 to 1e-6, docs/performance.md).
IMPLICIT_STEPS_PER_DRAINED = 13.0
#: RKC integrator: stage sweeps per drained pore are ``RKC_STAGES sqrt(1.54 T rho)`` (T the
#: time a pore takes, ``2.8 / q``; rho the spectral radius, ~0.7 of the Gershgorin bound
#: 2 / dt) plus ``RKC_EXPLICIT`` explicit steps near each landing; a stage sweep costs
#: ``RKC_STAGE_FACTOR`` times an explicit step's sweep (docs/performance.md).
RKC_STAGES = 3.2
RKC_EXPLICIT = 12.0
RKC_RHO_FRACTION = 0.7
RKC_STAGE_FACTOR = 1.6
#: Stages of an average RKC step, to count its steps (13.5 measured at n = 400, Ca = 1e-5,
#: ``python tests/benchmarks/bench_viscous.py --skip-fig1b --low-ca-full``; a round 10 here).
RKC_STAGES_PER_STEP = 10.0
#: Local time steps (RKC, ``local_steps``): the wall time of the integration times
#: ``LOCAL_STEPS_FACTOR[1]`` from ``LOCAL_STEPS_FACTOR[0]`` pores up (773 s single-rate ->
#: 256 s at n = 400, Ca = 1e-5, one thread; docs/performance.md), 1 below the active box
#: where ``auto`` starts using them (:attr:`porenet.kinds.viscous.local_steps.LocalSteps.min_box`,
#: 40 000 pores: 0.69 measured at n = 200), geometric in N between.
LOCAL_STEPS_FACTOR = (160_000, 0.33)
LOCAL_STEPS_MIN_BOX = (40_000, 0.69)
#: Fracturing, by fluid kind: drained pores per pore of side once fractured, and the N_f
#: range interpolated over (viscous: Fig. 5 at n = 100 and 400; invasion percolation:
#: n = 50 and 100, one straight fracture).
FRACTURE = {"viscous": (2.0, (0.3, 1.5)), "invasion-percolation": (0.5, (1.0, 5.0))}
#: Adaptive coupling: fraction of fluid steps followed by a mechanical update (N_f >= 0.1),
#: and the N_f below which a solid is never updated at the default tolerance 3e-3.
ADAPTIVE_UPDATE_FRACTION = 0.3
ADAPTIVE_FULL_NF = 0.1
ADAPTIVE_NONE_NF = 0.01
ADAPTIVE_TOLERANCE = 3e-3

#: Viscous fluid in a Hertzian solid: above this N_f the estimate says it is outside its
#: calibration (steps and updates 14x and 30x the estimate at N_f = 1e6, n = 30).
SOFT_NF = 10.0

#: Peak memory, bytes per pore.
MEMORY_BASE = 240.0
MEMORY_VISCOUS = 250.0
MEMORY_IMPLICIT = 2000.0
MEMORY_HERTZ = 600.0

#: Fast injection (explicit integrator): steps the accuracy limit ``pressure_step`` adds,
#: ``PRESSURE_STEP_STEPS n sqrt(Ca) (S(0.3) / S(lambda)) (0.1 / pressure_step)`` with
#: ``S(lambda) = 4 lambda / (1 - lambda^2)`` the spread of entry pressures it is a fraction of
#: (fitted to n = 15, 30, 60 at Ca = 1e2-1e6, lambda = 0.3, and lambda = 0.01 and 0.1 at
#: Ca = 1e-2 and 1e-1, centre injection; docs/cost.md, "Hard cases").
PRESSURE_STEP_STEPS = 20.0
#: Fast injection drains more than invasion percolation before breakthrough: the fraction
#: moves from IP's at Ca <= FAST_CA[0] to ``a n^b`` (FAST_FRACTION) at Ca >= FAST_CA[1],
#: linearly in log Ca (n = 15-100, docs/cost.md, "Hard cases").
FAST_CA = (1e-2, 1e2)
FAST_FRACTION = (0.3, 0.12)

#: Wall time (s): invasion percolation, fixed and per pore ...
IP_SECONDS = (3e-3, 230e-9)
#: ... times ``(N / N0)^p`` above N0 pores, where the arrays outgrow the caches (n = 3000:
#: 6.2 s measured, 2.1 s without it; docs/cost.md, "Hard cases").
IP_LARGE = (640_000, 0.3)
#: Explicit viscous step: per pore of side (the menisci, the pump) and per pore of the
#: lattice (the sweep of the active box).
EXPLICIT_STEP_SECONDS = (1.5e-7, 1.8e-9)
#: One RKC stage sweep or explicit step of the RKC integrator: fixed and per pore.
RKC_SWEEP_SECONDS = (15e-6, 1.8e-9)
#: Per pore of a sweep on the adjacency lists (any lattice but the square grid), in place
#: of the grid stencil's 1.8e-9: the explicit integrator on the 64 x 64 x 64 cubic lattice
#: at Ca = 1e-3 took 80 s for 14 272 steps over ~262 000 active pores
#: (``tests/benchmarks/bench_csr.py``, docs/cost.md, "Other lattices").
LIST_PORE_SECONDS = 2.1e-8
#: Explicit viscous, per drained pore and pore of side (the located landing, new menisci).
EXPLICIT_DRAINED_SECONDS = 2.9e-6
#: Implicit viscous, per drained pore at N = 2500, and the exponent of N.
IMPLICIT_DRAINED_SECONDS = (0.039, 1.41)
#: Extra per fluid step in a deformable medium (one step per call, the coupler's check).
COUPLED_STEP_SECONDS = (30e-6, 1.8e-9)
#: One mechanical update of the Hertzian solid: ``(c + c_fracture w) N^p`` s, with ``w`` the
#: fracture weight (contacts opening make an update ~4x dearer).
UPDATE_SECONDS = (2.3e-9, 7e-9, 1.15)
#: One mechanical update of the frictional solid (kind ``hertz-mindlin``, rotations held, no
#: sliding), per pore: the multigrid solve is linear in N (n = 400 Fig. 5 at N_f = 10: 29.7 ms
#: an update, ``tests/benchmarks/bench_frictional.py run``, 2026-12-06, docs/cost.md).
MINDLIN_UPDATE_SECONDS = 1.9e-7
#: With sliding (``solid.friction``) a frictional update costs ``1 + c sqrt(r_t) w`` times
#: one without (``r_t = K_t / K_n``, ``w`` the fracture weight): contacts at Coulomb's cap
#: change mode as the load moves, each change a new solve, and the more so the stiffer the
#: contacts and the more the medium fractures. Fitted to the n = 400 study's runs with and
#: without sliding made with one code on one machine: the constant that keeps the worst
#: point's median over its seeds closest (``examples/scripts/fracture_shear.py
#: --sliding-cost``: 12 points, 24-30 pairs (30: the complete study), c = 1.69-1.74, every
#: median within 1.23x, every pair within 1.61x; seeds of one point differ by up to 1.4x); the form
#: ``1 + c r_t w`` came within 1.32x at best on the medians, docs/cost.md. It was 1.9,
#: fitted to the worst pair, until 2026-12-07, and ``1 + 8 r_t w`` before the multigrid's
#: hierarchies were built with every sliding contact stuck (11f18f4).
MINDLIN_SLIDING = 1.7
#: Extra peak memory of the frictional solid per pore (two multigrid hierarchies).
MEMORY_MINDLIN = 600.0
#: Solid kinds whose fracturing and coupling the model follows (the same coupler and
#: fracture mechanics; their updates cost differently).
_HERTZ_KINDS = ("hertz", "hertz-mindlin")

_KNOWN_FLUIDS = ("invasion-percolation", "viscous")


@dataclass(frozen=True)
class CostEstimate:
    """Estimated size of a run (docs/cost.md); ``None`` where the model has no estimate.

    Attributes
    ----------
    drained : int or None
        Pores drained by the stop condition (inlets included).
    steps : int or None
        Fluid steps: time steps of the viscous model, drained pores of invasion percolation.
    mechanical_updates : int or None
        Solid updates (0 in a rigid medium).
    memory_bytes : int or None
        Peak memory of the run's arrays.
    wall_seconds : float or None
        Wall time of build and run on the calibration machine (no imports, no compilation).
    notes : tuple of str
        Assumptions and the parts the model does not cover.
    """

    drained: int | None
    steps: int | None
    mechanical_updates: int | None
    memory_bytes: int | None
    wall_seconds: float | None
    notes: tuple[str, ...] = ()

    def summary(self) -> str:
        """The estimate on one line."""
        return (
            f"{_count(self.drained)} drained pores, {_count(self.steps)} steps, "
            f"{_count(self.mechanical_updates)} mechanical updates, "
            f"{format_bytes(self.memory_bytes)}, {format_seconds(self.wall_seconds)}"
        )

    def lines(self) -> list[str]:
        """The estimate as text, one quantity a line, with units."""
        return [
            f"  {'drained pores':<20} {_count(self.drained)}",
            f"  {'fluid steps':<20} {_count(self.steps)}",
            f"  {'mechanical updates':<20} {_count(self.mechanical_updates)}",
            f"  {'memory':<20} {format_bytes(self.memory_bytes)}",
            f"  {'wall time':<20} {format_seconds(self.wall_seconds)}"
            + (
                " (build and run; not imports or numba's first compile)"
                if self.wall_seconds
                else ""
            ),
            *(f"  note: {note}" for note in self.notes),
        ]


def _count(value: int | None) -> str:
    if value is None:
        return "unknown"
    if value == 0:
        return "0"
    return f"~{_round2(value):,}"


def _round2(value: float) -> int:
    """``value`` to two significant figures."""
    if value < 100:
        return round(value)
    digits = math.floor(math.log10(value)) - 1
    return int(round(value / 10**digits) * 10**digits)


def format_bytes(value: float | None) -> str:
    """``~12 MB`` style, or ``unknown``."""
    if value is None:
        return "unknown"
    for unit, size in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if value >= size:
            scaled = value / size
            return f"~{scaled:.2g} {unit}" if scaled < 10 else f"~{_round2(scaled)} {unit}"
    return f"~{value:.0f} B"


def format_seconds(value: float | None) -> str:
    """``~40 s``, ``~3.5 min``, ``~2.1 h``, or ``unknown``."""
    if value is None:
        return "unknown"
    if value < 0.1:
        return "< 0.1 s"
    for unit, size, limit in (("s", 1, 90), ("min", 60, 5400), ("h", 3600, 48 * 3600)):
        if value < limit:
            scaled = value / size
            return f"~{scaled:.2g} {unit}" if scaled < 10 else f"~{_round2(scaled)} {unit}"
    return f"~{_round2(value / 86400)} days"


def ip_drained_fraction(n: int, *, at: str, trapping: bool, injection: str = "centre") -> float:
    """Expected fraction of an ``n x n`` lattice invasion percolation drains at the stop."""
    edge = site_geometry(injection) == "face"
    if at == "complete":
        if not trapping:
            return 1.0
        a, b = IP_COMPLETE_EDGE if edge else IP_COMPLETE_CENTRE
        return min(1.0, a * n**-b)
    a, b = IP_BREAKTHROUGH_EDGE if edge else IP_BREAKTHROUGH_CENTRE
    fraction = a * n**-b * (1.0 if trapping else IP_NO_TRAPPING_FACTOR)
    return min(1.0, fraction)


def fracture_weight(nf: float | None, fluid: str = "viscous") -> float:
    """0 for a medium that does not fracture (rigid, or ``N_f`` below the fluid's range in
    :data:`FRACTURE`), 1 for one that does (above it), linear in ``log N_f`` between."""
    lo, hi = FRACTURE[fluid][1]
    if nf is None or nf <= lo:
        return 0.0
    if nf >= hi:
        return 1.0
    return math.log(nf / lo) / math.log(hi / lo)


def sliding_factor(stiffness_ratio: float, weight: float) -> float:
    """What Coulomb sliding multiplies a frictional update's cost by: ``1 + c sqrt(r_t) w``
    (:data:`MINDLIN_SLIDING`; ``r_t = K_t / K_n``, ``w`` the fracture weight,
    :func:`fracture_weight`)."""
    return 1.0 + MINDLIN_SLIDING * math.sqrt(stiffness_ratio) * weight


def adaptive_update_fraction(nf: float | None, tolerance: float = ADAPTIVE_TOLERANCE) -> float:
    """Fraction of fluid steps after which adaptive coupling updates the solid.

    ~0.3 for ``N_f >= 0.1`` at the default tolerance, falling linearly in ``log N_f`` to 0 at
    ``N_f = 0.01``; a larger tolerance acts like a stiffer solid (``N_f`` scaled by
    ``3e-3 / tolerance``).
    """
    if nf is None:
        return ADAPTIVE_UPDATE_FRACTION
    x = nf * ADAPTIVE_TOLERANCE / tolerance if tolerance > 0 else math.inf
    if x >= ADAPTIVE_FULL_NF:
        return ADAPTIVE_UPDATE_FRACTION
    if x <= ADAPTIVE_NONE_NF:
        return 0.0
    return (
        ADAPTIVE_UPDATE_FRACTION
        * math.log(x / ADAPTIVE_NONE_NF)
        / math.log(ADAPTIVE_FULL_NF / ADAPTIVE_NONE_NF)
    )


def entry_spread(disorder: float) -> float:
    """Spread of entry pressures ``2 (1/r_min - 1/r_max)`` in units of ``gamma / r_mean``:
    ``4 lambda / (1 - lambda^2)`` (the scale of ``pressure_step``)."""
    return 4.0 * disorder / (1.0 - disorder**2)


def fast_injection_fraction(n: int, ca: float, ip_fraction: float) -> float:
    """Drained fraction at breakthrough of the viscous model at capillary number ``ca``: IP's
    up to :data:`FAST_CA` ``[0]``, ``a n^b`` (:data:`FAST_FRACTION`) from ``FAST_CA[1]``,
    linear in ``log Ca`` between."""
    lo, hi = FAST_CA
    if ca <= lo:
        return ip_fraction
    a, b = FAST_FRACTION
    fast = max(ip_fraction, min(1.0, a * n**b))
    w = min(1.0, math.log(ca / lo) / math.log(hi / lo))
    return ip_fraction + w * (fast - ip_fraction)


def pressure_step_steps(n: int, ca: float, disorder: float, pressure_step: float | None) -> float:
    """Explicit steps that the accuracy limit ``pressure_step`` adds to a run to
    breakthrough (:data:`PRESSURE_STEP_STEPS`; 0 without the limit)."""
    if pressure_step is None or not math.isfinite(pressure_step) or disorder <= 0:
        return 0.0
    scale = entry_spread(0.3) / entry_spread(disorder) * 0.1 / pressure_step
    return PRESSURE_STEP_STEPS * n * math.sqrt(ca) * scale


def explicit_step(scene: Any, disorder: float) -> float:
    """Stable explicit step (scaled time ``mu a / gamma``): ``c_V / (4 g_max)`` with
    ``g_max = c_A c_k r_max^4 / 2`` the conductance of the widest throat."""
    lat, fluid = scene.lattice, scene.fluid
    r0 = _mean_aperture(lat)
    c_area = float(getattr(lat, "area_factor", 1.0))
    c_perm = float(getattr(lat, "permeability_factor", 1.0))
    c_vol = float(getattr(lat, "volume_factor", 1.0))
    g_max = c_area * c_perm * ((1.0 + disorder) * r0) ** 4 / 2.0
    return float(getattr(fluid, "safety_factor", 1.0)) * c_vol / (4.0 * g_max)


def _mean_aperture(lat: Any) -> float:
    mean = getattr(lat, "mean_aperture", None)
    size = getattr(lat, "pore_size", None)
    return 1.0 if mean is None or not size else float(mean) / float(size)


def pump_rate(scene: Any) -> float | None:
    """Injection rate ``q`` in scaled units (volume ``a^3`` per scaled time ``mu a / gamma``),
    ``None`` without rate control."""
    fluid, lat = scene.fluid, scene.lattice
    extent = lattice_extent(lat)
    if getattr(fluid, "control", "rate") != "rate" or extent is None:
        return None
    cross_section = extent.cross_section(site_geometry(scene.injection.at))
    ca = getattr(fluid, "capillary_number", None)
    if ca is not None:
        return float(ca) * cross_section
    rate = getattr(fluid, "injection_rate", None)
    if rate is None:
        return None
    a = float(getattr(lat, "pore_size", 1.0))
    return float(rate) * float(fluid.viscosity) / (a**2 * float(fluid.interfacial_tension))


def solid_fracturing_number(scene: Any) -> float | None:
    """``N_f`` of the scene's solid (given, or from its modulus by Eq. 2), None if rigid."""
    solid, lat = scene.solid, scene.lattice
    nf = getattr(solid, "fracturing_number", None)
    if nf is not None:
        return float(nf)
    modulus = getattr(solid, "modulus", None)
    gamma = getattr(scene.fluid, "interfacial_tension", None)
    lam = getattr(lat, "disorder", None)
    pore = getattr(lat, "pore_size", None)
    eps = getattr(solid, "prestrain", None)
    if None in (modulus, gamma, lam, pore, eps):
        return None
    return fracturing_number(float(gamma), float(lam), float(pore), float(modulus), float(eps))


def local_steps_factor(scene: Any, pores: int, rigid: bool) -> float:
    """What local time steps do to the RKC integration's wall time (:data:`LOCAL_STEPS_FACTOR`):
    1 where they do not apply (``local_steps = "off"``, a coupled solid, pressure control, a
    lattice other than the square grid) or, on lattices smaller than the box where they start."""
    fluid = scene.fluid
    if getattr(fluid, "local_steps", "off") == "off" or not rigid or fluid.control != "rate":
        return 1.0
    extent = lattice_extent(scene.lattice)
    if extent is None or not extent.canonical_grid:  # local steps need a square grid
        return 1.0
    (n0, f0), (n1, f1) = LOCAL_STEPS_MIN_BOX, LOCAL_STEPS_FACTOR
    if pores < n0:
        return 1.0
    if pores >= n1:
        return f1
    return f0 * (f1 / f0) ** (math.log(pores / n0) / math.log(n1 / n0))


def estimate_cost(scene: Any) -> CostEstimate:
    """Estimate drained pores, steps, mechanical updates, memory and wall time of ``scene``.

    ``scene`` is a validated scene; nothing is built. Kinds the model does not know give
    ``None`` for what depends on them, with a note.
    """
    notes: list[str] = []
    lat, fluid, solid, stop = scene.lattice, scene.fluid, scene.solid, scene.stop
    extent = lattice_extent(lat)
    if extent is None:
        return CostEstimate(None, None, None, None, None, (f"lattice {lat.kind!r}: no size",))
    n, pores = extent.side, extent.pores
    if extent.dimension == 3:
        notes.append(
            "3-D lattice: drained pores from 3-D invasion percolation at breakthrough "
            f"({IP_3D[0]} n^-{IP_3D[1]} from the centre, {IP_3D_FACE[0]} n^-{IP_3D_FACE[1]} from "
            "a face); viscous sweeps at the adjacency lists' cost per pore (measured"
            " for the explicit integrator, not for rkc or implicit; docs/cost.md)"
        )
    elif not extent.canonical_grid:
        notes.append(
            f"lattice {lat.kind!r} costed as a square lattice of {pores:,} pores, its viscous "
            "sweeps at the adjacency lists' cost per pore"
        )
    list_sweep = not extent.canonical_grid
    disorder = extent.disorder
    if disorder is None:
        disorder = 0.3
        notes.append("apertures from a file: disorder taken as 0.3")
    rigid = bool(getattr(type(solid), "builds_nothing", False))
    hertz = solid.kind in _HERTZ_KINDS
    mindlin = solid.kind == "hertz-mindlin"
    if not rigid and not hertz:
        notes.append(f"solid {solid.kind!r}: no cost model for its updates")
    sliding = mindlin and getattr(solid, "friction", None) is not None
    nf = None if rigid else solid_fracturing_number(scene)
    at = scene.injection.at

    if fluid.kind not in _KNOWN_FLUIDS:
        drained = None if stop.max_drained is None else int(stop.max_drained)
        notes.append(f"fluid {fluid.kind!r}: no cost model")
        return CostEstimate(drained, None, None, None, None, tuple(notes))

    # -- drained pores --------------------------------------------------------------------
    trapping = bool(getattr(fluid, "trapping", True))
    if extent.dimension == 3:
        a, b = IP_3D_FACE if site_geometry(at) == "face" else IP_3D
        fraction = a * n**-b if stop.at == "breakthrough" else 1.0
    else:
        fraction = ip_drained_fraction(n, at=stop.at, trapping=trapping, injection=at)
    q = pump_rate(scene) if fluid.kind == "viscous" else None
    ca = None if q is None else q / extent.cross_section(site_geometry(at))
    if ca is not None and stop.at == "breakthrough":
        fraction = fast_injection_fraction(n, ca, fraction)
    expected = pores * fraction
    if stop.max_drained is not None:
        expected = min(expected, float(stop.max_drained))
    #: What the medium would drain were it rigid: the viscous model's time to breakthrough,
    #: and so its steps, change far less with fracturing than the drained count does.
    unfractured = max(1.0, expected)
    w = fracture_weight(nf, fluid.kind) if hertz else 0.0
    slide = sliding_factor(solid.stiffness_ratio, w) if sliding else 1.0
    if sliding:
        notes.append(
            f"solid.friction: sliding costed at {slide:.2g}x the mechanics of the same run "
            "without it (fitted to n = 400 runs with K_t/K_n 0.1-0.8 at N_f 1-30: each "
            "point's median over its seeds within 1.23x, single runs within 1.6x; "
            "docs/cost.md)"
        )
    if hertz and fluid.kind == "viscous" and nf is not None and nf > SOFT_NF:
        notes.append(
            f"N_f = {nf:.3g} is beyond the model's calibration (N_f <= {SOFT_NF:g}): a soft "
            "solid opens throats towards the aperture cap and shortens the stable step; "
            "measured 14x the steps and 30x the updates at N_f = 1e6 (docs/cost.md, "
            '"Hard cases")'
        )
    if w > 0:
        fractured = min(expected, FRACTURE[fluid.kind][0] * n)
        expected = expected ** (1.0 - w) * fractured**w
        notes.append(f"N_f = {nf:.3g}: fracturing expected, few pores drain")
    drained = max(1.0, expected)

    # -- steps and time -------------------------------------------------------------------
    memory = MEMORY_BASE * pores
    steps: float | None
    wall: float | None
    if fluid.kind == "invasion-percolation":
        steps = drained
        big, power = IP_LARGE
        wall = IP_SECONDS[0] + IP_SECONDS[1] * pores * max(1.0, pores / big) ** power
        if not rigid:
            notes.append("deformable: the invasion runs pore by pore")
    else:
        memory += MEMORY_VISCOUS * pores
        if q is None or q <= 0 or ca is None:
            notes.append(f"control = {fluid.control!r}: steps and time not modelled")
            steps = wall = None
        else:
            dt = explicit_step(scene, float(disorder))
            per_drained = VOLUME_PER_DRAINED * float(getattr(lat, "volume_factor", 1.0)) / (q * dt)
            integrator = getattr(fluid, "integrator", "explicit")
            if integrator == "auto":
                integrator = auto_integrator(per_drained, pores)
            max_time = getattr(fluid, "max_time", None)
            if max_time is not None:
                t_scale = float(fluid.viscosity) * float(lat.pore_size)
                t_scale /= float(fluid.interfacial_tension)
                reachable = max_time / t_scale * q / VOLUME_PER_DRAINED
                if reachable < unfractured:
                    drained = min(drained, max(1.0, reachable))
                    unfractured = max(1.0, reachable)
                    notes.append("stops at max_time before the stop condition")
            if integrator == "implicit":
                memory += MEMORY_IMPLICIT * pores
                steps = IMPLICIT_STEPS_PER_DRAINED * drained
                c, p = IMPLICIT_DRAINED_SECONDS
                wall = drained * c * (pores / 2500.0) ** p
                notes.append("implicit integrator (integrator = 'auto' picks it here)")
            elif integrator == "rkc":
                rho = RKC_RHO_FRACTION * 2.0 / dt
                stages = RKC_STAGES * math.sqrt(1.54 * per_drained * dt * rho)
                steps = unfractured * (RKC_EXPLICIT + stages / RKC_STAGES_PER_STEP)
                c0, c1 = RKC_SWEEP_SECONDS
                c1 = LIST_PORE_SECONDS if list_sweep else c1
                wall = unfractured * stages * (c0 + RKC_STAGE_FACTOR * c1 * pores)
                wall += unfractured * RKC_EXPLICIT * (c0 + c1 * pores)
                wall *= local_steps_factor(scene, pores, rigid)
                wall += drained * EXPLICIT_DRAINED_SECONDS * n
                notes.append("rkc integrator (stabilised explicit steps)")
            else:
                steps = unfractured * (1.0 + per_drained)
                steps += pressure_step_steps(
                    n, ca, float(disorder), getattr(fluid, "pressure_step", None)
                )
                c0, c1 = EXPLICIT_STEP_SECONDS
                c1 = LIST_PORE_SECONDS if list_sweep else c1
                wall = steps * (c0 * n + c1 * pores)
                wall += drained * EXPLICIT_DRAINED_SECONDS * n
        if stop.at == "complete":
            notes.append("stop.at = 'complete' with the viscous model: drained count from IP")

    updates: float | None = 0.0
    if not rigid:
        if not hertz:
            updates = None
            wall = None
        elif steps is None:
            updates = None
        else:
            memory += (MEMORY_HERTZ + (MEMORY_MINDLIN if mindlin else 0.0)) * pores
            schedule = getattr(solid, "coupling", "every-step")
            tol = float(getattr(solid, "coupling_tolerance", ADAPTIVE_TOLERANCE))
            if schedule == "every-step":
                updates = steps
            elif schedule == "interval":
                updates = steps / max(1, int(getattr(solid, "coupling_interval", 1)))
            elif fluid.kind == "invasion-percolation":
                # one per drained pore, unless the solid is too stiff to move by the tolerance
                updates = steps * adaptive_update_fraction(nf, tol) / ADAPTIVE_UPDATE_FRACTION
            else:
                updates = steps * adaptive_update_fraction(nf, tol)
            if wall is not None:
                wall += steps * (COUPLED_STEP_SECONDS[0] + COUPLED_STEP_SECONDS[1] * pores)
                c, c_fracture, p = UPDATE_SECONDS
                if mindlin:
                    wall += updates * MINDLIN_UPDATE_SECONDS * pores * slide
                else:
                    wall += updates * (c + c_fracture * w) * pores**p

    def _int(value: float | None) -> int | None:
        return None if value is None else round(value)

    return CostEstimate(
        drained=_int(drained),
        steps=_int(steps),
        mechanical_updates=_int(updates),
        memory_bytes=_int(memory),
        wall_seconds=wall,
        notes=tuple(notes),
    )
