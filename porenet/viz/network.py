"""The invasion pattern of a lattice without a grid layout: an irregular 2-D network drawn as
its pores and throats, a 3-D lattice as three projections (docs/plots.md).

:func:`porenet.viz.pattern.plot_pattern` calls :func:`draw_network_pattern` for such lattices;
the values (drainage step or invasion time) and their label come from it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from porenet.viz.style import TRAPPED_GREY, length_unit

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from porenet.result import RunData

#: Throats drawn as lines up to this many (beyond, only the pores: the lines would fill the
#: picture and take long to draw).
MAX_THROAT_LINES = 200_000
#: The projections of a 3-D pattern: (horizontal axis, vertical axis) of each panel.
PROJECTIONS = ((0, 1), (0, 2), (1, 2))
AXIS_NAMES = "xyz"


def _marker_size(n_shown: int, panel_pores: float) -> float:
    """Scatter marker area (points^2): pores touch at ~1/sqrt(pores per panel) of the width."""
    return float(np.clip(4e4 / max(panel_pores, 1.0), 0.5, 40.0)) if n_shown else 1.0


def draw_network_pattern(
    data: RunData, values: np.ndarray, label: str, cmap: str, ax: Axes | None
) -> tuple[Figure, list[Axes]]:
    """Draw drained pores coloured by ``values`` (nan where undrained), trapped defender grey.

    2-D: the throats as thin grey lines under the pores (when there are at most
    :data:`MAX_THROAT_LINES`). 3-D: the x-y, x-z and y-z projections side by side (each a
    scatter of the drained pores, later ones on top), or the x-y projection alone in ``ax``.
    Returns the figure and its map axes.
    """
    from matplotlib.figure import Figure

    xyz = np.asarray(data.pore_coords, dtype=np.float64)
    unit, factor = length_unit(float(np.ptp(xyz, axis=0).max()) or data.pore_size)
    xyz = xyz / factor
    three_d = xyz.shape[1] == 3
    panels = PROJECTIONS if three_d and ax is None else PROJECTIONS[:1]
    if ax is None:
        fig = Figure(figsize=(4.6 * len(panels), 4.3), dpi=150, layout="constrained")
        axes = [fig.add_subplot(1, len(panels), k + 1) for k in range(len(panels))]
    else:
        fig, axes = ax.figure, [ax]  # type: ignore[assignment]
    drained = np.isfinite(values)
    trapped = np.asarray(data.trapped, dtype=bool).ravel() & ~drained
    order = np.argsort(np.where(drained, values, -np.inf))[-int(drained.sum()) :]
    size = _marker_size(int(drained.sum()), len(xyz) ** (2.0 / 3.0) if three_d else len(xyz))
    image = None
    for panel, (h, v) in zip(axes, panels, strict=True):
        if not three_d and len(data.throat_pores) <= MAX_THROAT_LINES:
            _draw_throats(panel, xyz, np.asarray(data.throat_pores))
        if trapped.any():
            panel.scatter(xyz[trapped, h], xyz[trapped, v], s=size, c=TRAPPED_GREY,
                          linewidths=0, label="trapped defender")  # fmt: skip
        image = panel.scatter(xyz[order, h], xyz[order, v], s=size, c=values[order],
                              cmap=cmap, linewidths=0)  # fmt: skip
        panel.set_xlabel(f"{AXIS_NAMES[h]} ({unit})")
        panel.set_ylabel(f"{AXIS_NAMES[v]} ({unit})")
        panel.set_aspect("equal")
        lo, hi = xyz.min(axis=0), xyz.max(axis=0)
        pad = 0.02 * float(np.ptp(xyz, axis=0).max() or 1.0)
        panel.set_xlim(lo[h] - pad, hi[h] + pad)
        panel.set_ylim(lo[v] - pad, hi[v] + pad)
    if image is not None:
        fig.colorbar(image, ax=axes, label=label, shrink=0.85)
    if three_d:
        for panel, (h, v) in zip(axes, panels, strict=True):
            panel.set_title(f"{AXIS_NAMES[h]}-{AXIS_NAMES[v]} projection", fontsize="small")
    return fig, axes


def _draw_throats(ax: Axes, xyz: np.ndarray, throat_pores: np.ndarray) -> None:
    from matplotlib.collections import LineCollection

    segments = np.stack([xyz[throat_pores[:, 0], :2], xyz[throat_pores[:, 1], :2]], axis=1)
    ax.add_collection(LineCollection(segments, colors="0.85", linewidths=0.4, zorder=0))
