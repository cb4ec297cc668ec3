"""Statistics of the correlated.gaussian apertures: marginal, spatial correlation, determinism."""

from __future__ import annotations

import math

import numpy as np
import porenet_correlated.lattice as lattice_module
import pytest
from porenet_correlated.config import CorrelatedLatticeConfig
from porenet_correlated.lattice import (
    CorrelatedLattice,
    correlated_apertures,
    correlated_field,
    grid_size,
    next_fast_len,
    sample_at_throats,
)


def make_lattice(seed: int = 3, **fields) -> CorrelatedLattice:
    params = {"n": 100, "disorder": 0.3, "correlation_length": 5.0, **fields}
    return CorrelatedLattice(CorrelatedLatticeConfig(**params), np.random.default_rng(seed))


def ks_uniform(values: np.ndarray, low: float, high: float) -> float:
    """Kolmogorov-Smirnov distance between the sample and the uniform law on [low, high]."""
    u = np.sort((values - low) / (high - low))
    m = u.size
    i = np.arange(1, m + 1)
    return float(max(np.max(i / m - u), np.max(u - (i - 1) / m)))


def pair_correlation(r: np.ndarray, n: int, lag: int) -> float:
    """Pearson correlation of apertures ``lag`` pores apart, along rows and columns.

    Horizontal throats form an (n, n-1) grid and vertical throats an (n-1, n) grid, both with
    one pore between neighbours, so each contributes pairs along x and along y.
    """
    h = r[: n * (n - 1)].reshape(n, n - 1)
    v = r[n * (n - 1) :].reshape(n - 1, n)
    firsts, seconds = [], []
    for g in (h, v):
        firsts += [g[:, :-lag].ravel(), g[:-lag, :].ravel()]
        seconds += [g[:, lag:].ravel(), g[lag:, :].ravel()]
    return float(np.corrcoef(np.concatenate(firsts), np.concatenate(seconds))[0, 1])


def uniform_pearson(rho: float) -> float:
    """Pearson correlation of the uniform ranks of a bivariate normal with correlation rho."""
    return 6.0 / math.pi * math.asin(rho / 2.0)


@pytest.mark.parametrize("length", [0.01, 1.0, 5.0, 40.0])
def test_marginal_is_the_uniform_law_of_the_disorder(length):
    lat = make_lattice(correlation_length=length)
    r = lat.initial_apertures
    n = lat.n
    assert r.shape == (2 * n * (n - 1),)
    assert r.min() >= 0.7 and r.max() <= 1.3
    assert r.min() < 0.7 + 0.001 and r.max() > 1.3 - 0.001  # fills the whole interval
    assert ks_uniform(r, 0.7, 1.3) < 1.63 / math.sqrt(r.size)  # KS test at the 1 % level
    deciles = np.quantile(r, np.linspace(0.1, 0.9, 9))
    np.testing.assert_allclose(deciles, 0.7 + 0.6 * np.linspace(0.1, 0.9, 9), atol=0.01)


def test_mean_aperture_and_pore_size_scale_the_interval():
    lat = make_lattice(n=60, disorder=0.5, pore_size=2e-7, mean_aperture=3e-7)
    r = lat.initial_apertures  # r / a: r_mean / a = 1.5, interval [0.75, 2.25]
    assert r.min() >= 0.75 and r.max() <= 2.25
    assert ks_uniform(r, 0.75, 2.25) < 1.63 / math.sqrt(r.size)
    # the mean of m iid uniform draws: standard error 1.5 / sqrt(12 m); allow 4 of them
    assert r.mean() == pytest.approx(1.5, abs=4 * 1.5 / math.sqrt(12 * r.size))


def test_neighbours_are_correlated_for_a_long_correlation_length():
    lat = make_lattice(correlation_length=5.0)
    assert pair_correlation(lat.initial_apertures, lat.n, 1) > 0.5


def test_tiny_correlation_length_is_white_noise():
    lat = make_lattice(correlation_length=0.01)
    r = lat.initial_apertures
    for lag in (1, 2, 5):
        assert abs(pair_correlation(r, lat.n, lag)) < 0.1


