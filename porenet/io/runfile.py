"""The HDF5 run file: writer (atomic) and reader. Layout in docs/run-file.md."""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from porenet.core.errors import RunFileError
from porenet.result import TIMESERIES_UNITS, RunData, Snapshot

#: Layout version written to the ``format_version`` attribute. 2 added ``/timeseries`` and
#: ``/snapshots``; the reader still reads version 1 and refuses versions it does not know.
FORMAT_VERSION = 2

#: Solid fields in ``/final`` (deformable media), in canonical spring (= throat) order.
MECHANICS_FINAL = ("spring_compression", "spring_force", "removed_springs", "displacement")

#: Units of the per-update series in ``/mechanics`` (deformable media).
MECHANICS_UNITS = {
    "time": "s",
    "drained": "pores",
    "removed_springs": "springs",
    "max_aperture_change": "m",
    "balance_residual": "N",
}


def _grid(data: RunData, values: np.ndarray) -> np.ndarray:
    return data.as_grid(values) if data.grid_shape is not None else np.asarray(values)


def _attr(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    return value


def _check_outputs(path: Path, data: RunData) -> None:
    """Refuse time series and snapshots the layout cannot hold (before anything is written)."""
    first: tuple[str, int] | None = None
    for name, values in data.timeseries.items():
        if not isinstance(name, str) or not name or "/" in name or name == ".":
            raise RunFileError(f"{path}: time series name {name!r} is not a valid dataset name")
        shape = np.shape(values)
        if len(shape) != 1:
            raise RunFileError(f"{path}: time series {name!r} is not 1-D (shape {shape})")
        if first is None:
            first = (name, shape[0])
        elif shape[0] != first[1]:
            raise RunFileError(
                f"{path}: time series {name!r} has length {shape[0]}, "
                f"but {first[0]!r} has length {first[1]}; all series must have equal length"
            )
    n = data.n_pores
    for i, snap in enumerate(data.snapshots):
        for field_name in ("pressure", "drained"):
            shape = np.shape(getattr(snap, field_name))
            if shape != (n,):
                raise RunFileError(
                    f"{path}: snapshot {i} (t = {snap.time:g} s) {field_name} has shape "
                    f"{shape}, expected ({n},)"
                )


def write_run(path: str | Path, data: RunData) -> Path:
    """Write ``data`` to ``path`` atomically and return the path.

    The file is written under a temporary name in the same directory and renamed into place
    only when complete, so a crash never leaves a half-written file under the final name.
    Snapshots are stored in time order.

    Raises
    ------
    RunFileError
        If the directory does not exist, the file cannot be written, or the time series
        (not 1-D, unequal lengths) or snapshots (not one value per pore) do not fit the
        layout; nothing is written in the last case.
    """
    import h5py

    path = Path(path)
    _check_outputs(path, data)
    directory = path.resolve().parent
    if not directory.is_dir():
        raise RunFileError(f"{path}: directory {directory} does not exist")
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".partial", dir=directory)
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        with h5py.File(tmp, "w") as f:
            f.attrs["porenet_version"] = data.porenet_version
            f.attrs["format_version"] = FORMAT_VERSION
            f.attrs["scene"] = json.dumps(data.scene, sort_keys=True)
            lat = f.create_group("lattice")
            lat.attrs["pore_size"] = data.pore_size
            lat.attrs["kind"] = str(data.scene.get("lattice", {}).get("kind", ""))
            if data.grid_shape is not None:
                lat.attrs["grid_shape"] = np.asarray(data.grid_shape, dtype=np.int64)
                # the two lengths of a grid, each with its convention (docs/run-file.md)
                side = float(max(data.grid_shape))
                lat.attrs["length_L"] = side * data.pore_size
                lat.attrs["extent"] = 2.0 * side * data.pore_size
            lat.create_dataset("apertures", data=data.apertures, compression="gzip")
            lat.create_dataset("throat_pores", data=data.throat_pores, compression="gzip")
            lat.create_dataset("pore_coords", data=data.pore_coords, compression="gzip")
            fin = f.create_group("final")
            fin.create_dataset("drained", data=_grid(data, data.drained), compression="gzip")
            fin.create_dataset("trapped", data=_grid(data, data.trapped), compression="gzip")
            if data.pressure is not None:
                fin.create_dataset("pressure", data=_grid(data, data.pressure), compression="gzip")
            if data.final_apertures is not None:
                fin.create_dataset("apertures", data=data.final_apertures, compression="gzip")
            for name, values in data.mechanics_final.items():
                fin.create_dataset(name, data=np.asarray(values), compression="gzip")
            if data.mechanics_series:
                mech = f.create_group("mechanics", track_order=True)
                for name, values in data.mechanics_series.items():
                    ds = mech.create_dataset(name, data=np.asarray(values), compression="gzip")
                    ds.attrs["units"] = MECHANICS_UNITS.get(name, "")
            inv = f.create_group("invasion")
            inv.create_dataset("order", data=data.order, compression="gzip")
            inv.create_dataset("throat", data=data.throat, compression="gzip")
            inv.create_dataset("pressure", data=data.invasion_pressure, compression="gzip")
            inv.create_dataset("burst_sizes", data=data.burst_sizes, compression="gzip")
            if data.invasion_time is not None:
                inv.create_dataset("time", data=data.invasion_time, compression="gzip")
            summ = f.create_group("summary")
            for key, value in data.summary.items():
                if value is not None:
                    summ.attrs[key] = _attr(value)
            if data.timeseries:
                ts = f.create_group("timeseries", track_order=True)
                for name, values in data.timeseries.items():
                    ds = ts.create_dataset(name, data=np.asarray(values), compression="gzip")
                    ds.attrs["units"] = TIMESERIES_UNITS.get(name, "")
            if data.snapshots:
                snaps = f.create_group("snapshots")
                ordered = sorted(data.snapshots, key=lambda snap: snap.time)  # stable
                for i, snap in enumerate(ordered):
                    g = snaps.create_group(f"{i:06d}")
                    g.attrs["time"] = float(snap.time)
                    g.attrs["saturation"] = float(snap.saturation)
                    g.attrs["invading_pressure"] = float(snap.invading_pressure)
                    for key in ("pressure", "drained"):
                        values = _grid(data, getattr(snap, key))
                        g.create_dataset(key, data=values, compression="gzip")
                    for key, values in snap.mechanics.items():
                        g.create_dataset(key, data=np.asarray(values), compression="gzip")
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600; give the usual permissions
        os.replace(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        if isinstance(exc, OSError):
            raise RunFileError(f"{path}: cannot write run file: {exc}") from exc
        raise
    return path


def _is_porenet(f: Any) -> bool:
    """``f``, an open ``h5py.File``, holds a porenet run."""
    return "porenet_version" in f.attrs and "lattice" in f


def is_run_file(path: str | Path) -> bool:
    """Whether ``path`` is a porenet run file (what :func:`read_run` accepts as one); False
    for a missing, non-HDF5 or foreign file."""
    import h5py

    try:
        with h5py.File(path, "r") as f:
            return _is_porenet(f)
    except OSError:
        return False


def read_run(path: str | Path) -> RunData:
    """Read a run file written by :func:`write_run` (format version 1 or 2).

    Version 1 files have no time series or snapshots: those fields come back empty.

    Raises
    ------
    RunFileError
        If the file is missing, not HDF5, not a porenet run file, or of a newer format.
    """
    import h5py

    path = Path(path)
    if not path.is_file():
        raise RunFileError(f"{path}: no such run file")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise RunFileError(f"{path}: not an HDF5 file ({exc})") from None
    with f:
        if not _is_porenet(f):
            raise RunFileError(f"{path}: not a porenet run file")
        version = int(f.attrs.get("format_version", 0))
        if version > FORMAT_VERSION:
            raise RunFileError(
                f"{path}: format version {version} is newer than this porenet reads "
                f"({FORMAT_VERSION}); upgrade porenet"
            )
        lat = f["lattice"]
        shape = (
            tuple(int(x) for x in lat.attrs["grid_shape"]) if "grid_shape" in lat.attrs else None
        )

        def flat(name: str) -> np.ndarray | None:
            return np.asarray(f[name][()]).ravel() if name in f else None

        summary = {k: _attr(v) for k, v in f["summary"].attrs.items()}
        timeseries: dict[str, np.ndarray] = {}
        if "timeseries" in f:
            timeseries = {name: np.asarray(ds[()]) for name, ds in f["timeseries"].items()}
        mechanics_final = {
            name: np.asarray(f["final"][name][()]) for name in MECHANICS_FINAL if name in f["final"]
        }
        mechanics_series: dict[str, np.ndarray] = {}
        if "mechanics" in f:
            mechanics_series = {name: np.asarray(ds[()]) for name, ds in f["mechanics"].items()}
        snapshots: list[Snapshot] = []
        if "snapshots" in f:
            snaps = f["snapshots"]
            for name in sorted(snaps, key=int):  # zero-padded index, in time order
                g = snaps[name]
                snapshots.append(
                    Snapshot(
                        time=float(g.attrs["time"]),
                        saturation=float(g.attrs["saturation"]),
                        invading_pressure=float(g.attrs["invading_pressure"]),
                        pressure=np.asarray(g["pressure"][()]).ravel(),
                        drained=np.asarray(g["drained"][()]).ravel(),
                        mechanics={
                            key: np.asarray(g[key][()])
                            for key in ("apertures", *MECHANICS_FINAL)
                            if key in g
                        },
                    )
                )
        return RunData(
            porenet_version=str(f.attrs["porenet_version"]),
            scene=json.loads(f.attrs["scene"]),
            pore_size=float(lat.attrs["pore_size"]),
            grid_shape=shape,  # type: ignore[arg-type]
            throat_pores=lat["throat_pores"][()],
            pore_coords=lat["pore_coords"][()],
            apertures=lat["apertures"][()],
            drained=flat("final/drained"),  # type: ignore[arg-type]
            trapped=flat("final/trapped"),  # type: ignore[arg-type]
            pressure=flat("final/pressure"),
            final_apertures=flat("final/apertures"),
            order=f["invasion/order"][()],
            throat=f["invasion/throat"][()],
            invasion_pressure=f["invasion/pressure"][()],
            invasion_time=flat("invasion/time"),
            burst_sizes=f["invasion/burst_sizes"][()],
            summary=summary,
            timeseries=timeseries,
            snapshots=snapshots,
            mechanics_final=mechanics_final,
            mechanics_series=mechanics_series,
        )


def update_summary(path: str | Path, values: dict[str, Any]) -> None:
    """Set attributes of an existing run file's ``/summary`` (``porenet classify``).

    The file is checked with :func:`read_run` first, so only porenet run files are changed.

    Raises
    ------
    RunFileError
        If the file is not a readable run file or cannot be written.
    """
    import h5py

    read_run(path)
    try:
        with h5py.File(path, "r+") as f:
            for key, value in values.items():
                if value is not None:
                    f["summary"].attrs[key] = _attr(value)
    except OSError as exc:
        raise RunFileError(f"{path}: cannot update the run file: {exc}") from None
