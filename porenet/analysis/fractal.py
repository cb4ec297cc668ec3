"""Fractal dimension of a drained set by mass against distance from the inlet (MODEL.md 7).

The paper's Figs. 4-5 measure ``M(R) ~ R^{D_f}``: the number of drained pores within distance
``R`` of the inlet, fitted on a log-log scale over radii well inside the pattern. This module
gives that estimate; box counting and ensemble statistics come with the analysis issue.
"""

from __future__ import annotations

import numpy as np


def mass_radius_dimension(
    drained: np.ndarray,
    coords: np.ndarray,
    centre: np.ndarray | tuple[float, float],
    r_min: float,
    r_max: float,
    n_radii: int = 12,
) -> tuple[float, np.ndarray, np.ndarray]:
    """Slope of log M(R) against log R, M(R) the drained pores within R of ``centre``.

    Parameters
    ----------
    drained : ndarray of bool, shape (N,)
        The pattern.
    coords : ndarray of float, shape (N, 2)
        Pore centres (any length unit, the same as ``centre`` and the radii).
    centre : (2,) float
        The inlet.
    r_min, r_max : float
        Fit range (0 < r_min < r_max); choose r_max inside the pattern's extent (the paper's
        patterns reach the outlet at L/2; a range up to ~0.35 L stays clear of the edge).
    n_radii : int
        Geometrically spaced radii in the fit.

    Returns
    -------
    dimension : float
        The fitted exponent D_f.
    radii, mass : ndarray
        The points fitted.
    """
    if not 0 < r_min < r_max:
        raise ValueError(f"need 0 < r_min < r_max, got r_min = {r_min}, r_max = {r_max}")
    xy = np.asarray(coords, dtype=np.float64)[np.asarray(drained, dtype=bool)]
    r = np.sort(np.hypot(xy[:, 0] - centre[0], xy[:, 1] - centre[1]))
    radii = np.geomspace(r_min, r_max, n_radii)
    mass = np.searchsorted(r, radii, side="right").astype(np.float64)
    if np.count_nonzero(mass > 0) < 2:
        raise ValueError("fewer than two radii enclose a drained pore: cannot fit D_f")
    keep = mass > 0
    slope = np.polyfit(np.log(radii[keep]), np.log(mass[keep]), 1)[0]
    return float(slope), radii, mass
