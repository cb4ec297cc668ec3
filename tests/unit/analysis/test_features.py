"""Pattern features on shapes whose answer is known by construction."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import porenet
from porenet.analysis.features import (
    LONG_RUN,
    anisotropy,
    finger_widths,
    longest_straight_run,
    opened_fraction,
    pattern_features,
    straight_runs,
)


def cross(n: int = 41) -> np.ndarray:
    grid = np.zeros((n, n), dtype=bool)
    grid[n // 2, :] = True
    grid[:, n // 2] = True
    return grid


def test_straight_runs_of_a_line_and_a_block():
    line = np.zeros((9, 9), dtype=bool)
    line[4, 1:8] = True
    assert sorted(straight_runs(line))[-1] == 7
    assert longest_straight_run(line) == 7
    block = np.zeros((9, 9), dtype=bool)
    block[2:7, 2:7] = True
    assert longest_straight_run(block) == 5
    # a compact block holds rows of 5 but no channel one pore wide
    assert straight_runs(block, thin=True).size == 0
    assert straight_runs(line, thin=True).max() == 7


def test_thin_runs_of_a_cross_stop_at_the_crossing():
    thin = straight_runs(cross(41), thin=True)
    # four arms of 20 pores: the crossing cell has drained neighbours across both arms
    assert sorted(thin.tolist()) == [20, 20, 20, 20]


def test_finger_widths():
    widths = finger_widths(cross(21))
    assert np.count_nonzero(widths != 1.0) == 1  # the crossing: 2 sqrt(2) - 1 (diagonal gap)
    assert widths.max() == pytest.approx(2 * np.sqrt(2) - 1)
    block = np.zeros((11, 11), dtype=bool)
    block[3:8, 3:8] = True
    assert finger_widths(block).max() == pytest.approx(5.0)
    assert finger_widths(np.zeros((4, 4), dtype=bool)).size == 0


def test_anisotropy_of_a_line_a_disc_and_a_cross():
    line = np.zeros((20, 20), dtype=bool)
    line[10, 2:18] = True
    a = anisotropy(line)
    assert a["gyration_ratio"] == pytest.approx(0.0, abs=1e-12)
    assert a["axis_bias"] == pytest.approx(1.0)
    y, x = np.mgrid[-30:31, -30:31]
    disc = anisotropy(x**2 + y**2 <= 25**2)
    assert disc["gyration_ratio"] == pytest.approx(1.0, abs=1e-9)  # symmetric under x <-> y
    assert disc["axis_bias"] == pytest.approx(0.0, abs=1e-12)
    assert anisotropy(cross())["gyration_ratio"] == pytest.approx(1.0)
    assert np.isnan(anisotropy(np.zeros((3, 3), dtype=bool))["gyration_ratio"])


def test_pattern_features_of_an_invasion_percolation_run():
    result = porenet.run(
        {
            "seed": 1,
            "lattice": {"n": 48, "disorder": 0.5},
            "fluid": {"trapping": True},
            "classifier": {"kind": "none"},
        }
    )
    f = pattern_features(result.data)
    assert f["drained_fraction"] == pytest.approx(result.summary["drained_fraction"])
    assert 0 <= f["trapped_fraction"] < 1 - f["drained_fraction"]
    assert f["finger_width_mean"] >= 1.0
    assert f["longest_run"] >= f["longest_thin_run"] >= 1
    assert 0 <= f["thin_run_fraction"] <= 1
    assert f["n_bursts"] == result.summary["n_bursts"]
    assert LONG_RUN > 1


def test_opened_fraction_counts_pores_entered_through_removed_springs():
    result = porenet.run(
        {
            "seed": 2,
            "lattice": {"n": 24, "disorder": 0.5},
            "fluid": {"kind": "invasion-percolation"},
            "classifier": {"kind": "none"},
        }
    )
    data = result.data
    f = pattern_features(data)
    assert np.isnan(f["opened_fraction"])  # rigid: no springs
    entered = data.throat[data.throat >= 0]
    removed = np.zeros(len(data.throat_pores), dtype=bool)
    removed[entered[::2]] = True  # every other entered pore came through an opened throat
    # as a deformable run records it: the solid's removed springs, apertures that could change
    deformable = data.summary | {"plan_deformable": True}
    opened = dataclasses.replace(
        data, mechanics_final={"removed_springs": removed}, summary=deformable
    )
    assert opened_fraction(opened) == pytest.approx(len(entered[::2]) / len(entered))
    none = dataclasses.replace(opened, mechanics_final={"removed_springs": removed & False})
    assert opened_fraction(none) == 0.0
    # coupled one way, the fluid never went through what the solid opened
    one_way = dataclasses.replace(opened, summary=data.summary | {"plan_deformable": False})
    assert np.isnan(opened_fraction(one_way))


@pytest.mark.parametrize(("n_f", "label"), [(3.0, "FR"), (0.01, None)])
def test_rules_call_invasion_through_opened_throats_fracturing(n_f, label):
    scene = {
        "seed": 1,
        "lattice": {"n": 30, "disorder": 0.1, "pore_size": 1e-7},
        "fluid": {"kind": "invasion-percolation"},
        "solid": {"kind": "hertz", "fracturing_number": n_f},
    }
    result = porenet.run(scene)
    f = pattern_features(result.data)
    if label == "FR":
        assert f["opened_fraction"] >= 0.5
        assert result.summary["regime"] == "FR"
    else:
        assert f["opened_fraction"] == 0.0
        assert not result.summary["regime"].startswith("FR")
