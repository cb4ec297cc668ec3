"""The invasion pattern, coloured by drainage order or by invasion time."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from porenet.viz.style import SEQUENTIAL, TRAPPED_GREY, length_unit, scene_title, styled, time_unit

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from porenet.result import RunData

#: What :func:`plot_pattern` can colour drained pores by.
COLOR_BY = ("order", "time")


def grid_axes(
    data: RunData, ax: Axes | None, figsize: tuple[float, float] = (5.0, 4.3)
) -> tuple[Figure, Axes, tuple, str]:
    """A figure and axes for a map of a grid lattice (new ones unless ``ax`` is given), the
    image extent ``(left, right, bottom, top)`` in a readable length unit, and that unit.

    Pore ``(i, j)`` is drawn centred at ``x = (2j + 1) a``, ``y = (2i + 1) a`` (row 0 at the top),
    as in ``RunData.pore_coords``.
    """
    from matplotlib.figure import Figure

    if data.grid_shape is None:
        raise ValueError("this lattice has no grid layout, so it cannot be drawn as a map")
    if ax is None:
        fig = Figure(figsize=figsize, dpi=150, layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure  # type: ignore[assignment]
    rows, cols = data.grid_shape
    side = 2.0 * data.pore_size
    unit, factor = length_unit(max(rows, cols) * side)
    return fig, ax, (0.0, cols * side / factor, rows * side / factor, 0.0), unit


def label_map(ax: Axes, unit: str) -> None:
    """Axis labels in ``unit`` and an equal aspect ratio. The axes span the lattice's physical
    extent, ``2 n a`` (node spacing 2a), twice the paper's ``L = n a`` (docs/model.md
    section 1); the x label says so."""
    ax.set_xlabel(f"x ({unit}; the lattice spans 2 n a, L = n a)")
    ax.set_ylabel(f"y ({unit})")
    ax.set_aspect("equal")


def draw_trapped(data: RunData, ax: Axes, extent: tuple, legend: bool = True) -> None:
    """Trapped defender pores in grey (and a legend entry below the axes if any)."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    trapped = data.as_grid(data.trapped & ~data.drained).astype(float)
    if not trapped.any():
        return
    trapped[trapped == 0] = np.nan
    ax.imshow(trapped, cmap=ListedColormap([TRAPPED_GREY]), extent=extent, interpolation="nearest")
    if legend:  # below the x label (as wide as a small panel's axes), not over it
        from matplotlib.transforms import offset_copy

        label = ax.xaxis.label.get_size()
        labels = label + max((t.get_size() for t in ax.get_xticklabels()), default=label)
        below = offset_copy(ax.transAxes, fig=ax.figure, y=-(1.5 * labels + 8), units="points")
        ax.legend(
            handles=[Patch(facecolor=TRAPPED_GREY, label="trapped defender")],
            loc="upper right",
            bbox_to_anchor=(1.0, 0.0),
            bbox_transform=below,
            borderaxespad=0.0,
            handlelength=1.0,
        )


def pore_times(data: RunData) -> np.ndarray:
    """(N,) invasion time of every pore (s), ``nan`` where never drained.

    Raises ValueError for quasi-static runs, which record no times.
    """
    if data.invasion_time is None:
        kind = data.scene.get("fluid", {}).get("kind", "?")
        raise ValueError(
            f"colouring by time needs a dynamic run; this {kind!r} run is quasi-static "
            "(no invasion times recorded): colour by 'order' instead"
        )
    times = np.full(data.n_pores, np.nan)
    times[data.order] = data.invasion_time
    return times


@styled
def plot_pattern(
    data: RunData,
    ax: Axes | None = None,
    cmap: str = SEQUENTIAL,
    title: str | None = None,
    color_by: str = "order",
) -> Figure:
    """Drained pores coloured by drainage order or invasion time; trapped defender grey;
    defender white.

    Parameters
    ----------
    data : RunData
        A run (``porenet.read_run(path)`` or ``RunResult.data``). A grid lattice is drawn as
        an image; any other as its pores (and throats) in 2-D, or as three projections in
        3-D (:mod:`porenet.viz.network`).
    ax : matplotlib Axes, optional
        Axes to draw into; a new figure is made otherwise.
    cmap : str
        A perceptually uniform, colour-blind-safe map (default viridis).
    title : str, optional
        Defaults to a description of the scene.
    color_by : {"order", "time"}
        ``"order"``: drainage step (0 for the inlet). ``"time"``: time of drainage since the
        start of injection, in s (dynamic runs only; ValueError otherwise).
    """
    if color_by not in COLOR_BY:
        raise ValueError(f"color_by must be one of {', '.join(COLOR_BY)}, not {color_by!r}")
    if color_by == "time":
        values = pore_times(data)
        t_unit, t_factor = time_unit(np.nanmax(values) if np.isfinite(values).any() else 1.0)
        values = values / t_factor
        label = f"invasion time ({t_unit})"
    else:
        values = data.drainage_step().astype(float)
        values[values < 0] = np.nan
        label = "drainage step"
    if data.grid_shape is None:  # an irregular network or a 3-D lattice
        from porenet.viz.network import draw_network_pattern

        fig, axes = draw_network_pattern(data, values, label, cmap, ax)
        ax = axes[0]
        if len(axes) > 1:  # the projections of a 3-D pattern: one title over the panels
            fig.suptitle(title or scene_title(data, _extra(data)))
            return fig
    else:
        fig, ax, extent, unit = grid_axes(data, ax)
        draw_trapped(data, ax, extent)
        im = ax.imshow(data.as_grid(values), cmap=cmap, extent=extent, interpolation="nearest")
        fig.colorbar(im, ax=ax, label=label, shrink=0.85)
        label_map(ax, unit)
    ax.set_title(title or scene_title(data, _extra(data)))
    return fig


def _extra(data: RunData) -> list[str]:
    """Whether the run trapped the defender, for the title (where the fluid model says)."""
    fluid = data.scene.get("fluid", {})
    return [("trapping" if fluid["trapping"] else "no trapping")] if "trapping" in fluid else []


def save_figure(fig: Figure, path: Any, **kwargs: Any) -> None:
    """Save a figure made without pyplot (Agg canvas; porenet's dpi and font defaults).

    The format follows the file's suffix (png, pdf, svg, ...) unless ``format`` is given;
    ``kwargs`` go to ``Figure.savefig``. A path is written atomically: the picture is drawn
    in memory and written by :func:`porenet.io.atomic.atomic_write_bytes`, so a failure (a
    full disk) leaves no partial picture and raises an
    :class:`~porenet.core.errors.OutputError` naming the path. A file object is written
    directly.
    """
    import io
    import os

    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from porenet.viz.style import rc

    FigureCanvasAgg(fig)
    if not isinstance(path, str | os.PathLike):
        with matplotlib.rc_context(rc()):
            fig.savefig(path, **kwargs)
        return
    from porenet.io.atomic import atomic_write_bytes

    suffix = os.path.splitext(os.fspath(path))[1].lstrip(".").lower()
    kwargs.setdefault("format", suffix or None)
    buffer = io.BytesIO()
    with matplotlib.rc_context(rc()):
        fig.savefig(buffer, **kwargs)
    atomic_write_bytes(path, buffer.getbuffer(), what="picture")
