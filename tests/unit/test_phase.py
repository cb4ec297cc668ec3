"""Phase diagrams of a sweep (porenet.analysis.phase aggregates, porenet.viz.phase draws,
`porenet phase-diagram`): both axis kinds from hand-made summaries, coordinates read from run
files when they are not columns, replicates aggregated, failed runs drawn, and the command's
exit codes and messages."""

from __future__ import annotations

import csv
import itertools
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg

import porenet
from porenet.analysis.numbers import modified_capillary_number
from porenet.analysis.phase import (
    choose_axes,
    dimension_curve,
    phase_points,
    points_table,
    regime_dimensions,
)
from porenet.cli.main import main
from porenet.core.errors import ConfigError
from porenet.sweep.records import read_summary
from porenet.viz.phase import MARKERS, plot_dimension_curve, plot_phase_diagram

RESULT = [
    "seed",
    "status",
    "fractal_dimension",
    "fractal_dimension_error",
    "regime",
    "regime_confidence",
    "capillary_number_measured",
    "wall_time_s",
    "run_file",
    "error",
]


#: The swept columns of :func:`deformable_rows`.
DEFORMABLE_PARAMS = ["ca_star", "fluid.capillary_number", "solid.fracturing_number"]


def write_summary(folder, rows, params):
    """Write ``folder/summary.csv`` with the engine's columns (run_id, params, results)."""
    folder.mkdir(parents=True, exist_ok=True)
    columns = ["run_id", *params, *RESULT]
    with (folder / "summary.csv").open("w", newline="") as f:
        writer = csv.DictWriter(f, columns)
        writer.writeheader()
        for i, row in enumerate(rows):
            writer.writerow({"run_id": f"r{i:03d}", "status": "done", **row})
    return folder


def rigid_rows():
    """A 3 x 3 Ca-lambda grid, two seeds each; one point's seeds disagree, one run failed."""
    rows = []
    for lam in (0.1, 0.5, 0.9):
        for ca in (1e-4, 1e-3, 1e-2):
            label = "VF" if modified_capillary_number(ca, 100, lam) > 1 else "CF"
            for seed in (0, 1):
                rows.append(
                    {
                        "lattice.disorder": lam,
                        "fluid.capillary_number": ca,
                        "lattice.n": 100,
                        "seed": seed,
                        "regime": label,
                        "regime_confidence": 0.8,
                        "fractal_dimension": 1.64 if label == "VF" else 1.82,
                    }
                )
    rows[0]["regime"], rows[0]["regime_confidence"] = "CF/VF", 0.6  # point 1: CF/VF vs VF
    rows[-1].update(status="failed", regime="", fractal_dimension="", error="boom")
    return rows


def deformable_rows():
    rows = []
    for cs in (0.1, 10.0):
        for nf in (0.01, 10.0):
            label = "FR" if nf > 1 else ("VF" if cs > 1 else "CF")
            rows.append(
                {
                    "ca_star": cs,
                    "fluid.capillary_number": cs * 0.101 / 64,
                    "solid.fracturing_number": nf,
                    "seed": 0,
                    "regime": label,
                    "regime_confidence": 0.9,
                    "fractal_dimension": 1.5,
                }
            )
    return rows


@pytest.fixture
def rigid_dir(tmp_path):
    return write_summary(
        tmp_path / "rigid",
        rigid_rows(),
        ["lattice.disorder", "fluid.capillary_number", "lattice.n"],
    )


@pytest.fixture
def deformable_dir(tmp_path):
    return write_summary(tmp_path / "deformable", deformable_rows(), DEFORMABLE_PARAMS)


