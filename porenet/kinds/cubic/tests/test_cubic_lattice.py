"""The built-in ``cubic`` lattice (docs/lattices.md, "The cubic lattice").

With ``nz = 1`` and ``nx = ny`` it must be the square lattice: the same pores, throats,
apertures and particles, and every run the same to the bit. In 3-D: the right topology, the
sites at faces and centre, and clear errors.
"""

from __future__ import annotations

import numpy as np
import pytest

from porenet.core.errors import ConfigError
from porenet.kinds.cubic.config import CubicLatticeConfig
from porenet.kinds.cubic.model import CubicLattice
from porenet.kinds.square.config import SquareLatticeConfig
from porenet.kinds.square.model import SquareLattice
from porenet.simulation import Simulation


def lattices(n: int = 7, seed: int = 4) -> tuple[SquareLattice, CubicLattice]:
    square = SquareLattice(SquareLatticeConfig(n=n, disorder=0.4), np.random.default_rng(seed))
    cubic = CubicLattice(
        CubicLatticeConfig(shape=(n, n, 1), disorder=0.4), np.random.default_rng(seed)
    )
    return square, cubic


def test_one_layer_is_the_square_lattice():
    square, cubic = lattices()
    assert cubic.dimension == square.dimension == 2
    names = ("throat_pores", "pore_coords", "initial_apertures", "boundary_pores",
             "pore_volumes", "particle_coords", "spring_particles", "fixed_particles")  # fmt: skip
    for name in names:
        np.testing.assert_array_equal(getattr(cubic, name), getattr(square, name), err_msg=name)
    for a, b in zip(cubic.adjacency, square.adjacency, strict=True):
        np.testing.assert_array_equal(a, b)
    for at in ("centre", "left-edge", "x+", "y-"):
        np.testing.assert_array_equal(cubic.inlet_pores(at), square.inlet_pores(at))
        np.testing.assert_array_equal(cubic.outlet_mask(at), square.outlet_mask(at))
        np.testing.assert_array_equal(cubic.outlet_links(at), square.outlet_links(at))
    assert cubic.grid_shape == square.grid_shape and cubic.canonical_grid
    assert cubic.throat_factors == square.throat_factors
    assert cubic.mean_aperture == square.mean_aperture
    np.testing.assert_array_equal(cubic.throat_lengths, square.throat_lengths)


def _run(lattice: dict, fluid: dict, **sections) -> dict:
    sc = {"seed": 2, "lattice": lattice, "fluid": fluid, "classifier": {"kind": "none"}}
    data = Simulation.from_scene(sc | sections).run().data
    out = {name: getattr(data, name) for name in
           ("order", "throat", "drained", "trapped", "invasion_pressure", "invasion_time",
            "pressure", "final_apertures")}  # fmt: skip
    out["timeseries"] = data.timeseries
    return out


VISCOUS = {"kind": "viscous", "capillary_number": 1e-3}
IP = {"kind": "invasion-percolation"}
HERTZ = {"solid": {"kind": "hertz", "fracturing_number": 1.0}}


@pytest.mark.parametrize(
    ("fluid", "sections"),
    [
        pytest.param(IP, {}, id="ip-trapping"),
        pytest.param(IP | {"trapping": False}, {"stop": {"at": "complete"}}, id="ip-complete"),
        pytest.param(IP, {"injection": {"at": "left-edge"}}, id="ip-left-edge"),
        pytest.param(VISCOUS | {"integrator": "explicit"}, {}, id="explicit"),
        pytest.param(VISCOUS | {"integrator": "rkc"}, {}, id="rkc"),
        pytest.param(VISCOUS | {"integrator": "implicit"}, {}, id="implicit"),
        pytest.param(IP, HERTZ, id="ip-hertz"),
    ],
)
def test_one_layer_runs_are_the_square_lattice_runs_to_the_bit(fluid, sections):
    square = _run({"kind": "square", "n": 10, "disorder": 0.5}, fluid, **sections)
    cubic = _run({"kind": "cubic", "shape": [10, 10, 1], "disorder": 0.5}, fluid, **sections)
    assert len(square["order"]) > 1
    for name, value in square.items():
        if name == "timeseries":
            assert value.keys() == cubic[name].keys()
            for key in value:
                np.testing.assert_array_equal(value[key], cubic[name][key], err_msg=key)
        elif value is None:
            assert cubic[name] is None, name
        else:
            np.testing.assert_array_equal(value, cubic[name], err_msg=name)


