"""Every regression scene gives the stored outcome: the same drained pores in the same order,
the same trapped set, times, pressures, apertures, time series, snapshots and mechanics to
round-off (``outcome.differences``). The outcomes were stored by ``generate.py`` at the
commit named in ``outcomes/provenance.json``; refactorings must not change them."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from outcome import differences, outcome  # noqa: E402
from scenes import SCENES  # noqa: E402

from porenet.simulation import Simulation  # noqa: E402

OUTCOMES = HERE / "outcomes"


def test_every_scene_has_a_stored_outcome_and_its_provenance() -> None:
    provenance = json.loads((OUTCOMES / "provenance.json").read_text())
    for name in SCENES:
        assert (OUTCOMES / f"{name}.npz").exists(), name
        assert provenance[name]["commit"], name


@pytest.mark.parametrize("name", list(SCENES))
def test_outcome_unchanged(name: str) -> None:
    with np.load(OUTCOMES / f"{name}.npz") as stored:
        expected = dict(stored)
    now = outcome(Simulation.from_scene(SCENES[name]).run().data)
    problems = differences(expected, now)
    assert not problems, f"{name}: " + "; ".join(problems[:8])