@pytest.fixture(scope="module")
def run_files(tmp_path_factory):
    """Two tiny real runs (n = 24): a rigid viscous one and a deformable one."""
    folder = tmp_path_factory.mktemp("sweep") / "runs"
    folder.mkdir()
    viscous = {"kind": "viscous", "capillary_number": 2e-2}
    porenet.run(
        {"seed": 1, "lattice": {"n": 24, "disorder": 0.3}, "fluid": viscous},
        output=folder / "rigid.h5",
    )
    porenet.run(
        {
            "seed": 1,
            "lattice": {"n": 24, "disorder": 0.1},
            "fluid": viscous,
            "solid": {"kind": "hertz", "fracturing_number": 3.0},
        },
        output=folder / "hertz.h5",
    )
    return folder.parent


def test_replicates_are_aggregated_by_majority_and_mean(rigid_dir):
    kind, points = phase_points(rigid_dir)
    assert kind == "ca-lambda" and len(points) == 9
    first = points[0]  # lambda 0.1, Ca 1e-4: labels CF/VF (0.6) and CF (0.8): a tie
    assert first.n_done == 2 and first.agreement == 0.5
    assert first.regime == "CF"  # tie goes to the larger summed confidence
    assert (first.x, first.y) == (0.1, 1e-4)
    assert first.ca_star == pytest.approx(modified_capillary_number(1e-4, 100, 0.1))
    last = points[-1]
    assert (last.n_done, last.n_failed, last.regime) == (1, 1, "CF")  # Ca* = 0.21
    assert last.dimension == pytest.approx(1.82) and math.isnan(last.dimension_sd)
    assert "| 0.9 | 0.01 |" in points_table(points)
    stats = regime_dimensions(rigid_dir)
    assert stats["VF"][0] == pytest.approx(1.64) and stats["CF/VF"][2] == 1


def test_ca_lambda_diagram(rigid_dir):
    fig = plot_phase_diagram(rigid_dir)
    ax = fig.axes[0]
    assert ax.get_yscale() == "log" and ax.get_xscale() == "linear"
    assert "lambda" in ax.get_xlabel() and "Ca" in ax.get_ylabel()
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any("a/L" in t and "L = 100a" in t for t in texts)  # the theoretical line
    assert {"CF", "VF"} <= set(texts) and "failed (1 run)" in texts
    assert "D_f" in fig.axes[1].get_ylabel()  # the colour bar


def test_nf_castar_diagram_is_picked_from_the_columns(deformable_dir):
    assert choose_axes(deformable_dir) == "nf-castar"
    fig = plot_phase_diagram(read_summary(deformable_dir), axes="auto")
    ax = fig.axes[0]
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    assert "Ca*" in ax.get_xlabel() and "N_f" in ax.get_ylabel()
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any("N_f" in t and "= 1" in t for t in texts) and any("Ca* = 1" in t for t in texts)
    assert {"CF", "VF", "FR"} <= set(texts)
    _, points = phase_points(deformable_dir, "nf-castar")
    assert sorted((p.x, p.y) for p in points) == [
        (0.1, 0.01),
        (0.1, 10.0),
        (10.0, 0.01),
        (10.0, 10.0),
    ]


def test_a_narrow_axis_gets_plain_labels_that_do_not_overlap(tmp_path):
    # a sweep still running (or over a narrow range) spans about a decade: matplotlib labelled
    # its minor ticks "2 x 10^-1", "3 x 10^-1", "4 x 10^-1", which overlapped
    rows = [row for row in deformable_rows() if row["ca_star"] == 0.1]
    for row in rows:
        row["ca_star"] = 0.3
    rows.append(rows[0] | {"ca_star": 1.0})
    fig = plot_phase_diagram(write_summary(tmp_path / "narrow", rows, DEFORMABLE_PARAMS))
    ax = fig.axes[0]
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    lo, hi = ax.get_xlim()
    ticks = [t for t in ax.xaxis.get_majorticklabels() + ax.xaxis.get_minorticklabels()
             if t.get_visible() and t.get_text() and lo <= t.get_position()[0] <= hi]  # fmt: skip
    assert sorted(float(t.get_text()) for t in ticks) == [0.2, 0.3, 0.5, 1.0, 2.0]
    boxes = sorted((t.get_window_extent(renderer) for t in ticks), key=lambda b: b.x0)
    assert all(a.x1 < b.x0 for a, b in itertools.pairwise(boxes))
    # the full-size diagrams (several decades) keep matplotlib's decade labels
    wide = plot_phase_diagram(
        write_summary(tmp_path / "wide", deformable_rows(), DEFORMABLE_PARAMS)
    )
    wide.draw(FigureCanvasAgg(wide).get_renderer())
    assert any("10^" in t.get_text() for t in wide.axes[0].xaxis.get_majorticklabels())


