"""Readers of pore networks saved by other programs, for the ``network`` lattice
(docs/lattices.md, "Imported networks (kind `network`)").

Two formats:

* an OpenPNM or PoreSpy network dict saved with ``numpy.savez`` (``.npz``): arrays named
  ``pore.coords``, ``throat.conns``, ``throat.inscribed_diameter`` or ``throat.diameter``,
  ``throat.total_length`` (OpenPNM 3: ``throat.spacing``) or ``throat.length``,
  ``pore.volume`` (or PoreSpy's
  ``pore.region_volume``), optionally ``throat.shape_factor``, and boolean ``pore.<name>``
  arrays, the labels;
* the Statoil format of pnextract and pnflow: ``<prefix>_node1.dat``, ``_node2.dat``,
  ``_link1.dat`` and ``_link2.dat``, text files of numbers in metres.

:func:`read_network` returns one :class:`NetworkData`, in SI units, with every field checked
(a bad field is a ValueError naming the file and the key or line). :func:`describe` reads only
what is cheap (an archive's array headers, the first line of the Statoil files), for the
config's validation. numpy and the standard library only: the config imports this module;
the Statoil numbers are parsed by a compiled kernel (:mod:`porenet.kernels.text`)
imported only when a file is read.

Length (over the ~500 lines of docs/architecture.md's rule): the two readers of one
structure, :class:`NetworkData`, with the checks they share (finite and positive sizes, pore
pairs in range, no throat from a pore to itself) and the messages that name the file and the
key or line of every problem; in two modules the Statoil reader would import the other's
checks anyway.
"""

from __future__ import annotations

import functools
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

#: Throat sizes, in order of preference: the diameter of the largest inscribed sphere (the
#: constriction that sets the entry pressure) is preferred over an equivalent diameter.
RADIUS_KEYS = ("throat.inscribed_diameter", "throat.diameter")
#: Pore volumes, in order of preference (``pore.region_volume``: PoreSpy's ``snow2``).
VOLUME_KEYS = ("pore.volume", "pore.region_volume")
#: The arrays of each ``throat_length`` setting, in order of preference (``"centres"`` is
#: computed from the coords): OpenPNM 3 calls the centre-to-centre length ``throat.spacing``.
LENGTH_KEYS = {
    "total": ("throat.total_length", "throat.spacing"),
    "throat": ("throat.length",),
}
SHAPE_FACTOR_KEY = "throat.shape_factor"
COORDS_KEY = "pore.coords"
CONNS_KEY = "throat.conns"
#: The four files of a Statoil network, ``<prefix><suffix>``.
STATOIL_SUFFIXES = ("_node1.dat", "_node2.dat", "_link1.dat", "_link2.dat")
#: Labels of a Statoil network: pores linked to the inlet reservoir (index -1 in link1) and
#: to the outlet reservoir (index 0), each under two names.
STATOIL_LABELS = ("inlet", "outlet", "pore.inlet", "pore.outlet")
#: The first bytes of a zip archive (an ``.npz``).
ZIP_MAGICS = (b"PK\x03\x04", b"PK\x05\x06")


@dataclass(frozen=True)
class NetworkData:
    """A pore network as read from a file, in SI units.

    Attributes
    ----------
    coords : ndarray, shape (N, d)
        Pore centres (m); d = 3, or 2 when every z of the file is equal.
    conns : ndarray of int64, shape (M, 2)
        The two pores each throat joins (0-based; reservoir links of a Statoil file are not
        throats).
    radius : ndarray, shape (M,)
        Throat radius (m).
    length : ndarray, shape (M,)
        Throat length (m), as the ``throat_length`` setting chose it.
    shape_factor : ndarray, shape (M,), or None
        Throat shape factor G = A / P^2 (-), if the file has one.
    volume : ndarray, shape (N,)
        Pore volume (m^3).
    labels : dict
        Named pore sets, name -> (N,) bool.
    source : str
        The file read (for messages).
    """

    coords: np.ndarray
    conns: np.ndarray
    radius: np.ndarray
    length: np.ndarray
    shape_factor: np.ndarray | None
    volume: np.ndarray
    labels: dict[str, np.ndarray] = field(default_factory=dict)
    source: str = ""

    @property
    def n_pores(self) -> int:
        return int(self.coords.shape[0])

    @property
    def n_throats(self) -> int:
        return int(self.conns.shape[0])


