"""The ``correlated.gaussian`` lattice: the paper's square lattice with correlated apertures.

Only the drawing of the apertures changes (:meth:`CorrelatedLattice.draw_apertures`); geometry,
topology, canonical throat order and the solid network are those of
:class:`porenet.kinds.square.model.SquareLattice`.

Algorithm (:func:`correlated_apertures`)
----------------------------------------
1. *Grid.* Throat midpoints lie on a grid of spacing ``a`` (half the pore spacing ``2a``). In
   units of ``a``, pore ``(i, j)`` is centred at ``(x, y) = (2j + 1, 2i + 1)``, the horizontal
   throat ``(i, j)-(i, j+1)`` at ``(2j + 2, 2i + 1)`` and the vertical throat ``(i, j)-(i+1, j)``
   at ``(2j + 1, 2i + 2)``. Grid node ``[p, q]`` is the point ``(x, y) = (q + 1, p + 1)``, so
   the midpoints fill the ``D x D`` block ``0 <= p, q < D``, ``D = 2n - 1``.
2. *White noise* of unit variance is drawn on a periodic ``M x M`` grid (:func:`grid_size`),
   ``M >= D + 16 l + 1`` nodes: the block plus 8 kernel standard deviations of padding, so that
   any two midpoints are at least ``8 s`` apart across the periodic boundary and the
   wrap-around correlation is below ``exp(-16) ~ 1e-7``.
3. *Spectral (FFT) filtering* [1]_ [2]_. The noise is multiplied in Fourier space
   (``numpy.fft``) by the transfer function ``exp(-2 pi^2 s^2 |f|^2)`` of a Gaussian kernel of
   standard deviation ``s = 2 l`` nodes, that is ``l`` = ``correlation_length`` pores. The
   result is a stationary Gaussian random field with Gaussian covariance
   ``rho(d) = exp(-d^2 / (4 l^2))`` at a distance of ``d`` pores (the autocorrelation of a
   Gaussian kernel of width ``l`` is a Gaussian of width ``l sqrt(2)``).
4. *Sampling* at every throat midpoint, in canonical throat order (:func:`sample_at_throats`).
5. *Rank transform* [3]_. ``2 n (n-1)`` values drawn independently and uniformly on
   ``[(1 - lambda) r_mean, (1 + lambda) r_mean]``, exactly as the ``square`` kind draws them,
   are sorted and handed out in the order of the field's ranks. The multiset of apertures thus
   has exactly the law of the uncorrelated case (``disorder`` keeps its meaning); only the
   spatial arrangement changes. The Pearson correlation of two apertures is that of the ranks
   of a bivariate normal, ``(6 / pi) arcsin(rho / 2)``. For ``l`` much smaller than half a
   pore the field is white noise and the lattice is statistically identical to ``square``.

Everything is drawn from the generator porenet hands to the lattice (noise first, row by row,
then the uniform values), so the scene's ``seed`` fixes the apertures.

The Gaussian filter is separable, so step 3 runs as two passes of one-dimensional FFTs: along
``x`` over chunks of rows, keeping only the ``D`` columns of the block, then along ``y`` over
chunks of those columns. This equals the two-dimensional periodic filter exactly, while memory
stays ``O(D M)`` rather than ``O(M^2)``; time is ``O(M^2 log M)``, about 5 s at the largest
``l = 1000`` pores (``M ~ 16000``) and well under a second for ``l`` up to tens of pores.

References
----------
.. [1] E. Pardo-Igúzquiza and M. Chica-Olmo, "The Fourier integral method: an efficient spectral
   method for simulation of random fields", Mathematical Geology 25, 177-217 (1993).
.. [2] F. Ruan and D. McLaughlin, "An efficient multivariate random field generator using the
   fast Fourier transform", Advances in Water Resources 21, 385-399 (1998).
.. [3] C. V. Deutsch and A. G. Journel, GSLIB: Geostatistical Software Library and User's
   Guide, 2nd ed., Oxford University Press (1998) (normal-score / rank transforms).
"""

from __future__ import annotations

import math

import numpy as np

from porenet.kinds.square.model import SquareLattice

#: Padding of the periodic grid beyond the lattice block, in kernel standard deviations.
PAD_SIGMAS = 8.0
#: Target number of grid values per FFT chunk (about 32 MB of float64).
CHUNK_VALUES = 1 << 22


