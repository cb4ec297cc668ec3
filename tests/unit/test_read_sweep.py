"""``porenet.read_sweep``: a sweep's summary as a pandas DataFrame, with the same rows and
columns as ``summary.csv``, and a clear message without pandas."""

from __future__ import annotations

import csv
import sys

import pytest

import porenet
from porenet.core.errors import ConfigError
from porenet.sweep.runner import run_sweep

SWEEP = """
name = "ip"
replicates = 2
[base]
lattice = { n = 20, disorder = 0.3 }
fluid = { kind = "invasion-percolation" }
[[axes]]
key = "lattice.n"
values = [18, 22]
"""


@pytest.fixture(scope="module")
def sweep_dir(tmp_path_factory):
    root = tmp_path_factory.mktemp("sweep")
    (root / "sweep.toml").write_text(SWEEP)
    run_sweep(root / "sweep.toml", root / "out", workers=1)
    return root / "out"


def test_the_frame_holds_the_summary(sweep_dir):
    frame = porenet.read_sweep(sweep_dir)
    with (sweep_dir / "summary.csv").open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(frame.columns) == list(rows[0])
    assert len(frame) == len(rows) == 4
    assert sorted(frame["lattice.n"]) == [18.0, 18.0, 22.0, 22.0]  # numbers, not text
    assert (frame["status"] == "done").all()
    assert frame.attrs["parameters"] == ["lattice.n"]
    # pandas' own tools work on it: the mean wall time a point
    assert set(frame.groupby("lattice.n")["wall_time_s"].mean().index) == {18.0, 22.0}


def test_no_sweep_there_names_the_directory(tmp_path):
    with pytest.raises(ConfigError, match="porenet sweep"):
        porenet.read_sweep(tmp_path / "nothing")


def test_without_pandas_the_message_says_how_to_install_it(sweep_dir, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas fails
    with pytest.raises(ImportError, match=r"porenet\[pandas\]"):
        porenet.read_sweep(sweep_dir)
