"""Publication defaults for porenet's figures, colour-blind-safe colours and readable units.

Every plotting function of :mod:`porenet.viz` draws inside :func:`styled` (a
``matplotlib.rc_context`` with :func:`rc`), so the defaults never leak into the caller's
global matplotlib state. Maps use perceptually uniform sequential colour maps (viridis,
cividis, magma); signed data use a diverging ColorBrewer map (``RdBu_r``) centred on zero;
lines cycle through the Okabe-Ito palette. None of these rely on red-green contrast.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, TypeVar

F = TypeVar("F", bound=Callable[..., Any])

#: Okabe & Ito (2008) colour-blind-safe palette (black last: kept for reference lines).
OKABE_ITO: tuple[str, ...] = (
    "#0072B2",  # blue
    "#E69F00",  # orange
    "#009E73",  # bluish green
    "#D55E00",  # vermillion
    "#CC79A7",  # reddish purple
    "#56B4E9",  # sky blue
    "#F0E442",  # yellow
    "#000000",  # black
)

#: Sequential maps (drainage order, time, pressure) and the diverging map (signed changes).
SEQUENTIAL = "viridis"
DIVERGING = "RdBu_r"

#: Defender pores cut off from the outlet, in pattern maps.
TRAPPED_GREY = "0.72"


def rc() -> dict[str, Any]:
    """The rc parameters of porenet's figures (fonts, ticks, lines, colour cycle, dpi)."""
    from cycler import cycler

    return {
        "font.size": 9.0,
        "axes.titlesize": 9.5,
        "axes.labelsize": 9.0,
        "xtick.labelsize": 8.0,
        "ytick.labelsize": 8.0,
        "legend.fontsize": 8.0,
        "legend.frameon": False,
        "axes.linewidth": 0.8,
        "axes.prop_cycle": cycler(color=OKABE_ITO),
        "axes.formatter.use_mathtext": True,
        "axes.formatter.limits": (-3, 4),
        "lines.linewidth": 1.4,
        "lines.markersize": 4.5,
        "xtick.direction": "out",
        "ytick.direction": "out",
        "xtick.major.width": 0.8,
        "ytick.major.width": 0.8,
        "image.cmap": SEQUENTIAL,
        "image.interpolation": "nearest",
        "mathtext.default": "regular",
        "figure.dpi": 150,
        "savefig.dpi": 300,
        "pdf.fonttype": 42,  # TrueType fonts in PDF/PS: editable text for journals
        "ps.fonttype": 42,
        "svg.fonttype": "none",
    }


def styled(func: F) -> F:
    """Run ``func`` inside ``matplotlib.rc_context(rc())`` (imports matplotlib lazily)."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        import matplotlib

        with matplotlib.rc_context(rc()):
            return func(*args, **kwargs)

    return wrapper  # type: ignore[return-value]


def _prefixed(
    value: float, units: tuple[tuple[str, float], ...], least: float = 1.0
) -> tuple[str, float]:
    """The largest unit in which ``|value|`` is at least ``least``."""
    value = abs(float(value))
    for unit, factor in units:
        if value >= least * factor:
            return unit, factor
    return units[-1]


def length_unit(length_m: float) -> tuple[str, float]:
    """A readable unit for lengths up to ``length_m`` (m) and its size in m."""
    return _prefixed(length_m, (("m", 1.0), ("mm", 1e-3), ("µm", 1e-6), ("nm", 1e-9)))


def pressure_unit(pressure_pa: float) -> tuple[str, float]:
    """A readable unit (Pa, kPa, MPa, GPa) for pressures up to ``pressure_pa`` and its size."""
    return _prefixed(pressure_pa, (("GPa", 1e9), ("MPa", 1e6), ("kPa", 1e3), ("Pa", 1.0)))


def time_unit(time_s: float) -> tuple[str, float]:
    """A readable unit (s, ms, µs, ns) for times up to ``time_s`` and its size in s."""
    return _prefixed(time_s, (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6), ("ns", 1e-9)))


def volume_unit(volume_m3: float) -> tuple[str, float]:
    """A readable unit (m³, mm³, µm³, nm³) for volumes up to ``volume_m3`` and its size
    (the prefixes are 10⁹ apart, so the largest in which the volume is at least 0.001)."""
    units = (("m³", 1.0), ("mm³", 1e-9), ("µm³", 1e-18), ("nm³", 1e-27))
    return _prefixed(volume_m3, units, least=1e-3)


def format_pressure(pressure_pa: float) -> str:
    """``1.48e6`` -> ``"1.48 MPa"``."""
    unit, factor = pressure_unit(pressure_pa)
    return f"{pressure_pa / factor:.3g} {unit}"


def scene_title(data: Any, extra: list[str] | None = None, width: int = 48) -> str:
    """A short description of a run's scene (name or models, n, Ca, λ, N_f, then ``extra``),
    broken into lines of about ``width`` characters."""
    scene = data.scene
    lat, fluid, solid = scene.get("lattice", {}), scene.get("fluid", {}), scene.get("solid", {})
    kind = fluid.get("kind", "")
    from porenet.core.plan import scene_is_deformable

    if solid.get("kind") is not None and scene_is_deformable(scene, data.summary):
        kind = f"{kind} + {solid['kind']}" if kind else solid["kind"]
    parts = [scene.get("name") or kind]
    shape = lat.get("shape")
    if shape is not None:  # the cubic lattice: nx x ny x nz
        parts.append(" x ".join(str(s) for s in (shape if shape[-1] > 1 else shape[:2])))
    elif data.grid_shape is not None:
        parts.append(f"n = {data.grid_shape[0]}")
    if fluid.get("capillary_number") is not None:
        parts.append(f"Ca = {fluid['capillary_number']:.3g}")
    if lat.get("disorder") is not None:
        parts.append(f"λ = {lat['disorder']:.3g}")
    nf = data.summary.get("fracturing_number", solid.get("fracturing_number"))
    if nf is not None:
        parts.append(f"N_f = {nf:.3g}")
    lines: list[str] = []
    for part in [p for p in [*parts, *(extra or [])] if p]:
        if lines and len(lines[-1]) + len(part) + 2 <= width:
            lines[-1] += f", {part}"
        else:
            lines.append(part)
    return ",\n".join(lines)
