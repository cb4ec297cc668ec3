"""A run file seen by ParaView: an XDMF file that points into it (docs/run-file.md, "ParaView
(XDMF export)").

``porenet export RUN.h5`` writes ``RUN.xdmf``, an XML file that describes the pores as
points, the throats as two-node cells (``Polyline``) and the run's per-pore and per-throat
fields, and refers to the arrays where they are stored: in the run file itself, never
copied, whenever a reader can take them as they are. What a reader cannot take goes into a
small HDF5 sidecar beside the XDMF file, ``RUN.xdmf.h5``:

* booleans (h5py stores them as an HDF5 enum, which XDMF readers reject): ``uint8`` copies;
* the drain index (each pore's place in ``/invasion/order``, -1 for a pore that never
  drained), which is computed;
* pore fields stored as ``(n, n)`` grids and 2-D pore coordinates: HDF5 *virtual* datasets,
  views that hold no data and read the run file's dataset as one value per pore (flat), or
  as three coordinates per pore (``z = 0``: XDMF's ``XYZ``, which every reader takes).

A run with snapshots becomes a temporal collection (one grid per snapshot, then the final
state); a run without, one grid (the final state). Paths in both files are relative to the
XDMF file's directory, so the three files can be moved together.

:func:`plan_export` decides all of this from an open run file (pure: it reads, writes
nothing), :func:`xdmf_text` writes the XML, :func:`sidecar_image` builds the sidecar in
memory, and :func:`export_xdmf` writes both atomically (:mod:`porenet.io.atomic`).
"""

from __future__ import annotations

import io
import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from porenet.core.errors import ConfigError, RunFileError

#: Version written to the XDMF root (meshio's time-series reader wants 3).
XDMF_VERSION = "3.0"
#: The sidecar is the XDMF file's name with this suffix added (``RUN.xdmf.h5``).
SIDECAR_SUFFIX = ".h5"
#: The comment that marks an XDMF file as porenet's (so that it may be replaced).
MARKER = "written by porenet export"
#: Root attribute of the sidecar: the porenet version that wrote it.
SIDECAR_ATTR = "porenet_export"
#: Where each array the XDMF points at is: the run file or the sidecar.
RUN, SIDECAR = "run", "sidecar"
#: Per-pore fields of ``/final`` and of each snapshot (units in docs/run-file.md).
PORE_FIELDS = ("drained", "trapped", "pressure")
#: Per-throat fields of ``/final`` and of each snapshot (deformable media but apertures).
THROAT_FIELDS = ("apertures", "spring_compression", "spring_force", "removed_springs")


@dataclass(frozen=True)
class Array:
    """An array the XDMF file points at: the file (:data:`RUN` or :data:`SIDECAR`), the
    dataset in it, and its shape and dtype as readers see them."""

    file: str
    path: str
    shape: tuple[int, ...]
    dtype: np.dtype


@dataclass(frozen=True)
class SidecarDataset:
    """A dataset of the sidecar: ``values`` stored there, or (``values`` None) a virtual view
    of the run file's dataset ``source`` (of shape ``source_shape``), with fill value 0."""

    path: str
    shape: tuple[int, ...]
    dtype: np.dtype
    values: np.ndarray | None = None
    source: str = ""
    source_shape: tuple[int, ...] = ()


@dataclass(frozen=True)
class Attribute:
    """One field of a grid: its name, ``"Node"`` (pores) or ``"Cell"`` (throats)."""

    name: str
    center: str
    array: Array


@dataclass(frozen=True)
class Step:
    """One grid: a snapshot or the final state, at ``time`` (None: the grid has no time)."""

    name: str
    time: float | None
    attributes: tuple[Attribute, ...]


@dataclass
class Export:
    """What the XDMF file shows (:func:`plan_export`)."""

    points: Array
    cells: Array
    steps: list[Step]
    temporal: bool
    sidecar: list[SidecarDataset] = field(default_factory=list)


