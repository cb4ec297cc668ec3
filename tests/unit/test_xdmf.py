"""``porenet export RUN.h5 --format xdmf``: an XDMF file that a real reader (meshio's, a
test-only dependency) opens, with the run's coordinates, throats and fields, snapshots as
time steps, and the run file's own datasets referenced rather than copied
(docs/run-file.md, "ParaView (XDMF export)")."""

from __future__ import annotations

import dataclasses
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np
import pytest

import porenet
from porenet.cli.main import main
from porenet.io.runfile import read_run, write_run
from porenet.io.xdmf import export_xdmf, sidecar_path

meshio = pytest.importorskip("meshio")

BASE = {"seed": 3, "lattice": {"n": 8, "disorder": 0.3, "pore_size": 1e-7},
        "classifier": {"kind": "none"}}  # fmt: skip
IP = BASE | {"fluid": {"kind": "invasion-percolation"}}
VISCOUS = BASE | {
    "fluid": {"kind": "viscous", "capillary_number": 1e-3, "integrator": "explicit",
              "snapshot_saturations": [0.05, 0.15], "snapshot_times": [1e-9]},
}  # fmt: skip
HERTZ = VISCOUS | {"solid": {"kind": "hertz", "fracturing_number": 1.0}}
IP_SNAPSHOTS = IP | {
    "stop": {"at": "complete"},
    "observers": [{"kind": "snapshots", "saturations": [0.2, 0.5]}],
}


def _run(tmp_path_factory: pytest.TempPathFactory, scene: dict, name: str) -> Path:
    path = tmp_path_factory.mktemp(name) / f"{name}.h5"
    porenet.run(scene, output=path)
    return path


@pytest.fixture(scope="module")
def ip_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _run(tmp_path_factory, IP, "ip")


@pytest.fixture(scope="module")
def viscous_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _run(tmp_path_factory, VISCOUS, "viscous")


@pytest.fixture(scope="module")
def hertz_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _run(tmp_path_factory, HERTZ, "hertz")


def _padded(coords: np.ndarray) -> np.ndarray:
    return np.column_stack([coords, np.zeros(len(coords))]) if coords.shape[1] == 2 else coords


def _copy(run: Path, where: Path) -> Path:
    where.mkdir(parents=True, exist_ok=True)
    return Path(shutil.copy(run, where / run.name))


def _check_mesh(points: np.ndarray, cells: list, data: porenet.RunData) -> None:
    np.testing.assert_array_equal(points, _padded(data.pore_coords))
    assert len(cells) == 1 and cells[0].type == "line"
    np.testing.assert_array_equal(cells[0].data, data.throat_pores)


def test_meshio_reads_points_cells_and_final_fields(ip_file: Path, tmp_path: Path) -> None:
    """A run without snapshots is one grid: meshio.read gives the pores, throats and fields."""
    run = _copy(ip_file, tmp_path)
    xdmf, sidecar = export_xdmf(run)
    assert xdmf == tmp_path / "ip.xdmf" and sidecar == tmp_path / "ip.xdmf.h5"
    mesh = meshio.read(xdmf)
    data = read_run(run)
    _check_mesh(mesh.points, mesh.cells, data)
    np.testing.assert_array_equal(mesh.point_data["drained"], data.drained)
    np.testing.assert_array_equal(mesh.point_data["trapped"], data.trapped)
    np.testing.assert_array_equal(mesh.point_data["drain_index"], data.drainage_step())
    assert "pressure" not in mesh.point_data  # invasion percolation defines none
    np.testing.assert_array_equal(mesh.cell_data["apertures"][0], data.apertures)