def test_coordinates_missing_from_the_columns_come_from_the_run_files(run_files):
    rows = [
        {
            "fluid.capillary_number": 2e-2,
            "run_file": "runs/rigid.h5",
            "regime": "VF",
            "fractal_dimension": 1.6,
        }
    ]
    folder = write_summary(run_files / "rigid", rows, ["fluid.capillary_number"])
    (folder / "runs").symlink_to(run_files / "runs")
    kind, (point,) = phase_points(folder)
    assert kind == "ca-lambda" and (point.x, point.y, point.n) == (0.3, 2e-2, 24)
    rows = [
        {"solid.fracturing_number": 3.0, "run_file": "runs/hertz.h5", "regime": "FR"},
        {"solid.fracturing_number": 3.0, "run_file": "", "status": "failed", "seed": 1},
    ]
    folder = write_summary(run_files / "hertz", rows, ["solid.fracturing_number"])
    (folder / "runs").symlink_to(run_files / "runs")
    kind, (point,) = phase_points(folder)  # Ca* from the run file's n, lambda and Ca
    assert kind == "nf-castar" and point.y == 3.0 and point.n_failed == 1
    assert point.x == pytest.approx(modified_capillary_number(2e-2, 24, 0.1))
    assert plot_phase_diagram(folder).axes[0].get_xscale() == "log"


def test_coordinates_from_sweep_json_when_runs_failed(tmp_path):
    """`porenet sweep` writes every run's scene to DIR/sweep.json: failed runs (no run file)
    are placed from it."""
    scene = {"lattice": {"n": 50, "disorder": 0.4}, "fluid": {"capillary_number": 1e-3}}
    rows = [{"fluid.capillary_number": 1e-3, "status": "failed", "error": "boom"}]
    folder = write_summary(tmp_path / "s", rows, ["fluid.capillary_number"])
    runs = [{"run_id": "r000", "scene": scene}]
    (folder / "sweep.json").write_text(json.dumps({"runs": runs}))
    _, (point,) = phase_points(folder)
    assert (point.x, point.y, point.n, point.n_failed, point.regime) == (0.4, 1e-3, 50, 1, None)
    texts = [t.get_text() for t in plot_phase_diagram(folder).axes[0].get_legend().get_texts()]
    assert "failed (1 run)" in texts


def test_a_real_sweep_end_to_end(tmp_path):
    sweep = tmp_path / "tiny.toml"
    sweep.write_text(
        'name = "tiny"\nreplicates = 1\n[base]\nlattice = { n = 24, disorder = 0.3 }\n'
        'fluid = { kind = "viscous", capillary_number = 1e-2 }\n'
        '[[axes]]\nkey = "ca_star"\nvalues = [3, 30]\n'
    )
    out = tmp_path / "out"
    assert main(["sweep", str(sweep), "-o", str(out), "--workers", "1", "-q"]) == 0
    assert main(["phase-diagram", str(out), "-o", str(tmp_path / "p.png")]) == 0
    kind, points = phase_points(out)
    assert kind == "ca-lambda" and [p.n for p in points] == [24, 24]
    assert [p.ca_star for p in points] == [3, 30] and all(p.n_done == 1 for p in points)


def test_unplaceable_points_are_an_error_naming_the_columns(tmp_path):
    folder = write_summary(tmp_path / "s", [{"seed": 0, "regime": "CF"}], [])
    with pytest.raises(ConfigError, match=r"lattice\.disorder and fluid\.capillary_number"):
        plot_phase_diagram(folder)
    with pytest.raises(ConfigError, match="unknown"):
        phase_points(folder, "ca-nf")


