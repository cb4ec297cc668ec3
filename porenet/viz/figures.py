"""Every figure ``porenet plot --kind KIND`` makes, by kind, and what each needs of a run.

>>> from porenet.io.runfile import read_run
>>> fig = make_figure(read_run("run.h5"), "pressure")  # doctest: +SKIP
>>> save_figure(fig, "halo.pdf")  # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from porenet.plot_kinds import PLOT_KIND_DESCRIPTIONS
from porenet.viz.style import scene_title, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from porenet.result import RunData


def _fluid_kind(data: RunData) -> str:
    return str(data.scene.get("fluid", {}).get("kind", "?"))


def figure_pattern(data: RunData) -> Figure:
    from porenet.viz.pattern import plot_pattern

    return plot_pattern(data, color_by="order")


def figure_time(data: RunData) -> Figure:
    from porenet.viz.pattern import plot_pattern

    return plot_pattern(data, color_by="time")


def figure_pressure(data: RunData) -> Figure:
    from porenet.viz.pressure import plot_pressure_halo

    return plot_pressure_halo(data)


@styled
def figure_fractal(data: RunData) -> Figure:
    """Mass against distance from the inlet with its fit (injection at the centre) beside box
    counting, each from ``pattern_dimension`` with its automatic range."""
    from matplotlib.figure import Figure

    from porenet.analysis.fractal import pattern_dimension
    from porenet.viz.fractal import plot_fractal_fit

    methods = ["box-counting"]
    if data.scene.get("injection", {}).get("at", "centre") == "centre":
        methods.insert(0, "mass-radius")
    fits = [pattern_dimension(data, method=m) for m in methods]
    fig = Figure(figsize=(4.2 * len(fits), 3.6), dpi=150, layout="constrained")
    for ax, fit in zip(fig.subplots(1, len(fits), squeeze=False)[0], fits, strict=True):
        plot_fractal_fit(fit, ax=ax, spacing=2.0 * data.pore_size)
        ax.set_title(fit.method)
    fig.suptitle(scene_title(data, width=40 * len(fits)))
    return fig


def figure_mechanics(data: RunData) -> Figure:
    from porenet.viz.mechanics import plot_mechanics

    return plot_mechanics(data)


def figure_timeseries(data: RunData) -> Figure:
    from porenet.viz.timeseries import plot_timeseries

    return plot_timeseries(data)


#: kind -> function(RunData) -> Figure; the kinds and their order are
#: :data:`porenet.plot_kinds.PLOT_KIND_DESCRIPTIONS`'s.
_FIGURES: dict[str, Callable[[RunData], Figure]] = {
    "pattern": figure_pattern,
    "time": figure_time,
    "pressure": figure_pressure,
    "fractal": figure_fractal,
    "mechanics": figure_mechanics,
    "timeseries": figure_timeseries,
}

#: kind -> (function(RunData) -> Figure, one-line description).
PLOT_KINDS: dict[str, tuple[Callable[[RunData], Figure], str]] = {
    kind: (_FIGURES[kind], description) for kind, description in PLOT_KIND_DESCRIPTIONS.items()
}

#: Kinds drawn as an image of the grid (the pattern and times are drawn on any lattice:
#: porenet.viz.network).
_MAPS = ("mechanics",)


def missing(data: RunData, kind: str) -> str | None:
    """What ``data`` lacks for a figure of ``kind``, as the end of a sentence starting with the
    run's name (e.g. ``"is a rigid run (no mechanics recorded)"``); None if nothing."""
    if kind not in PLOT_KINDS:
        raise ValueError(f"unknown plot kind {kind!r}; known kinds: {', '.join(PLOT_KINDS)}")
    if kind == "time" and data.invasion_time is None:
        return f"is a quasi-static {_fluid_kind(data)!r} run (no invasion times recorded)"
    if kind == "pressure" and data.pressure is None:
        return f"has no pressure field (fluid kind {_fluid_kind(data)!r} defines none)"
    if kind == "mechanics" and (data.final_apertures is None or not data.mechanics_final):
        return "is a rigid run (no mechanics recorded)"
    if kind in _MAPS and data.grid_shape is None:
        return (
            "has no grid layout (the mechanics map needs a grid lattice; `porenet export "
            "RUN.h5` writes the apertures for ParaView, docs/run-file.md)"
        )
    if kind in ("fractal", "timeseries") and len(data.order) == 0:
        return "has no drained pores"
    return None


def make_figure(data: RunData, kind: str) -> Figure:
    """The figure of ``kind`` (a key of :data:`PLOT_KINDS`) for a run.

    Raises ValueError naming the kind and what the run lacks (e.g. ``kind 'mechanics': the
    run is a rigid run (no mechanics recorded)``).
    """
    lack = missing(data, kind)
    if lack is not None:
        raise ValueError(f"kind {kind!r}: the run {lack}")
    return PLOT_KINDS[kind][0](data)
