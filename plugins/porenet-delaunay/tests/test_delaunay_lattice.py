"""The network ``delaunay.random`` builds: the hard-core points, the triangulation against
scipy's plain one, the cells against a slow shoelace sum, the faces, the sites and outlets,
the plan's estimate, and the refusal of a deformable solid."""

from __future__ import annotations

import math

import numpy as np
import pytest
from porenet_delaunay.config import KIND, DelaunayLatticeConfig
from porenet_delaunay.model import DelaunayLattice, tessellate
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import Delaunay, Voronoi, cKDTree

from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.core.plan import make_plan
from porenet.simulation import Simulation


def lattice(n_pores: int = 300, seed: int = 1, **fields) -> DelaunayLattice:
    config = DelaunayLatticeConfig(n_pores=n_pores, disorder=0.3, **fields)
    return DelaunayLattice(config, np.random.default_rng(seed))


def edges(simplices: np.ndarray) -> set[tuple[int, int]]:
    pairs = np.concatenate([simplices[:, [0, 1]], simplices[:, [1, 2]], simplices[:, [0, 2]]])
    return set(map(tuple, np.sort(pairs, axis=1).tolist()))


@pytest.mark.parametrize("min_distance", [0.0, 1.0, 1.2])
def test_points_fill_the_square_no_two_closer_than_min_distance(min_distance):
    lat = lattice(min_distance=min_distance)
    xy, side = lat.pore_coords, 2 * math.sqrt(300)
    assert xy.shape == (300, 2) and np.all((xy >= 0) & (xy <= side))
    assert len(cKDTree(xy).query_pairs(min_distance * (1 - 1e-12))) == 0
    assert lat.throat_lengths.min() >= min_distance


def test_throats_are_the_triangulation_without_its_hull_slivers():
    """Every throat is an edge of scipy's Delaunay triangulation of the points; the edges
    left out join two boundary pores (the long, thin triangles along the hull)."""
    lat = lattice()
    plain = edges(Delaunay(lat.pore_coords).simplices)
    throats = set(map(tuple, lat.throat_pores.tolist()))
    assert throats <= plain
    left_out = np.array(sorted(plain - throats))
    assert len(left_out) > 0 and lat.boundary_pores[left_out].all()
    tp = lat.throat_pores
    assert np.all(tp[:, 0] < tp[:, 1])
    assert np.array_equal(tp, tp[np.lexsort((tp[:, 1], tp[:, 0]))])


def test_a_triangulated_square_euler_and_connected():
    """A triangulation of N points whose outer boundary holds b of them has 3N - 3 - b edges;
    the network is one cluster (the cells tile a convex square)."""
    lat = lattice(n_pores=1000)
    n, tp = lat.n_pores, lat.throat_pores
    assert lat.n_throats == 3 * n - 3 - int(lat.boundary_pores.sum())
    graph = coo_matrix((np.ones(len(tp)), (tp[:, 0], tp[:, 1])), shape=(n, n))
    assert connected_components(graph, directed=False)[0] == 1


def test_volumes_are_a_quarter_of_each_cell_by_a_slow_shoelace_sum():
    """Pore volumes against the areas of the bounded Voronoi cells computed the obvious way:
    every point mirrored across every side, each cell's corners sorted by angle, the shoelace
    formula; they add up to N (the cells tile the square of side 2 sqrt(N))."""
    lat = lattice(n_pores=200)
    xy, side = lat.pore_coords, 2 * math.sqrt(200)
    images = [xy]
    for axis in (0, 1):
        for edge in (0.0, side):
            image = xy.copy()
            image[:, axis] = 2 * edge - image[:, axis]
            images.append(image)
    vor = Voronoi(np.concatenate(images))
    areas = []
    for i in range(len(xy)):
        corners = vor.vertices[vor.regions[vor.point_region[i]]]
        angle = np.arctan2(*(corners - xy[i])[:, ::-1].T)
        x, y = corners[np.argsort(angle)].T
        areas.append(0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))
    np.testing.assert_allclose(lat.pore_volumes, np.array(areas) / 4, rtol=1e-10)
    assert lat.pore_volumes.sum() == pytest.approx(200, rel=1e-12)


