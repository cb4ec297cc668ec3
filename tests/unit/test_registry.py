"""Plugin registry and loading policy."""

from __future__ import annotations

import types
from typing import Literal

import pytest

from porenet.core.errors import ConfigError, PluginError
from porenet.core.registry import Registry
from porenet.hooks import build_registry, hookimpl
from porenet.kinds.square.model import SquareLattice, SquareLatticeConfig


def plugin_module(**hooks):
    return types.SimpleNamespace(**{name: hookimpl(fn) for name, fn in hooks.items()})


def load_with(name, strict=True, **hooks):
    """Build a registry with one extra plugin made of ``hooks``."""
    return build_registry(strict=strict, extra_plugins={name: plugin_module(**hooks)})


class NamespacedConfig(SquareLatticeConfig):
    kind: Literal["demo.square"] = "demo.square"


class BareConfig(SquareLatticeConfig):
    kind: Literal["bare"] = "bare"


def test_builtins_registered_through_hooks(monkeypatch):
    monkeypatch.setenv("PORENET_PLUGINS", "")  # installed third-party plugins are not ours
    reg = build_registry(strict=True)
    assert reg.kinds("lattice") == ["cubic", "network", "square"]
    assert "invasion-percolation" in reg.kinds("fluid")
    assert reg.get("solid", "rigid").implementation is None
    assert all(e.package == "porenet" for e in reg)


def test_third_party_kind_and_lazy_implementation():
    def porenet_register_lattices(register):
        register(NamespacedConfig, "porenet.kinds.square.model:SquareLattice")

    reg = load_with("demo", strict=True, porenet_register_lattices=porenet_register_lattices)
    entry = reg.get("lattice", "demo.square")
    assert entry.package == "demo" and entry.load() is SquareLattice


def test_duplicate_kind_names_both_packages():
    def porenet_register_lattices(register):
        register(SquareLatticeConfig, SquareLattice)

    with pytest.raises(PluginError, match=r"registered twice.*'porenet'.*'dup'"):
        load_with("dup", strict=True, porenet_register_lattices=porenet_register_lattices)


def test_unnamespaced_third_party_kind_rejected():
    def porenet_register_lattices(register):
        register(BareConfig, SquareLattice)

    with pytest.raises(PluginError, match="must be namespaced"):
        load_with("bare", strict=True, porenet_register_lattices=porenet_register_lattices)


def test_misspelt_hook_is_an_error():
    def porenet_register_latices(register):
        pass

    with pytest.raises(PluginError, match="unknown hook"):
        load_with("typo", strict=False, porenet_register_latices=porenet_register_latices)


def test_broken_plugin_is_isolated_unless_strict():
    def porenet_register_lattices(register):
        raise RuntimeError("broken on purpose")

    mod = plugin_module(porenet_register_lattices=porenet_register_lattices)
    reg = build_registry(strict=False, extra_plugins={"broken": mod})
    # the other plugins still register (whatever else is installed, e.g. porenet-correlated)
    assert reg.kinds("lattice") == build_registry(strict=False).kinds("lattice")
    assert "square" in reg.kinds("lattice") and reg.failures[0][0] == "broken"
    with pytest.raises(PluginError, match="broken on purpose"):
        build_registry(strict=True, extra_plugins={"broken": mod})


def test_unimportable_lazy_implementation_fails_when_selected():
    reg = Registry()
    entry = reg.add("lattice", NamespacedConfig, "no_such_module:Thing", package="x", plugin="x")
    with pytest.raises(PluginError, match="cannot import"):
        entry.load()


def test_unknown_kind_is_config_error():
    with pytest.raises(ConfigError, match="did you mean 'square'"):
        build_registry().get("lattice", "sqare")


def test_env_restricts_entry_points(monkeypatch):
    monkeypatch.setenv("PORENET_PLUGINS", "")
    assert {e.package for e in build_registry()} == {"porenet"}
