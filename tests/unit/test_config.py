"""Scene validation: every bad input is a ConfigError naming the file, field and value."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from porenet.config.loading import apply_overrides, load_scene, parse_override
from porenet.core.errors import ConfigError

GOOD = """
seed = 3
[lattice]
kind = "square"
n = 20
disorder = 0.3
[fluid]
kind = "invasion-percolation"
"""


def error_of(scene, *overrides) -> str:
    with pytest.raises(ConfigError) as info:
        load_scene(scene, list(overrides))
    return str(info.value)


def test_defaults_and_round_trip(write_scene):
    scene = load_scene(write_scene(GOOD))
    assert scene.seed == 3 and scene.lattice.n == 20
    assert scene.solid.kind == "rigid" and scene.stop.at == "breakthrough"
    assert scene.fluid.trapping is True and scene.fluid.interfacial_tension == 0.07
    assert scene.injection.at == "centre"
    again = load_scene(scene.model_dump(mode="json"))
    assert again == scene


def test_kind_may_be_omitted(scene_dict):
    del scene_dict["lattice"]["kind"], scene_dict["fluid"]["kind"], scene_dict["solid"]
    scene = load_scene(scene_dict)
    assert scene.lattice.kind == "square" and scene.fluid.kind == "invasion-percolation"


def test_typo_in_field_name_suggests_the_right_one(write_scene):
    path = write_scene(GOOD.replace("disorder", "dissorder"))
    msg = error_of(path)
    assert str(path) in msg and "lattice.dissorder" in msg and "did you mean 'disorder'" in msg


def test_typo_in_top_level_field(write_scene):
    msg = error_of(write_scene("sead = 1\n" + GOOD))
    assert "sead: unknown field" in msg and "'seed'" in msg


@pytest.mark.parametrize(
    ("override", "field", "shown"),
    [
        ("lattice.disorder=-0.1", "lattice.disorder", "-0.1"),
        ("lattice.disorder=1.0", "lattice.disorder", "1.0"),
        ("lattice.n=2", "lattice.n", "2"),
        ("lattice.pore_size=0", "lattice.pore_size", "0"),
        ("fluid.interfacial_tension=-1", "fluid.interfacial_tension", "-1"),
        ("stop.at='never'", "stop.at", "'never'"),
        ("stop.max_drained=0", "stop.max_drained", "0"),
        ("seed=-4", "seed", "-4"),
        ("injection.at='top'", "injection.at", "'top'"),
    ],
)
def test_bad_values_name_field_and_value(write_scene, override, field, shown):
    path = write_scene(GOOD)
    msg = error_of(path, override)
    assert f"{path}: {field} = {shown}" in msg


def test_unknown_kind_lists_registered_kinds(write_scene):
    msg = error_of(write_scene(GOOD.replace('"square"', '"sqaure"')))
    assert "lattice.kind = 'sqaure'" in msg and "did you mean 'square'" in msg


def test_missing_file_and_bad_toml(tmp_path, write_scene):
    assert "no such file" in error_of(tmp_path / "absent.toml")
    assert "not valid TOML" in error_of(write_scene("x = [\n"))


def test_disorder_required_without_file(write_scene):
    msg = error_of(write_scene(GOOD.replace("disorder = 0.3\n", "")))
    assert "'disorder' is required" in msg


def test_apertures_file_relative_to_scene(tmp_path, write_scene):
    n = 6
    np.savez(tmp_path / "ap.npz", apertures=np.full(2 * n * (n - 1), 1e-7))
    text = f'[lattice]\nn = {n}\napertures_file = "ap.npz"\n[fluid]\n'
    scene = load_scene(write_scene(text))
    assert scene.lattice.apertures_file == (tmp_path / "ap.npz").resolve()


@pytest.mark.parametrize(
    ("content", "expected"),
    [
        (dict(apertures=np.ones(7)), "has shape (7,), expected (60,)"),
        (dict(apertures=-np.ones(60)), "not positive and finite"),
        (dict(apertures=np.r_[np.ones(59), np.nan]), "not positive and finite"),
        (dict(radii=np.ones(60)), "no array named 'apertures'"),
    ],
)
def test_bad_apertures_file(tmp_path, write_scene, content, expected):
    np.savez(tmp_path / "ap.npz", **content)
    msg = error_of(write_scene('[lattice]\nn = 6\napertures_file = "ap.npz"\n[fluid]\n'))
    assert expected in msg and "ap.npz" in msg


def test_missing_apertures_file(write_scene):
    msg = error_of(write_scene('[lattice]\nn = 6\napertures_file = "gone.npz"\n[fluid]\n'))
    assert "lattice.apertures_file = 'gone.npz': file not found" in msg


def test_overrides_are_validated_like_the_file(write_scene):
    scene = load_scene(write_scene(GOOD), ["lattice.n=12", "stop.at='complete'", "name=run1"])
    assert scene.lattice.n == 12 and scene.stop.at == "complete" and scene.name == "run1"
    assert "lattice.n = 'abc'" in error_of(write_scene(GOOD), "lattice.n=abc")
    assert "expected KEY=VALUE" in error_of(write_scene(GOOD), "lattice.n")


def test_configs_are_frozen(write_scene):
    scene = load_scene(write_scene(GOOD))
    with pytest.raises(Exception):  # noqa: B017 - pydantic's frozen error
        scene.lattice.n = 5  # type: ignore[misc]


@settings(max_examples=50, deadline=None)
@given(
    n=st.integers(-5, 60),
    disorder=st.one_of(st.floats(-1, 2), st.just(float("nan")), st.just(float("inf"))),
    trapping=st.sampled_from([True, False, "x", 3]),
)
def test_any_input_validates_or_raises_config_error(n, disorder, trapping):
    data = {
        "lattice": {"n": n, "disorder": disorder},
        "fluid": {"trapping": trapping},
    }
    try:
        scene = load_scene(data)
    except ConfigError as exc:
        assert "invalid scene" in str(exc)
    else:
        assert scene.lattice.n >= 3 and 0 < scene.lattice.disorder < 1


def test_parse_override_types():
    assert parse_override("a.b=3") == (["a", "b"], 3)
    assert parse_override("a=0.5") == (["a"], 0.5)
    assert parse_override("a=true") == (["a"], True)
    assert parse_override("a=plain") == (["a"], "plain")
    assert apply_overrides({"a": {"b": 1}}, ["a.c=2"]) == {"a": {"b": 1, "c": 2}}


def test_an_empty_override_restores_the_default():
    data = {"fluid": {"kind": "viscous", "capillary_number": 1e-3}}
    out = apply_overrides(
        data,
        ["fluid.capillary_number=", "fluid.control=pressure", "fluid.injection_pressure=2e6"],
    )
    assert "capillary_number" not in out["fluid"] and data["fluid"]["capillary_number"] == 1e-3
    scene = load_scene({"lattice": {"n": 10, "disorder": 0.3}} | out)
    assert scene.fluid.capillary_number is None and scene.fluid.control == "pressure"
    assert apply_overrides({"a": 1}, ["b.c="]) == {"a": 1, "b": {}}  # nothing to remove


#: (section, kind, field) of the float fields that take a list of floats.
LIST_FIELDS: set[tuple[str, str, str]] = set()


def _float_fields() -> list[tuple[str, str, str]]:
    """(section, kind, field) of every float field of the built-in kinds, and the scene's;
    those that take a list are also in :data:`LIST_FIELDS`."""
    import typing

    from porenet.config.scene import StopConfig
    from porenet.hooks import get_registry

    def floats(section: str, kind: str, model) -> list[tuple[str, str, str]]:
        names = []
        for name, info in model.model_fields.items():
            args = typing.get_args(info.annotation) or (info.annotation,)
            flat = [a for arg in args for a in (typing.get_args(arg) or (arg,))]
            if float in flat:
                names.append((section, kind, name))
                if list in {typing.get_origin(a) for a in (info.annotation, *args)}:
                    LIST_FIELDS.add(names[-1])
        return names

    found = floats("stop", "-", StopConfig)
    for entry in get_registry():
        section = {"observer": "observers"}.get(entry.family, entry.family)
        if entry.package == "porenet" and entry.config is not None:
            found += floats(section, entry.kind, entry.config)
    return found


#: Every float field with nan, inf and -inf; not pressure_step = inf, its "no limit" (None).
NON_FINITE = [
    (*where, value)
    for where in _float_fields()
    for value in (float("nan"), float("inf"), float("-inf"))
    if not (where[2] == "pressure_step" and value == float("inf"))
]


@pytest.mark.parametrize(("section", "kind", "field", "value"), NON_FINITE, ids=str)
def test_a_non_finite_number_in_any_float_field_is_named(section, kind, field, value):
    """nan or +-inf in any float field: "<field> = nan: must be a finite number", never a
    bound's message ("less than 1"); +inf only where it stands for None (pressure_step)."""
    scene: dict = {"lattice": {"n": 8, "disorder": 0.3}, "fluid": {}}
    listed = (section, kind, field) in LIST_FIELDS
    table = {field: [value] if listed else value}
    if section == "observers":
        scene["observers"] = [{"kind": kind, **table}]
        dotted = f"observers[0].{field}"
    elif section == "stop":
        scene["stop"] = table
        dotted = f"stop.{field}"
    else:
        scene[section] = {**scene.get(section, {}), "kind": kind, **table}
        dotted = f"{section}.{field}"
    dotted += "[0]" if listed else ""
    msg = error_of(scene)
    assert f"{dotted} = {value!r}: must be a finite number" in msg