def test_snapshots_are_time_steps(viscous_file: Path, tmp_path: Path) -> None:
    """One step per snapshot at its time (s), then the final state at the run's end time."""
    run = _copy(viscous_file, tmp_path)
    xdmf, _ = export_xdmf(run)
    data = read_run(run)
    assert len(data.snapshots) == 3
    with meshio.xdmf.TimeSeriesReader(xdmf) as reader:
        points, cells = reader.read_points_cells()
        _check_mesh(points, cells, data)
        assert reader.num_steps == len(data.snapshots) + 1
        steps = [reader.read_data(k) for k in range(reader.num_steps)]
    for (time, point_data, cell_data), snap in zip(steps, data.snapshots, strict=False):
        assert time == snap.time
        np.testing.assert_array_equal(point_data["drained"], snap.drained)
        np.testing.assert_array_equal(point_data["pressure"], snap.pressure)
        np.testing.assert_array_equal(cell_data["apertures"][0], data.apertures)  # rigid
    time, point_data, _ = steps[-1]
    assert time == max(data.invasion_time[-1], data.timeseries["time"][-1])
    assert time > data.snapshots[-1].time
    np.testing.assert_array_equal(point_data["drained"], data.drained)
    np.testing.assert_array_equal(point_data["pressure"], data.pressure)
    np.testing.assert_array_equal(point_data["drain_index"], data.drainage_step())


def test_deformable_media_export_the_solid(hertz_file: Path, tmp_path: Path) -> None:
    """Apertures at each time, and the springs; particle displacements are not pores."""
    run = _copy(hertz_file, tmp_path)
    xdmf, _ = export_xdmf(run)
    data = read_run(run)
    with meshio.xdmf.TimeSeriesReader(xdmf) as reader:
        reader.read_points_cells()
        steps = [reader.read_data(k) for k in range(reader.num_steps)]
    assert len(steps) == len(data.snapshots) + 1
    for (_, point_data, cell_data), snap in zip(steps, data.snapshots, strict=False):
        for name in ("apertures", "spring_force", "removed_springs"):
            np.testing.assert_array_equal(cell_data[name][0], snap.mechanics[name])
        assert "displacement" not in point_data
    _, point_data, cell_data = steps[-1]
    np.testing.assert_array_equal(cell_data["apertures"][0], data.final_apertures)
    np.testing.assert_array_equal(cell_data["initial_apertures"][0], data.apertures)
    for name in ("spring_compression", "spring_force", "removed_springs"):
        np.testing.assert_array_equal(cell_data[name][0], data.mechanics_final[name])


def test_invasion_percolation_steps_count_drained_pores(tmp_path: Path) -> None:
    """Without a clock, a step's time is its number of drained pores."""
    run = tmp_path / "ip.h5"
    data = porenet.run(IP_SNAPSHOTS, output=run).data
    xdmf, _ = export_xdmf(run)
    with meshio.xdmf.TimeSeriesReader(xdmf) as reader:
        reader.read_points_cells()
        steps = [reader.read_data(k) for k in range(reader.num_steps)]
    expected = [int(s.drained.sum()) for s in data.snapshots] + [int(data.drained.sum())]
    assert [time for time, _, _ in steps] == expected
    assert expected == sorted(set(expected))


def _data_items(xdmf: Path) -> list[tuple[str, str, tuple[int, ...]]]:
    """(file, dataset, dimensions) of every array the XDMF file points at."""
    found = []
    for item in ET.parse(xdmf).getroot().iter("DataItem"):
        assert item.get("Format") == "HDF"
        file, _, dataset = item.text.strip().partition(":")
        found.append((file, dataset, tuple(int(n) for n in item.get("Dimensions").split())))
    return found


