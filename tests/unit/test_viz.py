"""Figures of run files: every plot kind on a run that has what it needs, clear refusals
otherwise, and the pieces (fractal fit, aperture map, units, style) checked on known input."""

from __future__ import annotations

import math

import numpy as np
import pytest

import porenet
from porenet.analysis.fractal import FractalFit
from porenet.cli.main import main
from porenet.io.runfile import read_run
from porenet.viz import PLOT_KINDS, make_figure, plot_fractal_fit, plot_pattern, save_figure
from porenet.viz.figures import missing
from porenet.viz.mechanics import aperture_change, spring_segments, throat_image
from porenet.viz.style import format_pressure, length_unit, scene_title, time_unit, volume_unit

IP = {"kind": "invasion-percolation"}
SCENES = {
    "ip": {"seed": 3, "lattice": {"n": 24, "disorder": 0.4}, "fluid": IP},
    "viscous": {
        "seed": 1,
        "lattice": {"n": 20, "disorder": 0.3},
        "fluid": {"kind": "viscous", "capillary_number": 1e-2},
    },
    "hertz": {
        "seed": 1,
        "lattice": {"n": 20, "disorder": 0.1},
        "fluid": IP,
        "solid": {"kind": "hertz", "fracturing_number": 3},
    },
}
VALID = {
    "ip": ["pattern", "fractal", "timeseries"],
    "viscous": ["pattern", "time", "pressure", "fractal", "timeseries"],
    "hertz": ["pattern", "mechanics", "timeseries"],
}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Run files of a rigid IP, a rigid viscous and a deformable IP scene."""
    folder = tmp_path_factory.mktemp("runs")
    paths = {}
    for name, scene in SCENES.items():
        paths[name] = folder / f"{name}.h5"
        porenet.run(scene, output=paths[name])
    return paths


def test_every_kind_is_listed_with_a_description():
    assert {"pattern", "time", "pressure", "fractal", "mechanics", "timeseries"} <= set(PLOT_KINDS)
    assert all(callable(f) and d for f, d in PLOT_KINDS.values())


def test_the_figures_are_the_kinds_the_command_line_offers():
    """``porenet plot --kind`` takes its kinds from the light list; every one has a figure."""
    from porenet.plot_kinds import PLOT_KIND_DESCRIPTIONS
    from porenet.viz.figures import _FIGURES

    assert list(_FIGURES) == list(PLOT_KIND_DESCRIPTIONS)
    assert {k: d for k, (_, d) in PLOT_KINDS.items()} == PLOT_KIND_DESCRIPTIONS


PAIRS = [(r, k) for r, kinds in VALID.items() for k in kinds]


@pytest.mark.parametrize(("run", "kind"), PAIRS, ids=[f"{r}-{k}" for r, k in PAIRS])
def test_cli_draws_each_kind_on_a_suitable_run(runs, tmp_path, capsys, run, kind):
    png = tmp_path / f"{run}-{kind}.png"
    assert main(["plot", str(runs[run]), "--kind", kind, "-o", str(png), "--dpi", "60"]) == 0
    assert png.stat().st_size > 2000
    assert str(png) in capsys.readouterr().out


@pytest.mark.parametrize(
    ("run", "kind", "expected"),
    [
        ("ip", "mechanics", "is a rigid run (no mechanics recorded)"),
        ("ip", "pressure", "has no pressure field"),
        ("ip", "time", "quasi-static"),
        ("viscous", "mechanics", "rigid run"),
    ],
)
def test_wrong_kind_for_the_run_exits_2_naming_kind_and_file(runs, capsys, run, kind, expected):
    path = str(runs[run])
    assert main(["plot", path, "--kind", kind]) == 2
    err = capsys.readouterr().err
    assert f"--kind {kind}: {path} " in err and expected in err and "Traceback" not in err
    with pytest.raises(ValueError, match=f"kind '{kind}'"):
        make_figure(read_run(path), kind)


def test_pressure_flag_is_kind_pressure_and_default_names(runs, tmp_path, capsys):
    import shutil

    path = tmp_path / "v.h5"
    shutil.copy(runs["viscous"], path)
    assert main(["plot", str(path), "--pressure", "--dpi", "50"]) == 0
    assert (tmp_path / "v-pressure.png").stat().st_size > 2000
    assert main(["plot", str(path), "--dpi", "50"]) == 0  # the pattern keeps RUN.png
    assert (tmp_path / "v.png").is_file()
    assert main(["plot", str(path), "--pressure", "--kind", "time"]) == 2
    assert main(["plot", str(path), "-o", str(tmp_path / "v.nope")]) == 2
    assert "unknown picture format" in capsys.readouterr().err


def test_vector_output_and_api_figures(runs, tmp_path):
    from matplotlib.figure import Figure

    data = read_run(runs["viscous"])
    fig = make_figure(data, "time")
    assert isinstance(fig, Figure)
    assert fig.axes[1].get_ylabel() == "invasion time (ns)"  # colour bar, readable unit
    save_figure(fig, tmp_path / "t.pdf")
    assert (tmp_path / "t.pdf").read_bytes().startswith(b"%PDF")
    ts = make_figure(data, "timeseries")
    labels = [ax.get_ylabel() for ax in ts.axes]
    assert labels == ["$p_{inv}$ (MPa)", "volume (µm³)", "Ca (-)"]
    assert ts.axes[-1].get_xlabel() == "time (ns)"
    with pytest.raises(ValueError, match="unknown plot kind 'nope'"):
        make_figure(data, "nope")


def test_pattern_by_order_or_time(runs):
    ip = read_run(runs["ip"])
    fig = plot_pattern(ip)
    ax, cbar = fig.axes
    assert cbar.get_ylabel() == "drainage step"
    # the axes span 2 n a (docs/model.md section 1), and the label says which length it is
    assert ax.get_xlabel() == "x (µm; the lattice spans 2 n a, L = n a)"
    assert ax.get_ylabel() == "y (µm)"
    assert ax.get_xlim() == pytest.approx((0.0, 24 * 2e-7 / 1e-6))
    image = ax.get_images()[-1].get_array()
    assert np.nanmax(image) == len(ip.order) - 1
    with pytest.raises(ValueError, match="needs a dynamic run"):
        plot_pattern(ip, color_by="time")
    with pytest.raises(ValueError, match="color_by"):
        plot_pattern(ip, color_by="colour")
    visc = read_run(runs["viscous"])
    image = plot_pattern(visc, color_by="time").axes[0].get_images()[-1].get_array()
    assert np.nanmax(image) == pytest.approx(visc.invasion_time.max() / 1e-9)


def test_static_timeseries_is_the_entry_pressure_signal(runs):
    ip = read_run(runs["ip"])
    ax = make_figure(ip, "timeseries").axes[0]
    points, running = ax.get_lines()
    steps = np.asarray(ip.throat) >= 0
    np.testing.assert_allclose(points.get_ydata(), ip.invasion_pressure[steps] / 1e6)
    assert np.nanmax(running.get_ydata()) == pytest.approx(ip.invasion_pressure.max() / 1e6)
    assert ax.get_ylabel() == "pressure (MPa)" and ax.get_xlabel() == "drainage step"


def test_mechanics_map_places_throats_and_removed_springs(runs):
    data = read_run(runs["hertz"])
    change = aperture_change(data)
    np.testing.assert_allclose(change, data.final_apertures / data.apertures - 1)
    image = throat_image(data, change, fill=False)
    cols = data.grid_shape[1]
    p, q = data.throat_pores[0]
    (r1, c1), (r2, c2) = divmod(int(p), cols), divmod(int(q), cols)
    assert image[r1 + r2 + 1, c1 + c2 + 1] == change[0]
    assert np.count_nonzero(np.isfinite(image)) == len(change)
    removed = np.flatnonzero(data.mechanics_final["removed_springs"])
    assert removed.size > 0
    seg = spring_segments(data, removed)
    length = np.linalg.norm(seg[:, 1] - seg[:, 0], axis=1)
    np.testing.assert_allclose(length, 2 * data.pore_size)  # particle to particle
    pores = data.throat_pores[removed]
    axis = data.pore_coords[pores[:, 1]] - data.pore_coords[pores[:, 0]]
    np.testing.assert_allclose(np.sum((seg[:, 1] - seg[:, 0]) * axis, axis=1), 0, atol=1e-20)
    fig = make_figure(data, "mechanics")
    assert f"{removed.size} springs removed" in fig.get_suptitle()
    legend = fig.axes[0].get_legend().get_texts()[0].get_text()
    assert legend == f"removed springs ({removed.size})"


def test_fractal_fit_plot_from_a_hand_made_fit():
    r = np.geomspace(1, 20, 10)
    fitted = (r > 1.5) & (r < 12)
    fit = FractalFit("mass-radius", 1.8, 0.05, 0.02, -0.03, r, 2 * r**1.8, fitted, math.log(2))
    fig = plot_fractal_fit(fit, label="test", spacing=2e-7)
    ax = fig.axes[0]
    outside, inside, line = ax.get_lines()
    assert len(inside.get_xdata()) == fitted.sum() and len(outside.get_xdata()) == (~fitted).sum()
    x, y = line.get_xdata(), line.get_ydata()
    slope = np.diff(np.log(y))[0] / np.diff(np.log(x))[0]
    assert slope == pytest.approx(1.8)
    np.testing.assert_allclose(x[[0, -1]], r[fitted][[0, -1]] * 0.2)  # µm, spacing 0.2 µm
    assert "test: $D_f$ = 1.80 ± 0.05" in [t.get_text() for t in ax.get_legend().get_texts()]
    assert ax.get_xlabel() == "distance from the inlet $R$ (µm)"
    box = FractalFit("box-counting", 1.6, math.nan, 0.01, math.nan, r, 500 * r**-1.6, fitted, 6.2)
    line = plot_fractal_fit(box).axes[0].get_lines()[-1]
    x, y = line.get_xdata(), line.get_ydata()
    assert np.diff(np.log(y))[0] / np.diff(np.log(x))[0] == pytest.approx(-1.6)
    assert "(lattice spacings)" in plot_fractal_fit(box).axes[0].get_xlabel()


def test_missing_names_what_the_run_lacks(runs):
    hertz = read_run(runs["hertz"])
    assert missing(hertz, "mechanics") is None
    assert "quasi-static" in missing(hertz, "time")
    with pytest.raises(ValueError, match="known kinds: pattern"):
        missing(hertz, "nope")


def test_units_and_titles():
    assert length_unit(4.8e-6) == ("µm", 1e-6)
    assert time_unit(2.8e-7) == ("ns", 1e-9)
    assert volume_unit(1.9e-19) == ("µm³", 1e-18)
    assert format_pressure(1.48e6) == "1.48 MPa" and format_pressure(350.0) == "350 Pa"

    from types import SimpleNamespace

    fluid = {"kind": "viscous", "capillary_number": 9e-4}
    run = SimpleNamespace(
        grid_shape=(400, 400),
        summary={},
        scene={"name": "", "lattice": {"disorder": 0.3}, "fluid": fluid},
    )
    assert scene_title(run) == "viscous, n = 400, Ca = 0.0009, λ = 0.3"
    assert "\n" in scene_title(run, ["p_inv = 1.48 MPa", "t = 3 µs"], width=40)


def test_style_does_not_leak_into_global_rc(runs):
    import matplotlib

    before = dict(matplotlib.rcParams)
    plot_pattern(read_run(runs["ip"]))
    assert dict(matplotlib.rcParams) == before


def test_importing_viz_loads_no_matplotlib():
    import subprocess
    import sys

    code = "import sys, porenet.viz, porenet.cli.main; print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_the_run_file_names_both_lengths(runs):
    """/lattice attrs: length_L = n a (the paper's L) and extent = 2 n a, the span of the
    pore centres plus half a node spacing on each side."""
    import h5py

    with h5py.File(runs["ip"]) as f:
        lat = f["lattice"]
        a, cols = lat.attrs["pore_size"], max(lat.attrs["grid_shape"])
        assert lat.attrs["length_L"] == pytest.approx(cols * a)
        assert lat.attrs["extent"] == pytest.approx(2 * cols * a)
        extent = lat.attrs["extent"]
        coords = lat["pore_coords"][:]
    assert coords[:, 0].min() - a == pytest.approx(0.0, abs=1e-3 * a)
    assert coords[:, 0].max() + a == pytest.approx(extent)


def test_trapped_legend_sits_below_the_x_label_in_a_narrow_panel(runs):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    data = read_run(runs["ip"])
    data.trapped[: data.n_pores // 4] = True  # some defender trapped, whatever the run did
    data.drained[: data.n_pores // 4] = False
    fig = Figure(figsize=(12, 3.3), layout="constrained")
    axes = fig.subplots(1, 4)  # a panel narrower than the x label
    plot_pattern(data, ax=axes[1], title="narrow")
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    label = axes[1].xaxis.label.get_window_extent(renderer)
    legend = axes[1].get_legend()
    assert legend.get_texts()[0].get_text() == "trapped defender"
    assert legend.get_window_extent(renderer).y1 <= label.y0  # wholly below the label
