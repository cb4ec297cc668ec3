"""The front's measures (:func:`porenet_front.front.measure`) on hand-drawn patterns whose
answer is counted by hand, and on random patterns against a slow, obvious reference: one
breadth-first search per meniscus from its defending pore, through defending pores, to the
outlet.

Square lattice of ``n x n`` pores (docs/model.md section 1): pore ``(i, j)`` is number
``i n + j`` at ``x = 2j + 1``, ``y = 2i + 1`` (units of ``a``). With injection at the left edge
the distance is ``x - 1``: ``2j`` for a pore of column ``j``, ``2j + 1`` for the horizontal
throat ``(i, j)-(i, j+1)``, ``2j`` for a vertical throat of column ``j``.
"""

from __future__ import annotations

from collections import deque

import numpy as np
import pytest
from porenet_front.front import front_geometry, injection_distance, measure

from porenet.simulation import Simulation

N = 5


def lattice(reg, n: int = N, seed: int = 1):
    """A square lattice of n x n pores, built as a run builds it."""
    scene = {
        "seed": seed,
        "lattice": {"kind": "square", "n": n, "disorder": 0.3},
        "fluid": {"kind": "invasion-percolation"},
        "classifier": {"kind": "none"},
    }
    return Simulation.from_scene(scene, registry=reg).lattice


def pattern(*pores: tuple[int, int], n: int = N, columns: int = 1) -> np.ndarray:
    """Drained mask: the first ``columns`` columns and the listed ``(i, j)`` pores."""
    drained = np.zeros((n, n), dtype=bool)
    drained[:, :columns] = True
    for i, j in pores:
        drained[i, j] = True
    return drained.ravel()


def test_distances_from_the_injection_site():
    points = np.array([[1.0, 7.0], [4.0, 3.0], [9.0, 9.0]])
    inlets = np.array([[1.0, 1.0], [1.0, 3.0]])
    np.testing.assert_array_equal(injection_distance(points, inlets, "left-edge"), [0, 3, 8])
    centre = np.array([[5.0, 5.0]])
    np.testing.assert_allclose(
        injection_distance(points, centre, "centre"), [np.hypot(4, 2), np.hypot(1, 2), 4 * 2**0.5]
    )
    with pytest.raises(ValueError, match="unknown injection site"):
        injection_distance(points, inlets, "top")


def test_flat_front_of_the_inlet_column(reg):
    """Only the inlets drained: one meniscus per row, all at x = 2 (distance 1), width 0."""
    geometry = front_geometry(lattice(reg), "left-edge")
    front = measure(geometry, pattern())
    assert (front.menisci, front.front_menisci) == (N, N)
    assert (front.position, front.width, front.extent) == (1.0, 0.0, 0.0)


def test_a_finger_along_the_middle_row(reg):
    """Pores (2, 1) and (2, 2) drained beyond the inlets: four menisci of the inlet column
    (distance 1), the finger's tip (throat (2,2)-(2,3), distance 5) and two vertical throats
    beside each finger pore (distances 2 and 4)."""
    geometry = front_geometry(lattice(reg), "left-edge")
    front = measure(geometry, pattern((2, 1), (2, 2)))
    distances = np.array([1, 1, 1, 1, 5, 2, 2, 4, 4], dtype=float)
    assert (front.menisci, front.front_menisci) == (9, 9)
    assert front.position == pytest.approx(21 / 9, rel=1e-15)
    assert front.width == pytest.approx(np.sqrt(np.mean((distances - 21 / 9) ** 2)), rel=1e-14)
    assert front.extent == 4.0


def test_menisci_around_an_enclosed_pore_are_not_front(reg):
    """A drained ring around pore (2, 2): its four menisci face trapped defender."""
    ring = [(1, 1), (1, 2), (1, 3), (2, 1), (2, 3), (3, 1), (3, 2), (3, 3)]
    geometry = front_geometry(lattice(reg), "left-edge")
    front = measure(geometry, pattern(*ring))
    # By hand: column 0 -> 1 at rows 0 and 4 (distance 1); the ring's outer side: (0,1),
    # (0,2), (0,3) below it and (4,1), (4,2), (4,3) above it (vertical, distances 2, 4, 6),
    # (1,3)-(1,4), (2,3)-(2,4), (3,3)-(3,4) to its right (distance 7); four around (2, 2).
    front_distances = np.array([1, 1, 2, 4, 6, 2, 4, 6, 7, 7, 7], dtype=float)
    assert front.menisci == front_distances.size + 4
    assert front.front_menisci == front_distances.size
    assert front.position == pytest.approx(front_distances.mean(), rel=1e-14)
    assert front.width == pytest.approx(front_distances.std(), rel=1e-14)
    assert front.extent == 6.0


