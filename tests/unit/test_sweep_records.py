"""The summary of a sweep (porenet.sweep.records): what SummaryWriter writes, read_summary
reads back, row for row, with the documented types; the directory's file names are
porenet.sweep.layout's; a missing or foreign summary is an error naming the place."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from porenet.core.errors import ConfigError
from porenet.sweep import layout
from porenet.sweep.records import (
    SUMMARY_FIELDS,
    TEXT_COLUMNS,
    SummaryWriter,
    SweepSummary,
    as_summary,
    read_summary,
)
from porenet.sweep.spec import RunSpec

SWEPT = ["ca_star", "fluid.capillary_number", "lattice.disorder"]


def run(i: int, ca_star: float, disorder: float) -> RunSpec:
    params = {
        "ca_star": ca_star,
        "fluid.capillary_number": ca_star * 1e-3,
        "lattice.disorder": disorder,
    }
    return RunSpec(f"p{i:04d}-r00", point=i, replicate=0, seed=1000 + i, params=params, scene={})


@pytest.fixture
def written(tmp_path):
    """A summary of three runs written by the runner's writer, recorded out of order: a
    finished run with numpy values, a failed one, a finished one with NaN and no regime."""
    runs = [run(0, 0.5, 0.1), run(1, 5.0, 0.1), run(2, 50.0, 0.9)]
    writer = SummaryWriter(tmp_path, runs, SWEPT)
    writer.record(runs[2], "done", {"fractal_dimension": math.nan, "wall_time_s": 1.5})
    writer.record(runs[1], "failed", {"wall_time_s": 0.25}, "NumericalError: boom")
    values = {
        "fractal_dimension": np.float64(1.8125),
        "fractal_dimension_error": 0.03125,
        "regime": "CF",
        "regime_confidence": np.float32(0.75),
        "capillary_number_measured": None,
        "wall_time_s": 12.0,
    }
    writer.record(runs[0], "done", values)
    writer.write()
    return tmp_path, runs, writer


def test_the_writer_writes_where_the_layout_says(written):
    folder, _, writer = written
    assert writer.path == folder / layout.SUMMARY_CSV and writer.path.is_file()
    assert run(0, 1.0, 0.1).run_file == f"{layout.RUNS_DIR}/p0000-r00.h5"


def test_what_the_writer_writes_the_reader_reads(written):
    folder, runs, writer = written
    table = read_summary(folder)
    assert isinstance(table, SweepSummary)
    assert table.columns == writer.header
    assert table.columns == [
        "run_id",
        *SWEPT,
        "seed",
        "status",
        *SUMMARY_FIELDS,
        "run_file",
        "error",
    ]
    assert table.parameter_columns == SWEPT
    assert (table.root, table.source, table.scenes) == (folder, writer.path, {})
    assert table.name == folder.name
    assert [r["run_id"] for r in table.rows] == [r.run_id for r in runs]  # run order
    first, failed, last = table.rows
    assert first == {
        "run_id": "p0000-r00",
        "ca_star": 0.5,
        "fluid.capillary_number": 0.5e-3,
        "lattice.disorder": 0.1,
        "seed": 1000.0,
        "status": "done",
        "fractal_dimension": 1.8125,
        "fractal_dimension_error": 0.03125,
        "regime": "CF",
        "regime_confidence": 0.75,
        "capillary_number_measured": None,
        "wall_time_s": 12.0,
        "run_file": "runs/p0000-r00.h5",
        "error": None,
    }
    assert (failed["status"], failed["error"], failed["run_file"]) == (
        "failed",
        "NumericalError: boom",
        None,
    )
    assert failed["wall_time_s"] == 0.25 and failed["regime"] is None
    assert math.isnan(last["fractal_dimension"]) and last["regime"] is None
    for row in table.rows:  # numbers come back as float, text columns as str, empty as None
        for column, value in row.items():
            kind = str if column in TEXT_COLUMNS else float
            assert value is None or type(value) is kind, (column, value)


def test_the_csv_file_reads_as_its_directory(written):
    folder, _, _ = written
    same = read_summary(folder / layout.SUMMARY_CSV)
    assert repr(same.rows) == repr(read_summary(folder).rows)  # repr: NaN equals NaN


def test_scenes_come_from_sweep_json_when_it_reads(written):
    folder, runs, _ = written
    scene = {"lattice": {"n": 50}}
    listed = [{"run_id": runs[0].run_id, "scene": scene}, {"run_id": runs[1].run_id}]
    (folder / layout.SWEEP_JSON).write_text(json.dumps({"runs": listed}))
    assert read_summary(folder).scenes == {runs[0].run_id: scene}
    (folder / layout.SWEEP_JSON).write_text("{not json")
    assert read_summary(folder).scenes == {}  # a damaged sweep.json gives no scenes


def test_missing_summary_says_to_run_the_sweep(tmp_path):
    with pytest.raises(ConfigError, match=r"no summary\.csv; run `porenet sweep"):
        read_summary(tmp_path)
    with pytest.raises(ConfigError, match="no such directory"):
        read_summary(tmp_path / "nowhere")


def test_a_table_without_status_is_not_a_summary(tmp_path):
    (tmp_path / layout.SUMMARY_CSV).write_text("a,b\n1,2\n")
    with pytest.raises(ConfigError, match=r"summary\.csv: column 'status' missing"):
        read_summary(tmp_path)


def test_rows_given_as_dicts_are_a_summary_as_they_are(written):
    folder, _, _ = written
    rows = [{"lattice.disorder": 0.1, "status": "done"}, {"seed": 2, "lattice.disorder": 0.5}]
    table = as_summary(rows)
    assert table.rows == rows and table.rows[0] is not rows[0]
    assert table.columns == ["lattice.disorder", "status", "seed"]
    assert table.parameter_columns == ["lattice.disorder"] and table.name == ""
    assert as_summary(table) is table
    assert repr(as_summary(str(folder)).rows) == repr(read_summary(folder).rows)