def test_mirroring_a_band_gives_the_network_of_mirroring_everything():
    lat = lattice(n_pores=500, seed=3)
    side = 2 * math.sqrt(500)
    whole = tessellate(np.asarray(lat.pore_coords), side, band=side)
    assert np.array_equal(whole.throat_pores, lat.throat_pores)
    np.testing.assert_allclose(whole.cell_areas / 4, lat.pore_volumes, rtol=1e-12)
    assert all(np.array_equal(whole.faces[k], lat.labels[k]) for k in whole.faces)


def test_faces_are_the_pores_whose_cells_touch_each_side():
    lat = lattice()
    xy, side = lat.pore_coords, 2 * math.sqrt(300)
    for face, (axis, edge) in {"x-": (0, 0), "x+": (0, side), "y-": (1, 0),
                               "y+": (1, side)}.items():  # fmt: skip
        mask = lat.sites(face)
        assert np.array_equal(mask, lat.labels[face])
        distance = np.abs(xy[:, axis] - edge)
        # the pore nearest the side is on it; a face pore is within a few spacings of it
        assert mask[np.argmin(distance)] and distance[mask].max() < 6
        assert 0.6 * math.sqrt(300) < mask.sum() < 1.4 * math.sqrt(300)
    assert np.array_equal(lat.sites("left-edge"), lat.sites("x-"))
    faces = np.logical_or.reduce([lat.labels[f] for f in ("x-", "x+", "y-", "y+")])
    assert np.array_equal(lat.boundary_pores, faces)
    with pytest.raises(ValueError, match="2-D"):
        lat.sites("z-")


def test_sites_and_outlets():
    lat = lattice()
    centre = lat.inlet_pores("centre")
    assert len(centre) == 1
    xy = lat.pore_coords
    assert centre[0] == np.argmin(np.linalg.norm(xy - xy.mean(axis=0), axis=1))
    assert np.array_equal(lat.outlet_mask("centre"), lat.boundary_pores)
    assert np.array_equal(lat.outlet_mask("x-"), lat.sites("x+"))
    assert np.array_equal(lat.outlet_mask("y+"), lat.sites("y-"))


def test_apertures_uniform_and_the_same_network_for_the_same_seed():
    a, b, c = lattice(n_pores=2000), lattice(n_pores=2000), lattice(n_pores=2000, seed=2)
    r = a.initial_apertures
    assert r.min() >= 0.7 and r.max() <= 1.3 and a.mean_aperture == 1.0
    assert abs(r.mean() - 1) < 4 * 0.6 / math.sqrt(12 * len(r))  # 4 standard errors
    for name in ("pore_coords", "throat_pores", "initial_apertures", "pore_volumes"):
        assert np.array_equal(getattr(a, name), getattr(b, name))
    assert not np.array_equal(a.pore_coords, c.pore_coords)


def test_the_plan_sizes_and_costs_the_network(reg):
    scene = load_scene(
        {"lattice": {"kind": KIND, "n_pores": 4000, "disorder": 0.3}, "fluid": {}}, registry=reg
    )
    extent = scene.lattice.extent()
    built = lattice(n_pores=4000)
    assert extent.pores == 4000 and extent.side == 63
    assert abs(extent.throats - built.n_throats) < 0.005 * built.n_throats
    assert abs(extent.outlet_links["centre"] - built.boundary_pores.sum()) < 0.05 * 240
    plan = make_plan(scene, reg)
    assert plan.cost is not None and plan.cost.drained is not None
    assert "lattice.n_pores" in scene.lattice.extent().size_field


def test_injection_sites_it_lacks_are_refused_when_validated(reg):
    with pytest.raises(ConfigError, match=r"injection\.at"):
        load_scene(
            {"lattice": {"kind": KIND, "n_pores": 100, "disorder": 0.3}, "fluid": {},
             "injection": {"at": "z-"}},
            registry=reg,
        )  # fmt: skip


def test_a_deformable_solid_is_refused_naming_the_lattice(reg):
    """The network describes no particles: a solid that needs them is a ConfigError that
    names the lattice, when the Simulation is built (the plan cannot know)."""
    scene = {"lattice": {"kind": KIND, "n_pores": 100, "disorder": 0.3}, "fluid": {},
             "solid": {"kind": "hertz", "fracturing_number": 1.0}}  # fmt: skip
    plan = make_plan(load_scene(scene, registry=reg), reg)
    with pytest.raises(ConfigError, match=r"'delaunay\.random' lattice describes no solid"):
        Simulation(plan, reg)
