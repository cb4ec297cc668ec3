"""The pressure halo: ``log10(p / p_inv)`` around the invasion pattern (the paper's Fig. 1b)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from porenet.viz.pattern import grid_axes, label_map
from porenet.viz.style import format_pressure, scene_title, styled, time_unit

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from porenet.result import RunData


def pressure_ratio(data: RunData, snapshot: int | None = None) -> tuple[np.ndarray, float]:
    """``p / p_inv`` of every pore (1 in drained pores) and ``p_inv`` (Pa).

    Parameters
    ----------
    data : RunData
        A run of a model with a pressure field (kind ``viscous``).
    snapshot : int, optional
        Index into ``data.snapshots``; the final field by default.
    """
    if snapshot is not None:
        snap = data.snapshots[snapshot]
        pressure, drained, p_inv = snap.pressure, snap.drained, snap.invading_pressure
    else:
        if data.pressure is None:
            raise ValueError("this run has no pressure field (invasion percolation defines none)")
        pressure, drained = data.pressure, data.drained
        p_inv = float(data.summary.get("final_invading_pressure", np.max(pressure)))
    if not p_inv > 0:
        raise ValueError(f"the invading pressure is {p_inv:g} Pa; p / p_inv is undefined")
    ratio = np.asarray(pressure, dtype=np.float64) / p_inv
    ratio[np.asarray(drained, dtype=bool)] = 1.0
    return ratio, p_inv


@styled
def plot_pressure_halo(
    data: RunData,
    ax: Axes | None = None,
    snapshot: int | None = None,
    floor: float = 1e-4,
    cmap: str = "magma",
    title: str | None = None,
) -> Figure:
    """``log10(p / p_inv)`` of every pore: 0 in the invader, falling off through the defender.

    Parameters
    ----------
    data : RunData
        A run with a pressure field. On a grid lattice a map; on a network its pores
        (2-D) or three maximum projections (3-D; :func:`porenet.viz.network.draw_network_field`).
    ax : matplotlib Axes, optional
    snapshot : int, optional
        Index into ``data.snapshots`` (default: the final field).
    floor : float
        Ratios below ``floor`` (and non-positive ones) are drawn at ``log10(floor)``.
    cmap : str
        A perceptually uniform colour map.
    title : str, optional
    """
    ratio, p_inv = pressure_ratio(data, snapshot)
    values = np.log10(np.clip(ratio, floor, None))
    label = r"$\log_{10}(p / p_{inv})$"
    if data.grid_shape is None:
        from porenet.viz.network import draw_network_field

        fig, axes = draw_network_field(data, values, label, cmap, ax, (np.log10(floor), 0.0))
    else:
        fig, ax, extent, unit = grid_axes(data, ax)
        im = ax.imshow(values.reshape(data.grid_shape), cmap=cmap, extent=extent,
                       interpolation="nearest", vmin=np.log10(floor), vmax=0.0)  # fmt: skip
        fig.colorbar(im, ax=ax, label=label, shrink=0.85)
        label_map(ax, unit)
        axes = [ax]
    if title is None:
        extra = [f"p_inv = {format_pressure(p_inv)}"]
        if snapshot is not None:
            t = data.snapshots[snapshot].time
            t_unit, t_factor = time_unit(t or 1.0)
            extra.append(f"t = {t / t_factor:.3g} {t_unit}")
        title = scene_title(data, extra)
    if len(axes) > 1:  # the projections keep their own titles
        fig.suptitle(title)
    else:
        axes[0].set_title(title)
    return fig