@dataclass(frozen=True)
class NetworkHeader:
    """What :func:`describe` learns cheaply about a network file.

    Attributes
    ----------
    format : str
        ``"openpnm"`` (an ``.npz``) or ``"statoil"``.
    path : Path
        The ``.npz`` file or the Statoil ``_node1.dat`` file.
    n_pores, n_throats : int
        From the array shapes or the Statoil headers (reservoir links counted as throats).
    dimension : int or None
        2 or 3 (None for a Statoil network: known once its coordinates are read).
    labels : tuple of str
        The label names.
    keys : tuple of str
        The arrays of an ``.npz`` (the Statoil format's fixed columns: empty).
    """

    format: str
    path: Path
    n_pores: int
    n_throats: int
    dimension: int | None
    labels: tuple[str, ...]
    keys: tuple[str, ...] = ()

    @property
    def has_shape_factor(self) -> bool:
        return self.format == "statoil" or SHAPE_FACTOR_KEY in self.keys

    def has_length(self, setting: str) -> bool:
        """Whether the file gives the throat lengths of a ``throat_length`` setting."""
        if self.format == "statoil" or setting == "centres":
            return True
        return any(key in self.keys for key in LENGTH_KEYS[setting])


# -- finding the files ----------------------------------------------------------------------


def statoil_files(prefix: Path) -> list[Path]:
    """The four files of the Statoil network ``prefix`` (node1, node2, link1, link2)."""
    return [prefix.with_name(prefix.name + suffix) for suffix in STATOIL_SUFFIXES]


def statoil_prefix(path: Path) -> Path:
    """The prefix of a Statoil network named by one of its files or by the prefix."""
    for suffix in STATOIL_SUFFIXES:
        if path.name.endswith(suffix):
            return path.with_name(path.name[: -len(suffix)])
    return path


def is_npz(path: Path) -> bool:
    """Whether ``path`` is a file that starts like a zip archive (an ``.npz``)."""
    try:
        with path.open("rb") as fh:
            return fh.read(4) in ZIP_MAGICS
    except OSError:
        return False


def locate(path: Path) -> tuple[str, Path]:
    """``("openpnm", the .npz)`` or ``("statoil", the _node1.dat file)`` for a path that names
    an ``.npz`` archive, a Statoil file or a Statoil prefix.

    Raises
    ------
    ValueError
        Naming the files that were looked for.
    """
    if path.is_file() and (path.suffix == ".npz" or is_npz(path)):
        return "openpnm", path
    if path.suffix == ".npz":
        raise ValueError(f"file not found: {path}")
    files = statoil_files(statoil_prefix(path))
    missing = [p.name for p in files if not p.is_file()]
    if missing:
        raise ValueError(
            f"{path}: expected an .npz network (OpenPNM or PoreSpy) or the four files of a "
            f"Statoil network, {files[0].parent}/{statoil_prefix(path).name}_node1.dat, "
            f"_node2.dat, _link1.dat and _link2.dat; missing: {', '.join(missing)}"
        )
    return "statoil", files[0]


# -- cheap description, for the config --------------------------------------------------------


def describe(path: Path) -> NetworkHeader:
    """What a network file holds, read cheaply (an ``.npz``'s array headers and coordinates,
    the first line of the Statoil files), checked for the required keys and their shapes.
    Cached while the file is unchanged.

    Raises
    ------
    ValueError
        Naming the file and the key that is missing or of the wrong shape.
    """
    fmt, found = locate(Path(path))
    stat = found.stat()
    return _describe(str(found), fmt, stat.st_mtime_ns, stat.st_size)


@functools.lru_cache(maxsize=32)
def _describe(path: str, fmt: str, mtime: int, size: int) -> NetworkHeader:
    if fmt == "statoil":
        return _describe_statoil(Path(path))
    return _describe_npz(Path(path))


