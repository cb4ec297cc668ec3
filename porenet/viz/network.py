"""The invasion pattern of a lattice without a grid layout: an irregular 2-D network drawn as
its pores and throats, a 3-D lattice as three projections (docs/plots.md).

:func:`porenet.viz.pattern.plot_pattern` calls :func:`draw_network_pattern` for such lattices;
the values (drainage step or invasion time) and their label come from it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

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
    frame = _Frame(data, ax)
    drained = np.isfinite(values)
    trapped = np.asarray(data.trapped, dtype=bool).ravel() & ~drained
    order = np.argsort(np.where(drained, values, -np.inf))[-int(drained.sum()) :]
    size = frame.marker_size(int(drained.sum()))
    image = None
    for panel, (h, v) in zip(frame.axes, frame.panels, strict=True):
        if trapped.any():
            panel.scatter(frame.xyz[trapped, h], frame.xyz[trapped, v], s=size, c=TRAPPED_GREY,
                          linewidths=0, label="trapped defender")  # fmt: skip
        image = panel.scatter(frame.xyz[order, h], frame.xyz[order, v], s=size,
                              c=values[order], cmap=cmap, linewidths=0)  # fmt: skip
    frame.finish(image, label)
    return frame.fig, frame.axes


def draw_network_field(
    data: RunData,
    values: np.ndarray,
    label: str,
    cmap: str,
    ax: Axes | None,
    limits: tuple[float, float],
) -> tuple[Figure, list[Axes]]:
    """Draw every pore coloured by ``values`` (a field such as the pressure), the larger
    values on top: in 2-D the network itself, in 3-D each projection shows the largest value
    along the axis it looks down (a maximum projection; ParaView shows the field inside,
    ``porenet export``). Returns the figure and its map axes."""
    frame = _Frame(data, ax)
    order = np.argsort(values, kind="stable")
    size = frame.marker_size(len(order))
    image = None
    for panel, (h, v) in zip(frame.axes, frame.panels, strict=True):
        image = panel.scatter(frame.xyz[order, h], frame.xyz[order, v], s=size,
                              c=values[order], cmap=cmap, vmin=limits[0], vmax=limits[1],
                              linewidths=0)  # fmt: skip
    frame.finish(image, label, projection="maximum " if frame.three_d else "")
    return frame.fig, frame.axes


class _Frame:
    """The figure, axes and pore coordinates of a network drawing, and its finishing (axes'
    labels and limits, colour bar, projection titles)."""

    def __init__(self, data: RunData, ax: Axes | None) -> None:
        from matplotlib.figure import Figure

        xyz = np.asarray(data.pore_coords, dtype=np.float64)
        self.unit, factor = length_unit(float(np.ptp(xyz, axis=0).max()) or data.pore_size)
        self.xyz = xyz / factor
        self.three_d = xyz.shape[1] == 3
        self.panels = PROJECTIONS if self.three_d and ax is None else PROJECTIONS[:1]
        if ax is None:
            self.fig = Figure(figsize=(4.6 * len(self.panels), 4.3), dpi=150,
                              layout="constrained")  # fmt: skip
            self.axes = [self.fig.add_subplot(1, len(self.panels), k + 1)
                         for k in range(len(self.panels))]  # fmt: skip
        else:
            self.fig, self.axes = ax.figure, [ax]  # type: ignore[assignment]
        if not self.three_d and len(data.throat_pores) <= MAX_THROAT_LINES:
            for panel in self.axes:
                _draw_throats(panel, self.xyz, np.asarray(data.throat_pores))

    def marker_size(self, n_shown: int) -> float:
        n = len(self.xyz)
        return _marker_size(n_shown, n ** (2.0 / 3.0) if self.three_d else n)

    def finish(self, image: Any, label: str, projection: str = "") -> None:
        lo, hi = self.xyz.min(axis=0), self.xyz.max(axis=0)
        pad = 0.02 * float(np.ptp(self.xyz, axis=0).max() or 1.0)
        for panel, (h, v) in zip(self.axes, self.panels, strict=True):
            panel.set_xlabel(f"{AXIS_NAMES[h]} ({self.unit})")
            panel.set_ylabel(f"{AXIS_NAMES[v]} ({self.unit})")
            panel.set_aspect("equal")
            panel.set_xlim(lo[h] - pad, hi[h] + pad)
            panel.set_ylim(lo[v] - pad, hi[v] + pad)
            if self.three_d:
                name = f"{AXIS_NAMES[h]}-{AXIS_NAMES[v]} {projection}projection"
                panel.set_title(name, fontsize="small")
        if image is not None:
            self.fig.colorbar(image, ax=self.axes, label=label, shrink=0.85)


def _draw_throats(ax: Axes, xyz: np.ndarray, throat_pores: np.ndarray) -> None:
    from matplotlib.collections import LineCollection

    segments = np.stack([xyz[throat_pores[:, 0], :2], xyz[throat_pores[:, 1], :2]], axis=1)
    ax.add_collection(LineCollection(segments, colors="0.85", linewidths=0.4, zorder=0))