def test_pressure_step_inf_means_no_limit():
    scene = {"lattice": {"n": 8, "disorder": 0.3}, "fluid": {"kind": "viscous"}}
    loaded = load_scene(scene, ["fluid.capillary_number=1e-2", "fluid.pressure_step=inf"])
    assert loaded.fluid.pressure_step is None


@pytest.mark.parametrize(
    ("override", "expected"),
    [
        ("lattice.pore_size=1e300", "lattice.pore_size = 1e+300: must be 0 or between 1e-30"),
        ("lattice.pore_size=1e-300", "lattice.pore_size = 1e-300: must be 0 or between"),
        ("fluid.interfacial_tension=1e40", "fluid.interfacial_tension = 1e+40: must be 0 or"),
        ("seed=99999999999999999999", "seed = 99999999999999999999: must be at most"),
        ("lattice.n=1e400", "lattice.n = inf: must be a finite number"),
    ],
)
def test_numbers_out_of_range_are_named(override, expected):
    assert expected in error_of({"lattice": {"n": 8, "disorder": 0.3}, "fluid": {}}, override)


@pytest.mark.parametrize(
    ("make", "expected"),
    [
        (lambda p: p.write_text("1e-7 " * 60), "is not a NumPy file (it looks like a text file)"),
        (lambda p: p.write_bytes(b"\x80\x04\x95" + b"\0" * 20), "looks like a Python pickle"),
        (lambda p: p.write_bytes(b""), "is not a NumPy file (it is empty)"),
        (
            lambda p: np.save(p, np.array([1e-7] * 60, dtype=object), allow_pickle=True),
            "holds Python objects, not numbers",
        ),
        (lambda p: np.save(p, np.ones(60, dtype=np.int64)), "holds int64 values, not floats"),
        (lambda p: np.save(p, np.ones((60, 2))), "has shape (60, 2), expected (60,)"),
        (lambda p: np.save(p, np.r_[np.ones(59), np.inf]), "not positive and finite"),
        (lambda p: p.write_bytes(b"\x93NUMPY\x01\x00v"), "is damaged"),
    ],
    ids=["text", "pickle", "empty", "objects", "integers", "shape", "inf", "truncated"],
)
def test_an_apertures_file_that_is_not_an_array_of_apertures(tmp_path, write_scene, make, expected):
    """Named as lattice.apertures_file with the file and what is expected; numpy's advice to
    allow pickles never reaches the user."""
    make(tmp_path / "ap.npy")
    msg = error_of(write_scene('[lattice]\nn = 6\napertures_file = "ap.npy"\n[fluid]\n'))
    assert "lattice.apertures_file = 'ap.npy'" in msg and expected in msg
    assert "allow_pickle" not in msg
    if "shape" not in expected and "not positive" not in expected:
        assert "expected an .npz file with an array named 'apertures'" in msg


def test_an_npy_file_of_apertures_is_read(tmp_path, write_scene):
    np.save(tmp_path / "ap.npy", np.full(60, 1e-7))
    scene = load_scene(write_scene('[lattice]\nn = 6\napertures_file = "ap.npy"\n[fluid]\n'))
    assert scene.lattice.apertures_file == (tmp_path / "ap.npy").resolve()


def test_an_apertures_directory_is_named(tmp_path, write_scene):
    (tmp_path / "ap").mkdir()
    msg = error_of(write_scene('[lattice]\nn = 6\napertures_file = "ap"\n[fluid]\n'))
    assert "is a directory; give the .npz or .npy file of apertures" in msg
