"""Run files: documented layout, atomic writes, reader returns the same arrays."""

from __future__ import annotations

import json
import os
import stat

import h5py
import numpy as np
import pytest

import porenet
from porenet.core.errors import RunFileError
from porenet.io import runfile
from porenet.io.runfile import FORMAT_VERSION, read_run, write_run
from porenet.result import TIMESERIES_UNITS, RunData, Snapshot


def test_layout_and_round_trip(scene_dict, tmp_path):
    out = tmp_path / "r.h5"
    result = porenet.run(scene_dict, output=out)
    assert result.path == out
    n = scene_dict["lattice"]["n"]
    with h5py.File(out) as f:
        assert f.attrs["porenet_version"] == porenet.__version__
        assert json.loads(f.attrs["scene"])["seed"] == 7
        assert f["lattice/apertures"].shape == (2 * n * (n - 1),)
        assert f["final/drained"].shape == (n, n) and f["final/drained"].dtype == bool
        assert "pressure" not in f["final"]  # IP defines no pressure field
        assert f["invasion/order"].shape == f["invasion/pressure"].shape
        for key in ("n_drained", "breakthrough", "wall_time_s"):
            assert key in f["summary"].attrs
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(out.stat().st_mode) == 0o666 & ~mask  # permissions like any new file
    data = read_run(out)
    ref = result.data
    names = (
        "apertures",
        "drained",
        "trapped",
        "order",
        "throat",
        "invasion_pressure",
        "burst_sizes",
    )
    for name in names:
        np.testing.assert_array_equal(getattr(data, name), getattr(ref, name))
    assert data.summary["n_drained"] == ref.summary["n_drained"]
    assert data.scene == ref.scene and data.grid_shape == (n, n)


def test_apertures_in_metres_and_pressures_in_pascal(scene_dict, tmp_path):
    result = porenet.run(scene_dict)
    a, gamma = 1e-7, 0.07
    r = result.data.apertures
    assert np.all((r >= 0.7 * a) & (r <= 1.3 * a))
    steps = result.data.throat >= 0
    np.testing.assert_allclose(
        result.data.invasion_pressure[steps], 2 * gamma / r[result.data.throat[steps]]
    )


