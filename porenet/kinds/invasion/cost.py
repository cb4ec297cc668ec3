"""The cost estimate of invasion percolation (docs/cost.md): arithmetic on the scene alone.

Drained pores: invasion percolation from the centre drains a fraction ``0.21 n^-0.14`` of an
``n x n`` lattice by breakthrough (ensemble mean with trapping, x1.2 without), ``1.37
n^-0.167`` at completion with trapping, all of it without; left-edge injection and the 3-D
lattice have their own fits. The viscous model drains about as much and uses
:func:`drained_pores` too. A deformable medium that fractures drains ~``n / 2`` for ``N_f >=
5``, interpolated geometrically from the rigid count over :data:`FRACTURE`'s range. Steps: one
per drained pore. Wall time: ``3e-3 + 2.3e-7 N`` (times ``(N / 640 000)^0.3`` above 640 000
pores). Each constant's measurement is in docs/cost.md.
"""

from __future__ import annotations

import math
from typing import Any

from porenet.core.cost import CostRequest, FluidCost
from porenet.core.sites import site_geometry

#: Centre injection, ensemble mean drained fraction at breakthrough ``a n^-b`` with trapping
#: (n = 25-800, 12-32 seeds each; docs/cost.md).
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
#: Fracturing: drained pores per pore of side once fractured, and the N_f range interpolated
#: over (n = 50 and 100, one straight fracture).
FRACTURE = (0.5, (1.0, 5.0))
#: Wall time (s): fixed and per pore ...
IP_SECONDS = (3e-3, 230e-9)
#: ... times ``(N / N0)^p`` above N0 pores, where the arrays outgrow the caches (n = 3000:
#: 6.2 s measured, 2.1 s without it; docs/cost.md, "Hard cases").
IP_LARGE = (640_000, 0.3)
#: An adaptive coupler updates the solid after every drained pore that moves it by more than
#: its tolerance: the fraction of the steps at full strength (:attr:`FluidCost.adaptive_scale`).
ADAPTIVE_SCALE = 1.0


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


def drained_fraction(request: CostRequest) -> tuple[float, list[str]]:
    """The fraction of the lattice invasion percolation drains by the scene's stop condition,
    on the scene's lattice (2-D fits, or the 3-D ones), and the notes that say which."""
    scene, extent = request.scene, request.extent
    n, at = extent.side, scene.injection.at
    trapping = bool(getattr(scene.fluid, "trapping", True))
    if extent.dimension == 3:
        a, b = IP_3D_FACE if site_geometry(at) == "face" else IP_3D
        note = (
            "3-D lattice: drained pores from 3-D invasion percolation at breakthrough "
            f"({IP_3D[0]} n^-{IP_3D[1]} from the centre, {IP_3D_FACE[0]} n^-{IP_3D_FACE[1]} "
            "from a face; docs/cost.md)"
        )
        return (a * n**-b if scene.stop.at == "breakthrough" else 1.0), [note]
    return ip_drained_fraction(n, at=scene.stop.at, trapping=trapping, injection=at), []


def fracture_weight(nf: float | None, span: tuple[float, float] = FRACTURE[1]) -> float:
    """0 for a medium that does not fracture (rigid, or ``N_f`` below ``span``), 1 for one
    that does (above it), linear in ``log N_f`` between."""
    lo, hi = span
    if nf is None or nf <= lo:
        return 0.0
    if nf >= hi:
        return 1.0
    return math.log(nf / lo) / math.log(hi / lo)


def fractured(
    request: CostRequest, expected: float, fracture: tuple[float, tuple[float, float]]
) -> tuple[float, float, list[str]]:
    """What fracturing does to ``expected`` drained pores: the fracture weight ``w`` of the
    scene's solid (0 unless its contacts open, :attr:`CostRequest.fractures`) over the span
    of ``fracture = (pores per pore of side once fractured, (N_f from, N_f to))``, and the
    drained count interpolated geometrically towards the fractured one."""
    nf = request.fracturing_number
    w = fracture_weight(nf, fracture[1]) if request.fractures else 0.0
    if w <= 0:
        return expected, 0.0, []
    fractured_count = min(expected, fracture[0] * request.extent.side)
    note = f"N_f = {nf:.3g}: fracturing expected, few pores drain"
    return expected ** (1.0 - w) * fractured_count**w, w, [note]


def estimate(config: Any, request: CostRequest) -> FluidCost:
    """Drained pores, steps (one per drained pore) and wall time of invasion percolation."""
    stop, extent = request.scene.stop, request.extent
    pores = extent.pores
    fraction, notes = drained_fraction(request)
    expected = pores * fraction
    if stop.max_drained is not None:
        expected = min(expected, float(stop.max_drained))
    expected, w, fracture_notes = fractured(request, expected, FRACTURE)
    notes += fracture_notes
    drained = max(1.0, expected)
    big, power = IP_LARGE
    wall = IP_SECONDS[0] + IP_SECONDS[1] * pores * max(1.0, pores / big) ** power
    if request.deformable:
        notes.append("deformable: the invasion runs pore by pore")
    return FluidCost(
        drained=drained,
        steps=drained,
        wall_seconds=wall,
        notes=tuple(notes),
        fracture_weight=w,
        adaptive_scale=ADAPTIVE_SCALE,
    )
