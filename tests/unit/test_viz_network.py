"""Plots of patterns on lattices without a grid layout (porenet.viz.network): a 3-D lattice as
three projections, an irregular 2-D network as pores over its throats; the CLI draws them."""

from __future__ import annotations

import dataclasses
import subprocess
import sys

import numpy as np
import pytest

from porenet.simulation import Simulation
from porenet.viz.pattern import plot_pattern

CUBIC = {"kind": "cubic", "shape": [12, 10, 8], "disorder": 0.5}


@pytest.fixture(scope="module")
def run_3d(tmp_path_factory):
    path = tmp_path_factory.mktemp("viz3d") / "run.h5"
    sc = {"seed": 1, "lattice": CUBIC, "fluid": {"kind": "viscous", "capillary_number": 1e-2},
          "classifier": {"kind": "none"}}  # fmt: skip
    result = Simulation.from_scene(sc, output=path).run()
    return result.data, path


def test_3d_pattern_is_three_projections(run_3d):
    data, _ = run_3d
    fig = plot_pattern(data)
    maps = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    assert [ax.get_title() for ax in maps] == ["x-y projection", "x-z projection",
                                                "y-z projection"]  # fmt: skip
    # every drained pore is drawn in each projection, at its coordinates (here in µm)
    points = maps[0].collections[-1].get_offsets()
    assert len(points) == int(data.drained.sum())
    np.testing.assert_allclose(np.sort(points[:, 0]),
                               np.sort(data.pore_coords[data.drained, 0] * 1e6))  # fmt: skip
    assert "12 x 10 x 8" in fig.get_suptitle()


def test_irregular_2d_network_draws_its_throats(run_3d):
    sc = {"seed": 2, "lattice": {"n": 10, "disorder": 0.5},
          "fluid": {"kind": "invasion-percolation"}, "classifier": {"kind": "none"}}  # fmt: skip
    data = dataclasses.replace(Simulation.from_scene(sc).run().data, grid_shape=None)
    fig = plot_pattern(data, title="network")
    (ax,) = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    lines = [c for c in ax.collections if type(c).__name__ == "LineCollection"]
    assert len(lines) == 1 and len(lines[0].get_segments()) == len(data.throat_pores)


@pytest.mark.parametrize(("kind", "status"), [("pattern", 0), ("time", 0), ("fractal", 2),
                                              ("pressure", 0), ("mechanics", 2)])  # fmt: skip
def test_cli_plots_a_3d_run(run_3d, tmp_path, kind, status):
    _, path = run_3d
    out = tmp_path / f"{kind}.png"
    proc = subprocess.run([sys.executable, "-m", "porenet", "plot", str(path), "-k", kind,
                           "-o", str(out)], capture_output=True, text=True)  # fmt: skip
    assert proc.returncode == status, proc.stderr
    assert out.exists() == (status == 0)
    if status:  # a rigid run has no mechanics; this small pattern is too small for D_f
        assert "Traceback" not in proc.stderr
        assert ("rigid run" if kind == "mechanics" else "too small") in proc.stderr


def test_3d_pressure_is_three_maximum_projections_of_every_pore(run_3d):
    from porenet.viz.pressure import plot_pressure_halo, pressure_ratio

    data, _ = run_3d
    fig = plot_pressure_halo(data)
    maps = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    assert [ax.get_title() for ax in maps] == [f"{p} maximum projection"
                                               for p in ("x-y", "x-z", "y-z")]  # fmt: skip
    points = maps[0].collections[-1]
    assert len(points.get_offsets()) == data.n_pores  # every pore, not only the drained
    # the largest values are drawn last (on top): 0 for the drained pores, p = p_inv
    ratio, _ = pressure_ratio(data)
    shown = np.asarray(points.get_array())
    assert np.all(np.diff(shown) >= 0) and shown[-1] == pytest.approx(0.0)
    assert np.sort(shown) == pytest.approx(np.sort(np.log10(np.clip(ratio, 1e-4, None))))


def test_a_mechanics_map_on_a_network_points_to_paraview():
    from porenet.viz.figures import missing

    data = dataclasses.replace(_deformable_data(), grid_shape=None)
    assert "porenet export" in missing(data, "mechanics")


def _deformable_data():
    sc = {"seed": 1, "lattice": {"n": 10, "disorder": 0.3},
          "fluid": {"kind": "invasion-percolation"},
          "solid": {"kind": "hertz", "fracturing_number": 1.0},
          "classifier": {"kind": "none"}}  # fmt: skip
    return Simulation.from_scene(sc).run().data


def test_fractal_figure_of_a_3d_pattern():
    from porenet.viz.figures import make_figure

    sc = {"seed": 0, "lattice": CUBIC | {"shape": [40, 40, 40]},
          "fluid": {"kind": "invasion-percolation", "trapping": False},
          "stop": {"at": "complete", "max_drained": 6000},
          "classifier": {"kind": "none"}}  # fmt: skip
    fig = make_figure(Simulation.from_scene(sc).run().data, "fractal")
    assert [ax.get_title() for ax in fig.axes] == ["mass-radius", "box-counting"]
