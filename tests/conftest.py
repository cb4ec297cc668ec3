"""Shared fixtures."""

from __future__ import annotations

import os

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")


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
