"""The invasion pattern, coloured by drainage order."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from porenet.result import RunData


def _length_unit(length_m: float) -> tuple[str, float]:
    for unit, factor in (("m", 1.0), ("mm", 1e-3), ("µm", 1e-6), ("nm", 1e-9)):
        if length_m >= factor:
            return unit, factor
    return "nm", 1e-9


def grid_axes(data: RunData, ax: Axes | None) -> tuple[Figure, Axes, tuple, str]:
    """A figure and axes for a map of a grid lattice (new ones unless ``ax`` is given), the
    image extent in a readable length unit, and that unit."""
    from matplotlib.figure import Figure

    if ax is None:
        fig = Figure(figsize=(5.6, 4.8), dpi=150, layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure  # type: ignore[assignment]
    rows, cols = data.grid_shape  # type: ignore[misc]
    side = 2.0 * data.pore_size
    unit, factor = _length_unit(max(rows, cols) * side)
    return fig, ax, (0.0, cols * side / factor, rows * side / factor, 0.0), unit


def plot_pattern(
    data: RunData, ax: Axes | None = None, cmap: str = "viridis", title: str | None = None
) -> Figure:
    """Drained pores coloured by drainage step; trapped defender grey; defender white.

    Parameters
    ----------
    data : RunData
        A run (``porenet.read_run(path)`` or ``RunResult.data``) on a grid lattice.
    ax : matplotlib Axes, optional
        Axes to draw into; a new figure is made otherwise.
    cmap : str
        A perceptually uniform, colour-blind-safe map (default viridis).
    title : str, optional
        Defaults to a description of the scene.
    """
    from matplotlib.colors import ListedColormap

    if data.grid_shape is None:
        raise ValueError("plot_pattern needs a lattice with a grid layout")
    rows = data.grid_shape[0]
    step = data.drainage_step().astype(float)
    step[step < 0] = np.nan
    image = data.as_grid(step)
    fig, ax, extent, unit = grid_axes(data, ax)
    trapped = data.as_grid(data.trapped & ~data.drained).astype(float)
    trapped[trapped == 0] = np.nan
    ax.imshow(trapped, cmap=ListedColormap(["0.75"]), extent=extent, interpolation="nearest")
    im = ax.imshow(image, cmap=cmap, extent=extent, interpolation="nearest")
    fig.colorbar(im, ax=ax, label="drainage step", shrink=0.85)
    ax.set_xlabel(f"x ({unit})")
    ax.set_ylabel(f"y ({unit})")
    ax.set_aspect("equal")
    if title is None:
        scene = data.scene
        lat, fluid = scene.get("lattice", {}), scene.get("fluid", {})
        parts = [scene.get("name") or fluid.get("kind", ""), f"n = {rows}"]
        if lat.get("disorder") is not None:
            parts.append(f"λ = {lat['disorder']:g}")
        if "trapping" in fluid:
            parts.append("trapping" if fluid["trapping"] else "no trapping")
        title = ", ".join(p for p in parts if p)
    ax.set_title(title, fontsize=10)
    return fig


def save_figure(fig: Figure, path: Any) -> None:
    """Save a figure made without pyplot (Agg canvas)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    fig.savefig(path)