def test_numeric_arrays_are_the_run_file_s_own(hertz_file: Path, tmp_path: Path) -> None:
    """Every number comes from the run file: referenced there, or through a virtual dataset
    of the sidecar that holds no data; the sidecar stores only booleans (uint8) and the
    computed drain index."""
    run = _copy(hertz_file, tmp_path)
    xdmf, sidecar = export_xdmf(run)
    items = _data_items(xdmf)
    assert {file for file, _, _ in items} == {run.name, sidecar.name}
    stored = set()
    with h5py.File(run) as f, h5py.File(sidecar) as side:
        for file, dataset, dims in items:
            if file == run.name:
                assert f[dataset].shape == dims and f[dataset].dtype != bool
                continue
            ds = side[dataset]
            assert ds.shape == dims
            if ds.is_virtual:
                assert ds.id.get_storage_size() == 0
                assert {m.file_name for m in ds.virtual_sources()} == {run.name}
                assert {m.dset_name for m in ds.virtual_sources()} == {dataset.lstrip("/")}
                assert f[dataset].size == ds.size or dataset == "/lattice/pore_coords"
            else:
                stored.add(dataset)
                assert dataset == "/final/drain_index" or f[dataset].dtype == bool
                np.testing.assert_array_equal(ds[()], np.ravel(f.get(dataset, ds)[()]))
    assert "/final/apertures" in {d for _, d, _ in items}
    assert "/final/drained" in stored and "/final/removed_springs" in stored


def test_the_files_can_be_moved_together(ip_file: Path, tmp_path: Path) -> None:
    """Paths are relative to the XDMF file's directory, also with -o elsewhere."""
    run = _copy(ip_file, tmp_path / "a")
    (tmp_path / "a" / "views").mkdir()
    xdmf, _ = export_xdmf(run, tmp_path / "a" / "views" / "v.xdmf")
    assert "../ip.h5:/lattice/throat_pores" in xdmf.read_text()
    moved = tmp_path / "b"
    shutil.copytree(tmp_path / "a", moved)
    shutil.rmtree(tmp_path / "a")
    mesh = meshio.read(moved / "views" / "v.xdmf")
    np.testing.assert_array_equal(mesh.point_data["drained"], read_run(moved / "ip.h5").drained)


@pytest.mark.parametrize("grid", [True, False], ids=["3-D grid", "3-D flat"])
def test_three_dimensional_and_flat_layouts(viscous_file: Path, tmp_path: Path, grid: bool) -> None:
    """(N, 3) coordinates and flat pore datasets are referenced as they are; grid-shaped
    ones through a flat view."""
    data = read_run(viscous_file)
    data = dataclasses.replace(
        data,
        pore_coords=np.column_stack([data.pore_coords, np.arange(data.n_pores) * 1e-7]),
        grid_shape=data.grid_shape if grid else None,
    )
    run = write_run(tmp_path / "r3.h5", data)
    xdmf, _ = export_xdmf(run)
    items = _data_items(xdmf)
    assert ("r3.h5", "/lattice/pore_coords", (data.n_pores, 3)) in items
    pressure = "r3.xdmf.h5" if grid else "r3.h5"
    assert (pressure, "/final/pressure", (data.n_pores,)) in items
    with meshio.xdmf.TimeSeriesReader(xdmf) as reader:
        points, _ = reader.read_points_cells()
        _, point_data, _ = reader.read_data(reader.num_steps - 1)
    np.testing.assert_array_equal(points, data.pore_coords)
    np.testing.assert_array_equal(point_data["drained"], data.drained)
    np.testing.assert_array_equal(point_data["pressure"], data.pressure)


# ---------------------------------------------------------------------------- the command