def next_fast_len(size: int) -> int:
    """Smallest integer ``>= size`` whose only prime factors are 2, 3 and 5.

    Parameters
    ----------
    size : int
        Minimum length.

    Returns
    -------
    int
        A length for which ``numpy.fft`` is fast (at least 1).
    """
    length = max(1, int(size))
    while True:
        rest = length
        for p in (2, 3, 5):
            while rest % p == 0:
                rest //= p
        if rest == 1:
            return length
        length += 1


def grid_size(n: int, correlation_length: float) -> int:
    """Side ``M`` (nodes) of the periodic grid for ``n`` pores per side and length ``l``.

    Parameters
    ----------
    n : int
        Pores per side.
    correlation_length : float
        ``l`` (pores).

    Returns
    -------
    int
        ``next_fast_len(D + ceil(8 * 2 l) + 1)`` with ``D = 2n - 1``: the block of throat
        midpoints plus 8 kernel standard deviations (of ``2 l`` nodes) of padding.
    """
    sigma = 2.0 * correlation_length
    return next_fast_len(2 * n - 1 + math.ceil(PAD_SIGMAS * sigma) + 1)


def gaussian_transfer(m: int, sigma: float) -> np.ndarray:
    """Fourier transfer function of a Gaussian kernel on a periodic 1-D grid (``rfft`` layout).

    Parameters
    ----------
    m : int
        Period (nodes).
    sigma : float
        Standard deviation of the kernel (nodes).

    Returns
    -------
    numpy.ndarray
        ``exp(-2 pi^2 sigma^2 f^2)`` at ``f = numpy.fft.rfftfreq(m)`` (cycles per node),
        shape ``(m // 2 + 1,)``.
    """
    f = np.fft.rfftfreq(m)
    return np.exp(-2.0 * np.pi**2 * sigma**2 * f**2)


