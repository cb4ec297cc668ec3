"""Sweep files: validation with readable errors, expansion, seeds and derived keys."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from porenet.analysis.numbers import capillary_number_at
from porenet.core.errors import ConfigError
from porenet.sweep import spec as sweep_spec
from porenet.sweep.spec import DERIVED, DerivedKey, columns, expand, load_sweep, replicate_seed

ROOT = Path(__file__).resolve().parents[2]
DEMO = ROOT / "examples" / "sweeps" / "demo.toml"

BASE = """
[base]
lattice = { n = 16, disorder = 0.3 }
fluid = { kind = "invasion-percolation" }
"""


def _write(tmp_path, text, name="sweep.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_demo_expands_to_eight_validated_runs():
    sweep = load_sweep(DEMO)
    runs = expand(sweep)
    assert [r.run_id for r in runs[:3]] == ["p0000-r00", "p0000-r01", "p0001-r00"]
    assert len(runs) == 8 and {r.point for r in runs} == {0, 1, 2, 3}
    assert columns(sweep.spec) == ["lattice.disorder", "ca_star", "fluid.capillary_number"]
    for r in runs:
        lam, ca_star = r.params["lattice.disorder"], r.params["ca_star"]
        ca = capillary_number_at(ca_star, 40, lam)
        assert r.scene["fluid"]["capillary_number"] == pytest.approx(ca, rel=1e-15)
        assert r.params["fluid.capillary_number"] == r.scene["fluid"]["capillary_number"]
        assert r.scene["lattice"]["disorder"] == lam and r.scene["seed"] == r.seed
    # grid order: the last axis varies fastest
    assert [(r.params["lattice.disorder"], r.params["ca_star"]) for r in runs[::2]] == [
        (0.2, 0.1),
        (0.2, 10.0),
        (0.6, 0.1),
        (0.6, 10.0),
    ]


def test_common_random_numbers_same_seeds_at_every_point():
    runs = expand(load_sweep(DEMO))
    seeds = {r.point: [s.seed for s in runs if s.point == r.point] for r in runs}
    assert all(v == seeds[0] for v in seeds.values())
    expected = [int(np.random.SeedSequence([0, r]).generate_state(1)[0]) for r in range(2)]
    assert seeds[0] == expected == [replicate_seed(0, 0), replicate_seed(0, 1)]
    assert replicate_seed(1, 0) != replicate_seed(0, 0)


def test_zip_mode_ranges_and_base_file(tmp_path):
    (tmp_path / "scenes").mkdir()
    (tmp_path / "scenes" / "ip.toml").write_text(
        'seed = 99\n[lattice]\nn = 16\ndisorder = 0.3\n[fluid]\nkind = "invasion-percolation"\n'
    )
    path = _write(
        tmp_path,
        """