def test_dimension_curve_over_the_most_varied_key(rigid_dir, deformable_dir):
    fig = plot_dimension_curve(rigid_dir, key="fluid.capillary_number")
    ax = fig.axes[0]
    assert ax.get_xscale() == "log" and "Ca" in ax.get_xlabel()
    assert "mean ± sd over seeds" in [t.get_text() for t in ax.get_legend().get_texts()]
    ax = plot_dimension_curve(deformable_dir).axes[0]  # 2 values each: the first such column
    assert "Ca*" in ax.get_xlabel()
    with pytest.raises(ConfigError, match="no column"):
        plot_dimension_curve(rigid_dir, key="solid.fracturing_number")


def test_dimension_curve_numbers(rigid_dir):
    """Mean and sample sd per Ca over the finished runs (rigid_rows: D_f 1.64 for VF, 1.82
    for CF; the failed run at lambda 0.9, Ca 1e-2 has no D_f)."""
    curve = dimension_curve(rigid_dir, key="fluid.capillary_number")
    assert curve.values == [1e-4, 1e-3, 1e-2]
    assert len(curve.runs) == 17  # 18 runs, one failed
    for value, mean, sd in zip(curve.values, curve.means, curve.sds, strict=True):
        dims = [d for x, d, _ in curve.runs if x == value]
        assert mean == pytest.approx(sum(dims) / len(dims))
        assert sd == pytest.approx(float(np.std(dims, ddof=1)))
    with pytest.raises(ConfigError, match=r"summary\.csv: no column 'nope'"):
        dimension_curve(rigid_dir, key="nope")


def test_aggregation_imports_no_matplotlib():
    code = (
        "import sys; import porenet.analysis.phase; "
        "print(sorted(m for m in sys.modules if m.startswith('matplotlib')))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_every_regime_has_its_own_marker():
    assert len(set(MARKERS.values())) == len(MARKERS)


def test_cli_draws_both_kinds(rigid_dir, deformable_dir, tmp_path, capsys):
    out = tmp_path / "rigid.png"
    table = tmp_path / "points.md"
    assert main(["phase-diagram", str(rigid_dir), "-o", str(out), "--table", str(table)]) == 0
    assert out.stat().st_size > 10_000 and table.read_text().startswith("| λ | Ca |")
    out = tmp_path / "deformable.svg"
    assert main(["phase-diagram", str(deformable_dir), "-o", str(out), "--axes", "nf-castar"]) == 0
    assert out.read_text().lstrip().startswith("<?xml")
    assert "figure:" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["DIR_EMPTY", "-o", "OUT/x.png"], "no summary.csv; run `porenet sweep"),
        (["DIR_RIGID", "-o", "OUT/missing/x.png"], "directory does not exist"),
        (["DIR_RIGID", "-o", "OUT/x.xyz"], "unknown picture format"),
        (["DIR_BARE", "-o", "OUT/x.png"], "lattice.disorder and fluid.capillary_number"),
    ],
)
def test_cli_errors_exit_2_with_a_message(args, message, rigid_dir, tmp_path, capsys):
    empty = tmp_path / "empty"
    empty.mkdir()
    bare = write_summary(tmp_path / "bare", [{"seed": 0}], [])
    paths = {"DIR_EMPTY": empty, "DIR_RIGID": rigid_dir, "DIR_BARE": bare, "OUT": tmp_path}
    argv = ["phase-diagram"]
    for a in args:
        for k, v in paths.items():
            a = a.replace(k, str(v))
        argv.append(a)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("porenet phase-diagram: error:") and message in err


def test_cli_rejects_unknown_axes(rigid_dir, tmp_path):
    with pytest.raises(SystemExit) as exc:
        main(["phase-diagram", str(rigid_dir), "-o", str(tmp_path / "x.png"), "--axes", "x"])
    assert exc.value.code == 2
