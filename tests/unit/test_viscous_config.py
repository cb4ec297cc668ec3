"""Validation of the viscous fluid config (kind "viscous"): every bad combination is a
ConfigError naming the offending fields; every valid config round-trips."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from porenet.config.base import SMALLEST
from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.kinds.viscous.model import ViscousConfig

GAMMA_OVER_A = 0.07 / 1e-7  # capillary pressure scale gamma / a (Pa) of the scenes below


def scene(**fluid):
    return {
        "seed": 1,
        "lattice": {"n": 10, "disorder": 0.3, "pore_size": 1e-7},
        "fluid": {"kind": "viscous", **fluid},
    }


def error_of(**fluid) -> str:
    with pytest.raises(ConfigError) as info:
        load_scene(scene(**fluid))
    return str(info.value)


# -- valid configs ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    "fluid",
    [
        {"capillary_number": 1e-2},
        {"injection_rate": 1e-15},
        {"capillary_number": 1e-2, "reservoir": "drained", "meniscus": "latching"},
        {"control": "pressure", "injection_pressure": 2.2 * GAMMA_OVER_A},
        {"control": "ramp", "ramp_rate": 1e12},
        {"control": "ramp", "ramp_rate": 1e12, "injection_pressure": GAMMA_OVER_A},
        {"capillary_number": 1e-2, "snapshot_saturations": [0.05, 1.0], "snapshot_times": [1e-6]},
        {"capillary_number": 1e-2, "safety_factor": 1.0, "pressure_floor": 0.0},
    ],
)
def test_valid_configs_load(fluid):
    cfg = load_scene(scene(**fluid)).fluid
    assert isinstance(cfg, ViscousConfig)
    for key, value in fluid.items():
        assert getattr(cfg, key) == value


def test_defaults_are_the_papers():
    cfg = load_scene(scene(capillary_number=1e-2)).fluid
    assert cfg.viscosity == 1e-3 and cfg.interfacial_tension == 0.07  # docs/model.md section 6
    assert cfg.control == "rate" and cfg.reservoir == "pore" and cfg.meniscus == "threshold"
    assert 0 < cfg.safety_factor <= 1 and cfg.injection_pressure == 0.0


# -- rate control: exactly one of capillary_number / injection_rate ------------------------------


def test_rate_control_needs_one_of_ca_or_rate():
    msg = error_of()
    assert "capillary_number" in msg and "injection_rate" in msg and "neither" in msg


def test_rate_control_rejects_both_ca_and_rate():
    msg = error_of(capillary_number=1e-2, injection_rate=1e-15)
    assert "capillary_number" in msg and "injection_rate" in msg and "exactly one" in msg


# -- ramp and pressure control ----------------------------------------------------------------


def test_ramp_needs_ramp_rate():
    msg = error_of(control="ramp")
    assert "ramp_rate" in msg and "ramp" in msg


def test_ramp_rate_only_for_ramp():
    assert "ramp_rate" in error_of(capillary_number=1e-2, ramp_rate=1e12)


@pytest.mark.parametrize("pressure", [None, 0.0])
def test_pressure_control_needs_positive_injection_pressure(pressure):
    fluid = {"control": "pressure"}
    if pressure is not None:
        fluid["injection_pressure"] = pressure
    msg = error_of(**fluid)
    assert "injection_pressure" in msg and "positive" in msg


def test_negative_injection_pressure_rejected():
    assert "injection_pressure" in error_of(control="pressure", injection_pressure=-1.0)


@pytest.mark.parametrize("field", ["capillary_number", "injection_rate"])
def test_pressure_control_rejects_rate_fields(field):
    value = 1e-2 if field == "capillary_number" else 1e-15
    msg = error_of(control="pressure", injection_pressure=GAMMA_OVER_A, **{field: value})
    assert field in msg and "rate" in msg


# -- ranges -------------------------------------------------------------------------------------


@pytest.mark.parametrize("bad", [[0.0], [-0.1], [1.5], [0.2, 1.0000001]])
def test_snapshot_saturations_outside_unit_interval_rejected(bad):
    assert "snapshot_saturations" in error_of(capillary_number=1e-2, snapshot_saturations=bad)


@pytest.mark.parametrize("bad", [[0.0], [-1e-6]])
def test_snapshot_times_must_be_positive(bad):
    assert "snapshot_times" in error_of(capillary_number=1e-2, snapshot_times=bad)


@pytest.mark.parametrize("bad", [0.0, -0.5, 1.0000001, 2.0])
def test_safety_factor_outside_unit_interval_rejected(bad):
    msg = error_of(capillary_number=1e-2, safety_factor=bad)
    assert "safety_factor" in msg and str(bad) in msg


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("capillary_number", 0.0),
        ("capillary_number", -1e-3),
        ("viscosity", 0.0),
        ("interfacial_tension", -0.07),
        ("max_steps", 0),
        ("pressure_floor", -1e-9),
    ],
)
def test_non_positive_physical_inputs_rejected(field, value):
    fluid = {"capillary_number": 1e-2, field: value}
    assert field in error_of(**fluid)


@pytest.mark.parametrize(
    ("field", "value"),
    [("control", "flow"), ("reservoir", "pump"), ("meniscus", "sticky"), ("integrator", "rk4")],
)
def test_unknown_choice_rejected(field, value):
    assert field in error_of(capillary_number=1e-2, **{field: value})


def test_unknown_field_rejected_with_suggestion():
    msg = error_of(capillary_number=1e-2, capilary_number=1e-2)
    assert "fluid.capilary_number" in msg and "unknown field" in msg
    assert "did you mean 'capillary_number'" in msg


def test_ip_fields_are_not_viscous_fields():
    # extra="forbid": a field of another fluid kind is an error, not silently ignored
    assert "trapping" in error_of(capillary_number=1e-2, trapping=True)


# -- property: every valid config validates and round-trips ------------------------------------


@settings(max_examples=60, deadline=None)
@given(
    ca=st.floats(min_value=1e-6, max_value=1.0),
    # from the smallest non-zero magnitude a scene accepts: 5e-324 divided by zero in a run
    # (docs/reliability.md, "Numbers in a scene")
    safety=st.floats(min_value=SMALLEST, max_value=1.0),
    reservoir=st.sampled_from(["pore", "drained"]),
    meniscus=st.sampled_from(["threshold", "latching"]),
    saturations=st.lists(st.floats(min_value=SMALLEST, max_value=1.0), max_size=3),
)
def test_valid_configs_round_trip(ca, safety, reservoir, meniscus, saturations):
    fields = {
        "capillary_number": ca,
        "safety_factor": safety,
        "reservoir": reservoir,
        "meniscus": meniscus,
        "snapshot_saturations": saturations,
    }
    cfg = ViscousConfig(**fields)
    assert cfg.capillary_number == ca and cfg.safety_factor == safety
    assert ViscousConfig.model_validate(cfg.model_dump()) == cfg
    assert ViscousConfig.model_validate_json(cfg.model_dump_json()) == cfg
    # and through the scene loader, which is where users meet it
    loaded = load_scene(scene(**fields))
    assert loaded.fluid == cfg
    assert load_scene(loaded.model_dump(mode="json")) == loaded