base = "scenes/ip.toml"
mode = "zip"
root_seed = 5
[[axes]]
key = "lattice.disorder"
range = { start = 0.1, stop = 0.5, num = 3 }
[[axes]]
key = "lattice.n"
values = [16, 18, 20]
[[axes]]
key = "lattice.pore_size"
range = { start = 1e-7, stop = 1e-5, num = 3, scale = "log" }
""",
    )
    runs = expand(load_sweep(path))
    assert [r.scene["lattice"]["n"] for r in runs] == [16, 18, 20]
    assert [r.params["lattice.disorder"] for r in runs] == pytest.approx([0.1, 0.3, 0.5])
    assert [r.params["lattice.pore_size"] for r in runs] == pytest.approx([1e-7, 1e-6, 1e-5])
    assert runs[-1].params["lattice.pore_size"] == 1e-5  # log range endpoints exact
    assert {r.seed for r in runs} == {replicate_seed(5, 0)}  # the base's seed is replaced


def test_no_axes_is_one_point(tmp_path):
    runs = expand(load_sweep(_write(tmp_path, "replicates = 3\n" + BASE)))
    assert [r.run_id for r in runs] == ["p0000-r00", "p0000-r01", "p0000-r02"]
    assert len({r.seed for r in runs}) == 3


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("replicates = 0\n" + BASE, "replicates = 0: Input should be greater than or equal to 1"),
        ('mode = "grd"\n' + BASE, "mode = 'grd': Input should be 'grid' or 'zip'"),
        ("bse = 1\n" + BASE, "bse: unknown field; did you mean 'base'?"),
        ("name = 'x'\n", "base: required field is missing"),
        ("base = 3\n", "base = 3: must be a scene file (a string) or a [base] table"),
        (
            BASE + '[[axes]]\nkey = "lattice.n"\nvales = [1]\n',
            "axes[0].vales: unknown field; did you mean 'values'?",
        ),
        (
            BASE + '[[axes]]\nkey = "lattice.n"\nvalues = [1]\nrange = {start=1, stop=2, num=2}\n',
            "axes[0]: give exactly one of 'values' and 'range'",
        ),
        (BASE + '[[axes]]\nkey = "lattice.n"\nvalues = []\n', "axes[0]: 'values' is empty"),
        (
            BASE + '[[axes]]\nkey = "lattice.disorder"\n'
            'range = { start = 0, stop = 1, num = 3, scale = "log" }\n',
            "axes[0].range: a log range needs start > 0",
        ),
        (
            BASE + '[[axes]]\nkey = "lattice.n"\nrange = { start = 1, stop = 2, num = 0 }\n',
            "axes[0].range.num = 0",
        ),
        (BASE + '[[axes]]\nkey = "seed"\nvalues = [1]\n', "axes[0].key = 'seed': seeds are not"),
        (BASE + '[[axes]]\nkey = "lattice..n"\nvalues = [1]\n', "axes[0].key = 'lattice..n'"),
        (
            'mode = "zip"\n' + BASE + '[[axes]]\nkey = "lattice.n"\nvalues = [16, 18]\n'
            '[[axes]]\nkey = "lattice.disorder"\nvalues = [0.1]\n',
            "mode 'zip' needs axes of equal length (got lattice.n: 2, lattice.disorder: 1)",
        ),
        (
            BASE + '[[axes]]\nkey = "lattice.n"\nvalues = [16]\n'
            '[[axes]]\nkey = "lattice.n"\nvalues = [18]\n',
            "key 'lattice.n' is swept by more than one axis",
        ),
        (
            BASE + '[[axes]]\nkey = "ca_star"\nvalues = [1]\n'
            '[[axes]]\nkey = "fluid.capillary_number"\nvalues = [1e-3]\n',
            "axes[0] 'ca_star' sets 'fluid.capillary_number', which axes[1] also sweeps",
        ),
        ("base = 'absent.toml'\n", "base = 'absent.toml': no such scene file"),
    ],
)
def test_bad_sweep_files_name_the_file_and_the_field(tmp_path, text, expected):
    path = _write(tmp_path, text)
    with pytest.raises(ConfigError) as info:
        load_sweep(path)
    message = str(info.value)
    assert expected in message and str(path) in message


def test_not_toml_and_missing_file(tmp_path):
    with pytest.raises(ConfigError, match="no such file"):
        load_sweep(tmp_path / "absent.toml")
    with pytest.raises(ConfigError, match="not valid TOML"):
        load_sweep(_write(tmp_path, "base = [\n"))


def test_an_invalid_point_names_the_sweep_the_point_and_the_scene_message(tmp_path):
    path = _write(tmp_path, BASE + '[[axes]]\nkey = "lattice.disorder"\nvalues = [0.1, 1.5]\n')
    sweep = load_sweep(path)
    with pytest.raises(ConfigError) as info:
        expand(sweep)
    message = str(info.value)
    assert f"{path}: point 1 (lattice.disorder = 1.5) is not a valid scene" in message
    assert "lattice.disorder = 1.5" in message.splitlines()[-1]


def test_unknown_scene_key_is_refused_with_a_suggestion(tmp_path):
    path = _write(tmp_path, BASE + '[[axes]]\nkey = "lattice.dissorder"\nvalues = [0.1]\n')
    with pytest.raises(ConfigError, match=r"lattice\.dissorder: unknown field; did you mean"):
        expand(load_sweep(path))


def test_ca_star_fills_a_viscous_fluid_and_refuses_invasion_percolation(tmp_path):
    viscous = """
[base]
lattice = { n = 20, disorder = 0.4 }
fluid = { kind = "viscous" }   # no Ca: the derived axis gives it
[[axes]]
key = "ca_star"
values = [0.5, 5]
"""
    runs = expand(load_sweep(_write(tmp_path, viscous)))
    assert [r.scene["fluid"]["capillary_number"] for r in runs] == [
        capillary_number_at(0.5, 20, 0.4),
        capillary_number_at(5, 20, 0.4),
    ]
    ip = BASE + '[[axes]]\nkey = "ca_star"\nvalues = [1]\n'
    with pytest.raises(ConfigError, match=r"fluid\.capillary_number: unknown field"):
        expand(load_sweep(_write(tmp_path, ip, "ip.toml")))
    negative = viscous.replace("[0.5, 5]", "[-1]")
    with pytest.raises(ConfigError, match="ca_star = -1: must be a number > 0"):
        expand(load_sweep(_write(tmp_path, negative, "neg.toml")))


def test_ca_star_uses_the_points_own_lattice_after_the_other_axes(tmp_path):
    text = """
[base]
lattice = { disorder = 0.4 }   # n from the axis below (after it), default otherwise
fluid = { kind = "viscous" }
[[axes]]
key = "ca_star"
values = [1]
[[axes]]
key = "lattice.n"
values = [16, 32]
"""
    runs = expand(load_sweep(_write(tmp_path, text)))
    assert [r.scene["fluid"]["capillary_number"] for r in runs] == [
        capillary_number_at(1, 16, 0.4),
        capillary_number_at(1, 32, 0.4),
    ]


def test_the_derived_registry_takes_new_keys(tmp_path, monkeypatch):
    def half_n(scene, value):
        return {**scene, "lattice": {**scene["lattice"], "n": int(value) // 2}}

    monkeypatch.setitem(DERIVED, "double_n", DerivedKey(half_n, ("lattice.n",), "test"))
    path = _write(tmp_path, BASE + '[[axes]]\nkey = "double_n"\nvalues = [32, 40]\n')
    sweep = load_sweep(path)
    assert sweep_spec.columns(sweep.spec) == ["double_n", "lattice.n"]
    assert [r.params for r in expand(sweep)] == [
        {"double_n": 32, "lattice.n": 16},
        {"double_n": 40, "lattice.n": 20},
    ]


def test_validated_scene_is_a_fixed_point():
    """What a worker's run file records equals the scene the sweep intends (resume)."""
    from porenet.config.loading import load_scene

    for run in expand(load_sweep(DEMO)):
        assert load_scene(run.scene).model_dump(mode="json") == run.scene
