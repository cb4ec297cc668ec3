"""The ``network`` lattice (docs/lattices.md, "Imported networks (kind `network`)"): both
readers, the mapping of the files' fields onto the lattice contract, labels and faces as
injection sites and outlets, and clear errors naming the file and the key or line."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from network_helpers import EXAMPLE, example_dict, jittered_cubic, write_npz, write_statoil

from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.kernels.text import parse_numbers
from porenet.kinds.network.config import NetworkLatticeConfig
from porenet.kinds.network.files import read_network
from porenet.kinds.network.model import NetworkLattice, shape_factors
from porenet.simulation import Simulation

A = 8e-6  # the length unit a of these tests (m)


def lattice(file: Path, **config) -> NetworkLattice:
    cfg = NetworkLatticeConfig(file=file, pore_size=A, **config)
    return NetworkLattice(cfg, np.random.default_rng(0))


def scene(file: Path, at="pore.left", fluid=None, **lattice) -> dict:
    return {
        "lattice": {"kind": "network", "file": str(file), "pore_size": A, **lattice},
        "injection": {"at": at},
        "fluid": fluid or {"kind": "invasion-percolation"},
        "classifier": {"kind": "none"},
    }


def run(sc: dict, **sections):
    return Simulation.from_scene(sc | sections).run().data


# -- reading and mapping --------------------------------------------------------------------


def test_example_network_maps_onto_the_contract():
    arrays = example_dict()
    lat = lattice(EXAMPLE)
    n, m = len(arrays["pore.coords"]), len(arrays["throat.conns"])
    assert lat.n_pores == n and lat.n_throats == m and lat.dimension == 2  # every z is 0
    np.testing.assert_array_equal(lat.pore_coords, arrays["pore.coords"][:, :2] / A)
    np.testing.assert_array_equal(lat.throat_pores, arrays["throat.conns"])
    np.testing.assert_array_equal(
        lat.initial_apertures, arrays["throat.inscribed_diameter"] / 2 / A
    )
    np.testing.assert_array_equal(lat.throat_lengths, arrays["throat.total_length"] / A)
    np.testing.assert_array_equal(lat.pore_volumes, arrays["pore.volume"] / A**3)
    assert set(lat.labels) == {"pore.left", "pore.right", "pore.front", "pore.back",
                               "pore.surface"}  # fmt: skip
    np.testing.assert_array_equal(lat.boundary_pores, arrays["pore.surface"])
    g = arrays["throat.shape_factor"]
    c_area, c_perm = lat.throat_factors
    np.testing.assert_array_equal(c_area, 1 / (4 * g))
    assert set(np.unique(c_perm)) == {0.6 / 4, 0.5623 / 4, 0.5 / 4}  # all three shapes
    np.testing.assert_array_equal(lat.entry_pressures(lat.initial_apertures),
                                  2 / lat.initial_apertures)  # fmt: skip
    assert lat.grid_shape is None and not lat.canonical_grid
    with pytest.raises(NotImplementedError, match="deformable solids need the square lattice"):
        _ = lat.particle_coords


def test_throat_length_settings():
    arrays = example_dict()
    own = lattice(EXAMPLE, throat_length="throat").throat_lengths
    np.testing.assert_array_equal(own, arrays["throat.length"] / A)
    centres = lattice(EXAMPLE, throat_length="centres").throat_lengths
    xy, tp = arrays["pore.coords"], arrays["throat.conns"]
    np.testing.assert_allclose(
        centres, np.linalg.norm(xy[tp[:, 1]] - xy[tp[:, 0]], axis=1) / A, rtol=1e-15
    )


@pytest.mark.parametrize(
    ("g", "area", "k_g"),
    [
        (1 / (4 * math.pi), math.pi, 0.5),  # circle of radius r
        (1 / 16, 4.0, 0.5623),  # square of side 2r
        (math.sqrt(3) / 36, 3 * math.sqrt(3), 0.6),  # equilateral triangle, inscribed r
    ],
)
def test_shape_factor_gives_the_shapes_area_and_pnflow_conductance(g, area, k_g):
    c_area, c_perm = shape_factors(np.array([g]))
    np.testing.assert_allclose(c_area, area, rtol=1e-14)  # A = c_A r^2
    np.testing.assert_allclose(c_perm, k_g / 4, rtol=1e-15)
    # A k = k_G G A^2: pnflow's conductance (times viscosity and length)
    np.testing.assert_allclose(c_area * c_perm, k_g * g * c_area**2, rtol=1e-14)


def test_entry_pressure_and_cross_section_options(tmp_path):
    arrays = example_dict()
    arrays["throat.shape_factor"][:3] = [1 / (4 * math.pi), 1 / 16, math.sqrt(3) / 36]
    path = write_npz(tmp_path / "g.npz", arrays)
    lat = lattice(path, entry_pressure="shape-factor")
    r = lat.initial_apertures
    pe = lat.entry_pressures(r)
    np.testing.assert_allclose(pe[0], 2 / r[0], rtol=1e-15)  # a circle: 2 / r
    np.testing.assert_allclose(pe[1], (1 + math.sqrt(math.pi) / 2) / r[1], rtol=1e-15)
    np.testing.assert_array_equal(lat.entry_pressures(r[[2, 5]], np.array([2, 5])), pe[[2, 5]])
    assert lattice(path, cross_sections="circle").throat_factors == (math.pi, 0.125)
    del arrays["throat.shape_factor"]
    plain = lattice(write_npz(tmp_path / "plain.npz", arrays))
    assert plain.throat_factors == (math.pi, 0.125)
    with pytest.raises(ConfigError, match=r"lattice.entry_pressure = 'shape-factor': .*plain"
                       r"\.npz: no array 'throat.shape_factor'"):  # fmt: skip
        load_scene(scene(tmp_path / "plain.npz", entry_pressure="shape-factor"))


def test_throat_diameter_and_region_volume_are_the_fallbacks(tmp_path):
    arrays = example_dict()
    d = arrays.pop("throat.inscribed_diameter")
    arrays["throat.diameter"] = 2 * d
    arrays["pore.region_volume"] = arrays.pop("pore.volume")
    lat = lattice(write_npz(tmp_path / "f.npz", arrays))
    np.testing.assert_array_equal(lat.initial_apertures, d / A)
    np.testing.assert_array_equal(lat.pore_volumes, arrays["pore.region_volume"] / A**3)


# -- the Statoil reader ---------------------------------------------------------------------


@pytest.fixture(scope="module")
def statoil(tmp_path_factory):
    """The example network written in the Statoil format, inlet = pore.left, outlet =
    pore.right; link2's throat lengths are the file's throat.length."""
    net = read_network(EXAMPLE)
    own = read_network(EXAMPLE, "throat").length
    prefix = tmp_path_factory.mktemp("statoil") / "example"
    return write_statoil(prefix, net, net.labels["pore.left"], net.labels["pore.right"], own)


def test_statoil_reads_the_same_network(statoil):
    npz, dat = read_network(EXAMPLE), read_network(statoil)
    for name in ("coords", "conns", "radius", "length", "shape_factor", "volume"):
        np.testing.assert_array_equal(getattr(dat, name), getattr(npz, name), err_msg=name)
    np.testing.assert_array_equal(dat.labels["inlet"], npz.labels["pore.left"])
    np.testing.assert_array_equal(dat.labels["pore.outlet"], npz.labels["pore.right"])
    assert sorted(dat.labels) == ["inlet", "outlet", "pore.inlet", "pore.outlet"]
    own = read_network(statoil.with_name("example"), "throat").length  # by the prefix
    np.testing.assert_array_equal(own, read_network(EXAMPLE, "throat").length)


@pytest.mark.parametrize("trapping", [True, False])
def test_statoil_and_npz_give_the_same_invasion(statoil, trapping):
    fluid = {"kind": "invasion-percolation", "trapping": trapping}
    a = run(scene(EXAMPLE, "pore.left", fluid, outlet="pore.right"), stop={"at": "complete"})
    b = run(scene(statoil, "inlet", fluid, outlet="outlet"), stop={"at": "complete"})
    assert len(a.order) > 100
    np.testing.assert_array_equal(a.order, b.order)
    np.testing.assert_array_equal(a.throat, b.throat)
    np.testing.assert_array_equal(a.trapped, b.trapped)


def test_a_3d_network_in_both_formats(tmp_path):
    arrays = jittered_cubic((5, 4, 3), seed=3)
    npz = write_npz(tmp_path / "cube.npz", arrays)
    net = read_network(npz)
    dat = write_statoil(tmp_path / "cube", net, arrays["pore.left"], arrays["pore.right"])
    lat = lattice(dat)
    assert lat.dimension == 3 and lat.n_pores == 60 and lat.n_throats == 133
    np.testing.assert_array_equal(lat.pore_coords, arrays["pore.coords"] / A)
    # faces within half the median distance between joined centres (jitter 0.2 spacing)
    np.testing.assert_array_equal(lat.sites("z-"), np.arange(60) < 20)
    np.testing.assert_array_equal(lat.outlet_mask("x-"), arrays["pore.right"])
    assert lat.boundary_pores.sum() == 60 - 3 * 2 * 1  # no pore.surface in Statoil files
    fluid = {"kind": "invasion-percolation"}
    a = run(scene(npz, "pore.left", fluid, outlet="pore.right"))
    b = run(scene(dat, "inlet", fluid, outlet="outlet"))
    np.testing.assert_array_equal(a.order, b.order)


def test_parse_numbers_is_pythons_float_and_names_the_line():
    rng = np.random.default_rng(1)
    x = rng.random(5000) * 10.0 ** rng.integers(-30, 30, 5000)
    for fmt in ("%.6e", "%.7g", "%.17g", "%.3f", "%r"):
        text = "\n".join(fmt % float(v) for v in x).encode()
        np.testing.assert_array_equal(parse_numbers(text).values, [float(v) for v in text.split()])
    parsed = parse_numbers(b"3 1.5 -2e3\n\n  +4. .5 1.0D-05 nan\n")
    np.testing.assert_array_equal(parsed.counts, [3, 4])
    np.testing.assert_array_equal(parsed.lines, [1, 3])
    np.testing.assert_array_equal(parsed.values[:6], [3, 1.5, -2000, 4, 0.5, 1e-5])
    with pytest.raises(ValueError, match=r"line 2: '1\.2\.3' is not a number"):
        parse_numbers(b"1 2\n3 1.2.3\n")


# -- sites and outlets ----------------------------------------------------------------------


def test_labels_faces_and_outlets():
    arrays = example_dict()
    lat = lattice(EXAMPLE)
    left, right = arrays["pore.left"], arrays["pore.right"]
    np.testing.assert_array_equal(lat.inlet_pores("pore.left"), np.flatnonzero(left))
    # default outlet for a label: the boundary (pore.surface) less the inlets
    np.testing.assert_array_equal(lat.outlet_mask("pore.left"), arrays["pore.surface"] & ~left)
    # faces: the pores within half the median throat span of the box (here the outer columns)
    np.testing.assert_array_equal(lat.sites("x-"), left)
    np.testing.assert_array_equal(lat.outlet_mask("left-edge"), right)
    assert lat.sites("centre").sum() == 1
    assert lattice(EXAMPLE, outlet="pore.right").outlet_mask("centre").sum() == right.sum()
    assert lattice(EXAMPLE, outlet="x+").outlet_mask("pore.left").sum() == right.sum()
    wide = lattice(EXAMPLE, face_tolerance=200e-6)  # four columns of 50 µm spacing
    assert left.sum() < wide.sites("x-").sum()
    with pytest.raises(ValueError, match="needs a 3-D network"):
        lat.sites("z+")


def test_the_scene_names_labels_and_the_outlet():
    data = run(scene(EXAMPLE, "pore.left", outlet="pore.right"))
    right = example_dict()["pore.right"]
    assert data.order[0] in np.flatnonzero(example_dict()["pore.left"])
    assert right[data.order[-1]] and not right[data.order[:-1]].any()  # breakthrough


@pytest.mark.parametrize(
    ("sections", "message"),
    [
        ({"injection": {"at": "pore.lefft"}}, "injection.at = 'pore.lefft': not a site of the"),
        ({"injection": {"at": "z-"}}, "injection.at = 'z-': not a site"),
        ({"lattice": {"outlet": "pore.rigth"}}, "lattice.outlet = 'pore.rigth': not an outlet"),
        ({"lattice": {"outlet": "centre"}}, "lattice.outlet = 'centre': not an outlet"),
        ({"lattice": {"throat_length": "throat", "file": "missing.npz"}}, "file not found"),
        ({"lattice": {"pore_size": None}}, "lattice.pore_size: required field is missing"),
    ],
)
def test_validate_refuses_unknown_sites_and_outlets(sections, message):
    sc = scene(EXAMPLE)
    for key, table in sections.items():
        sc[key] = {k: v for k, v in {**sc[key], **table}.items() if v is not None}
    with pytest.raises(ConfigError, match=message) as err:
        load_scene(sc)
    if "pore.lefft" in message:  # the labels of the file are listed
        assert "pore.left, pore.right, pore.surface" in str(err.value)


def test_isolated_pores_are_kept_and_never_drain(tmp_path):
    arrays = example_dict()
    conns = arrays["throat.conns"]
    lonely = 210  # cut every throat of one interior pore, and of a pair of neighbours
    t = np.flatnonzero((conns == lonely).any(axis=1))
    pair = conns[np.flatnonzero((conns == 90).any(axis=1))[0]]
    keep = ~np.isin(np.arange(len(conns)), t)
    keep &= ~(np.isin(conns, pair).any(axis=1) & ~(np.sort(conns, axis=1) == np.sort(pair)).all(1))
    for key in ("throat.conns", "throat.inscribed_diameter", "throat.total_length",
                "throat.length", "throat.shape_factor"):  # fmt: skip
        arrays[key] = arrays[key][keep]
    path = write_npz(tmp_path / "cut.npz", arrays)
    fluid = {"kind": "invasion-percolation", "trapping": False}
    data = run(scene(path, "pore.left", fluid), stop={"at": "complete"})
    assert data.n_pores == 400 and not data.drained[[lonely, *pair]].any()
    assert data.drained.sum() == 400 - 3


def test_validation_imports_no_numerics():
    code = (
        "import json, sys; from porenet.cli.main import main; "
        f"status = main(['validate', {str(EXAMPLE.parents[1] / 'scenes' / 'network.toml')!r}]); "
        "print(json.dumps([status, sorted(m for m in sys.modules if m.startswith(('numba', "
        "'scipy', 'porenet.kernels', 'porenet.kinds.network.model', 'h5py')))]))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    status, heavy = json.loads(out.stdout.strip().splitlines()[-1])
    assert status == 0
    assert heavy == []  # the network's config and file reader are light; its model is not


# -- bad files ------------------------------------------------------------------------------


def _broken(arrays: dict, change: str) -> dict:
    arrays = dict(arrays)
    if change.startswith("-"):
        del arrays[change[1:]]
        return arrays
    key, _, how = change.partition(":")
    value = np.array(arrays[key], copy=True)
    if how == "nan":
        value[3] = np.nan
    elif how == "zero":
        value[5] = 0.0
    elif how == "loop":
        value[7] = [4, 4]
    elif how == "outside":
        value[2] = [1, 400]
    elif how == "short":
        value = value[:-1]
    elif how == "float":
        value = value.astype(float)
    elif how == "object":
        value = value.astype(object)
    arrays[key] = value
    return arrays


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ("-pore.coords", "no array 'pore.coords'"),
        (
            "-throat.inscribed_diameter",
            "no array of the throat radii: expected "
            "'throat.inscribed_diameter' or 'throat.diameter'",
        ),
        ("-pore.volume", "expected 'pore.volume' or 'pore.region_volume'"),
        (
            "throat.conns:outside",
            r"'throat.conns' names pores outside \[0, 400\) "
            r"\(first: throat 2 = \[1, 400\]\)",
        ),
        ("throat.conns:loop", "'throat.conns': 1 throat.s. join a pore to itself .first: throat 7"),
        ("throat.conns:float", "'throat.conns' is float64 .965, 2., expected integers"),
        (
            "throat.inscribed_diameter:zero",
            "'throat.inscribed_diameter' has 1 value.s. that are "
            r"not positive and finite \(first: \[5\] = 0.0\)",
        ),
        ("pore.volume:nan", r"'pore.volume' has 1 value.s. .* \(first: \[3\] = nan\)"),
        ("throat.total_length:short", r"'throat.total_length' has shape \(964,\), expected"),
        ("pore.left:short", r"label 'pore.left' has shape \(399,\), expected \(400,\)"),
        ("pore.coords:nan", r"'pore.coords' has 3 value.s. that are not finite .first: \[3, 0\]"),
        ("throat.shape_factor:zero", "'throat.shape_factor' has 1 value"),
        ("pore.volume:object", "'pore.volume' holds Python objects"),
    ],
)
def test_bad_npz_files_name_the_file_and_key(tmp_path, change, message):
    arrays = _broken(example_dict(), change)
    path = tmp_path / "bad.npz"
    if change.endswith("object"):
        np.savez(path, **arrays)  # allowed to pickle: the reader must refuse it
    else:
        write_npz(path, arrays)
    with pytest.raises(ConfigError, match=message) as err:
        Simulation.from_scene(scene(path))
    assert str(path) in str(err.value)


def test_a_missing_length_names_the_setting(tmp_path):
    arrays = example_dict()
    del arrays["throat.total_length"]
    path = write_npz(tmp_path / "nolength.npz", arrays)
    with pytest.raises(
        ConfigError,
        match=r"lattice.throat_length: .*no array "
        r"'throat.total_length'.*throat_length = 'centres'",
    ):
        load_scene(scene(path))
    assert load_scene(scene(path, throat_length="centres")).lattice.throat_length == "centres"


def _edit(path: Path, line: int, new: str | None) -> None:
    """Replace (or with None delete) 1-based ``line`` of a text file."""
    lines = path.read_text().splitlines()
    if new is None:
        del lines[line - 1]
    else:
        lines[line - 1] = new
    path.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize(
    ("suffix", "line", "new", "message"),
    [
        (
            "link1",
            -1,
            None,
            r"_link1.dat: \d+ lines of data, but its first line says \d+ "
            r"\(truncated\?\)",
        ),
        ("node2", 5, "5 1e-13 1e-5 0.05", r"_node2.dat, line 5: 4 numbers, expected 5"),
        ("link2", 3, "3 2 9 1 1 1 0 0", r"_link2.dat: throat 3 joins pores \[2, 9\], but "),
        ("node1", 1, "401 1 1 1", r"_node1.dat: 400 lines of data, but its first line says 401"),
        ("node1", 3, "2 1 1 0 1 7 0 0 9", r"_node1.dat, line 3: pore 2 has 1 throats, but "),
        ("node1", 4, "3 1 1 0 2 7 0 0 9", r"_node1.dat, line 4: 9 numbers, expected 7 \+ 2 x 2"),
        ("link1", 8, "6 3 4 1e-5 0.05 1e-4", r"_link1.dat, line 8: index 6, expected 7"),
        ("link1", 9, "8 3 500 1e-5 0.05 1e-4", r"_link1.dat, line 9: pores \[3, 500\] outside"),
        ("node2", 2, "2 1e-13 1e-5 0.05 x", r"_node2.dat, line 2: 'x' is not a number"),
        ("node2", 7, "7 -1e-13 1e-5 0.05 0", r"_node2.dat: 'volume \(column 2\)' .*line 7"),
    ],
)
def test_bad_statoil_files_name_the_file_and_line(tmp_path, suffix, line, new, message):
    net = read_network(EXAMPLE)
    node1 = write_statoil(tmp_path / "bad", net, net.labels["pore.left"], net.labels["pore.right"])
    path = tmp_path / f"bad_{suffix}.dat"
    if line < 0:
        line = len(path.read_text().splitlines()) + 1 + line
    _edit(path, line, new)
    with pytest.raises(ConfigError, match=message):
        Simulation.from_scene(scene(node1, "inlet", outlet="outlet"))


def test_missing_statoil_files_are_named(tmp_path):
    net = read_network(EXAMPLE)
    node1 = write_statoil(tmp_path / "net", net, net.labels["pore.left"], net.labels["pore.right"])
    (tmp_path / "net_link2.dat").unlink()
    with pytest.raises(ConfigError, match=r"lattice.file = .*missing: net_link2\.dat"):
        load_scene(scene(node1, "inlet"))


# -- files written by OpenPNM and PoreSpy themselves ------------------------------------------

REFERENCE = Path(__file__).resolve().parents[4] / "tests" / "data" / "networks"


def test_an_openpnm_network_runs():
    """OpenPNM 3's Cubic with its spheres-and-cylinders geometry: throat.diameter, and
    throat.spacing (its centre-to-centre length) as the total length."""
    path = REFERENCE / "openpnm-cubic.npz"
    with np.load(path) as data:
        arrays = {key: data[key] for key in data.files}
    lat = lattice(path)
    assert lat.dimension == 2 and lat.n_pores == 48 and lat.n_throats == 82
    np.testing.assert_array_equal(lat.initial_apertures, arrays["throat.diameter"] / 2 / A)
    np.testing.assert_array_equal(lat.throat_lengths, arrays["throat.spacing"] / A)
    assert lat.throat_factors == (math.pi, 0.125)  # no shape factor: cylinders
    assert {"pore.left", "pore.right", "pore.xmin", "pore.surface"} <= set(lat.labels)
    fluid = {"kind": "viscous", "capillary_number": 1e-3}
    data = run(scene(path, "pore.left", fluid, outlet="pore.right"))
    assert data.drained[arrays["pore.right"]].any() and data.summary["volume_balance_error"] < 1e-10


def test_a_porespy_network_runs():
    """PoreSpy's snow2: float32 throat.inscribed_diameter, throat.total_length, 3-D, only the
    label pore.all; injection at a face."""
    path = REFERENCE / "porespy-snow2.npz"
    with np.load(path) as data:
        arrays = {key: data[key] for key in data.files}
    lat = lattice(path)
    assert lat.dimension == 3 and lat.labels.keys() == {"pore.all"}
    r = arrays["throat.inscribed_diameter"]
    assert r.dtype == np.float32
    np.testing.assert_array_equal(lat.initial_apertures, r.astype(np.float64) / 2 / A)
    np.testing.assert_array_equal(lat.pore_volumes, arrays["pore.volume"] / A**3)
    data = run(scene(path, "x-"), stop={"at": "complete"})
    assert data.drained.sum() > lat.sites("x-").sum()


def test_a_truncated_npz_is_named(tmp_path):
    path = tmp_path / "cut.npz"
    path.write_bytes(EXAMPLE.read_bytes()[:20_000])
    with pytest.raises(ConfigError, match=r"lattice.file = .*cut\.npz is not a readable .npz"):
        load_scene(scene(path))
