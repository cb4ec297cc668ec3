"""The cost estimate of the viscous model (docs/cost.md): arithmetic on the scene alone.

Drained pores: as invasion percolation (:func:`porenet.kinds.invasion.cost.drained_fraction`;
measured within ~1.3x from Ca* = 0.3 to 10), more under fast injection (up to ~``0.3 n^0.12``
of the lattice from Ca = 1e2); a medium that fractures drains ~``2 n`` for ``N_f >= 1.5``.
Steps, explicit integrator: the pump delivers ``q = Ca A_b / a^2`` volumes ``a^3`` per unit
scaled time, a drained pore takes ~2.8 mean pore volumes (counting what the compressible
defender stores), the step is the stability limit with the widest throats, ``c_V / (2 c_A c_k
r_max^4)`` with ``r_max = (1 + lambda) r_mean``, and each landing adds a step: ``1 + 2.8 c_V /
(q dt)`` steps per drained pore, counted on the pores a rigid medium would drain (fracturing
changes the time to breakthrough far less than the drained count); the accuracy limit
``pressure_step`` adds ~``20 n sqrt(Ca)`` steps. Implicit integrator: 13 steps per drained
pore. RKC: stage sweeps per drained pore ``3.2 sqrt(1.54 T rho)`` plus 12 explicit steps near
each landing. ``integrator = "auto"`` is resolved by the model's own rule
(:func:`porenet.kinds.viscous.config.auto_integrator`). Wall time: ``steps (1.5e-7 n + 1.8e-9
N) + drained 2.9e-6 n`` (explicit), ``drained 0.039 (N / 2500)^1.41`` (implicit); RKC with
local time steps on large lattices ~1/3 of its time without (:data:`LOCAL_STEPS_FACTOR`).
"""

from __future__ import annotations

import math
from typing import Any

from porenet.core.cost import CostRequest, FluidCost
from porenet.core.sites import site_geometry
from porenet.kinds.invasion import cost as invasion_cost
from porenet.kinds.invasion.cost import drained_fraction, fractured
from porenet.kinds.viscous.config import auto_integrator

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
#: Fracturing: drained pores per pore of side once fractured, and the N_f range interpolated
#: over (Fig. 5 at n = 100 and 400).
FRACTURE = (2.0, (0.3, 1.5))
#: Adaptive coupling: fraction of fluid steps followed by a mechanical update at full strength
#: (N_f >= 0.1 at the default tolerance; :attr:`FluidCost.adaptive_scale`).
ADAPTIVE_SCALE = 0.3
#: Peak memory of the model's fields, and of the implicit integrator's factorisation, bytes
#: per pore.
MEMORY_VISCOUS = 250.0
MEMORY_IMPLICIT = 2000.0
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
#: Per drained pore and pore of side (the located landing, new menisci).
EXPLICIT_DRAINED_SECONDS = 2.9e-6
#: Implicit integrator, per drained pore at N = 2500, and the exponent of N.
IMPLICIT_DRAINED_SECONDS = (0.039, 1.41)


def fracture_weight(nf: float | None) -> float:
    """How far a medium of ``N_f`` fractures under viscous injection: 0 up to ``N_f = 0.3``, 1
    from 1.5, linear in ``log N_f`` between (:data:`FRACTURE`)."""
    return invasion_cost.fracture_weight(nf, FRACTURE[1])


def entry_spread(disorder: float) -> float:
    """Spread of entry pressures ``2 (1/r_min - 1/r_max)`` in units of ``gamma / r_mean``:
    ``4 lambda / (1 - lambda^2)`` (the scale of ``pressure_step``)."""
    return 4.0 * disorder / (1.0 - disorder**2)


def fast_injection_fraction(n: int, ca: float, ip_fraction: float) -> float:
    """Drained fraction at breakthrough at capillary number ``ca``: IP's up to :data:`FAST_CA`
    ``[0]``, ``a n^b`` (:data:`FAST_FRACTION`) from ``FAST_CA[1]``, linear in ``log Ca``
    between."""
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


def pump_rate(scene: Any, cross_section: int) -> float | None:
    """Injection rate ``q`` in scaled units (volume ``a^3`` per scaled time ``mu a / gamma``),
    ``None`` without rate control; ``cross_section`` is the lattice's ``A_b / a^2`` at the
    scene's injection site."""
    fluid, lat = scene.fluid, scene.lattice
    if getattr(fluid, "control", "rate") != "rate":
        return None
    ca = getattr(fluid, "capillary_number", None)
    if ca is not None:
        return float(ca) * cross_section
    rate = getattr(fluid, "injection_rate", None)
    if rate is None:
        return None
    a = float(getattr(lat, "pore_size", 1.0))
    return float(rate) * float(fluid.viscosity) / (a**2 * float(fluid.interfacial_tension))


def local_steps_factor(request: CostRequest) -> float:
    """What local time steps do to the RKC integration's wall time (:data:`LOCAL_STEPS_FACTOR`):
    1 where they do not apply (``local_steps = "off"``, a coupled solid, pressure control, a
    lattice other than the square grid) or, on lattices smaller than the box where they start."""
    fluid, extent = request.scene.fluid, request.extent
    if getattr(fluid, "local_steps", "off") == "off" or request.deformable:
        return 1.0
    if fluid.control != "rate" or not extent.canonical_grid:  # local steps need a square grid
        return 1.0
    (n0, f0), (n1, f1) = LOCAL_STEPS_MIN_BOX, LOCAL_STEPS_FACTOR
    pores = extent.pores
    if pores < n0:
        return 1.0
    if pores >= n1:
        return f1
    return f0 * (f1 / f0) ** (math.log(pores / n0) / math.log(n1 / n0))


def estimate(config: Any, request: CostRequest) -> FluidCost:
    """Drained pores, time steps, memory and wall time of the viscous model."""
    scene, extent = request.scene, request.extent
    fluid, lat, stop = scene.fluid, scene.lattice, scene.stop
    n, pores = extent.side, extent.pores
    fraction, notes = drained_fraction(request)
    if extent.dimension == 3:
        notes.append(
            "3-D lattice: sweeps at the adjacency lists' cost per pore (measured for the "
            "explicit integrator, not for rkc or implicit; docs/cost.md)"
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
    cross_section = extent.cross_section(site_geometry(scene.injection.at))
    q = pump_rate(scene, cross_section)
    ca = None if q is None else q / cross_section
    if ca is not None and stop.at == "breakthrough":
        fraction = fast_injection_fraction(n, ca, fraction)
    expected = pores * fraction
    if stop.max_drained is not None:
        expected = min(expected, float(stop.max_drained))
    #: What the medium would drain were it rigid: the time to breakthrough, and so the
    #: steps, change far less with fracturing than the drained count does.
    unfractured = max(1.0, expected)
    expected, w, fracture_notes = fractured(request, expected, FRACTURE)
    notes += fracture_notes
    drained = max(1.0, expected)

    memory = MEMORY_VISCOUS * pores
    steps: float | None
    wall: float | None
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
            wall *= local_steps_factor(request)
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
    return FluidCost(
        drained=drained,
        steps=steps,
        wall_seconds=wall,
        memory_bytes=memory,
        notes=tuple(notes),
        fracture_weight=w,
        adaptive_scale=ADAPTIVE_SCALE,
    )