def test_correlation_follows_the_gaussian_covariance():
    """Pearson(lag d) of the rank-transformed field = (6/pi) asin(exp(-d^2/(4 l^2)) / 2)."""
    length, n = 2.0, 100
    estimates = {d: [] for d in (1, 2, 4, 8)}
    for seed in range(4):
        r = make_lattice(seed=seed, n=n, correlation_length=length).initial_apertures
        for d in estimates:
            estimates[d].append(pair_correlation(r, n, d))
    for d, values in estimates.items():
        expected = uniform_pearson(math.exp(-(d**2) / (4 * length**2)))
        assert np.mean(values) == pytest.approx(expected, abs=0.04), d


def test_correlation_grows_with_the_correlation_length():
    lags = [
        pair_correlation(make_lattice(correlation_length=ell).initial_apertures, 100, 3)
        for ell in (0.3, 1.0, 3.0, 10.0)
    ]
    assert lags == sorted(lags)


def test_deterministic_under_the_seed():
    a = make_lattice(seed=11).initial_apertures
    b = make_lattice(seed=11).initial_apertures
    c = make_lattice(seed=12).initial_apertures
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    assert not a.flags.writeable
    d = correlated_apertures(100, 5.0, 0.3, 1.0, np.random.default_rng(11))
    np.testing.assert_array_equal(a, d)


def test_throat_midpoints_are_sampled_in_canonical_order():
    n = 7
    lat = make_lattice(n=n)
    d = 2 * n - 1
    rows, cols = np.meshgrid(np.arange(d), np.arange(d), indexing="ij")
    code = sample_at_throats(rows * 1000 + cols, n)
    xy = lat.pore_coords  # units of a: pore (i, j) at (2j + 1, 2i + 1)
    mid = 0.5 * (xy[lat.throat_pores[:, 0]] + xy[lat.throat_pores[:, 1]])
    # half-pore grid node (row, col) = (y - 1, x - 1) in units of a
    expected = (mid[:, 1] - 1).astype(int) * 1000 + (mid[:, 0] - 1).astype(int)
    np.testing.assert_array_equal(code, expected)


@pytest.mark.parametrize(("n", "length"), [(3, 0.01), (50, 2.0), (100, 5.0), (400, 30.0)])
def test_grid_is_padded_against_wrap_around(n, length):
    m = grid_size(n, length)
    assert m >= 2 * n - 1 + 16 * length  # 8 kernel sigmas of 2 l nodes


def test_length_much_larger_than_the_lattice_is_a_smooth_field():
    # no cap on the grid: padding stays 8 sigmas, memory O(D M) thanks to the separable filter
    assert grid_size(10, 50.0) >= 2 * 10 - 1 + 16 * 50
    lat = make_lattice(n=10, correlation_length=50.0)
    assert pair_correlation(lat.initial_apertures, lat.n, 1) > 0.9


def test_separable_filter_equals_the_2d_spectral_filter():
    size, sigma, seed = 30, 2.5, 11
    m = next_fast_len(size + math.ceil(8 * sigma) + 1)
    field = correlated_field(np.random.default_rng(seed), size, sigma, m)
    noise = np.random.default_rng(seed).standard_normal((m, m))
    f = np.fft.fftfreq(m)
    transfer = np.exp(-2 * np.pi**2 * sigma**2 * (f[:, None] ** 2 + f[None, :] ** 2))
    expected = np.fft.ifft2(np.fft.fft2(noise) * transfer).real[:size, :size]
    np.testing.assert_allclose(field, expected, atol=1e-12)


def test_chunking_does_not_change_the_apertures(monkeypatch):
    expected = make_lattice(seed=5, n=20).initial_apertures
    monkeypatch.setattr(lattice_module, "CHUNK_VALUES", 7)
    np.testing.assert_array_equal(make_lattice(seed=5, n=20).initial_apertures, expected)


def test_next_fast_len():
    assert [next_fast_len(k) for k in (0, 1, 7, 11, 97, 121)] == [1, 1, 8, 12, 100, 125]


def test_geometry_is_the_square_lattice():
    from porenet.kinds.square.model import SquareLattice, SquareLatticeConfig

    cor = make_lattice(n=9)
    sq = SquareLattice(SquareLatticeConfig(n=9, disorder=0.3), np.random.default_rng(0))
    np.testing.assert_array_equal(cor.throat_pores, sq.throat_pores)
    np.testing.assert_array_equal(cor.pore_coords, sq.pore_coords)
    np.testing.assert_array_equal(cor.spring_particles, sq.spring_particles)
