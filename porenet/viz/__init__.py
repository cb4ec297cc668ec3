"""Matplotlib figures (never pyplot). Imports matplotlib only when a figure is made.

:func:`make_figure` gives the figure of a kind of :data:`PLOT_KINDS` for a run; the plotting
functions below take a :class:`~porenet.result.RunData` (or a fit) and an optional ``ax``, and
return the ``matplotlib.figure.Figure``; :func:`save_figure` writes one (format from the suffix).
"""

from porenet.viz.figures import PLOT_KINDS, make_figure
from porenet.viz.fractal import plot_fractal_fit
from porenet.viz.mechanics import (
    plot_aperture_change,
    plot_aperture_histogram,
    plot_mechanics,
    plot_spring_removal,
)
from porenet.viz.pattern import plot_pattern, save_figure
from porenet.viz.phase import plot_phase_diagram
from porenet.viz.pressure import plot_pressure_halo
from porenet.viz.timeseries import plot_entry_pressure, plot_timeseries

__all__ = [
    "PLOT_KINDS",
    "make_figure",
    "plot_aperture_change",
    "plot_aperture_histogram",
    "plot_entry_pressure",
    "plot_fractal_fit",
    "plot_mechanics",
    "plot_pattern",
    "plot_phase_diagram",
    "plot_pressure_halo",
    "plot_spring_removal",
    "plot_timeseries",
    "save_figure",
]
