"""Mass-radius fractal dimension on shapes of known dimension."""

from __future__ import annotations

import numpy as np
import pytest

from porenet.analysis.fractal import mass_radius_dimension


def grid(n: int) -> np.ndarray:
    i, j = np.divmod(np.arange(n * n), n)
    return np.stack([j.astype(float), i.astype(float)], axis=1)


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