class _Planner:
    """Arrays of an open run file as readers take them, collecting the sidecar's datasets."""

    def __init__(self, f: Any) -> None:
        self.f = f
        self.n_pores = int(f["lattice/pore_coords"].shape[0])
        self.n_throats = int(f["lattice/throat_pores"].shape[0])
        self.sidecar: dict[str, SidecarDataset] = {}

    def _store(self, path: str, values: np.ndarray) -> Array:
        self.sidecar[path] = SidecarDataset(path, values.shape, values.dtype, values=values)
        return Array(SIDECAR, path, values.shape, values.dtype)

    def _view(self, path: str, shape: tuple[int, ...]) -> Array:
        ds = self.f[path]
        self.sidecar[path] = SidecarDataset(
            path, shape, ds.dtype, source=path, source_shape=tuple(ds.shape)
        )
        return Array(SIDECAR, path, shape, ds.dtype)

    def flat(self, path: str, count: int) -> Array:
        """``path`` as ``count`` values: itself, a view (a grid), or a uint8 copy (booleans).

        Raises
        ------
        RunFileError
            If the dataset does not hold ``count`` values.
        """
        ds = self.f[path]
        if ds.size != count:
            raise RunFileError(
                f"{self.f.filename}: {path} has shape {ds.shape}, not one value for each of "
                f"the {count} {'pores' if count == self.n_pores else 'throats'}"
            )
        if ds.dtype == np.bool_:
            return self._store(path, np.asarray(ds[()], dtype=np.uint8).ravel())
        if ds.shape == (count,):
            return Array(RUN, path, (count,), ds.dtype)
        return self._view(path, (count,))

    def points(self) -> Array:
        """The pore coordinates (m) as x, y, z: themselves in 3-D, a view with z = 0 in 2-D."""
        path = "lattice/pore_coords"
        ds = self.f[path]
        if ds.ndim != 2 or ds.shape[1] not in (2, 3):
            raise RunFileError(f"{self.f.filename}: {path} has shape {ds.shape}, not (N, 2 or 3)")
        if ds.shape[1] == 3:
            return Array(RUN, path, tuple(ds.shape), ds.dtype)
        return self._view(path, (self.n_pores, 3))

    def drain_index(self) -> Array:
        """Each pore's place in ``/invasion/order`` (-1: never drained), stored."""
        from porenet.result import drainage_step

        order = self.f["invasion/order"][()]
        return self._store("final/drain_index", drainage_step(order, self.n_pores))

    def fields(self, group: str, *, rigid: bool) -> list[Attribute]:
        """The pore and throat fields of ``group`` (``final`` or a snapshot); in a rigid
        medium the apertures never change: the lattice's stand for the group's."""
        found = [
            Attribute(name, "Node", self.flat(f"{group}/{name}", self.n_pores))
            for name in PORE_FIELDS
            if name in self.f[group]
        ]
        for name in THROAT_FIELDS:
            path = f"{group}/{name}"
            if name == "apertures" and name not in self.f[group] and rigid:
                path = "lattice/apertures"
            if path in self.f:
                found.append(Attribute(name, "Cell", self.flat(path, self.n_throats)))
        return found


def _cells(f: Any) -> Array:
    """The throats, two pore indices each (``/lattice/throat_pores``, referenced)."""
    ds = f["lattice/throat_pores"]
    if ds.ndim != 2 or ds.shape[1] != 2:
        raise RunFileError(f"{f.filename}: lattice/throat_pores has shape {ds.shape}, not (M, 2)")
    return Array(RUN, "lattice/throat_pores", tuple(ds.shape), ds.dtype)


def _snapshot_groups(f: Any) -> list[str]:
    """The snapshots' group paths, in time order (their zero-padded index)."""
    if "snapshots" not in f:
        return []
    return [f"snapshots/{name}" for name in sorted(f["snapshots"], key=int)]


def _clock(f: Any) -> bool:
    """Whether the run has a model time (dynamic models: ``/invasion/time``)."""
    return "invasion/time" in f


def end_time(f: Any) -> float:
    """The time of the final state (s): the latest model time the run file records (the last
    drainage, the last entry of ``/timeseries/time``, the last snapshot)."""
    times = [0.0]
    for path in ("invasion/time", "timeseries/time"):
        if path in f and f[path].size:
            times.append(float(f[path][-1]))
    times += [float(f[g].attrs["time"]) for g in _snapshot_groups(f)]
    return max(times)


def _step_time(f: Any, group: str) -> float:
    """A step's time: its model time (s), or, without a clock (invasion percolation), the
    number of pores drained then."""
    if not _clock(f):
        return float(np.count_nonzero(f[f"{group}/drained"][()]))
    return end_time(f) if group == "final" else float(f[group].attrs["time"])