def test_command_writes_beside_the_run_file_and_leaves_it_unchanged(
    ip_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = _copy(ip_file, tmp_path)
    before = run.read_bytes()
    assert main(["export", str(run), "--format", "xdmf"]) == 0
    xdmf = tmp_path / "ip.xdmf"
    assert xdmf.is_file() and sidecar_path(xdmf).is_file()
    assert str(xdmf) in capsys.readouterr().out
    assert run.read_bytes() == before
    assert main(["export", str(run)]) == 0  # its own files are replaced
    assert run.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ip.h5", "ip.xdmf", "ip.xdmf.h5"]


def _fails(args: list[str], capsys: pytest.CaptureFixture[str], *words: str) -> str:
    assert main(args) == 2
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err and captured.out == ""
    message = captured.err.strip()
    assert message.count("\n") == 0, message
    for word in words:
        assert word in message, message
    return message


def test_bad_input_exits_2_naming_the_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    missing = tmp_path / "absent.h5"
    _fails(["export", str(missing)], capsys, str(missing), "no such run file")
    foreign = tmp_path / "other.h5"
    with h5py.File(foreign, "w") as f:
        f["x"] = np.arange(3)
    _fails(["export", str(foreign)], capsys, str(foreign), "not a porenet run file")
    text = tmp_path / "notes.h5"
    text.write_text("not HDF5")
    _fails(["export", str(text)], capsys, str(text))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.h5", "other.h5"]


def test_bad_output_exits_2(ip_file: Path, tmp_path: Path, capsys) -> None:
    run = _copy(ip_file, tmp_path)
    before = run.read_bytes()
    nowhere = tmp_path / "no" / "such" / "x.xdmf"
    _fails(["export", str(run), "-o", str(nowhere)], capsys, str(nowhere), "does not exist")
    itself = tmp_path / "ip"  # its sidecar would be ip.h5: the run file
    _fails(["export", str(run), "-o", str(itself), "--overwrite"], capsys, "run file", str(run))
    assert run.read_bytes() == before
    foreign = tmp_path / "mine.xdmf"
    foreign.write_text("<Xdmf/>")
    _fails(["export", str(run), "-o", str(foreign)], capsys, str(foreign), "--overwrite")
    assert foreign.read_text() == "<Xdmf/>"
    assert main(["export", str(run), "-o", str(foreign), "--overwrite"]) == 0
    assert meshio.read(foreign).points.shape == (64, 3)


def test_a_read_only_directory_exits_2(ip_file: Path, tmp_path: Path, tmpfs, capsys) -> None:
    folder = tmpfs(tmp_path / "ro", "1M", readonly=True, files=(ip_file,))
    run = folder / ip_file.name
    _fails(["export", str(run)], capsys, "read-only", str(run.with_suffix(".xdmf")))


def test_vtk_s_xdmf_reader_reads_it_too(viscous_file: Path, tmp_path: Path) -> None:
    """ParaView's "Xdmf Reader" is VTK's vtkXdmfReader: where VTK is installed (not a test
    dependency: a large package), it reads the export with the run's values."""
    xdmf2 = pytest.importorskip("vtkmodules.vtkIOXdmf2")
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

    run = _copy(viscous_file, tmp_path)
    xdmf, _ = export_xdmf(run)
    data = read_run(run)
    reader = xdmf2.vtkXdmfReader()
    reader.SetFileName(str(xdmf))
    reader.UpdateInformation()
    times = reader.GetOutputInformation(0).Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    assert list(times)[:-1] == [s.time for s in data.snapshots]
    reader.UpdateTimeStep(times[-1])
    grid = reader.GetOutputDataObject(0)
    np.testing.assert_array_equal(vtk_to_numpy(grid.GetPoints().GetData()),
                                  _padded(data.pore_coords))  # fmt: skip
    assert grid.GetNumberOfCells() == len(data.throat_pores)
    drained = vtk_to_numpy(grid.GetPointData().GetArray("drained"))
    np.testing.assert_array_equal(drained, data.drained)
    pressure = vtk_to_numpy(grid.GetPointData().GetArray("pressure"))
    np.testing.assert_array_equal(pressure, data.pressure)
    apertures = vtk_to_numpy(grid.GetCellData().GetArray("apertures"))
    np.testing.assert_array_equal(apertures, data.apertures)


def test_the_command_stays_light(ip_file: Path, tmp_path: Path) -> None:
    """``porenet export`` reads and writes HDF5 only: no numba, scipy or matplotlib."""
    import json
    import subprocess
    import sys

    run = _copy(ip_file, tmp_path)
    code = (
        "import json, sys; from porenet.cli.main import main; "
        "status = main(['export', sys.argv[1]]); "
        "print(json.dumps([status, sorted(m for m in ('numba', 'scipy', 'matplotlib') "
        "if m in sys.modules)]))"
    )
    done = subprocess.run([sys.executable, "-c", code, str(run)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout.splitlines()[-1]) == [0, []]