def test_a_pocket_on_a_closed_edge_is_trapped_but_drains_with_injection_at_the_centre(reg):
    """Columns 0-3 drained except the bottom pore (0, 1). With injection at the left edge
    only the right column is outlet, the bottom edge is closed: the pocket is trapped. With
    injection at the centre the whole outer edge drains, so the pocket faces the outlet."""
    lat = lattice(reg)
    drained = pattern(columns=4)
    drained[0 * N + 1] = False
    left = measure(front_geometry(lat, "left-edge"), drained)
    assert (left.menisci, left.front_menisci) == (N + 3, N)  # 3 menisci around the pocket
    assert (left.position, left.width, left.extent) == (7.0, 0.0, 6.0)
    centre = measure(front_geometry(lat, "centre"), drained)
    assert (centre.menisci, centre.front_menisci) == (N + 3, N + 3)


def test_radial_distances_with_injection_at_the_centre(reg):
    """Inlet (2, 2) at (5, 5) and its neighbour (2, 3) drained: throats at distance 1 (three),
    3 (the tip) and sqrt(5) (two, beside (2, 3)); extent 2."""
    geometry = front_geometry(lattice(reg), "centre")
    drained = np.zeros(N * N, dtype=bool)
    drained[[2 * N + 2, 2 * N + 3]] = True
    front = measure(geometry, drained)
    distances = np.array([1, 1, 1, 3, 5**0.5, 5**0.5])
    assert (front.menisci, front.front_menisci) == (6, 6)
    assert front.position == pytest.approx(distances.mean(), rel=1e-14)
    assert front.width == pytest.approx(distances.std(), rel=1e-14)
    assert front.extent == 2.0


def test_nothing_drained_and_everything_drained(reg):
    geometry = front_geometry(lattice(reg), "left-edge")
    empty = measure(geometry, np.zeros(N * N, dtype=bool))
    full = measure(geometry, np.ones(N * N, dtype=bool))
    for front in (empty, full):
        assert (front.menisci, front.front_menisci) == (0, 0)
        assert np.isnan(front.position) and np.isnan(front.width)
    assert np.isnan(empty.extent) and full.extent == 2 * (N - 1)


def reference(lat, at: str, drained: np.ndarray) -> tuple[int, list[float], float]:
    """Slow and obvious: each meniscus, then a BFS from its defending pore through defending
    pores; it is front if the search reaches an outlet pore. Distances from the coordinates."""
    xy = np.asarray(lat.pore_coords)
    outlet = lat.outlet_mask(at)
    inlet = xy[lat.inlet_pores(at)]
    neighbours: dict[int, list[int]] = {p: [] for p in range(lat.n_pores)}
    for a, b in lat.throat_pores:
        neighbours[int(a)].append(int(b))
        neighbours[int(b)].append(int(a))

    def distance(point):
        if at == "left-edge":
            return float(point[0] - inlet[:, 0].min())
        return float(np.hypot(*(point - inlet[0])))

    menisci, front = 0, []
    for a, b in lat.throat_pores:
        if drained[a] == drained[b]:
            continue
        menisci += 1
        start = int(b) if drained[a] else int(a)
        seen, queue, reached = {start}, deque([start]), False
        while queue:
            p = queue.popleft()
            if outlet[p]:
                reached = True
                break
            for q in neighbours[p]:
                if not drained[q] and q not in seen:
                    seen.add(q)
                    queue.append(q)
        if reached:
            front.append(distance(0.5 * (xy[a] + xy[b])))
    extent = max((distance(xy[p]) for p in np.flatnonzero(drained)), default=float("nan"))
    return menisci, front, extent


@pytest.mark.parametrize("at", ["left-edge", "centre"])
@pytest.mark.parametrize("fraction", [0.3, 0.55, 0.7])
def test_random_patterns_against_a_breadth_first_search_per_meniscus(reg, at, fraction):
    lat = lattice(reg, n=14)
    geometry = front_geometry(lat, at)
    rng = np.random.default_rng(17)
    trapped = 0
    for _ in range(8):
        drained = rng.random(lat.n_pores) < fraction
        menisci, front_distances, extent = reference(lat, at, drained)
        got = measure(geometry, drained)
        assert got.menisci == menisci
        assert got.front_menisci == len(front_distances)
        trapped += got.menisci - got.front_menisci
        if front_distances:
            assert got.position == pytest.approx(np.mean(front_distances), rel=1e-12)
            assert got.width == pytest.approx(np.std(front_distances), rel=1e-12, abs=1e-12)
        assert got.extent == pytest.approx(extent, rel=1e-15)
    assert trapped > 0  # the patterns do tell front from trapped menisci
