"""Deformable runs: relative aperture change of every throat and the removed springs."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from porenet.viz.pattern import grid_axes, label_map
from porenet.viz.style import DIVERGING, OKABE_ITO, scene_title, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from porenet.result import RunData


def _require_mechanics(data: RunData) -> None:
    if data.final_apertures is None or "removed_springs" not in data.mechanics_final:
        kind = (data.scene.get("solid") or {}).get("kind", "the default")
        raise ValueError(f"this run's solid ({kind!r}) recorded no mechanics: a rigid medium")


def aperture_change(data: RunData) -> np.ndarray:
    """(M,) relative aperture change ``r_final / r_initial - 1`` of every throat (-)."""
    _require_mechanics(data)
    return np.asarray(data.final_apertures, dtype=float) / np.asarray(data.apertures) - 1.0


def spring_segments(data: RunData, springs: np.ndarray) -> np.ndarray:
    """(K, 2, 2) end points (m) of the given springs: the two particles either side of each
    throat, ``a`` from its midpoint across the throat (docs/model.md section 1)."""
    pores = np.asarray(data.throat_pores)[springs]
    p, q = data.pore_coords[pores[:, 0]], data.pore_coords[pores[:, 1]]
    mid, d = 0.5 * (p + q), q - p
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    across = np.stack([-d[:, 1], d[:, 0]], axis=1) * data.pore_size
    return np.stack([mid - across, mid + across], axis=1)


def throat_image(data: RunData, values: np.ndarray, fill: bool = True) -> np.ndarray:
    """Doubled grid (2R+1, 2C+1): pore (i, j) at pixel (2i+1, 2j+1), particle (i, j) at
    (2i, 2j), and the throat between two 4-neighbour pores on the pixel between them.

    Throat pixels hold ``values``; with ``fill``, pore and particle pixels hold the mean of
    the throats beside them (so the map reads as a field), nan otherwise.
    """
    rows, cols = data.grid_shape  # type: ignore[misc]
    image = np.full((2 * rows + 1, 2 * cols + 1), np.nan)
    tp = np.asarray(data.throat_pores)
    r1, c1 = np.divmod(tp[:, 0], cols)
    r2, c2 = np.divmod(tp[:, 1], cols)
    near = np.abs(r1 - r2) + np.abs(c1 - c2) == 1
    image[(r1 + r2 + 1)[near], (c1 + c2 + 1)[near]] = values[near]
    if fill:  # three passes reach the lattice's edge and corners, beyond the outer throats
        for _ in range(3):
            padded = np.pad(image, 1, constant_values=np.nan)
            beside = np.stack(
                [padded[:-2, 1:-1], padded[2:, 1:-1], padded[1:-1, :-2], padded[1:-1, 2:]]
            )
            count = np.sum(np.isfinite(beside), axis=0)
            total = np.nansum(beside, axis=0)
            gaps = np.isnan(image) & (count > 0)
            image[gaps] = total[gaps] / count[gaps]
    return image


@styled
def plot_aperture_change(
    data: RunData,
    ax: Axes | None = None,
    cmap: str = DIVERGING,
    title: str | None = None,
    pattern: bool = True,
) -> Figure:
    """Map of the relative aperture change of every throat, with the removed springs.

    Throats are drawn between their pores on a doubled grid (pixels of side ``a``), coloured
    by ``r_final / r_initial - 1`` on a diverging map centred on 0 (blue: compacted, red:
    opened), symmetric and logarithmic beyond 1 % of the largest change so that the
    widespread small compaction and the few large openings both show; pore and particle
    pixels take the mean of the throats beside them. Springs open at the end (no contact)
    are black bars joining their two particles across the throat; drained pores are grey.

    Parameters
    ----------
    data : RunData
        A deformable run on a grid lattice (ValueError for a rigid one).
    ax : matplotlib Axes, optional
    cmap : str
        A diverging, colour-blind-safe map.
    title : str, optional
    pattern : bool
        Draw the drained pores in grey.
    """
    from matplotlib.collections import LineCollection
    from matplotlib.colors import ListedColormap, SymLogNorm

    change = aperture_change(data)
    fig, ax, extent, unit = grid_axes(data, ax)
    factor = 2.0 * data.pore_size * data.grid_shape[1] / extent[1]  # type: ignore[index]
    half = 0.5 * data.pore_size / factor
    wide = (extent[0] - half, extent[1] + half, extent[2] + half, extent[3] - half)
    bound = max(float(np.max(np.abs(change))), 1e-12)
    norm = SymLogNorm(10.0 ** (np.floor(np.log10(bound)) - 2), vmin=-bound, vmax=bound)
    image = throat_image(data, change)
    im = ax.imshow(image, cmap=cmap, norm=norm, extent=wide, interpolation="nearest", zorder=0)
    fig.colorbar(im, ax=ax, label=r"aperture change $r / r_0 - 1$ (-)", shrink=0.85)
    if pattern:
        rows, cols = data.grid_shape  # type: ignore[misc]
        shade = np.full((2 * rows + 1, 2 * cols + 1), np.nan)
        shade[1::2, 1::2] = np.where(data.as_grid(data.drained), 1.0, np.nan)
        ax.imshow(shade, cmap=ListedColormap(["0.55"]), extent=wide, interpolation="nearest")
    removed = np.flatnonzero(data.mechanics_final["removed_springs"])
    if removed.size:
        n = max(data.grid_shape)  # type: ignore[arg-type]
        segments = spring_segments(data, removed) / factor
        ax.add_collection(
            LineCollection(
                segments,
                colors="k",
                linewidths=float(np.clip(40.0 / n, 0.4, 1.6)),
                label=f"removed springs ({removed.size})",
                capstyle="butt",
            )
        )
        ax.legend(loc="upper right", bbox_to_anchor=(1.0, -0.1), borderaxespad=0.0)
    ax.set_xlim(extent[0], extent[1])
    ax.set_ylim(extent[2], extent[3])
    label_map(ax, unit)
    if title is None:
        title = scene_title(data)
    ax.set_title(title)
    return fig


@styled
def plot_aperture_histogram(data: RunData, ax: Axes | None = None, bins: int = 40) -> Figure:
    """Histogram of the relative aperture change ``r / r_0 - 1`` of the throats, split into
    throats whose spring holds and throats whose spring was removed (log count axis)."""
    from matplotlib.figure import Figure

    change = aperture_change(data)
    if ax is None:
        fig = Figure(figsize=(4.0, 3.0), dpi=150, layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure  # type: ignore[assignment]
    removed = np.asarray(data.mechanics_final["removed_springs"], dtype=bool)
    edges = np.histogram_bin_edges(change, bins=bins)
    groups = [(change[~removed], "spring holds", OKABE_ITO[0])]
    if removed.any():
        groups.append((change[removed], "spring removed", OKABE_ITO[3]))
    ax.hist(
        [g[0] for g in groups],
        bins=edges,
        stacked=True,
        color=[g[2] for g in groups],
        label=[g[1] for g in groups],
    )
    ax.axvline(0.0, color="0.3", lw=0.8, ls=":")
    ax.set_yscale("log")
    ax.set_xlabel(r"aperture change $r / r_0 - 1$ (-)")
    ax.set_ylabel("throats")
    ax.legend()
    return fig


@styled
def plot_spring_removal(data: RunData, ax: Axes | None = None) -> Figure:
    """Removed springs against drained pores, one point per mechanical update."""
    from matplotlib.figure import Figure

    _require_mechanics(data)
    series = data.mechanics_series
    if ax is None:
        fig = Figure(figsize=(4.0, 3.0), dpi=150, layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure  # type: ignore[assignment]
    if "removed_springs" in series and len(series["removed_springs"]):
        ax.plot(series["drained"], series["removed_springs"], color=OKABE_ITO[3])
    ax.set_xlabel("drained pores")
    ax.set_ylabel("removed springs")
    ax.set_ylim(bottom=0)
    ax.set_xlim(left=0)
    return fig


@styled
def plot_mechanics(data: RunData) -> Figure:
    """The deformable-run figure: aperture-change map with removed springs (left), the
    histogram of aperture changes (top right) and springs removed as drainage proceeds
    (bottom right)."""
    from matplotlib.figure import Figure

    _require_mechanics(data)
    fig = Figure(figsize=(8.6, 4.4), dpi=150, layout="constrained")
    axes = fig.subplot_mosaic([["map", "hist"], ["map", "series"]], width_ratios=[1.7, 1.0])
    plot_aperture_change(data, ax=axes["map"], title="")
    plot_aperture_histogram(data, ax=axes["hist"])
    plot_spring_removal(data, ax=axes["series"])
    removed = int(np.count_nonzero(data.mechanics_final["removed_springs"]))
    fig.suptitle(scene_title(data, [f"{removed} springs removed"], width=90))
    return fig