def plan_export(f: Any) -> Export:
    """What the XDMF file of the open run file ``f`` shows, and what its sidecar holds.

    Parameters
    ----------
    f : h5py.File
        A porenet run file open for reading (:func:`porenet.io.runfile.open_run`).

    Returns
    -------
    Export
        Points (pore centres, m, x y z), cells (throats: two pores each) and one
        :class:`Step` per snapshot in time order, then the final state. A step's time is in
        seconds; under invasion percolation, which has no clock, it is the number of drained
        pores. A snapshot at the time of an earlier one or of the final state is left out
        (the later grid holds its fields, and ParaView would draw two grids at one time).
        Without snapshots there is one step, with no time.

    Raises
    ------
    RunFileError
        If a dataset does not have the shape of the layout (docs/run-file.md).
    """
    planner = _Planner(f)
    rigid = "apertures" not in f["final"]
    final = _step_time(f, "final")
    steps: list[Step] = []
    for group in _snapshot_groups(f):
        time = _step_time(f, group)
        if time < final and (not steps or time > steps[-1].time):  # one grid per time
            fields = tuple(planner.fields(group, rigid=rigid))
            steps.append(Step(f"snapshot {group.rpartition('/')[2]}", time, fields))
    attributes = [*planner.fields("final", rigid=rigid)]
    attributes.append(Attribute("drain_index", "Node", planner.drain_index()))
    if not rigid:
        lattice = planner.flat("lattice/apertures", planner.n_throats)
        attributes.append(Attribute("initial_apertures", "Cell", lattice))
    temporal = bool(steps)
    steps.append(Step("final", final if temporal else None, tuple(attributes)))
    return Export(
        points=planner.points(),
        cells=_cells(f),
        steps=steps,
        temporal=temporal,
        sidecar=list(planner.sidecar.values()),
    )


def _number_type(dtype: np.dtype) -> dict[str, str]:
    """XDMF's ``NumberType`` and ``Precision`` (bytes) of ``dtype``."""
    dtype = np.dtype(dtype)
    names = {"f": "Float", "i": "Int", "u": "UInt"}
    if dtype.kind not in names:
        raise ValueError(f"no XDMF number type for {dtype}")
    name = names[dtype.kind]
    if dtype.itemsize == 1:
        name = "UChar" if dtype.kind == "u" else "Char"
    return {"NumberType": name, "Precision": str(dtype.itemsize)}


def _data_item(parent: ET.Element, array: Array, refs: dict[str, str]) -> None:
    """A ``DataItem`` under ``parent`` naming ``array`` as ``FILE:/dataset`` (``refs``: the
    file names by :data:`RUN` and :data:`SIDECAR`)."""
    item = ET.SubElement(
        parent,
        "DataItem",
        Dimensions=" ".join(str(n) for n in array.shape),
        **_number_type(array.dtype),
        Format="HDF",
    )
    item.text = f"{refs[array.file]}:/{array.path}"


def _grid(parent: ET.Element, export: Export, step: Step, refs: dict[str, str]) -> None:
    """One uniform grid under ``parent``: ``step``'s time (s), the throats, the pores and
    ``step``'s fields. Every grid repeats the topology and geometry (references, not data):
    the form every reader takes."""
    grid = ET.SubElement(parent, "Grid", Name=step.name, GridType="Uniform")
    if step.time is not None:
        ET.SubElement(grid, "Time", Value=repr(step.time))
    n_cells = str(export.cells.shape[0])
    topology = ET.SubElement(
        grid, "Topology", TopologyType="Polyline", NodesPerElement="2", NumberOfElements=n_cells
    )
    _data_item(topology, export.cells, refs)
    _data_item(ET.SubElement(grid, "Geometry", GeometryType="XYZ"), export.points, refs)
    for attribute in step.attributes:
        node = ET.SubElement(
            grid, "Attribute", Name=attribute.name, AttributeType="Scalar", Center=attribute.center
        )
        _data_item(node, attribute.array, refs)


def xdmf_text(export: Export, run_ref: str, sidecar_ref: str) -> str:
    """The XDMF file (XML) of ``export``.

    Parameters
    ----------
    export : Export
        From :func:`plan_export`.
    run_ref, sidecar_ref : str
        The run file and the sidecar as the XDMF file names them: paths relative to its
        directory.

    Returns
    -------
    str
        XDMF 3 with the attribute names XDMF 2 readers know too (``TopologyType``,
        ``GeometryType``, ``NumberType``); arrays as ``FILE:/dataset`` (format ``HDF``).
    """
    refs = {RUN: run_ref, SIDECAR: sidecar_ref}
    root = ET.Element("Xdmf", Version=XDMF_VERSION)
    domain = ET.SubElement(root, "Domain")
    parent = domain
    if export.temporal:
        parent = ET.SubElement(
            domain, "Grid", Name="run", GridType="Collection", CollectionType="Temporal"
        )
    for step in export.steps:
        _grid(parent, export, step, refs)
    ET.indent(root)
    body = ET.tostring(root, encoding="unicode")
    return f'<?xml version="1.0" encoding="utf-8"?>\n<!-- {MARKER} -->\n{body}\n'