def test_write_is_atomic(scene_dict, tmp_path, monkeypatch):
    result = porenet.run(scene_dict)
    out = tmp_path / "r.h5"

    def boom(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(h5py.Group, "create_group", boom)
    with pytest.raises(RuntimeError):
        write_run(out, result.data)
    assert list(tmp_path.iterdir()) == []


def test_reader_errors(tmp_path):
    with pytest.raises(RunFileError, match="no such run file"):
        read_run(tmp_path / "x.h5")
    (tmp_path / "t.h5").write_text("hello")
    with pytest.raises(RunFileError, match="not an HDF5 file"):
        read_run(tmp_path / "t.h5")
    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = 1
    with pytest.raises(RunFileError, match="not a porenet run file"):
        read_run(tmp_path / "other.h5")


def _run_data(grid: bool = True) -> RunData:
    """A small hand-made RunData (3 x 4 grid), independent of any fluid model."""
    rows, cols = 3, 4
    n = rows * cols
    rng = np.random.default_rng(0)
    throat_pores = np.array(
        [(i * cols + j, i * cols + j + 1) for i in range(rows) for j in range(cols - 1)]
        + [(i * cols + j, (i + 1) * cols + j) for i in range(rows - 1) for j in range(cols)],
        dtype=np.int64,
    )
    drained = np.zeros(n, dtype=bool)
    drained[[0, 4, 5]] = True
    return RunData(
        porenet_version=porenet.__version__,
        scene={"seed": 1, "lattice": {"kind": "square"}},
        pore_size=1e-7,
        grid_shape=(rows, cols) if grid else None,
        throat_pores=throat_pores,
        pore_coords=rng.random((n, 2)) * 1e-6,
        apertures=rng.random(len(throat_pores)) * 1e-7,
        drained=drained,
        trapped=np.zeros(n, dtype=bool),
        order=np.array([0, 4, 5], dtype=np.int64),
        throat=np.array([-1, 3, 12], dtype=np.int64),
        invasion_pressure=np.array([0.0, 1.5e6, 1.7e6]),
        summary={"n_drained": 3},
    )


def _snapshot(rng: np.random.Generator, n: int, time: float) -> Snapshot:
    return Snapshot(
        time=time,
        saturation=float(rng.random()),
        invading_pressure=float(rng.random() * 1e6),
        pressure=rng.random(n) * 1e5,
        drained=rng.random(n) < 0.5,
    )


@pytest.mark.parametrize("grid", [True, False])
def test_timeseries_and_snapshots_round_trip(tmp_path, grid):
    data = _run_data(grid)
    rng = np.random.default_rng(1)
    data.timeseries = {
        "time": np.linspace(0.0, 1e-3, 7),
        "invading_pressure": rng.random(7) * 1e6,
        "injected": rng.random(7) * 1e-18,
        "capillary_number": rng.random(7) * 1e-4,
        "n_drained": np.arange(7, dtype=np.int64),
        "custom": rng.random(7),
    }
    data.snapshots = [_snapshot(rng, data.n_pores, t) for t in (0.0, 2.5e-4, 1e-3)]
    out = write_run(tmp_path / "r.h5", data)
    with h5py.File(out) as f:
        assert f.attrs["format_version"] == FORMAT_VERSION == 2
        for name in data.timeseries:
            assert f[f"timeseries/{name}"].attrs["units"] == TIMESERIES_UNITS.get(name, "")
        assert f["timeseries/time"].attrs["units"] == "s"
        assert f["timeseries/injected"].attrs["units"] == "m^3"
        assert f["timeseries/custom"].attrs["units"] == ""
        assert list(f["snapshots"]) == ["000000", "000001", "000002"]
        shape = (3, 4) if grid else (12,)
        assert f["snapshots/000001/pressure"].shape == shape
        assert f["snapshots/000001/drained"].dtype == bool
    back = read_run(out)
    assert list(back.timeseries) == list(data.timeseries)
    for name, values in data.timeseries.items():
        np.testing.assert_array_equal(back.timeseries[name], values)
        assert back.timeseries[name].dtype == values.dtype
    assert len(back.snapshots) == len(data.snapshots)
    for got, ref in zip(back.snapshots, data.snapshots, strict=True):
        assert isinstance(got, Snapshot)
        assert (got.time, got.saturation, got.invading_pressure) == (
            ref.time,
            ref.saturation,
            ref.invading_pressure,
        )
        assert got.pressure.shape == got.drained.shape == (data.n_pores,)  # flat, like drained
        np.testing.assert_array_equal(got.pressure, ref.pressure)
        np.testing.assert_array_equal(got.drained, ref.drained)
        assert got.drained.dtype == bool
    np.testing.assert_array_equal(back.drained, data.drained)


def test_snapshots_are_stored_in_time_order(tmp_path):
    data = _run_data()
    rng = np.random.default_rng(2)
    data.snapshots = [_snapshot(rng, data.n_pores, t) for t in (3.0, 1.0, 2.0)]
    back = read_run(write_run(tmp_path / "r.h5", data))
    assert [s.time for s in back.snapshots] == [1.0, 2.0, 3.0]
    np.testing.assert_array_equal(back.snapshots[0].pressure, data.snapshots[1].pressure)


def test_no_timeseries_or_snapshots_writes_no_groups(tmp_path):
    out = write_run(tmp_path / "r.h5", _run_data())
    with h5py.File(out) as f:
        assert "timeseries" not in f and "snapshots" not in f
    back = read_run(out)
    assert back.timeseries == {} and back.snapshots == []


def test_format_1_file_still_reads(tmp_path, monkeypatch):
    monkeypatch.setattr(runfile, "FORMAT_VERSION", 1)
    out = write_run(tmp_path / "v1.h5", _run_data())
    monkeypatch.undo()
    with h5py.File(out) as f:
        assert f.attrs["format_version"] == 1
        assert "timeseries" not in f and "snapshots" not in f
    data = read_run(out)
    assert data.timeseries == {} and data.snapshots == []
    np.testing.assert_array_equal(data.order, [0, 4, 5])
    assert data.grid_shape == (3, 4) and data.drained.shape == (12,)


def test_newer_format_version_is_rejected(tmp_path):
    out = write_run(tmp_path / "future.h5", _run_data())
    with h5py.File(out, "a") as f:
        f.attrs["format_version"] = FORMAT_VERSION + 1
    with pytest.raises(RunFileError, match=f"format version {FORMAT_VERSION + 1} is newer") as info:
        read_run(out)
    assert str(out) in str(info.value)


def test_unequal_timeseries_are_rejected_and_nothing_written(tmp_path):
    data = _run_data()
    data.timeseries = {"time": np.arange(5.0), "injected": np.arange(4.0)}
    out = tmp_path / "r.h5"
    with pytest.raises(RunFileError, match="'injected'") as info:
        write_run(out, data)
    assert str(out) in str(info.value) and "length 4" in str(info.value)
    assert list(tmp_path.iterdir()) == []


def test_bad_timeseries_and_snapshot_shapes_are_rejected(tmp_path):
    data = _run_data()
    data.timeseries = {"time": np.zeros((2, 3))}
    with pytest.raises(RunFileError, match="'time' is not 1-D"):
        write_run(tmp_path / "r.h5", data)
    data.timeseries = {}
    rng = np.random.default_rng(3)
    data.snapshots = [_snapshot(rng, data.n_pores - 1, 0.0)]
    with pytest.raises(RunFileError, match=r"snapshot 0 .* pressure has shape"):
        write_run(tmp_path / "r.h5", data)
    assert list(tmp_path.iterdir()) == []
