"""Pattern features on any network: :mod:`porenet.analysis.features` measured on the pores'
coordinates and the throats instead of a grid, for lattices without a grid layout (3-D cubic
lattices, imported networks; docs/lattices.md, "Analysis on any network").

Each feature is defined so that on a square grid it equals the grid version exactly
(``tests/unit/analysis/test_network_features.py``), lengths in spacings (the median distance
between joined pores):

* **finger width**: ``2 d - 1`` on the medial axis, ``d`` the Euclidean distance to the
  nearest undrained pore or to the outside one spacing beyond the bounding box
  (:func:`finger_widths_any`);
* **straight runs**: chains of drained-drained throats continuing one another in nearly
  opposite directions, thin when no other drained neighbour lies off the line
  (:func:`straight_runs_any`);
* **anisotropy**: the gyration tensor's smallest over largest eigenvalue in d dimensions, and
  the bias of the drained-drained throats towards x or y (:func:`network_anisotropy`).

The rule-based classifier's thresholds were calibrated on the square lattice
(docs/classification.md); on other networks its verdict says so.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

if TYPE_CHECKING:  # pragma: no cover
    from porenet.result import RunData

#: Two throats of a pore continue a straight run when they point within this many degrees of
#: opposite directions (0 on a lattice's straight line).
STRAIGHT_DEGREES = 30.0


def _adjacency(throat_pores: np.ndarray, n_pores: int) -> sparse.csr_matrix:
    tp = np.asarray(throat_pores, dtype=np.int64)
    ones = np.ones(len(tp), dtype=np.int8)
    graph = sparse.coo_matrix((ones, (tp[:, 0], tp[:, 1])), shape=(n_pores, n_pores))
    return (graph + graph.T).tocsr()


def finger_widths_any(data: RunData, spacing: float) -> np.ndarray:
    """Local widths ``2 d - 1`` (pores) of the drained set, one per medial-axis pore: ``d`` is
    the Euclidean distance (in spacings) from a drained pore to the nearest undrained pore or,
    one spacing beyond the bounding box, to the outside; the medial axis is the drained pores
    where ``d`` is a local maximum over the pores within 1.5 spacings. On a square grid this
    is :func:`porenet.analysis.features.finger_widths` exactly."""
    drained = np.asarray(data.drained, dtype=bool).ravel()
    if not drained.any():
        return np.zeros(0)
    xyz = np.asarray(data.pore_coords, dtype=np.float64) / spacing
    inside = xyz[drained]
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    spread = hi > lo  # (a flat axis, one layer of pores, has no outside along it)
    d = np.minimum(inside - lo, hi - inside)[:, spread].min(axis=1) + 1.0
    if not drained.all():
        d = np.minimum(d, cKDTree(xyz[~drained]).query(inside)[0])
    pairs = cKDTree(inside).query_pairs(1.5, output_type="ndarray")
    local_max = d.copy()
    np.maximum.at(local_max, pairs[:, 0], d[pairs[:, 1]])
    np.maximum.at(local_max, pairs[:, 1], d[pairs[:, 0]])
    return 2.0 * d[d >= local_max - 1e-9] - 1.0  # (ties within round-off are maxima)


def straight_runs_any(data: RunData, thin: bool = False) -> np.ndarray:
    """Lengths (pores) of the straight runs of drained pores: chains of drained-drained throats
    that continue one another in nearly opposite directions at each pore (within
    :data:`STRAIGHT_DEGREES`). With ``thin``, only throats whose two pores have no other
    drained neighbour off the throat's line (a channel one pore wide, as
    :func:`porenet.analysis.features.straight_runs` with ``thin``). Single pores are not runs."""
    drained = np.asarray(data.drained, dtype=bool).ravel()
    tp = np.asarray(data.throat_pores, dtype=np.int64)
    inside = tp[drained[tp[:, 0]] & drained[tp[:, 1]]]
    if len(inside) == 0:
        return np.zeros(0, dtype=np.int64)
    xyz = np.asarray(data.pore_coords, dtype=np.float64)
    d = xyz[inside[:, 1]] - xyz[inside[:, 0]]
    u = d / np.linalg.norm(d, axis=1, keepdims=True)
    # every pair of throats (t, s) that meet at a pore, with the cosine of their directions
    # as seen from that pore (a throat's direction flips at its second pore)
    m = len(inside)
    pore = np.concatenate([inside[:, 0], inside[:, 1]])
    throat = np.concatenate([np.arange(m), np.arange(m)])
    sign = np.concatenate([np.ones(m), -np.ones(m)])
    order = np.argsort(pore, kind="stable")
    pore, throat, sign = pore[order], throat[order], sign[order]
    first = np.searchsorted(pore, pore, side="left")
    count = np.searchsorted(pore, pore, side="right") - first
    rep = np.repeat(np.arange(len(pore)), count)
    other = first[rep] + (np.arange(len(rep)) - np.repeat(np.cumsum(count) - count, count))
    keep = rep != other
    t, s = throat[rep[keep]], throat[other[keep]]
    cosine = np.einsum("ij,ij->i", u[t], u[s]) * sign[rep[keep]] * sign[other[keep]]
    limit = np.cos(np.radians(STRAIGHT_DEGREES))
    usable = np.ones(m, dtype=bool)
    if thin:  # a throat is thin when every other throat at its pores lies along its line
        usable[t[np.abs(cosine) < limit]] = False
    join = (cosine <= -limit) & usable[t] & usable[s]
    graph = sparse.coo_matrix((np.ones(join.sum()), (t[join], s[join])), shape=(m, m))
    _, label = csgraph.connected_components(graph, directed=False)
    throats_per_run = np.bincount(label[usable])
    return throats_per_run[throats_per_run > 0] + 1


def network_anisotropy(data: RunData) -> dict[str, float]:
    """``gyration_ratio`` (smallest over largest eigenvalue of the drained pores' gyration
    tensor, in d dimensions) and ``axis_bias`` (``(s_x - s_y) / (s_x + s_y)``, ``s`` the sums
    of the absolute direction components of the drained-drained throats along x and y)."""
    drained = np.asarray(data.drained, dtype=bool).ravel()
    xyz = np.asarray(data.pore_coords, dtype=np.float64)
    if np.count_nonzero(drained) < 2:
        return {"gyration_ratio": float("nan"), "axis_bias": float("nan")}
    eig = np.linalg.eigvalsh(np.cov(xyz[drained].T, bias=True))
    tp = np.asarray(data.throat_pores, dtype=np.int64)
    inside = tp[drained[tp[:, 0]] & drained[tp[:, 1]]]
    d = xyz[inside[:, 1]] - xyz[inside[:, 0]]
    u = np.abs(d) / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-300)
    sx, sy = float(u[:, 0].sum()), float(u[:, 1].sum())
    return {
        "gyration_ratio": float(eig[0] / eig[-1]) if eig[-1] > 0 else float("nan"),
        "axis_bias": (sx - sy) / (sx + sy) if sx + sy else float("nan"),
    }


def network_pattern_features(data: RunData, long_run: int) -> dict[str, Any]:
    """The features of :func:`porenet.analysis.features.pattern_features` on any network
    (module docstring); ``long_run`` as :data:`porenet.analysis.features.LONG_RUN`."""
    drained = np.asarray(data.drained, dtype=bool).ravel()
    n, n_drained = drained.size, int(np.count_nonzero(drained))
    tp = np.asarray(data.throat_pores, dtype=np.int64)
    xyz = np.asarray(data.pore_coords, dtype=np.float64)
    spacing = float(np.median(np.linalg.norm(xyz[tp[:, 1]] - xyz[tp[:, 0]], axis=1)))
    widths = finger_widths_any(data, spacing)
    runs = straight_runs_any(data)
    thin = straight_runs_any(data, thin=True)
    long_thin = thin[thin >= long_run]
    trapped = np.asarray(data.trapped, dtype=bool).ravel()
    return {
        "drained_fraction": n_drained / n,
        "trapped_fraction": float(np.count_nonzero(trapped & ~drained)) / n,
        "finger_width_mean": float(widths.mean()) if widths.size else float("nan"),
        "finger_width_median": float(np.median(widths)) if widths.size else float("nan"),
        "longest_run": int(runs.max()) if runs.size else min(n_drained, 1),
        "longest_thin_run": int(thin.max()) if thin.size else min(n_drained, 1),
        "thin_run_fraction": float(long_thin.sum()) / n_drained if n_drained else 0.0,
        **network_anisotropy(data),
    }
