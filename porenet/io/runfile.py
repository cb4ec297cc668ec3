"""The HDF5 run file: writer (atomic) and reader. Layout in docs/run-file.md."""

from __future__ import annotations

import contextlib
import errno
import io
import json
import os
import stat
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from porenet.core.errors import OutputError, PorenetError, RunFileError, RunFileLayoutError
from porenet.result import TIMESERIES_UNITS, RunData, Snapshot

#: Layout version written to the ``format_version`` attribute. 2 added ``/timeseries`` and
#: ``/snapshots``; the reader still reads version 1 and refuses versions it does not know.
FORMAT_VERSION = 2

#: Solid fields in ``/final`` (deformable media), in canonical spring (= throat) order; the
#: last four only for the frictional solid (kind ``hertz-mindlin``).
MECHANICS_FINAL = ("spring_compression", "spring_force", "removed_springs", "displacement",
                   "shear_force", "slip", "sliding", "rotation")  # fmt: skip

#: Units of the per-update series in ``/mechanics`` (deformable media).
MECHANICS_UNITS = {
    "time": "s",
    "drained": "pores",
    "removed_springs": "springs",
    "max_aperture_change": "m",
    "balance_residual": "N",
    "sliding_contacts": "contacts",
    "solver_iterations": "V-cycles",
}


def _grid(data: RunData, values: np.ndarray) -> np.ndarray:
    return data.as_grid(values) if data.grid_shape is not None else np.asarray(values)


