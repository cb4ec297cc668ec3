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
from porenet.io.runfile import read_run, write_run


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
