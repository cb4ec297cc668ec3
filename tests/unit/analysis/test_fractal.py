"""Fractal dimension: both estimators on sets of known dimension, bad inputs, a real run.

Tolerances (what the lattice does to each estimator on these sets, measured and explained):

* filled disk, radius 256: mass-radius counts lattice points in a circle, within O(R^(2/3))
  of pi R^2 (about 5 % at R = 2), giving 1.98 over radii 2 to 45; box counting adds the
  ~2 pi R / s boxes cut by the rim to pi R^2 / s^2, which lowers the slope by about s / R
  (1.96 over sides 2 to 32). Tolerance 0.05.
* straight line of 1025 pores: M(R) = 2 floor(R) + 1 has local slope 2R / (2R + 1) (0.8 at
  R = 2), giving 0.985; box counting a line of 1024 is exact. Tolerance 0.03.
* Sierpinski carpet, level 6 (729 x 729): the set is only self-similar in steps of 3, so both
  log-log curves oscillate (local slopes 1.5 to 2.3 over each factor 3); a fit over a few
  periods is off by up to ~0.05 (mass-radius about the carpet's corner 1.91, box counting
  with powers of 2 1.86, against log 8 / log 3 = 1.893). Tolerance 0.06.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from porenet.analysis.fractal import (
    BIAS_TABLE,
    METHODS,
    FractalFit,
    box_counting,
    finite_size_bias,
    mass_radius,
    mass_radius_dimension,
    pattern_dimension,
)

CARPET = math.log(8) / math.log(3)


def grid(n: int) -> np.ndarray:
    i, j = np.divmod(np.arange(n * n), n)
    return np.stack([j.astype(float), i.astype(float)], axis=1)


def cell_coords(shape: tuple[int, int]) -> np.ndarray:
    i, j = np.indices(shape)
    return np.stack([j.ravel(), i.ravel()], axis=1).astype(float)


def disk(radius: int) -> np.ndarray:
    i, j = np.indices((2 * radius + 1, 2 * radius + 1))
    return (i - radius) ** 2 + (j - radius) ** 2 <= radius**2


def carpet(level: int) -> np.ndarray:
    g = np.ones((1, 1), bool)
    for _ in range(level):
        z = np.zeros_like(g)
        g = np.block([[g, g, g], [g, z, g], [g, g, g]])
    return g


def check(fit: FractalFit, method: str, expected: float, tol: float) -> None:
    assert fit.method == method
    assert fit.dimension == pytest.approx(expected, abs=tol)
    assert np.isfinite(fit.stderr) and fit.stderr >= 0
    assert np.isfinite(fit.error) and fit.error > 0
    assert fit.error >= fit.stderr
    assert fit.scales.shape == fit.counts.shape == fit.fitted.shape
    assert fit.fitted.sum() >= 3
    # the stored line reproduces the dimension and passes through the fitted points
    sign = 1.0 if method == "mass-radius" else -1.0
    x, y = np.log(fit.scales[fit.fitted]), np.log(fit.counts[fit.fitted])
    assert np.max(np.abs(fit.intercept + sign * fit.dimension * x - y)) < 0.3


# --- the old function, kept for examples/scripts/fig5.py -------------------------------------


def test_filled_square_has_dimension_two():
    xy = grid(201)
    d, _, _ = mass_radius_dimension(np.ones(len(xy), bool), xy, (100, 100), 5, 70)
    assert d == pytest.approx(2.0, abs=0.02)


def test_straight_cross_has_dimension_one():
    n = 201
    xy = grid(n)
    cross = (xy[:, 0] == 100) | (xy[:, 1] == 100)
    d, _, _ = mass_radius_dimension(cross, xy, (100, 100), 5, 70)
    assert d == pytest.approx(1.0, abs=0.02)


def test_bad_range_is_refused():
    xy = grid(5)
    with pytest.raises(ValueError, match="r_min"):
        mass_radius_dimension(np.ones(25, bool), xy, (2, 2), 3, 1)


def test_longest_straight_run_along_rows_and_columns():
    from porenet.analysis.features import longest_straight_run

    grid = np.zeros((6, 7), bool)
    grid[1, 0:3] = grid[1, 4:7] = True  # two runs of 3 in a row
    grid[0:5, 5] = True  # a column of 5, crossing the second run
    assert longest_straight_run(grid) == 5
    assert longest_straight_run(grid.T) == 5
    assert longest_straight_run(np.zeros((3, 3), bool)) == 0
    assert longest_straight_run(np.ones((2, 9), bool)) == 9


# --- known dimensions ------------------------------------------------------------------------


def test_filled_disk_has_dimension_two():
    g = disk(256)
    check(mass_radius(g.ravel(), cell_coords(g.shape), (256, 256)), "mass-radius", 2.0, 0.05)
    check(box_counting(g), "box-counting", 2.0, 0.05)


def test_straight_line_has_dimension_one():
    x = np.arange(1025.0)
    line = np.stack([x, np.zeros_like(x)], axis=1)
    check(mass_radius(np.ones(1025, bool), line, (512.0, 0.0)), "mass-radius", 1.0, 0.03)
    g = np.zeros((8, 1024), bool)
    g[3] = True
    check(box_counting(g), "box-counting", 1.0, 0.03)


def test_sierpinski_carpet():
    g = carpet(6)
    # about the carpet's corner, the point the similarity maps fix (cell centres at j, i)
    fit = mass_radius(g.ravel(), cell_coords(g.shape), (-0.5, -0.5))
    check(fit, "mass-radius", CARPET, 0.06)
    check(box_counting(g), "box-counting", CARPET, 0.06)


def test_units_spacing_and_explicit_range():
    g = disk(100)
    xy = cell_coords(g.shape)
    auto = mass_radius(g.ravel(), xy, (100, 100))
    scaled = mass_radius(g.ravel(), xy * 2e-7, (2e-5, 2e-5), spacing=2e-7)
    assert scaled.dimension == pytest.approx(auto.dimension, rel=1e-9)
    np.testing.assert_allclose(scaled.scales, auto.scales)
    # an explicit range: exactly n_radii radii from r_min to r_max, no calibrated bias
    fit = mass_radius(g.ravel(), xy, (100, 100), r_min=3, r_max=60, n_radii=9)
    np.testing.assert_allclose(fit.scales[fit.fitted], np.geomspace(3, 60, 9))
    assert math.isnan(fit.bias) and fit.error == fit.stderr
    assert fit.dimension == pytest.approx(2.0, abs=0.03)
    box = box_counting(g, s_min=1, s_max=16)
    np.testing.assert_array_equal(box.scales[box.fitted], [1, 2, 4, 8, 16])
    assert box.counts[0] == g.sum() and box.counts[-1] == 1


def test_automatic_range_carries_the_tabulated_bias():
    g = disk(100)
    fit = box_counting(g)
    bias, sd = finite_size_bias("box-counting", g.shape[0])
    assert fit.bias == pytest.approx(bias) and bias < 0
    assert fit.error == pytest.approx(math.sqrt(fit.stderr**2 + sd**2 + bias**2))


def test_bias_table_interpolation_and_extrapolation():
    for key, rows in BIAS_TABLE.items():
        sizes = [r[0] for r in rows]
        assert sizes == sorted(sizes) and len(sizes) >= 2
        method, injection, trapping = key
        lo, hi = rows[0], rows[-1]
        assert finite_size_bias(method, lo[0], injection=injection, trapping=trapping) == (
            pytest.approx((lo[1], lo[2]))
        )
        # above the table: the largest size's values; below: never smaller than the smallest
        big = finite_size_bias(method, 10 * hi[0], injection=injection, trapping=trapping)
        assert big == pytest.approx((hi[1], hi[2]))
        small = finite_size_bias(method, 10, injection=injection, trapping=trapping)
        assert abs(small[0]) >= abs(lo[1]) and small[1] >= lo[2]
    assert all(map(math.isnan, finite_size_bias("mass-radius", 400, injection="left-edge")))


# --- bad inputs ------------------------------------------------------------------------------


def test_empty_and_single_pore_patterns_are_refused():
    xy = grid(9)
    for k in (0, 1):
        drained = np.zeros(81, bool)
        drained[:k] = True
        with pytest.raises(ValueError, match="at least 2"):
            mass_radius(drained, xy, (4, 4))
        with pytest.raises(ValueError, match="at least 2"):
            box_counting(drained.reshape(9, 9))


def test_bad_ranges_are_refused():
    g = disk(50)
    xy = cell_coords(g.shape)
    for r_min, r_max in ((10, 5), (5, 5), (0, 5), (-1, 5)):
        with pytest.raises(ValueError, match="r_min < r_max"):
            mass_radius(g.ravel(), xy, (50, 50), r_min=r_min, r_max=r_max)
        with pytest.raises(ValueError, match="s_min < s_max"):
            box_counting(g, s_min=r_min, s_max=r_max)
    with pytest.raises(ValueError, match="fewer than 3 box sides"):
        box_counting(g, s_min=2, s_max=5)
    with pytest.raises(ValueError, match="n_radii"):
        mass_radius(g.ravel(), xy, (50, 50), n_radii=2)
    with pytest.raises(ValueError, match="too small"):  # reaches 3 spacings, range needs 8
        mass_radius(disk(3).ravel(), cell_coords((7, 7)), (3, 3))
    with pytest.raises(ValueError, match="2-D"):
        box_counting(np.ones(10, bool))


# --- runs ------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def small_run():
    import porenet

    return porenet.run(
        {"seed": 3, "lattice": {"n": 64, "disorder": 0.5}, "fluid": {"trapping": True}}
    ).data


def test_pattern_dimension_of_a_run(small_run):
    for method in METHODS:
        fit = pattern_dimension(small_run, method)
        assert fit.method == method
        assert 1.2 < fit.dimension < 2.0
        assert np.isfinite(fit.bias) and fit.bias < 0
        assert fit.error > abs(fit.bias) and fit.error > fit.stderr > 0
    # the run's pattern, inlet and spacing are those of the pure function
    data = small_run
    fit = pattern_dimension(data)
    ref = mass_radius(data.drained, data.pore_coords, data.pore_coords[data.order[0]],
                      spacing=2 * data.pore_size)  # fmt: skip
    assert fit.dimension == pytest.approx(ref.dimension)
    box = box_counting(data.as_grid(data.drained))
    assert pattern_dimension(data, "box-counting").dimension == pytest.approx(box.dimension)


def test_pattern_dimension_refuses_what_it_cannot_measure(small_run):
    from dataclasses import replace

    with pytest.raises(ValueError, match="mass-radius, box-counting"):
        pattern_dimension(small_run, "sandbox")
    empty = replace(small_run, drained=np.zeros_like(small_run.drained))
    with pytest.raises(ValueError, match="not measurable"):
        pattern_dimension(empty)
    edge = replace(small_run, scene={**small_run.scene, "injection": {"at": "left-edge"}})
    with pytest.raises(ValueError, match="box-counting"):
        pattern_dimension(edge)
    fit = pattern_dimension(edge, "box-counting")
    bias, _ = finite_size_bias("box-counting", 64, injection="left-edge", trapping=True)
    assert fit.bias == pytest.approx(bias)


def test_bias_study_script_runs_quick(tmp_path):
    script = Path(__file__).resolve().parents[3] / "examples" / "scripts" / "fractal_bias.py"
    out = subprocess.run(
        [sys.executable, str(script), "--quick", "--sizes", "32", "--seeds", "3"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 0, out.stderr
    assert "BIAS_TABLE" in out.stdout and "box-counting" in out.stdout