def npz_headers(path: Path) -> dict[str, tuple[tuple[int, ...], np.dtype]]:
    """``name -> (shape, dtype)`` of every array of an ``.npz``, from the array headers only."""
    out: dict[str, tuple[tuple[int, ...], np.dtype]] = {}
    try:
        with zipfile.ZipFile(path) as archive:
            for name in archive.namelist():
                if not name.endswith(".npy"):
                    continue
                with archive.open(name) as fh:
                    version = np.lib.format.read_magic(fh)
                    read = (
                        np.lib.format.read_array_header_1_0
                        if version == (1, 0)
                        else np.lib.format.read_array_header_2_0  # 3.0: the same layout
                    )
                    shape, _, dtype = read(fh)
                out[name[: -len(".npy")]] = (tuple(shape), np.dtype(dtype))
    except (zipfile.BadZipFile, ValueError, OSError, EOFError) as exc:
        raise ValueError(f"{path} is not a readable .npz archive ({exc})") from None
    return out


def _describe_npz(path: Path) -> NetworkHeader:
    heads = npz_headers(path)
    for name, (_, dtype) in heads.items():
        if dtype.hasobject:
            raise ValueError(f"{path}: {name!r} holds Python objects, not numbers")
    n, m = _npz_sizes(path, heads)
    _first_key(path, heads, RADIUS_KEYS, (m,), "the throat radii")
    _first_key(path, heads, VOLUME_KEYS, (n,), "the pore volumes")
    for key in (*LENGTH_KEYS["total"], *LENGTH_KEYS["throat"], SHAPE_FACTOR_KEY):
        if key in heads and heads[key][0] != (m,):
            raise ValueError(f"{path}: {key!r} has shape {heads[key][0]}, expected ({m},)")
    labels = []
    for name, (shape, dtype) in heads.items():
        if name.startswith("pore.") and dtype == np.bool_:
            if shape != (n,):
                raise ValueError(f"{path}: label {name!r} has shape {shape}, expected ({n},)")
            labels.append(name)
    with np.load(path, allow_pickle=False) as data:
        coords = np.asarray(data[COORDS_KEY])
    dimension = 2 if coords.shape[1] == 2 or _flat(coords) else 3
    return NetworkHeader("openpnm", path, n, m, dimension, tuple(sorted(labels)), tuple(heads))


def _npz_sizes(path: Path, heads: dict[str, tuple[tuple[int, ...], np.dtype]]) -> tuple[int, int]:
    """N and M from ``pore.coords`` (N, 2 or 3) and ``throat.conns`` (M, 2)."""
    for key in (COORDS_KEY, CONNS_KEY):
        if key not in heads:
            raise ValueError(f"{path}: no array {key!r} (found: {', '.join(heads) or 'none'})")
    shape, dtype = heads[COORDS_KEY]
    if len(shape) != 2 or shape[1] not in (2, 3) or dtype.kind not in "fiu":
        raise ValueError(f"{path}: {COORDS_KEY!r} is {dtype} {shape}, expected floats (N, 3)")
    conns, conns_dtype = heads[CONNS_KEY]
    if len(conns) != 2 or conns[1] != 2 or conns_dtype.kind not in "iu":
        raise ValueError(
            f"{path}: {CONNS_KEY!r} is {conns_dtype} {conns}, expected integers (M, 2)"
        )
    return shape[0], conns[0]


def _first_key(
    path: Path,
    heads: dict[str, tuple[tuple[int, ...], np.dtype]],
    keys: tuple[str, ...],
    shape: tuple[int, ...],
    what: str,
) -> str:
    """The first of ``keys`` the archive holds, checked to have ``shape``."""
    for key in keys:
        if key in heads:
            if heads[key][0] != shape:
                raise ValueError(f"{path}: {key!r} has shape {heads[key][0]}, expected {shape}")
            return key
    family = keys[0].split(".")[0] + "."
    found = ", ".join(k for k in heads if k.startswith(family)) or "none"
    raise ValueError(
        f"{path}: no array of {what}: expected {' or '.join(map(repr, keys))} "
        f"(found {family}*: {found})"
    )


