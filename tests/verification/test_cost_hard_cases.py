"""The cost model (docs/cost.md) against measured runs on a cheap subset of the hard-case matrix.

``python tests/benchmarks/bench_cost.py --hard`` prints the whole matrix (docs/cost.md, "Hard
cases"); these are its cases that run in well under a second each. The model aims at a
factor ~2-3 (docs/cost.md); each case runs with the scene's fixed seed, so the counts are
deterministic and the factor 3 is the model's stated aim, not a tolerance for noise. A case
where the model is known not to hold must say so in its notes. Only counts are compared
(drained pores, fluid steps, mechanical updates), never wall times.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from porenet.config.loading import load_scene
from porenet.core.cost import estimate_cost
from porenet.simulation import Simulation

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
FIG1B = str(SCENES / "fig1b.toml")
FIG5 = str(SCENES / "fig5.toml")
IP = str(SCENES / "ip-400.toml")
CUBIC = str(SCENES / "cubic-viscous.toml")
FACTOR = 3.0

#: name -> (scene, overrides); all within the model's stated factor.
HOLDS = {
    "3 x 3, breakthrough": (FIG1B, ["lattice.n=3"]),
    "3 x 3, complete": (FIG1B, ["lattice.n=3", "stop.at=complete"]),
    "3 x 3, Ca = 1e-7": (FIG1B, ["lattice.n=3", "fluid.capillary_number=1e-7"]),
    "3 x 3, IP complete": (IP, ["lattice.n=3", "stop.at=complete"]),
    "lambda = 0.01": (FIG1B, ["lattice.n=30", "lattice.disorder=0.01",
                              "fluid.capillary_number=1e-2"]),
    "lambda = 0.95": (FIG1B, ["lattice.n=30", "lattice.disorder=0.95",
                              "fluid.capillary_number=1e-2"]),
    "lambda = 0.95, IP": (IP, ["lattice.n=30", "lattice.disorder=0.95"]),
    "Ca = 1e2": (FIG1B, ["lattice.n=30", "fluid.capillary_number=1e2"]),
    "Ca = 1e4": (FIG1B, ["lattice.n=15", "fluid.capillary_number=1e4"]),
    "N_f = 1e-6": (FIG5, ["lattice.n=30", "solid.fracturing_number=1e-6"]),
    "3-D, centre": (CUBIC, ["lattice.shape=[12, 12, 12]"]),
    "3-D, from a face": (CUBIC, ["lattice.shape=[12, 12, 12]", "injection.at=z-"]),
}  # fmt: skip


def _measure(scene):
    summary = Simulation.from_scene(scene).run().summary
    drained = summary["n_drained"]
    return drained, summary.get("time_steps", drained), summary.get("mechanical_updates", 0)


@pytest.mark.parametrize("name", list(HOLDS))
def test_estimate_within_the_stated_factor(name):
    source, overrides = HOLDS[name]
    scene = load_scene(source, [*overrides, "classifier.kind=none"])
    est = estimate_cost(scene)
    drained, steps, updates = _measure(scene)
    for what, pred, meas in (("drained", est.drained, drained), ("steps", est.steps, steps)):
        assert pred is not None
        assert meas / FACTOR <= pred <= meas * FACTOR, (what, pred, meas)
    if est.mechanical_updates:
        assert updates / FACTOR <= est.mechanical_updates <= updates * FACTOR


def test_fast_injection_is_costed_by_its_accuracy_limit():
    """The issue's miss: n = 30, Ca = 1e6 was estimated at ~120 steps and took 646 838 (the
    explicit step is limited by ``pressure_step``, not by stability). Estimate only."""
    scene = load_scene(FIG1B, ["lattice.n=30", "fluid.capillary_number=1e6"])
    est = estimate_cost(scene)
    assert 646_838 / FACTOR <= est.steps <= 646_838 * FACTOR
    assert est.wall_seconds > 0.5


def test_a_soft_solid_says_the_estimate_does_not_hold():
    """N_f = 1e6 in the viscous model: measured 14x the steps and 30x the updates (docs/cost.md,
    "Hard cases"); the estimate must say it is outside its calibration."""
    scene = load_scene(FIG5, ["lattice.n=30", "solid.fracturing_number=1e6"])
    est = estimate_cost(scene)
    assert any("beyond the model's calibration" in note for note in est.notes)
    rigid_like = estimate_cost(load_scene(FIG5, ["lattice.n=30", "solid.fracturing_number=1"]))
    assert not any("calibration" in note for note in rigid_like.notes)
