"""The contract suite (porenet.testing.contract, docs/contract.md) over every kind porenet
registers, and on toy kinds that each break one promise: the suite must fail for them."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from typing import Any, ClassVar, Literal

import numpy as np
import pytest
from pydantic import Field, model_validator

from porenet.config.base import ModelConfig
from porenet.core.interfaces import Observer
from porenet.hooks import hookimpl
from porenet.kinds.invasion.config import InvasionPercolationConfig
from porenet.kinds.invasion.model import InvasionPercolation
from porenet.testing.contract import (
    all_checks,
    check_kind,
    contract_checks,
    covered_kinds,
    plugin_registry,
)

#: porenet's own kinds only: an installed plugin is checked in its own tests.
REGISTRY = plugin_registry()


@pytest.mark.parametrize("check", all_checks(REGISTRY), ids=str)
def test_contract(check):
    check()


def test_every_registered_kind_is_covered():
    registered = {(entry.family, entry.kind) for entry in REGISTRY}
    assert covered_kinds(REGISTRY) == registered


def test_importing_the_suite_imports_no_numba():
    code = "import sys, porenet.testing.contract; assert 'numba' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True)


# -- toy kinds, each breaking one promise ----------------------------------------------------------
def toy_scene(fluid: dict[str, Any], **sections: Any) -> dict[str, Any]:
    return {
        "seed": 1,
        "lattice": {"kind": "square", "n": 12, "disorder": 0.3},
        "fluid": fluid,
        "stop": {"at": "breakthrough"},
        **sections,
    }


class UnseededConfig(InvasionPercolationConfig):
    kind: Literal["toy.unseeded"] = "toy.unseeded"  # type: ignore[assignment]

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        return toy_scene({"kind": "toy.unseeded"})


class Unseeded(InvasionPercolation):
    """Reports a draw of numpy's global generator, which no seed controls."""

    def summary(self, state):  # type: ignore[no-untyped-def]
        return {"noise": float(np.random.random())}


class UnnamedConfig(InvasionPercolationConfig):
    """Checks its field in a validator of the whole section, whose error names no field."""

    kind: Literal["toy.unnamed"] = "toy.unnamed"  # type: ignore[assignment]
    strength: float = Field(1.0, gt=0)

    @model_validator(mode="before")
    @classmethod
    def _strength_is_a_number(cls, data: Any) -> Any:
        if isinstance(data, dict) and not isinstance(data.get("strength", 1.0), int | float):
            raise ValueError("a number is needed")
        return data

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        return toy_scene({"kind": "toy.unnamed"})


class ForgetfulConfig(InvasionPercolationConfig):
    kind: Literal["toy.forgetful"] = "toy.forgetful"  # type: ignore[assignment]

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        return toy_scene({"kind": "toy.forgetful"})


class Forgetful(InvasionPercolation):
    """Forgets, when pickled into a checkpoint, how far it replayed the invasion."""

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "_cursor": 0}


class UnitlessConfig(ModelConfig):
    kind: Literal["toy.unitless"] = "toy.unitless"

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        return toy_scene({"kind": "invasion-percolation"}, observers=[{"kind": "toy.unitless"}])


class Unitless(Observer):
    """Records a number and gives it no unit."""

    output_units: ClassVar[dict[str, str]] = {}

    def outputs(self, state):  # type: ignore[no-untyped-def]
        return {"drained": np.array([state.n_drained])}


class UncoveredConfig(ModelConfig):
    """Gives no example scene."""

    kind: Literal["toy.uncovered"] = "toy.uncovered"


class ToyPlugin:
    @hookimpl
    def porenet_register_fluid_models(self, register):  # type: ignore[no-untyped-def]
        register(UnseededConfig, Unseeded)
        register(UnnamedConfig, InvasionPercolation)
        register(ForgetfulConfig, Forgetful)

    @hookimpl
    def porenet_register_observers(self, register):  # type: ignore[no-untyped-def]
        register(UnitlessConfig, Unitless)
        register(UncoveredConfig, Unitless)


@pytest.fixture(scope="module")
def toys():
    return plugin_registry({"toy": ToyPlugin()})  # type: ignore[dict-item]


def broken(family: str, kind: str, registry) -> str:  # type: ignore[no-untyped-def]
    """The suite's verdict on a kind that must fail it."""
    with pytest.raises(AssertionError) as failure:
        check_kind(family, kind, registry=registry)
    return str(failure.value)


def test_an_unseeded_random_draw_breaks_determinism(toys):
    message = broken("fluid", "toy.unseeded", toys)
    assert "fluid kind 'toy.unseeded'" in message
    assert "'deterministic'" in message and "summary['noise']" in message


def test_a_config_error_that_names_no_field_is_caught(toys):
    message = broken("fluid", "toy.unnamed", toys)
    assert "'config-errors'" in message
    assert "strength = 'not-a-number': the message does not name fluid.strength" in message
    assert "'deterministic'" not in message  # the rest of the kind keeps its promises


def test_a_model_that_loses_its_place_in_a_checkpoint_is_caught(toys):
    message = broken("fluid", "toy.forgetful", toys)
    assert "'checkpoint'" in message and "'deterministic'" not in message


def test_records_without_units_are_caught(toys):
    message = broken("observer", "toy.unitless", toys)
    assert "'run-file'" in message and "toy.unitless/drained" in message


def test_a_kind_without_an_example_scene_is_uncovered(toys):
    (check,) = contract_checks("observer", "toy.uncovered", registry=toys)
    assert str(check) == "observer:toy.uncovered:uncovered"
    with pytest.raises(AssertionError, match="has no example_scene"):
        check()
    assert ("observer", "toy.uncovered") not in covered_kinds(toys)
    assert ("observer", "toy.unitless") in covered_kinds(toys)


def test_a_config_module_that_imports_its_model_is_caught(tmp_path, monkeypatch):
    """A lazily registered kind whose config module imports the implementation anyway."""
    package = tmp_path / "heavy_toy"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "model.py").write_text(
        "from porenet.kinds.invasion.model import InvasionPercolation as Heavy\n"
    )
    (package / "config.py").write_text(
        textwrap.dedent(
            """
            from typing import Literal
            from porenet.kinds.invasion.config import InvasionPercolationConfig
            import heavy_toy.model  # the mistake: the model is imported with the config

            class HeavyConfig(InvasionPercolationConfig):
                kind: Literal["heavy.fluid"] = "heavy.fluid"

                @classmethod
                def example_scene(cls):
                    return {"lattice": {"n": 12}, "fluid": {"kind": "heavy.fluid"}}
            """
        )
    )
    (package / "plugin.py").write_text(
        "from porenet.hooks import hookimpl\nfrom heavy_toy.config import HeavyConfig\n\n"
        "@hookimpl\ndef porenet_register_fluid_models(register):\n"
        "    register(HeavyConfig, 'heavy_toy.model:Heavy')\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    import heavy_toy.plugin

    registry = plugin_registry({"heavy": heavy_toy.plugin})
    (check,) = [c for c in contract_checks("fluid", "heavy.fluid", registry=registry)
                if c.name == "light-import"]  # fmt: skip
    with pytest.raises(AssertionError, match=r"imports .*heavy_toy\.model"):
        check()