def _flat(coords: np.ndarray) -> bool:
    """Whether every z of (N, 3) coordinates is equal (the network is 2-D)."""
    return coords.shape[1] == 3 and bool(np.all(coords[:, 2] == coords[0, 2]))


def _first_numbers(path: Path) -> list[str]:
    try:
        with path.open("rb") as fh:
            return fh.readline(4096).decode("ascii", errors="replace").split()
    except OSError as exc:
        raise ValueError(f"cannot read {path}: {exc.strerror or exc}") from None


def _header_count(path: Path, what: str) -> int:
    words = _first_numbers(path)
    try:
        return int(words[0])
    except (IndexError, ValueError):
        raise ValueError(
            f"{path}: line 1 should start with the number of {what}, found {' '.join(words)!r}"
        ) from None


def _describe_statoil(node1: Path) -> NetworkHeader:
    prefix = statoil_prefix(node1)
    link1 = statoil_files(prefix)[2]
    n = _header_count(node1, "pores")
    m = _header_count(link1, "throats")
    return NetworkHeader("statoil", node1, n, m, None, STATOIL_LABELS)


# -- reading --------------------------------------------------------------------------------


def read_network(path: Path, throat_length: str = "total") -> NetworkData:
    """Read and check a network (an ``.npz`` or a Statoil network, :func:`locate`).

    Parameters
    ----------
    path : Path
        The ``.npz`` file, one of the Statoil files or their prefix.
    throat_length : {"total", "throat", "centres"}
        Which length is the throat's: pore centre to pore centre as the file gives it
        (``throat.total_length``, else ``throat.spacing``; Statoil: link1's length), the
        throat's own part
        (``throat.length``; Statoil: link2's throat length), or the distance between the two
        pore centres.

    Raises
    ------
    ValueError
        Naming the file and the key (or line) that is missing or wrong.
    """
    fmt, found = locate(Path(path))
    if fmt == "statoil":
        return read_statoil(found, throat_length)
    return read_npz(found, throat_length)


def read_npz(path: Path, throat_length: str = "total") -> NetworkData:
    """An OpenPNM or PoreSpy network dict saved as ``.npz`` (:func:`read_network`)."""
    header = describe(path)
    keys = set(header.keys)
    with np.load(path, allow_pickle=False) as data:
        coords = checked_floats(path, COORDS_KEY, data[COORDS_KEY])
        conns = checked_conns(path, CONNS_KEY, data[CONNS_KEY], header.n_pores)
        radius_key = next(k for k in RADIUS_KEYS if k in keys)
        radius = 0.5 * checked_floats(path, radius_key, data[radius_key], positive=True)
        volume_key = next(k for k in VOLUME_KEYS if k in keys)
        volume = checked_floats(path, volume_key, data[volume_key], positive=True)
        shape_factor = None
        if SHAPE_FACTOR_KEY in keys:
            shape_factor = checked_floats(
                path, SHAPE_FACTOR_KEY, data[SHAPE_FACTOR_KEY], positive=True
            )
        if throat_length == "centres":
            length = centre_distances(path, coords, conns)
        else:
            found = [k for k in LENGTH_KEYS[throat_length] if k in keys]
            if not found:
                raise ValueError(missing_length(path, throat_length))
            key = found[0]
            length = checked_floats(path, key, data[key], positive=True)
        labels = {name: np.asarray(data[name], dtype=bool) for name in header.labels}
    if _flat(coords):
        coords = np.ascontiguousarray(coords[:, :2])
    return NetworkData(coords, conns, radius, length, shape_factor, volume, labels, str(path))


def missing_length(path: Path, setting: str) -> str:
    """The message for a file without the throat lengths of a ``throat_length`` setting."""
    keys = " or ".join(map(repr, LENGTH_KEYS[setting]))
    return (
        f"{path}: no array {keys} for throat_length = {setting!r}; give it, or choose "
        "throat_length = 'centres' (the distance between the pore centres)"
    )


