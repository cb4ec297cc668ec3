"""Fractal dimension of a drained set: mass against distance from the inlet, and box counting.

docs/model.md section 7 and docs/fractal.md. Two estimators, both pure functions of arrays:

* :func:`mass_radius`: ``M(R) ~ R^{D_f}``, the drained pores within distance ``R`` of the
  inlet (the curves of the paper's Figs. 4-5);
* :func:`box_counting`: ``N(s) ~ s^{-D_f}``, the boxes of side ``s`` (powers of 2) holding at
  least one drained pore (occupied boxes, not boundary boxes).

Both fit a straight line on log-log axes over an automatic range (below) or one given by the
caller, and return a :class:`FractalFit` with the whole curve for plotting.
:func:`pattern_dimension` applies them to a run.

Automatic fitting range (docs/fractal.md explains the choice): from
:data:`SCALE_MIN` = 2 lattice spacings (below that the counts are a handful of pores and follow
the lattice, not the pattern) up to :data:`RANGE_FRACTION` = 1/4 of the pattern's median
distance ``l`` (mass-radius: of the drained pores from the inlet; box counting: of the
occupied cells from their centroid), and at least :data:`MIN_RANGE_RATIO` = 4 times the lower
end. At breakthrough ``l`` is about n / 4 for invasion percolation and the local slopes fall
steadily beyond about n / 20 (the outer, still-growing part of the pattern), so the fit stays
inside the self-similar part while spanning as many octaves as the lattice allows.

Finite-size bias: at the lattice sizes one can simulate both estimators read low on
invasion-percolation patterns. :data:`BIAS_TABLE` holds the bias and the pattern-to-pattern
standard deviation of each estimator, measured on ensembles at n = 100 to 1600
(``examples/scripts/fractal_bias.py``). With the automatic range, ``FractalFit.bias`` is that
bias at the pattern's size and ``FractalFit.error = sqrt(stderr^2 + sd^2 + bias^2)``.

Length (over the ~500 lines of docs/architecture.md's rule): two estimators (mass-radius, box
counting) that share the line fit, the automatic range and the finite-size calibration; a
quarter of the module is documentation of the fitting decisions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from porenet.core.sites import site_geometry

if TYPE_CHECKING:  # pragma: no cover
    from porenet.result import RunData

#: Methods of :func:`pattern_dimension`.
METHODS = ("mass-radius", "box-counting")
#: Lower end of the automatic fitting range, in lattice spacings (radius or box side).
SCALE_MIN = 2.0
#: Upper end of the automatic range as a fraction of the pattern's median distance ``l``.
RANGE_FRACTION = 0.25
#: The automatic range spans at least this factor (a pattern too small for it is refused).
MIN_RANGE_RATIO = 4.0
#: Radii per factor of 2 on the mass-radius ladder when ``n_radii`` is not given.
RADII_PER_OCTAVE = 4
#: Asymptotic D_f of invasion percolation on the square lattice, with and without trapping
#: (docs/model.md section 2; 91/48 is the percolation cluster's).
IP_DIMENSION = {True: 1.82, False: 91 / 48}
#: The table is extrapolated in log n down to this size at most (see :func:`finite_size_bias`).
SMALLEST_EXTRAPOLATED_N = 25

# Bias (mean estimate minus IP_DIMENSION) and pattern-to-pattern standard deviation of each
# estimator with its automatic range, on invasion-percolation patterns at breakthrough (square
# lattice of n x n pores, lambda = 0.5, seeds 0, 1, ...), keyed by (method, injection,
# trapping); rows (n, bias, sd, patterns). Written by (7 min on 2 shared cores; it prints this
# literal, and the tables of docs/fractal-bias.md):
#     python examples/scripts/fractal_bias.py --docs docs
BIAS_TABLE: dict[tuple[str, str, bool], tuple[tuple[int, float, float, int], ...]] = {
    ("mass-radius", "centre", True): (
        (100, -0.172, 0.238, 400),
        (200, -0.093, 0.217, 400),
        (400, -0.067, 0.176, 400),
        (800, -0.048, 0.136, 200),
        (1600, -0.046, 0.114, 60),
    ),
    ("mass-radius", "centre", False): (
        (100, -0.213, 0.234, 400),
        (200, -0.135, 0.214, 400),
        (400, -0.102, 0.168, 400),
        (800, -0.070, 0.138, 200),
        (1600, -0.072, 0.120, 60),
    ),
    ("box-counting", "centre", True): (
        (100, -0.229, 0.059, 400),
        (200, -0.153, 0.038, 400),
        (400, -0.113, 0.026, 400),
        (800, -0.085, 0.021, 200),
        (1600, -0.067, 0.014, 60),
    ),
    ("box-counting", "centre", False): (
        (100, -0.289, 0.064, 400),
        (200, -0.196, 0.047, 400),
        (400, -0.147, 0.033, 400),
        (800, -0.116, 0.028, 200),
        (1600, -0.096, 0.019, 60),
    ),
    ("box-counting", "left-edge", True): (
        (100, -0.113, 0.041, 40),
        (200, -0.081, 0.020, 40),
        (400, -0.067, 0.022, 40),
        (800, -0.050, 0.016, 40),
        (1600, -0.042, 0.013, 40),
    ),
    ("box-counting", "left-edge", False): (
        (100, -0.113, 0.061, 40),
        (200, -0.082, 0.034, 40),
        (400, -0.073, 0.033, 40),
        (800, -0.055, 0.029, 40),
        (1600, -0.048, 0.022, 40),
    ),
}


@dataclass(frozen=True, eq=False)
class FractalFit:
    """A fractal-dimension estimate and the curve it was fitted to.

    Attributes
    ----------
    method : str
        ``"mass-radius"`` (M(R), drained pores within R of the inlet) or ``"box-counting"``
        (N(s), boxes of side s holding at least one drained pore).
    dimension : float
        The fitted D_f (slope of log M against log R, or minus the slope of log N against
        log s).
    error : float
        Uncertainty reported with D_f: the fit's standard error combined with the estimator's
        documented bias at this size (see docs/fractal.md).
    stderr : float
        Standard error of the fitted slope alone.
    bias : float
        The estimator's expected bias at this size (estimate minus asymptotic value), from
        invasion-percolation ensembles; ``nan`` when not known.
    scales : ndarray (K,) float
        R or s, in lattice spacings.
    counts : ndarray (K,) float
        M(R) or N(s).
    fitted : ndarray (K,) bool
        The points inside the fitting range.
    intercept : float
        Intercept of the fitted line in natural logarithms: ``log counts = intercept +
        slope * log scales`` with ``slope = dimension`` (mass-radius) or ``-dimension`` (box
        counting).
    """

    method: str
    dimension: float
    error: float
    stderr: float
    bias: float
    scales: np.ndarray
    counts: np.ndarray
    fitted: np.ndarray
    intercept: float


def finite_size_bias(
    method: str, n: float, *, injection: str = "centre", trapping: bool = True
) -> tuple[float, float]:
    """Bias and pattern-to-pattern sd of an estimator (automatic range) at lattice size ``n``.

    From :data:`BIAS_TABLE`, linear in log n between the measured sizes. Above the largest
    size the largest size's values are used (the bias shrinks with n, so this overstates it);
    below the smallest they are extrapolated linearly in log n from the two smallest sizes
    (down to :data:`SMALLEST_EXTRAPOLATED_N`), never smaller in magnitude than at the smallest
    size. ``(nan, nan)`` for a combination the table does not hold.
    """
    rows = BIAS_TABLE.get((method, injection, bool(trapping)))
    if not rows or not n > 0:
        return math.nan, math.nan
    sizes = np.log([r[0] for r in rows])
    bias = np.array([r[1] for r in rows])
    sd = np.array([r[2] for r in rows])
    x = math.log(n)
    if x >= sizes[0] or len(rows) < 2:
        return float(np.interp(x, sizes, bias)), float(np.interp(x, sizes, sd))
    x = max(x, math.log(SMALLEST_EXTRAPOLATED_N))
    t = (x - sizes[0]) / (sizes[1] - sizes[0])
    b = bias[0] + t * (bias[1] - bias[0])
    s = sd[0] + t * (sd[1] - sd[0])
    b = b if abs(b) > abs(bias[0]) else bias[0]
    return float(b), float(max(s, sd[0]))


def _line_fit(x: np.ndarray, y: np.ndarray) -> tuple[float, float, float]:
    """Least-squares line y = intercept + slope x: slope, intercept, standard error of the
    slope (needs at least 3 points)."""
    k = x.size
    xm, ym = x.mean(), y.mean()
    sxx = float(np.sum((x - xm) ** 2))
    slope = float(np.sum((x - xm) * (y - ym)) / sxx)
    intercept = float(ym - slope * xm)
    residual = y - intercept - slope * x
    stderr = math.sqrt(float(np.sum(residual**2)) / (k - 2) / sxx)
    return slope, intercept, stderr


def _calibrated(fit: FractalFit, n: float, injection: str, trapping: bool) -> FractalFit:
    """``fit`` (automatic range) with the tabulated bias at size n and the error including it."""
    bias, sd = finite_size_bias(fit.method, n, injection=injection, trapping=trapping)
    if math.isnan(bias):
        return replace(fit, bias=math.nan, error=fit.stderr)
    return replace(fit, bias=bias, error=math.sqrt(fit.stderr**2 + sd**2 + bias**2))


def _auto_upper(extent: float, lower: float) -> float:
    """Upper end of the automatic range for a pattern of median distance ``extent``."""
    return max(RANGE_FRACTION * extent, MIN_RANGE_RATIO * lower)


def distances(dx: np.ndarray) -> np.ndarray:
    """Euclidean lengths of the rows of ``dx``, (N, 2) or (N, 3) (``hypot`` in 2-D)."""
    if dx.shape[1] == 2:
        return np.hypot(dx[:, 0], dx[:, 1])
    return np.sqrt(np.einsum("ij,ij->i", dx, dx))


def _mass_radius(
    drained: np.ndarray,
    coords: np.ndarray,
    centre: np.ndarray | tuple[float, float],
    spacing: float,
    r_min: float | None,
    r_max: float | None,
    n_radii: int | None,
) -> FractalFit:
    drained = np.asarray(drained)
    coords = np.asarray(coords, dtype=np.float64)
    centre = np.asarray(centre, dtype=np.float64)
    d = coords.shape[-1] if coords.ndim == 2 else 0
    if (
        drained.ndim != 1
        or coords.shape != (drained.size, d)
        or d not in (2, 3)
        or (centre.shape != (d,))
    ):
        raise ValueError(
            f"need drained (N,), coords (N, d) and centre (d,) with d = 2 or 3, got "
            f"{drained.shape}, {coords.shape} and {centre.shape}"
        )
    if not spacing > 0:
        raise ValueError(f"spacing must be positive, got {spacing}")
    drained = drained.astype(bool)
    if np.count_nonzero(drained) < 2:
        raise ValueError(
            f"the pattern has {np.count_nonzero(drained)} drained pore(s): D_f needs at least 2"
        )
    r = np.sort(distances((coords[drained] - centre) / spacing))
    far = float(r[-1])
    lo = SCALE_MIN if r_min is None else float(r_min)
    auto_hi = r_max is None
    hi = _auto_upper(float(np.median(r)), lo) if auto_hi else float(r_max)
    if not 0 < lo < hi:
        raise ValueError(f"need 0 < r_min < r_max, got r_min = {lo:g}, r_max = {hi:g} spacings")
    if auto_hi and hi > far:
        raise ValueError(
            f"pattern too small for the automatic range: it reaches {far:.3g} lattice spacings "
            f"from the inlet, the range [{lo:g}, {hi:.3g}] needs more"
        )
    if n_radii is None:
        q = 2.0 ** (1.0 / RADII_PER_OCTAVE)
    elif n_radii < 3:
        raise ValueError(f"n_radii must be at least 3, got {n_radii}")
    else:
        q = (hi / lo) ** (1.0 / (n_radii - 1))
    logq = math.log(q)
    k_top = math.floor(math.log(hi / lo) / logq + 1e-9)
    k_first = -math.floor(math.log(lo) / logq + 1e-9) if lo > 1 else 0
    k_last = max(k_top, math.ceil(math.log(max(far, lo) / lo) / logq - 1e-9))
    k = np.arange(k_first, k_last + 1)
    scales = lo * q**k
    counts = np.searchsorted(r, scales * (1 + 1e-12), side="right").astype(np.float64)
    fitted = (k >= 0) & (k <= k_top) & (counts > 0)
    if np.count_nonzero(fitted) < 3:
        raise ValueError(
            f"fewer than 3 radii in [{lo:g}, {hi:g}] lattice spacings enclose drained pores: "
            "cannot fit D_f (widen the range)"
        )
    slope, intercept, stderr = _line_fit(np.log(scales[fitted]), np.log(counts[fitted]))
    return FractalFit(
        method="mass-radius",
        dimension=slope,
        error=stderr,
        stderr=stderr,
        bias=math.nan,
        scales=scales,
        counts=counts,
        fitted=fitted,
        intercept=intercept,
    )


def mass_radius(
    drained: np.ndarray,
    coords: np.ndarray,
    centre: np.ndarray | tuple[float, float],
    *,
    spacing: float = 1.0,
    r_min: float | None = None,
    r_max: float | None = None,
    n_radii: int | None = None,
) -> FractalFit:
    """D_f from ``M(R) ~ R^{D_f}``, M(R) the drained pores within distance R of ``centre``.

    Parameters
    ----------
    drained : ndarray of bool, shape (N,)
        The pattern.
    coords : ndarray of float, shape (N, d), d = 2 or 3
        Pore centres, in any length unit.
    centre : (d,) float
        The inlet, in the unit of ``coords``.
    spacing : float
        Lattice spacing in the unit of ``coords`` (``2a`` for porenet's square lattice).
        Radii are measured in lattice spacings.
    r_min, r_max : float, optional
        Fitting range in lattice spacings (like ``FractalFit.scales``); each one not given is
        chosen automatically: ``r_min = SCALE_MIN`` (2), ``r_max = max(RANGE_FRACTION * l,
        MIN_RANGE_RATIO * r_min)`` with ``l`` the median distance of the drained pores from the
        inlet. Given limits must satisfy ``0 < r_min < r_max``.
    n_radii : int, optional
        Number of radii in the fitting range (geometric, at least 3); default 4 per factor
        of 2. The returned curve continues the same ladder from about 1 lattice spacing to the
        farthest drained pore.

    Returns
    -------
    FractalFit
        With ``method = "mass-radius"``. With both limits automatic, ``bias`` is the
        tabulated bias of the estimator on invasion-percolation patterns with trapping at the
        lattice's size (the side of the bounding box of ``coords``, in spacings) and ``error``
        includes it (see the module docstring); with a range of your own the bias is not
        calibrated: ``bias`` is ``nan`` and ``error`` is ``stderr``.

    Raises
    ------
    ValueError
        Fewer than 2 drained pores; a bad range; a pattern too small for the automatic range
        (it does not reach ``r_max``); fewer than 3 fitted radii enclosing drained pores.
    """
    fit = _mass_radius(drained, coords, centre, spacing, r_min, r_max, n_radii)
    if r_min is not None or r_max is not None:
        return fit
    coords = np.asarray(coords, dtype=np.float64)
    n = float(np.ptp(coords, axis=0).max()) / spacing + 1.0
    return _calibrated(fit, n, "centre", True)


def _box_counts(grid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Box sides 1, 2, 4, ... (boxes aligned with the grid's first cell along every axis, in
    2-D or 3-D) and the number of boxes holding at least one True cell, up to a single box."""
    sides, counts = [1], [int(np.count_nonzero(grid))]
    g = grid
    while any(size > 1 for size in g.shape):
        g = np.pad(g, [(0, size % 2) for size in g.shape])
        halves = [d for size in g.shape for d in (size // 2, 2)]
        g = g.reshape(halves).any(axis=tuple(range(1, 2 * g.ndim, 2)))
        sides.append(2 * sides[-1])
        counts.append(int(np.count_nonzero(g)))
    return np.asarray(sides, dtype=np.float64), np.asarray(counts, dtype=np.float64)


def occupancy(drained: np.ndarray, coords: np.ndarray, spacing: float) -> np.ndarray:
    """A 2-D or 3-D boolean grid of cells of side ``spacing`` holding the drained pores at
    ``coords`` (N, d): the pattern of a lattice without a grid layout, for box counting."""
    cells = np.floor((coords - coords.min(axis=0)) / spacing + 1e-9).astype(np.int64)
    grid = np.zeros(cells.max(axis=0) + 1, dtype=bool)
    grid[tuple(cells[np.asarray(drained, dtype=bool)].T)] = True
    return grid


def _box_counting(grid: np.ndarray, s_min: float | None, s_max: float | None) -> FractalFit:
    grid = np.asarray(grid)
    if grid.ndim not in (2, 3):
        raise ValueError(f"need a 2-D or 3-D grid, got shape {grid.shape}")
    grid = grid.astype(bool)
    cells = np.argwhere(grid).astype(np.float64)
    if len(cells) < 2:
        raise ValueError(f"the pattern has {len(cells)} occupied cell(s): D_f needs at least 2")
    lo = SCALE_MIN if s_min is None else float(s_min)
    auto_hi = s_max is None
    if auto_hi:
        extent = float(np.median(distances(cells - cells.mean(axis=0))))
        hi = _auto_upper(extent, lo)
    else:
        hi = float(s_max)
    if not 0 < lo < hi:
        raise ValueError(f"need 0 < s_min < s_max, got s_min = {lo:g}, s_max = {hi:g} cells")
    span = int(np.ptp(cells, axis=0).max()) + 1
    scales, counts = _box_counts(grid)
    if auto_hi:
        hi = float(scales[scales <= hi * (1 + 1e-9)].max(initial=0.0))
        if span < hi:
            raise ValueError(
                f"pattern too small for the automatic range: it spans {span} cells, the "
                f"largest fitted box would be {hi:g}"
            )
    fitted = (scales >= lo * (1 - 1e-9)) & (scales <= hi * (1 + 1e-9))
    if np.count_nonzero(fitted) < 3:
        raise ValueError(
            f"fewer than 3 box sides (powers of 2) in [{lo:g}, {hi:g}] cells: cannot fit D_f "
            "(widen the range)"
        )
    slope, intercept, stderr = _line_fit(np.log(scales[fitted]), np.log(counts[fitted]))
    return FractalFit(
        method="box-counting",
        dimension=-slope,
        error=stderr,
        stderr=stderr,
        bias=math.nan,
        scales=scales,
        counts=counts,
        fitted=fitted,
        intercept=intercept,
    )


def box_counting(
    grid: np.ndarray, *, s_min: float | None = None, s_max: float | None = None
) -> FractalFit:
    """D_f from ``N(s) ~ s^{-D_f}``, N(s) the occupied boxes of side s.

    Parameters
    ----------
    grid : ndarray of bool, shape (rows, cols)
        The pattern on a square lattice, one cell per pore (``RunData.as_grid(drained)``).
    s_min, s_max : float, optional
        Fitting range in cells; the box sides are the powers of 2 inside it. Each one not
        given is chosen automatically: ``s_min = SCALE_MIN`` (2), ``s_max`` the largest power
        of 2 not above ``max(RANGE_FRACTION * l, MIN_RANGE_RATIO * s_min)``, ``l`` the median
        distance of the occupied cells from their centroid.

    Returns
    -------
    FractalFit
        With ``method = "box-counting"``; ``scales`` are the box sides 1, 2, 4, ... up to one
        box covering the grid (boxes aligned with the grid's first row and column), ``counts``
        the occupied boxes. ``bias`` and ``error`` as in :func:`mass_radius` (size: the larger
        side of the grid; with both limits automatic, the IP-with-trapping, centre-injection
        bias).

    Raises
    ------
    ValueError
        Fewer than 2 occupied cells; a bad range; a pattern smaller than the largest fitted
        box; fewer than 3 box sides in the range.
    """
    fit = _box_counting(grid, s_min, s_max)
    if s_min is not None or s_max is not None:
        return fit
    return _calibrated(fit, float(max(np.shape(grid))), "centre", True)


def pattern_dimension(data: RunData, method: str = "mass-radius") -> FractalFit:
    """D_f of a run's drained pattern, automatic range, bias for the run's scene.

    The bias is the one tabulated for the scene's injection and trapping (patterns of models
    without a ``trapping`` option, the dynamic ones, trap the defender and take the trapping
    value); the size is the larger side of the grid.

    Parameters
    ----------
    data : RunData
        A run (``porenet.io.runfile.read_run(path)`` or ``RunResult.data``).
    method : {"mass-radius", "box-counting"}
        ``"mass-radius"`` measures distances from the first inlet pore (``data.order[0]``) in
        lattice spacings ``2a``; it needs injection at the centre: with ``left-edge``
        injection the mass within a distance of the inlet line grows like ``R^{D_f - 1}`` only
        while R is below the lattice width and is not a fractal measure, so use
        ``"box-counting"`` (on a lattice without a grid layout, over cells of one spacing:
        the median distance between joined pores, in 2-D or 3-D).

    Raises
    ------
    ValueError
        Unknown method; fewer than 2 drained pores or a pattern too small to fit (callers
        report D_f as not measurable); mass-radius with injection elsewhere than at the
        centre.
    """
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}: choose one of {', '.join(METHODS)}")
    drained = np.asarray(data.drained, dtype=bool)
    if np.count_nonzero(drained) < 2 or len(data.order) == 0:
        raise ValueError(
            f"the pattern has {np.count_nonzero(drained)} drained pore(s): D_f is not measurable"
        )
    scene = data.scene or {}
    injection = (scene.get("injection") or {}).get("at", "centre")
    # the bias tables know the paper's two geometries: the centre and a face ("left-edge")
    injection = {"centre": "centre", "face": "left-edge"}.get(
        site_geometry(injection), str(injection)
    )
    trapping = bool((scene.get("fluid") or {}).get("trapping", True))
    spacing = 2.0 * float(data.pore_size)
    coords = np.asarray(data.pore_coords, dtype=np.float64)
    if data.grid_shape is None:  # the median distance between joined pores (2a on lattices)
        tp = np.asarray(data.throat_pores)
        spacing = float(np.median(distances(coords[tp[:, 0]] - coords[tp[:, 1]])))
    if coords.shape[1] == 3:  # the bias tables are for 2-D lattices: none in 3-D
        injection = f"{injection} (3-D)"
    if data.grid_shape is not None:
        n = float(max(data.grid_shape))
    else:
        n = float(np.ptp(coords, axis=0).max()) / spacing + 1.0
    if method == "mass-radius":
        if not injection.startswith("centre"):
            raise ValueError(
                f"mass-radius needs a point inlet (injection at the centre), this run injects "
                f"at {injection!r}: use method='box-counting'"
            )
        centre = coords[int(data.order[0])]
        fit = _mass_radius(drained, coords, centre, spacing, None, None, None)
    else:
        if data.grid_shape is None:  # cells of one lattice spacing around the pores
            fit = _box_counting(occupancy(drained, coords, spacing), None, None)
        else:
            fit = _box_counting(data.as_grid(drained), None, None)
    return _calibrated(fit, n, injection, trapping)


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
    r = np.sort(distances(xy - np.asarray(centre, dtype=np.float64)))
    radii = np.geomspace(r_min, r_max, n_radii)
    mass = np.searchsorted(r, radii, side="right").astype(np.float64)
    if np.count_nonzero(mass > 0) < 2:
        raise ValueError("fewer than two radii enclose a drained pore: cannot fit D_f")
    keep = mass > 0
    slope = np.polyfit(np.log(radii[keep]), np.log(mass[keep]), 1)[0]
    return float(slope), radii, mass
