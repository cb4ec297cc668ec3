"""Geometric features of invasion patterns (docs/model.md section 7).

Pure functions on a pattern drawn on a square grid (a 2-D boolean array, one cell per pore,
``True`` where the invader is), plus :func:`pattern_features`, which collects them for a run.
Lengths are in lattice spacings (pores).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy import ndimage

if TYPE_CHECKING:  # pragma: no cover
    from porenet.result import RunData

#: A straight run counts as long from this many pores on (docs/model.md section 7:
#: fracturing opens straight segments "over many pores"; runs of 1-4 pores are common in any
#: fingering pattern).
LONG_RUN = 5


def _runs(lines: np.ndarray) -> np.ndarray:
    """Lengths of the maximal runs of ``True`` along the rows of a 2-D boolean array."""
    padded = np.zeros((lines.shape[0], lines.shape[1] + 2), dtype=np.int8)
    padded[:, 1:-1] = lines
    edges = np.diff(padded, axis=1)
    starts = np.argwhere(edges == 1)  # row-major: the k-th start and k-th end bound one run
    ends = np.argwhere(edges == -1)
    return (ends[:, 1] - starts[:, 1]).astype(np.int64)


def straight_runs(grid: np.ndarray, thin: bool = False) -> np.ndarray:
    """Lengths of all straight runs of drained cells along rows and columns.

    Parameters
    ----------
    grid : 2-D bool array
        The pattern.
    thin : bool
        Count only cells whose two neighbours across the run are not drained, so that a run
        is a channel one pore wide (a fracture or a thin finger), not a row through a compact
        cluster.
    """
    grid = np.asarray(grid, dtype=bool)
    out = []
    for lines in (grid, grid.T):
        if thin:
            side = np.zeros((lines.shape[0] + 2, lines.shape[1]), dtype=bool)
            side[1:-1] = lines
            lines = lines & ~side[:-2] & ~side[2:]
        out.append(_runs(lines))
    return np.concatenate(out)


def longest_straight_run(grid: np.ndarray) -> int:
    """Most consecutive ``True`` cells along any row or column of a 2-D boolean grid: the
    longest straight drained segment of a pattern on a square lattice (fracturing opens
    segments much longer than fingering does)."""
    runs = straight_runs(grid)
    return int(runs.max()) if runs.size else 0


def finger_widths(grid: np.ndarray) -> np.ndarray:
    """Local widths of the drained set, in pores, one per medial-axis cell.

    The width at a cell is ``2 d - 1`` with ``d`` its Euclidean distance (in pores, the cell
    itself counting 1) to the nearest undrained cell; the medial axis is the set of drained
    cells where ``d`` is a local maximum over the 8 neighbours. A finger one pore wide has
    width 1, a square blob of side w has width ~w at its centre. The grid's outside counts as
    undrained.
    """
    grid = np.asarray(grid, dtype=bool)
    if not grid.any():
        return np.zeros(0)
    d = ndimage.distance_transform_edt(np.pad(grid, 1))[1:-1, 1:-1]
    ridge = grid & (d >= ndimage.maximum_filter(d, size=3, mode="constant"))
    return 2.0 * d[ridge] - 1.0


def anisotropy(grid: np.ndarray) -> dict[str, float]:
    """Shape anisotropy of the drained set.

    Returns
    -------
    dict
        ``gyration_ratio``: smallest over largest eigenvalue of the gyration tensor of the
        drained cells (1 for an isotropic set, 0 for a line); ``axis_bias``:
        ``(n_x - n_y) / (n_x + n_y)`` with ``n_x``, ``n_y`` the drained-drained neighbour
        pairs along rows and along columns (0 without a preferred lattice axis).
    """
    grid = np.asarray(grid, dtype=bool)
    rows, cols = np.nonzero(grid)
    if rows.size < 2:
        return {"gyration_ratio": float("nan"), "axis_bias": float("nan")}
    eig = np.linalg.eigvalsh(np.cov(np.vstack([cols, rows]).astype(float), bias=True))
    nx = int(np.count_nonzero(grid[:, 1:] & grid[:, :-1]))
    ny = int(np.count_nonzero(grid[1:] & grid[:-1]))
    ratio = float(eig[0] / eig[1]) if eig[1] > 0 else float("nan")
    bias = (nx - ny) / (nx + ny) if nx + ny else float("nan")
    return {"gyration_ratio": ratio, "axis_bias": float(bias)}


def opened_fraction(data: RunData) -> float:
    """Fraction of the drained pores entered through a throat whose spring was removed.

    Spring ``t`` crosses throat ``t`` (docs/model.md section 5), so a removed spring is a throat
    the solid opened: invasion through opened throats is fracturing, whatever the fractures'
    shape. ``nan`` for runs without mechanics (rigid media), whose plan recorded that the
    apertures the fluid saw never change (``plan_deformable`` false: one-way coupling), or
    without entered pores.
    """
    if (data.summary or {}).get("plan_deformable") is False:
        return math.nan  # the fluid saw the rigid medium's apertures (one-way coupling)
    mechanics = data.mechanics_final or {}
    removed = mechanics.get("removed_springs")
    entered = np.asarray(data.throat)
    entered = entered[entered >= 0]
    if removed is None or entered.size == 0:
        return float("nan")
    return float(np.count_nonzero(np.asarray(removed, dtype=bool)[entered])) / entered.size


def _grid_features(data: RunData) -> dict[str, Any]:
    grid = data.as_grid(data.drained)
    n_drained = int(np.count_nonzero(grid))
    widths = finger_widths(grid)
    runs = straight_runs(grid)
    thin = straight_runs(grid, thin=True)
    long_thin = thin[thin >= LONG_RUN]
    return {
        "drained_fraction": n_drained / grid.size,
        "trapped_fraction": float(np.count_nonzero(data.trapped & ~data.drained)) / grid.size,
        "finger_width_mean": float(widths.mean()) if widths.size else float("nan"),
        "finger_width_median": float(np.median(widths)) if widths.size else float("nan"),
        "longest_run": int(runs.max()) if runs.size else 0,
        "longest_thin_run": int(thin.max()) if thin.size else 0,
        "thin_run_fraction": float(long_thin.sum()) / n_drained if n_drained else 0.0,
        **anisotropy(grid),
    }


def _network_features(data: RunData) -> dict[str, Any]:
    from porenet.analysis.network_features import network_pattern_features

    return network_pattern_features(data, LONG_RUN)


def pattern_features(data: RunData) -> dict[str, Any]:
    """The features a classifier needs, for a run on any lattice: on a grid lattice from the
    grid (the functions above), on any other from the pores and throats
    (:mod:`porenet.analysis.network_features`, the same keys).

    Returns
    -------
    dict
        ``drained_fraction``, ``trapped_fraction`` (defender cut off from the outlet, as a
        fraction of all pores), ``finger_width_mean`` / ``finger_width_median`` (pores, see
        :func:`finger_widths`), ``longest_run`` (any straight run), ``longest_thin_run`` and
        ``thin_run_fraction`` (fraction of drained pores in thin straight runs of at least
        :data:`LONG_RUN` pores), ``opened_fraction`` (:func:`opened_fraction`; ``nan`` in
        rigid media), ``gyration_ratio``, ``axis_bias`` (:func:`anisotropy`), ``n_bursts``,
        ``mean_burst``, ``largest_burst`` (where bursts were recorded).
    """
    features = _grid_features(data) if data.grid_shape is not None else _network_features(data)
    features["opened_fraction"] = opened_fraction(data)
    bursts = np.asarray(data.burst_sizes)
    features["n_bursts"] = int(bursts.size)
    features["mean_burst"] = float(bursts.mean()) if bursts.size else float("nan")
    features["largest_burst"] = int(bursts.max()) if bursts.size else 0
    return features