def checked_floats(
    path: Path | str,
    key: str,
    values: np.ndarray,
    positive: bool = False,
    lines: np.ndarray | None = None,
) -> np.ndarray:
    """``values`` as float64, checked to be finite (and positive); errors name the key and
    the first bad entry (its index, or its line of a text file when ``lines`` gives each
    row's line number)."""
    out = np.asarray(values, dtype=np.float64)
    bad = ~np.isfinite(out)
    if positive:
        bad |= ~(out > 0)
    if bad.any():
        first = np.unravel_index(int(np.flatnonzero(bad.ravel())[0]), out.shape)
        index = [int(i) for i in first]
        where = f"line {int(lines[index[0]])}" if lines is not None else f"{index}"
        rule = "positive and finite" if positive else "finite"
        raise ValueError(
            f"{path}: {key!r} has {int(bad.sum())} value(s) that are not {rule} "
            f"(first: {where} = {float(out[first])!r})"
        )
    return out


def checked_conns(path: Path | str, key: str, conns: np.ndarray, n_pores: int) -> np.ndarray:
    """Throat pore pairs as int64, each in ``[0, n_pores)`` and of two different pores."""
    out = np.asarray(conns, dtype=np.int64)
    outside = (out < 0) | (out >= n_pores)
    if outside.any():
        t = int(np.flatnonzero(outside.any(axis=1))[0])
        raise ValueError(
            f"{path}: {key!r} names pores outside [0, {n_pores}) "
            f"(first: throat {t} = {out[t].tolist()})"
        )
    loops = out[:, 0] == out[:, 1]
    if loops.any():
        t = int(np.flatnonzero(loops)[0])
        raise ValueError(
            f"{path}: {key!r}: {int(loops.sum())} throat(s) join a pore to itself "
            f"(first: throat {t} joins pore {int(out[t, 0])})"
        )
    return out


def centre_distances(path: Path | str, coords: np.ndarray, conns: np.ndarray) -> np.ndarray:
    """The distance between the two pore centres of each throat (m), checked positive."""
    d = np.sqrt(np.sum((coords[conns[:, 1]] - coords[conns[:, 0]]) ** 2, axis=1))
    return checked_floats(path, "distance between the pore centres", d, positive=True)


# -- the Statoil format -----------------------------------------------------------------------

#: Columns of the Statoil files (after node1's variable part, which :func:`_node1` reads).
NODE2_COLUMNS = ("index", "volume", "radius", "shape factor", "clay volume")
LINK1_COLUMNS = ("index", "pore 1", "pore 2", "radius", "shape factor", "total length")
LINK2_COLUMNS = ("index", "pore 1", "pore 2", "pore 1 length", "pore 2 length",
                 "throat length", "volume", "clay volume")  # fmt: skip


