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
from porenet.result import RunData

FORMAT_VERSION = 1


def _grid(data: RunData, values: np.ndarray) -> np.ndarray:
    return data.as_grid(values) if data.grid_shape is not None else np.asarray(values)


def _attr(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    return value


def write_run(path: str | Path, data: RunData) -> Path:
    """Write ``data`` to ``path`` atomically and return the path.

    The file is written under a temporary name in the same directory and renamed into place
    only when complete, so a crash never leaves a half-written file under the final name.
    """
    import h5py

    path = Path(path)
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


def read_run(path: str | Path) -> RunData:
    """Read a run file written by :func:`write_run`.

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
        if "porenet_version" not in f.attrs or "lattice" not in f:
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
        )