def _attr(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    return value


def _valid_name(name: Any) -> bool:
    """``name`` can name an HDF5 group or dataset of its own (no path separator)."""
    return isinstance(name, str) and bool(name) and "/" not in name and name != "."


def _check_observers(path: Path, data: RunData) -> None:
    """Refuse observers' records the layout cannot hold: bad names, non-numeric arrays."""
    for name, records in data.observers.items():
        if not _valid_name(name):
            raise RunFileLayoutError(f"{path}: observer name {name!r} is not a valid group name")
        for key, values in records.items():
            if not _valid_name(key):
                raise RunFileLayoutError(
                    f"{path}: observer {name!r} record name {key!r} is not a valid dataset name"
                )
            if np.asarray(values).dtype.kind not in "biuf":
                raise RunFileLayoutError(
                    f"{path}: observer {name!r} record {key!r} is not numbers or booleans "
                    f"(dtype {np.asarray(values).dtype})"
                )


def _check_outputs(path: Path, data: RunData) -> None:
    """Refuse time series, snapshots and observers' records the layout cannot hold (before
    anything is written)."""
    _check_observers(path, data)
    first: tuple[str, int] | None = None
    for name, values in data.timeseries.items():
        if not _valid_name(name):
            raise RunFileLayoutError(
                f"{path}: time series name {name!r} is not a valid dataset name"
            )
        shape = np.shape(values)
        if len(shape) != 1:
            raise RunFileLayoutError(f"{path}: time series {name!r} is not 1-D (shape {shape})")
        if first is None:
            first = (name, shape[0])
        elif shape[0] != first[1]:
            raise RunFileLayoutError(
                f"{path}: time series {name!r} has length {shape[0]}, "
                f"but {first[0]!r} has length {first[1]}; all series must have equal length"
            )
    n = data.n_pores
    for i, snap in enumerate(data.snapshots):
        for field_name in ("pressure", "drained"):
            shape = np.shape(getattr(snap, field_name))
            if shape != (n,):
                raise RunFileLayoutError(
                    f"{path}: snapshot {i} (t = {snap.time:g} s) {field_name} has shape "
                    f"{shape}, expected ({n},)"
                )


def write_run(path: str | Path, data: RunData) -> Path:
    """Write ``data`` to ``path`` atomically and return the path.

    The file is built in memory (HDF5 never touches the disk, so a full disk cannot upset
    it) and written by :func:`porenet.io.atomic.atomic_write_bytes`: under a temporary name in
    the same directory, renamed into place only when complete, so a failure never leaves a
    half-written file under the final name and leaves an old file there as it was.
    Snapshots are stored in time order.

    Raises
    ------
    RunFileLayoutError
        If the time series (not 1-D, unequal lengths), snapshots (not one value per pore) or
        observers' records (a name with ``/``, not numbers) do not fit the layout; nothing is
        written.
    OutputError
        If the file cannot be written (disk full, no permission, read-only file system, a
        directory that does not exist, ...): the message names the path and the reason.
    """
    from porenet.io.atomic import atomic_write_bytes

    path = Path(path)
    _check_outputs(path, data)
    if not path.parent.is_dir():  # before the file is built
        missing = FileNotFoundError(errno.ENOENT, "directory does not exist")
        raise OutputError.from_os_error(path, missing, "run file")
    atomic_write_bytes(path, _image(data).getbuffer(), what="run file")
    return path


def _image(data: RunData) -> io.BytesIO:
    """The run file's bytes, built in memory (h5py on a file object)."""
    import h5py

    buffer = io.BytesIO()
    with h5py.File(buffer, "w") as f:
        _write(f, data)
    return buffer


def _write(f: Any, data: RunData) -> None:
    """Fill ``f``, an ``h5py.File`` open for writing, with ``data`` (docs/run-file.md)."""
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
    if data.observers:
        groups = f.create_group("observers", track_order=True)
        for name, records in data.observers.items():
            g = groups.create_group(name, track_order=True)
            units = data.observer_units.get(name, {})
            for key, values in records.items():
                array = np.asarray(values)
                ds = g.create_dataset(key, data=array, compression="gzip" if array.ndim else None)
                ds.attrs["units"] = units.get(key, "")


def _is_porenet(f: Any) -> bool:
    """``f``, an open ``h5py.File``, holds a porenet run."""
    return "porenet_version" in f.attrs and "lattice" in f


def is_run_file(path: str | Path) -> bool:
    """Whether ``path`` is a porenet run file (what :func:`read_run` accepts as one); False
    for a missing, non-HDF5, damaged or foreign file."""
    import h5py

    try:
        with h5py.File(path, "r") as f:
            return _is_porenet(f)
    except Exception:  # any file h5py cannot open is not a run file
        return False


def check_readable(path: str | Path) -> None:
    """Raise a RunFileError if ``path`` is a directory, missing, not a regular file or not
    readable: what can be said of a run file to read without opening it."""
    path = Path(path)
    if path.is_dir():
        raise RunFileError(f"{path}: is a directory; give a run file (.h5)")
    if not path.is_file():
        if path.exists():
            raise RunFileError(f"{path}: not a regular file; give a run file (.h5)")
        raise RunFileError(f"{path}: no such run file")
    if not os.access(path, os.R_OK):
        raise RunFileError(
            f"cannot read run file {path}: permission denied (change its permissions, "
            "e.g. chmod u+r)"
        )


def _open(path: Path) -> Any:
    """``path`` open for reading with h5py, or a RunFileError saying why it cannot be."""
    import h5py

    check_readable(path)
    try:
        return h5py.File(path, "r")
    except OSError as exc:
        if isinstance(exc, PermissionError) or getattr(exc, "errno", None) == errno.EACCES:
            raise RunFileError(f"cannot read run file {path}: permission denied") from None
        raise RunFileError(
            f"cannot read run file {path}: not an HDF5 file, or a damaged or truncated one "
            f"(h5py: {exc})"
        ) from None


def _damaged(path: Path, exc: BaseException) -> RunFileError:
    source = "h5py" if isinstance(exc, OSError | RuntimeError | KeyError) else type(exc).__name__
    return RunFileError(
        f"cannot read run file {path}: it is damaged or not a porenet run file "
        f"({source}: {exc}); run its scene again to write it anew"
    )


def read_run(path: str | Path) -> RunData:
    """Read a run file written by :func:`write_run` (format version 1 or 2).

    Version 1 files have no time series or snapshots: those fields come back empty.

    Raises
    ------
    RunFileError
        If the file is missing, a directory, unreadable, not HDF5, not a porenet run file,
        damaged (any error while reading it), or of a newer format.
    """
    path = Path(path)
    with open_run(path) as f:
        return _read(f)


@contextlib.contextmanager
def open_run(path: str | Path) -> Iterator[Any]:
    """``path`` open for reading (an ``h5py.File``), once it is known to be a porenet run
    file of a version this reader knows.

    An error raised by h5py inside the block (a dataset that cannot be read) becomes the
    RunFileError of a damaged file, naming it, as :func:`read_run` reports one.

    Raises
    ------
    RunFileError
        As :func:`read_run`.
    """
    path = Path(path)
    f = _open(path)
    try:
        with f:
            _check_header(f, path)
            yield f
    except (PorenetError, MemoryError):
        raise
    except Exception as exc:  # whatever a damaged file makes h5py raise
        raise _damaged(path, exc) from None


def _check_header(f: Any, path: Path) -> None:
    """``f``, an open ``h5py.File``, is a porenet run file of a version this reader knows."""
    if not _is_porenet(f):
        raise RunFileError(f"cannot read run file {path}: an HDF5 file, but not a porenet run file")
    version = int(f.attrs.get("format_version", 0))
    if version > FORMAT_VERSION:
        raise RunFileError(
            f"{path}: format version {version} is newer than this porenet reads "
            f"({FORMAT_VERSION}); upgrade porenet"
        )


def check_run_file(path: str | Path) -> None:
    """Raise the RunFileError :func:`read_run` would for a file that is not a run file
    (missing, a directory, unreadable, not HDF5, foreign, too new), reading only its header:
    cheap, for commands that check their input before they start work. A file damaged
    further in is found by :func:`read_run`."""
    with open_run(path):
        pass


def _read(f: Any) -> RunData:
    """The RunData in ``f``, an open ``h5py.File`` (checked by :func:`open_run`)."""
    lat = f["lattice"]
    shape = tuple(int(x) for x in lat.attrs["grid_shape"]) if "grid_shape" in lat.attrs else None

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
    observers: dict[str, dict[str, np.ndarray]] = {}
    observer_units: dict[str, dict[str, str]] = {}
    if "observers" in f:
        for name, g in f["observers"].items():
            observers[name] = {key: np.asarray(ds[()]) for key, ds in g.items()}
            observer_units[name] = {key: str(ds.attrs.get("units", "")) for key, ds in g.items()}
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
        observers=observers,
        observer_units=observer_units,
    )


def update_summary(path: str | Path, values: dict[str, Any]) -> None:
    """Set attributes of an existing run file's ``/summary`` (``porenet classify``).

    The file is checked with :func:`read_run` first, so only porenet run files are changed.
    The new file is built in memory and replaces the old one atomically
    (:func:`porenet.io.atomic.atomic_write_bytes`, keeping its permissions): a failure leaves
    the old file as it was.

    Raises
    ------
    RunFileError
        If the file is not a readable run file.
    OutputError
        If it cannot be written (disk full, no permission, ...).
    """
    import h5py

    from porenet.io.atomic import atomic_write_bytes

    path = Path(path)
    read_run(path)
    try:
        buffer = io.BytesIO(path.read_bytes())
        mode = stat.S_IMODE(path.stat().st_mode)
    except OSError as exc:
        raise RunFileError(f"cannot read run file {path}: {exc.strerror or exc}") from None
    with h5py.File(buffer, "r+") as f:
        for key, value in values.items():
            if value is not None:
                f["summary"].attrs[key] = _attr(value)
    atomic_write_bytes(path, buffer.getbuffer(), what="run file", mode=mode)