def read_statoil(node1: Path, throat_length: str = "total") -> NetworkData:
    """A Statoil network (pnextract, pnflow), named by its ``_node1.dat`` file
    (:func:`read_network`).

    Pore indices are 1-based; in link1 and link2, index -1 is the inlet reservoir and 0 the
    outlet reservoir. A link to a reservoir is no throat of the network: it labels its pore
    ``inlet`` or ``outlet`` (also ``pore.inlet``, ``pore.outlet``). Columns: node1 ``index x y
    z n neighbours(n) is_inlet is_outlet throats(n)`` after a line ``N Lx Ly Lz``; node2 ``index
    volume radius shape_factor clay_volume``; link1 ``index pore1 pore2 radius shape_factor
    total_length`` after a line ``M``; link2 ``index pore1 pore2 pore1_length pore2_length
    throat_length volume clay_volume``.
    """
    paths = statoil_files(statoil_prefix(node1))
    coords, degree, node1_lines = _node1(paths[0])
    n = coords.shape[0]
    node2, node2_lines = _table(paths[1], _numbers(paths[1]), NODE2_COLUMNS, n, header=False)
    link1_numbers = _numbers(paths[2])
    m = _count_line(paths[2], link1_numbers, "throats")
    link1, link1_lines = _table(paths[2], link1_numbers, LINK1_COLUMNS, m, header=True)
    link2, _ = _table(paths[3], _numbers(paths[3]), LINK2_COLUMNS, m, header=False)
    pores = _integers(paths[2], "pore 1, pore 2 (columns 2, 3)", link1[:, 1:3], link1_lines)
    outside = (pores < -1) | (pores > n)
    if outside.any():
        t = int(np.flatnonzero(outside.any(axis=1))[0])
        raise ValueError(
            f"{paths[2]}, line {int(link1_lines[t])}: pores {pores[t].tolist()} outside "
            f"1..{n} (-1: inlet, 0: outlet reservoir)"
        )
    if not np.array_equal(link2[:, 1:3], link1[:, 1:3]):
        t = int(np.flatnonzero(np.any(link2[:, 1:3] != link1[:, 1:3], axis=1))[0])
        raise ValueError(
            f"{paths[3]}: throat {t + 1} joins pores {link2[t, 1:3].astype(int).tolist()}, "
            f"but {paths[2].name} says {link1[t, 1:3].astype(int).tolist()}"
        )
    _check_degree(paths, pores, degree, node1_lines)
    inner = np.all(pores > 0, axis=1)
    labels = _reservoir_labels(pores, n)
    rows, lines = np.flatnonzero(inner), link1_lines[inner]
    conns = checked_conns(paths[2], "pore 1, pore 2 (columns 2, 3)", pores[rows] - 1, n)
    radius = checked_floats(paths[2], "radius (column 4)", link1[rows, 3], True, lines)
    shape_factor = checked_floats(paths[2], "shape factor (column 5)", link1[rows, 4], True, lines)
    volume = checked_floats(paths[1], "volume (column 2)", node2[:, 1], True, node2_lines)
    if throat_length == "total":
        length = checked_floats(paths[2], "total length (column 6)", link1[rows, 5], True, lines)
    elif throat_length == "throat":
        length = checked_floats(paths[3], "throat length (column 6)", link2[rows, 5], True, lines)
    else:
        length = centre_distances(paths[0], coords, conns)
    if _flat(coords):
        coords = np.ascontiguousarray(coords[:, :2])
    return NetworkData(coords, conns, radius, length, shape_factor, volume, labels, str(paths[0]))


def _numbers(path: Path):  # -> porenet.kernels.text.Numbers
    """Every number of a text file, with its line structure."""
    from porenet.kernels.text import parse_numbers

    try:
        data = np.fromfile(path, dtype=np.uint8)
    except OSError as exc:
        raise ValueError(f"cannot read {path}: {exc.strerror or exc}") from None
    try:
        return parse_numbers(data)
    except ValueError as exc:
        raise ValueError(f"{path}, {exc}") from None


def _count_line(path: Path, numbers, what: str) -> int:
    """The count on the first line of a Statoil file (N pores or M throats)."""
    if numbers.counts.size == 0:
        raise ValueError(f"{path} is empty; line 1 should give the number of {what}")
    count = numbers.values[0]
    if count != int(count) or count < 0:
        raise ValueError(f"{path}: line 1 should start with the number of {what}, not {count!r}")
    return int(count)


def _table(
    path: Path, numbers, columns: tuple[str, ...], rows: int, header: bool
) -> tuple[np.ndarray, np.ndarray]:
    """The ``(rows, len(columns))`` table of a Statoil file (after its header line, if it has
    one) and each row's line number, checked: the row count, the numbers per row and the
    index column ``1..rows``."""
    counts, lines = numbers.counts, numbers.lines
    start = int(counts[0]) if header else 0
    counts, lines = (counts[1:], lines[1:]) if header else (counts, lines)
    _check_rows(path, lines, rows, header)
    wrong = counts != len(columns)
    if wrong.any():
        k = int(np.flatnonzero(wrong)[0])
        raise ValueError(
            f"{path}, line {int(lines[k])}: {int(counts[k])} numbers, expected {len(columns)} "
            f"({', '.join(columns)})"
        )
    table = numbers.values[start:].reshape(rows, len(columns))
    _check_index(path, table[:, 0], lines)
    return table, lines


