"""``porenet.run(scene, network=net)``: a network held in memory runs as the same network
from a file does, meets the same checks, and is saved once under a name of its content."""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest

import porenet
from porenet.core.errors import ConfigError
from porenet.io.networks import NETWORK_DIR_ENV, save_network
from porenet.kinds.network.config import NetworkLatticeConfig


@pytest.fixture(autouse=True)
def network_dir(tmp_path, monkeypatch):
    folder = tmp_path / "networks"
    monkeypatch.setenv(NETWORK_DIR_ENV, str(folder))
    return folder


def _file_scene():
    return NetworkLatticeConfig.example_scene()


def _network() -> dict[str, np.ndarray]:
    """The example scene's network, as OpenPNM holds it: a dict of arrays."""
    with np.load(_file_scene()["lattice"]["file"]) as f:
        return {k: f[k] for k in f.files}


def _memory_scene():
    scene = _file_scene()
    del scene["lattice"]["file"]
    return scene


def test_in_memory_runs_as_the_file_does(network_dir):
    from_file = porenet.run(_file_scene()).data
    in_memory = porenet.run(_memory_scene(), network=_network()).data
    assert np.array_equal(from_file.order, in_memory.order)
    assert np.array_equal(from_file.throat_pores, in_memory.throat_pores)
    assert np.allclose(from_file.apertures, in_memory.apertures)
    # the run's scene names the saved file, which holds the network
    saved = Path(in_memory.scene["lattice"]["file"])
    assert saved.parent == network_dir and saved.is_file()


def test_an_openpnm_network_object_is_a_dict():
    class Network(dict):  # OpenPNM 3's Network subclasses dict, with settings beside the arrays
        settings: ClassVar[dict[str, str]] = {"name": "net"}

    net = Network(_network())
    net["params"] = {"not": "an array"}  # not pore.* or throat.*: not part of the network
    result = porenet.run(_memory_scene(), network=net)
    assert result.summary["n_drained"] > 0


def test_the_same_network_is_saved_once_and_a_changed_one_apart(network_dir):
    first = save_network(_network())
    again = save_network(_network())
    changed = _network()
    changed["pore.coords"] = changed["pore.coords"] * 2.0
    assert first == again and save_network(changed) != first
    assert sorted(p.name for p in network_dir.iterdir()) == sorted(
        {first.name, save_network(changed).name}
    )


def test_a_bad_network_meets_the_checks_of_a_file():
    bad = _network()
    bad["throat.conns"] = bad["throat.conns"].copy()
    bad["throat.conns"][0, 0] = 10_000  # no such pore
    with pytest.raises(ConfigError, match=r"throat\.conns"):
        porenet.run(_memory_scene(), network=bad)


@pytest.mark.parametrize(
    ("network", "said"),
    [
        ([1, 2, 3], "network dict"),
        ({"a": 1}, "no 'pore.\\*' or 'throat.\\*' arrays"),
        ({"pore.coords": np.array([object()] * 3)}, "'pore.coords' holds object"),
    ],
)
def test_what_is_not_a_network_is_named(network, said):
    with pytest.raises(ConfigError, match=said):
        porenet.run(_memory_scene(), network=network)
