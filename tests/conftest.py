"""Shared fixtures."""

from __future__ import annotations

import os
import signal

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

# The Ctrl-C tests send SIGINT as a terminal does. A test run that a script started in the
# background (`.ci/run &`, nohup) inherits SIGINT ignored, and so would every process it
# starts: those tests would see no Ctrl-C at all (a run that finishes, exit 0 instead of 130).
# Python's own handler is restored for the run; processes started from it get the default.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


def pytest_collection_modifyitems(config, items):
    """Tests marked ``long`` (minutes each) first: with one worker per core (pytest-xdist) a
    long test started last would run alone at the end."""
    items.sort(key=lambda item: item.get_closest_marker("long") is None)


@pytest.fixture
def scene_dict():
    """A small, fast IP scene as a dict."""
    return {
        "seed": 7,
        "lattice": {"kind": "square", "n": 31, "disorder": 0.3, "pore_size": 1e-7},
        "fluid": {"kind": "invasion-percolation", "trapping": True, "interfacial_tension": 0.07},
        "solid": {"kind": "rigid"},
        "stop": {"at": "breakthrough"},
    }


@pytest.fixture
def write_scene(tmp_path):
    """Write TOML text to a file and return its path."""

    def _write(text: str, name: str = "scene.toml"):
        path = tmp_path / name
        path.write_text(text)
        return path

    return _write