def _check_rows(path: Path, lines: np.ndarray, rows: int, header: bool) -> None:
    if lines.size != rows:
        said = "its first line says" if header else "the network has"
        raise ValueError(
            f"{path}: {lines.size} lines of data, but {said} {rows}"
            + (" (truncated?)" if lines.size < rows else "")
        )


def _check_index(path: Path, index: np.ndarray, lines: np.ndarray) -> None:
    wrong = index != np.arange(1, index.size + 1)
    if wrong.any():
        k = int(np.flatnonzero(wrong)[0])
        raise ValueError(
            f"{path}, line {int(lines[k])}: index {index[k]:g}, expected {k + 1} "
            "(rows numbered 1, 2, ... in order)"
        )


def _integers(path: Path, key: str, values: np.ndarray, lines: np.ndarray) -> np.ndarray:
    wrong = values != np.round(values)
    if wrong.any():
        k = int(np.flatnonzero(wrong.reshape(values.shape[0], -1).any(axis=1))[0])
        raise ValueError(f"{path}, line {int(lines[k])}: {key} must be whole numbers")
    return values.astype(np.int64)


def _node1(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coordinates (N, 3) in m, the number of throats of each pore (reservoir links
    included) and each pore's line, from a ``_node1.dat`` file, whose lines hold ``index x y
    z n``, n neighbours, two flags and n throat indices."""
    numbers = _numbers(path)
    n = _count_line(path, numbers, "pores")
    counts, lines = numbers.counts[1:], numbers.lines[1:]
    _check_rows(path, lines, n, header=True)
    short = counts < 5
    if short.any():
        k = int(np.flatnonzero(short)[0])
        raise ValueError(
            f"{path}, line {int(lines[k])}: {int(counts[k])} numbers, expected at least 5 "
            "(index, x, y, z, number of throats)"
        )
    starts = int(numbers.counts[0]) + np.concatenate([[0], np.cumsum(counts)[:-1]])
    values = numbers.values
    degree = _integers(path, "the number of throats (column 5)", values[starts + 4], lines)
    wrong = counts != 7 + 2 * degree
    if wrong.any():
        k = int(np.flatnonzero(wrong)[0])
        raise ValueError(
            f"{path}, line {int(lines[k])}: {int(counts[k])} numbers, expected 7 + 2 x "
            f"{int(degree[k])} (index, x, y, z, n, n neighbours, is_inlet, is_outlet, n throats)"
        )
    _check_index(path, values[starts], lines)
    coords = values[starts[:, None] + np.arange(1, 4)]
    return checked_floats(path, "x, y, z (columns 2-4)", coords, lines=lines), degree, lines


def _check_degree(
    paths: list[Path], pores: np.ndarray, degree: np.ndarray, lines: np.ndarray
) -> None:
    """node1's number of throats of each pore must be the links link1 lists for it."""
    ends = pores[pores > 0] - 1
    listed = np.bincount(ends, minlength=degree.size)
    wrong = listed != degree
    if wrong.any():
        p = int(np.flatnonzero(wrong)[0])
        raise ValueError(
            f"{paths[0]}, line {int(lines[p])}: pore {p + 1} has {int(degree[p])} throats, but "
            f"{paths[2].name} lists {int(listed[p])} for it (files of different networks?)"
        )


def _reservoir_labels(pores: np.ndarray, n: int) -> dict[str, np.ndarray]:
    """``inlet`` and ``outlet`` (and ``pore.`` aliases): pores linked to the reservoirs."""
    labels = {}
    for name, reservoir in (("inlet", -1), ("outlet", 0)):
        mask = np.zeros(n, dtype=bool)
        for a, b in ((0, 1), (1, 0)):
            links = (pores[:, a] == reservoir) & (pores[:, b] > 0)
            mask[pores[links, b] - 1] = True
        labels[name] = mask
        labels[f"pore.{name}"] = mask
    return labels