def correlated_field(
    rng: np.random.Generator, size: int, sigma: float, m: int | None = None
) -> np.ndarray:
    """Gaussian random field with Gaussian covariance on a ``size x size`` block of nodes.

    White noise on a periodic ``m x m`` grid, filtered by FFT with a Gaussian kernel of
    standard deviation ``sigma`` nodes (spectral filtering of white noise [1]_ [2]_); the
    ``size x size`` corner block is returned. The filter is applied as two separable passes
    of one-dimensional FFTs over chunks, which equals the two-dimensional filter exactly.

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of the ``m * m`` standard normal draws (row-major).
    size : int
        Side of the returned block (nodes), ``<= m``.
    sigma : float
        Standard deviation of the kernel (nodes, > 0).
    m : int, optional
        Side of the periodic grid. Default: ``next_fast_len(size + ceil(8 sigma) + 1)``.

    Returns
    -------
    numpy.ndarray
        ``(size, size)`` float64 field of zero mean whose covariance between nodes ``r`` apart
        is proportional to ``exp(-r^2 / (4 sigma^2))`` (plus wrap-around terms, below
        ``exp(-16)`` with the default ``m``). Its scale is arbitrary.

    References
    ----------
    .. [1] E. Pardo-Igúzquiza and M. Chica-Olmo, Mathematical Geology 25, 177-217 (1993).
    .. [2] F. Ruan and D. McLaughlin, Advances in Water Resources 21, 385-399 (1998).
    """
    if not (sigma > 0 and math.isfinite(sigma)):
        raise ValueError(f"correlated_field: sigma must be positive and finite, got {sigma}")
    if m is None:
        m = next_fast_len(size + math.ceil(PAD_SIGMAS * sigma) + 1)
    if not 1 <= size <= m:
        raise ValueError(f"correlated_field: need 1 <= size <= m, got size {size}, m {m}")
    h = gaussian_transfer(m, sigma)
    step = max(1, CHUNK_VALUES // m)
    # pass 1: filter every row of the periodic grid along x; keep the block's `size` columns
    rows = np.empty((m, size))
    for start in range(0, m, step):
        stop = min(m, start + step)
        spectrum = np.fft.rfft(rng.standard_normal((stop - start, m)), axis=1)
        spectrum *= h
        rows[start:stop] = np.fft.irfft(spectrum, n=m, axis=1)[:, :size]
    # pass 2: filter the kept columns along y; keep the block's `size` rows
    field = np.empty((size, size))
    for start in range(0, size, step):
        stop = min(size, start + step)
        spectrum = np.fft.rfft(rows[:, start:stop], axis=0)
        spectrum *= h[:, None]
        field[:, start:stop] = np.fft.irfft(spectrum, n=m, axis=0)[:size]
    return field


def sample_at_throats(field: np.ndarray, n: int) -> np.ndarray:
    """Values of a midpoint-resolution field at the throats, in canonical throat order.

    Parameters
    ----------
    field : numpy.ndarray
        ``(2n - 1, 2n - 1)`` field; node ``[p, q]`` lies at ``(x, y) = (q + 1, p + 1)`` in units
        of ``a``.
    n : int
        Pores per side.

    Returns
    -------
    numpy.ndarray
        ``(2 n (n-1),)`` values: the horizontal throats ``(i, j)-(i, j+1)`` (node
        ``[2i, 2j + 1]``) row-major, then the vertical throats ``(i, j)-(i+1, j)`` (node
        ``[2i + 1, 2j]``) row-major, as in
        :func:`porenet.kinds.square.model.canonical_throats`.
    """
    if field.shape != (2 * n - 1, 2 * n - 1):
        raise ValueError(f"sample_at_throats: field of shape {field.shape} for n = {n}")
    horizontal = field[0::2, 1::2]  # (n, n-1)
    vertical = field[1::2, 0::2]  # (n-1, n)
    return np.concatenate([horizontal.ravel(), vertical.ravel()])


def rank_to_uniform(
    values: np.ndarray, low: float, high: float, rng: np.random.Generator
) -> np.ndarray:
    """Replace ``values`` by independent uniform draws on ``[low, high)`` with the same ranks.

    Parameters
    ----------
    values : numpy.ndarray
        1-D array whose ranks set the arrangement (ties broken by position).
    low, high : float
        Bounds of the uniform marginal.
    rng : numpy.random.Generator
        Source of the ``len(values)`` uniform draws.

    Returns
    -------
    numpy.ndarray
        The sorted draws, placed so that the k-th smallest value gets the k-th smallest draw.
    """
    draws = np.sort(rng.uniform(low, high, size=values.shape[0]))
    out = np.empty_like(draws)
    out[np.argsort(values, kind="stable")] = draws
    return out


def correlated_apertures(
    n: int,
    correlation_length: float,
    disorder: float,
    mean_aperture: float,
    rng: np.random.Generator,
) -> np.ndarray:
    """Correlated apertures of an ``n x n`` lattice in canonical throat order.

    Parameters
    ----------
    n : int
        Pores per side.
    correlation_length : float
        ``l``: standard deviation of the Gaussian kernel (pores).
    disorder : float
        ``lambda``: the marginal is uniform on ``[(1 - lambda), (1 + lambda)] * mean_aperture``.
    mean_aperture : float
        ``r_mean``, in any unit (the result is in the same unit).
    rng : numpy.random.Generator
        The only source of randomness.

    Returns
    -------
    numpy.ndarray
        ``(2 n (n-1),)`` apertures (see the module docstring for the algorithm).
    """
    sigma = 2.0 * float(correlation_length)  # pores -> nodes of spacing a
    field = correlated_field(rng, 2 * n - 1, sigma, grid_size(n, correlation_length))
    values = sample_at_throats(field, n)
    del field
    low = (1.0 - disorder) * mean_aperture
    high = (1.0 + disorder) * mean_aperture
    return rank_to_uniform(values, low, high, rng)


class CorrelatedLattice(SquareLattice):
    """Square lattice whose apertures are arranged by a Gaussian random field.

    Only :meth:`draw_apertures` differs from
    :class:`~porenet.kinds.square.model.SquareLattice`: geometry, canonical throat order,
    particles and springs are the same. See the module docstring for the algorithm.

    Parameters
    ----------
    config : CorrelatedLatticeConfig
        The validated ``[lattice]`` section.
    rng : numpy.random.Generator
        The lattice's generator; the apertures are a deterministic function of its state.
    """

    def draw_apertures(self, rng: np.random.Generator) -> np.ndarray:
        """Apertures ``r / a``, uniform on ``[(1-lambda), (1+lambda)] r_mean / a``, correlated.

        Parameters
        ----------
        rng : numpy.random.Generator
            Draws the white noise first, then the uniform values.

        Returns
        -------
        numpy.ndarray
            ``(2 n (n-1),)`` scaled apertures in canonical throat order, spatially correlated
            over ``correlation_length`` pores.
        """
        c = self.config
        return correlated_apertures(
            self.n,
            float(c.correlation_length),  # type: ignore[attr-defined]
            float(c.disorder),  # type: ignore[arg-type]
            self.mean_aperture_scaled,
            rng,
        )
