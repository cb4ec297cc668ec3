"""Test helpers for the ``network`` lattice: writing a network as an OpenPNM-style ``.npz`` and
in the Statoil format (tests only; porenet reads these formats, it never writes them)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from porenet.kinds.network.files import NetworkData

EXAMPLE = Path(__file__).resolve().parents[4] / "examples" / "networks" / "delaunay-2d.npz"


def example_dict() -> dict[str, np.ndarray]:
    """The arrays of the example network (examples/scripts/make_example_network.py)."""
    with np.load(EXAMPLE) as data:
        return {key: data[key] for key in data.files}


def jittered_cubic(shape: tuple[int, int, int], seed: int = 0) -> dict[str, np.ndarray]:
    """A cubic network of spacing 1e-4 m with jittered centres and random sizes, OpenPNM keys
    (labels ``pore.left``/``pore.right`` on the x faces, ``pore.surface``)."""
    rng = np.random.default_rng(seed)
    nx, ny, nz = shape
    k, rest = np.divmod(np.arange(nx * ny * nz), nx * ny)
    i, j = np.divmod(rest, nx)
    xyz = np.stack([j, i, k], axis=1) * 1e-4 + rng.uniform(-2e-5, 2e-5, size=(nx * ny * nz, 3))
    idx = np.arange(nx * ny * nz).reshape(nz, ny, nx)
    pairs = [(idx[:, :, :-1], idx[:, :, 1:]), (idx[:, :-1, :], idx[:, 1:, :]),
             (idx[:-1, :, :], idx[1:, :, :])]  # fmt: skip
    conns = np.concatenate([np.stack([a.ravel(), b.ravel()], axis=1) for a, b in pairs])
    m = len(conns)
    total = np.linalg.norm(xyz[conns[:, 1]] - xyz[conns[:, 0]], axis=1)
    surface = (j == 0) | (j == nx - 1) | (i == 0) | (i == ny - 1)
    if nz > 1:
        surface |= (k == 0) | (k == nz - 1)
    return {
        "pore.coords": xyz,
        "throat.conns": conns,
        "throat.inscribed_diameter": rng.uniform(1e-5, 3e-5, size=m),
        "throat.total_length": total,
        "throat.length": 0.5 * total,
        "throat.shape_factor": rng.uniform(0.03, 0.08, size=m),
        "pore.volume": rng.uniform(1e-13, 3e-13, size=nx * ny * nz),
        "pore.left": j == 0,
        "pore.right": j == nx - 1,
        "pore.surface": surface,
    }


def write_npz(path: Path, arrays: dict[str, np.ndarray]) -> Path:
    np.savez(path, **arrays)
    return path


def _fmt(values: np.ndarray) -> list[str]:
    """Shortest round-trip text of each float (Python's repr)."""
    return [repr(float(v)) for v in np.asarray(values, dtype=np.float64)]


def write_statoil(
    prefix: Path,
    net: NetworkData,
    inlet: np.ndarray,
    outlet: np.ndarray,
    throat_part: np.ndarray | None = None,
) -> Path:
    """Write ``net`` as the four Statoil files ``<prefix>_node1.dat`` ... and return the node1
    path. Pores ``inlet`` and ``outlet`` (bool masks) get a link to the inlet (-1) or outlet
    (0) reservoir; the reservoir links are written among the throats (inlet links first, the
    outlet links halfway), so the reader must drop them and keep the throats' order.
    ``throat_part``: link2's throat lengths (default half of ``net.length``)."""
    n, m = net.n_pores, net.n_throats
    coords = net.coords if net.coords.shape[1] == 3 else np.column_stack([net.coords, np.zeros(n)])
    g = net.shape_factor if net.shape_factor is not None else np.full(m, 1 / (4 * np.pi))
    part = 0.5 * net.length if throat_part is None else throat_part
    ends = net.conns + 1
    inlets, outlets = np.flatnonzero(inlet), np.flatnonzero(outlet)
    links = [(-1, p + 1, net.radius.mean(), 0.05, net.length.mean(), -1) for p in inlets]
    half = m // 2
    for t in range(m):
        if t == half:
            links += [(p + 1, 0, net.radius.mean(), 0.05, net.length.mean(), -1) for p in outlets]
        links.append((ends[t, 0], ends[t, 1], net.radius[t], g[t], net.length[t], t))
    if half >= m:
        links += [(p + 1, 0, net.radius.mean(), 0.05, net.length.mean(), -1) for p in outlets]
    link1 = [f"{len(links)}"]
    link2 = []
    neighbours: list[list[int]] = [[] for _ in range(n)]
    throats: list[list[int]] = [[] for _ in range(n)]
    for row, (a, b, r, gt, length, t) in enumerate(links, start=1):
        r_s, g_s, l_s = _fmt([r, gt, length])
        link1.append(f"{row} {a} {b} {r_s} {g_s} {l_s}")
        lt = part[t] if t >= 0 else 0.5 * length
        p1, p2, lt_s = _fmt([(length - lt) / 2, (length - lt) / 2, lt])
        link2.append(f"{row} {a} {b} {p1} {p2} {lt_s} 0.0 0.0")
        for x, y in ((a, b), (b, a)):
            if x > 0:
                neighbours[x - 1].append(y)
                throats[x - 1].append(row)
    extent = coords.max(axis=0) - coords.min(axis=0)
    node1 = [" ".join([str(n), *_fmt(extent)])]
    node2 = []
    for p in range(n):
        x = " ".join(_fmt(coords[p]))
        nb = " ".join(map(str, neighbours[p]))
        th = " ".join(map(str, throats[p]))
        flags = f"{int(inlet[p])} {int(outlet[p])}"
        node1.append(f"{p + 1} {x} {len(neighbours[p])} {nb} {flags} {th}")
        (v,) = _fmt([net.volume[p]])
        node2.append(f"{p + 1} {v} 1e-05 0.05 0.0")
    for suffix, lines in (("node1", node1), ("node2", node2), ("link1", link1), ("link2", link2)):
        Path(f"{prefix}_{suffix}.dat").write_text("\n".join(lines) + "\n")
    return Path(f"{prefix}_node1.dat")