def sidecar_image(export: Export, run_ref: str) -> io.BytesIO:
    """The sidecar's bytes, built in memory: the stored arrays (gzip) and the virtual views
    of the run file, whose source file is ``run_ref`` (relative to the sidecar's directory,
    where HDF5 looks for it first)."""
    import h5py

    from porenet._version import __version__

    buffer = io.BytesIO()
    with h5py.File(buffer, "w") as side:
        side.attrs[SIDECAR_ATTR] = __version__
        side.attrs["run_file"] = run_ref
        for ds in export.sidecar:
            if ds.values is not None:
                side.create_dataset(ds.path, data=ds.values, compression="gzip")
                continue
            layout = h5py.VirtualLayout(shape=ds.shape, dtype=ds.dtype)
            source = h5py.VirtualSource(run_ref, ds.source, shape=ds.source_shape)
            if len(ds.shape) == len(ds.source_shape):  # padded: the source at the origin
                layout[tuple(slice(0, n) for n in ds.source_shape)] = source
            else:  # flattened: the same values in row-major order
                layout[...] = source
            side.create_virtual_dataset(ds.path, layout, fillvalue=0)
    return buffer


def default_output(run: str | os.PathLike[str]) -> Path:
    """The XDMF file beside the run file: ``RUN.h5`` gives ``RUN.xdmf``."""
    return Path(run).with_suffix(".xdmf")


def sidecar_path(output: str | os.PathLike[str]) -> Path:
    """The sidecar of the XDMF file ``output``: ``RUN.xdmf.h5``."""
    output = Path(output)
    return output.with_name(output.name + SIDECAR_SUFFIX)


def is_export(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is an XDMF file or a sidecar written by porenet (replaceable)."""
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            head = fh.read(512)
    except OSError:
        return False
    if MARKER.encode() in head:
        return True
    import h5py

    try:
        with h5py.File(path, "r") as f:
            return SIDECAR_ATTR in f.attrs
    except Exception:  # any file h5py cannot open is not a sidecar
        return False


def _reference(target: Path, directory: Path) -> str:
    """``target`` as a path relative to ``directory`` (absolute where none exists)."""
    try:
        ref = os.path.relpath(target, directory)
    except ValueError:  # another drive (Windows)
        ref = os.path.abspath(target)
    if ":" in ref:
        raise ConfigError(
            f"{target}: an XDMF file cannot name a file whose path has a ':' (it separates "
            "the file from the dataset); rename or move it"
        )
    return Path(ref).as_posix()


def check_not_run_file(run: Path, output: Path) -> None:
    """Refuse an XDMF file or sidecar that would replace the run file itself.

    Raises
    ------
    ConfigError
        If ``output`` or its sidecar is ``run`` (``-o RUN`` names the sidecar ``RUN.h5``).
    """
    for path in (output, sidecar_path(output)):
        if path.exists() and run.exists() and os.path.samefile(path, run):
            raise ConfigError(
                f"{output}: the XDMF file or its sidecar {sidecar_path(output)} would "
                f"replace the run file {run}; choose another name"
            )


def export_xdmf(
    run: str | os.PathLike[str], output: str | os.PathLike[str] | None = None
) -> tuple[Path, Path]:
    """Write the XDMF file of the run file ``run`` and its sidecar; return both paths.

    Parameters
    ----------
    run : path
        A porenet run file; only read.
    output : path, optional
        The XDMF file to write (default :func:`default_output`); the sidecar goes beside it
        (:func:`sidecar_path`). Existing files there are replaced.

    Raises
    ------
    RunFileError
        If ``run`` is not a readable porenet run file, or does not have the layout.
    ConfigError
        If a path has a ``:``, which XDMF cannot name.
    OutputError
        If a file cannot be written (each is written atomically: the sidecar first, then
        the XDMF file, so an XDMF file never points at a sidecar that is not there).
    """
    from porenet.io.atomic import atomic_write_bytes
    from porenet.io.runfile import open_run

    run = Path(run)
    output = Path(output) if output is not None else default_output(run)
    sidecar = sidecar_path(output)
    check_not_run_file(run, output)
    run_ref = _reference(run, output.parent)
    sidecar_ref = _reference(sidecar, output.parent)
    with open_run(run) as f:
        export = plan_export(f)
    atomic_write_bytes(sidecar, sidecar_image(export, run_ref).getbuffer(), what="sidecar")
    text = xdmf_text(export, run_ref, sidecar_ref)
    atomic_write_bytes(output, text.encode("utf-8"), what="XDMF file")
    return output, sidecar
