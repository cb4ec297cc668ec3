"""A scene the lattice refuses beyond what its pydantic fields say (those, with the rest of
its contract: test_correlated_contract.py)."""

from __future__ import annotations

import numpy as np
import pytest

from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError


def scene(**lattice):
    return {
        "seed": 3,
        "lattice": {
            "kind": "correlated.gaussian",
            "n": 31,
            "disorder": 0.3,
            "correlation_length": 4.0,
            **lattice,
        },
        "fluid": {"kind": "invasion-percolation", "trapping": True},
        "stop": {"at": "breakthrough"},
    }


def test_apertures_file_is_rejected(reg, tmp_path):
    path = tmp_path / "ap.npz"
    np.savez(path, apertures=np.full(2 * 31 * 30, 1e-7))
    with pytest.raises(ConfigError, match="apertures_file"):
        load_scene(scene(apertures_file=str(path)), registry=reg)