def test_3d_topology():
    shape = (4, 3, 5)
    lat = CubicLattice(CubicLatticeConfig(shape=shape, disorder=0.3), np.random.default_rng(0))
    nx, ny, nz = shape
    assert lat.dimension == 3 and lat.n_pores == nx * ny * nz
    assert lat.n_throats == 3 * nx * ny * nz - nx * ny - ny * nz - nz * nx
    assert lat.throat_pores.shape == (lat.n_throats, 2)
    assert lat.initial_apertures.shape == (lat.n_throats,)
    xyz = lat.pore_coords
    # every throat joins two pores 2a apart along one axis
    d = xyz[lat.throat_pores[:, 1]] - xyz[lat.throat_pores[:, 0]]
    np.testing.assert_array_equal(np.sort(np.abs(d), axis=1), [[0, 0, 2]] * lat.n_throats)
    assert len({tuple(t) for t in np.sort(lat.throat_pores, axis=1)}) == lat.n_throats
    degree = np.bincount(lat.throat_pores.ravel(), minlength=lat.n_pores)
    interior = ~lat.boundary_pores
    assert np.all(degree[interior] == 6)
    assert interior.sum() == (nx - 2) * (ny - 2) * (nz - 2)
    # links to the outlet: one per face of the box a pore lies on, 2 (nx ny + ny nz + nz nx)
    assert lat.outlet_links("centre").sum() == 2 * (nx * ny + ny * nz + nz * nx)
    assert lat.grid_shape is None and not lat.canonical_grid


def test_3d_sites():
    lat = CubicLattice(CubicLatticeConfig(shape=(5, 6, 7), disorder=0.3), np.random.default_rng(0))
    xyz = lat.pore_coords
    (centre,) = lat.inlet_pores("centre")
    np.testing.assert_array_equal(xyz[centre], [5.0, 7.0, 7.0])  # (nx//2, ny//2, nz//2)
    bottom = lat.inlet_pores("z-")
    assert len(bottom) == 5 * 6 and np.all(xyz[bottom, 2] == 1.0)
    top = lat.outlet_mask("z-")
    assert top.sum() == 30 and np.all(xyz[top, 2] == 13.0)
    np.testing.assert_array_equal(lat.inlet_pores([3, 1]), [1, 3])
    with pytest.raises(ValueError, match=r"unknown site 'pore\.inlet'"):
        lat.inlet_pores("pore.inlet")


def test_no_particles_in_3d():
    lat = CubicLattice(CubicLatticeConfig(shape=(4, 4, 4), disorder=0.3), np.random.default_rng(0))
    with pytest.raises(NotImplementedError, match="deformable solids need nz = 1"):
        _ = lat.particle_coords


@pytest.mark.parametrize(
    ("lattice", "sections", "message"),
    [
        ({"shape": [2, 5, 5]}, {}, "nx >= 3"),
        ({"shape": [5, 5]}, {}, "shape"),
        ({"shape": [5, 5, 1]}, {"injection": {"at": "z-"}}, "injection.at = 'z-': not a site"),
        ({"shape": [5, 5, 3]}, {"injection": {"at": "pore.inlet"}}, "injection.at = 'pore"),
        ({"shape": [5, 5, 3]}, {"injection": {"at": [1000]}}, "pore indices must be in"),
    ],
)
def test_bad_cubic_scenes_are_config_errors(lattice, sections, message):
    sc = {"lattice": {"kind": "cubic", "disorder": 0.3} | lattice,
          "fluid": {"kind": "invasion-percolation"}} | sections  # fmt: skip
    with pytest.raises(ConfigError, match=message):
        Simulation.from_scene(sc)


def test_apertures_file_of_the_wrong_size_names_the_count(tmp_path):
    path = tmp_path / "r.npy"
    np.save(path, np.full(10, 1e-7))
    sc = {"lattice": {"kind": "cubic", "shape": [3, 3, 2], "apertures_file": str(path)},
          "fluid": {"kind": "invasion-percolation"}}  # fmt: skip
    with pytest.raises(ConfigError, match=r"expected \(33,\) = \(nx-1\) ny nz"):
        Simulation.from_scene(sc)


def test_3d_invasion_percolation_without_trapping_drains_everything():
    sc = {"lattice": {"kind": "cubic", "shape": [6, 5, 4], "disorder": 0.5},
          "fluid": {"kind": "invasion-percolation", "trapping": False},
          "stop": {"at": "complete"}, "classifier": {"kind": "none"}}  # fmt: skip
    data = Simulation.from_scene(sc).run().data
    assert len(data.order) == 120 and np.all(data.drained)
    assert data.pore_coords.shape == (120, 3)
    # each step enters the frontier throat of least entry pressure: non-increasing pressure
    # only between record highs; here simply: every entered throat touches an earlier pore
    seen = {int(data.order[0])}
    tp = Simulation.from_scene(sc).lattice.throat_pores
    for pore, throat in zip(data.order[1:], data.throat[1:], strict=True):
        a, b = tp[throat]
        assert pore in (a, b) and ({int(a), int(b)} - {int(pore)}) <= seen
        seen.add(int(pore))
