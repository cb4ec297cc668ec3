"""Running scenes in tests and comparing their patterns.

* :func:`simulate` builds and runs a scene (a dict, path or config);
* :func:`cached_run` runs a scene dict once per process, so tests that check different
  properties of the same run share it (they must only read the results);
* :func:`pattern_overlap` is the Jaccard overlap ``|A & B| / |A | B|`` of two drained sets,
  the measure docs/accuracy.md uses to compare patterns (its complement is the "pattern
  error");
* :func:`assert_viscous_run_sane` checks what every viscous run must satisfy, whatever its
  integrator;
* :func:`tiny_lattice_cases` and :func:`assert_tiny_lattice_outcome` are the 3 x 3 hard
  cases every viscous integrator's tests run, and what they must end with;
* :func:`frontier_menisci` lists the menisci of a finished run with the excess of their
  pressure difference over their entry pressure (an arrested meniscus has none);
* :class:`KilledAfterCheckpoint` is a checkpoint schedule that raises
  :class:`Killed` right after writing its first checkpoint: the process killed mid-run,
  for tests of resuming (docs/run-file.md, "Checkpoints").
"""

from __future__ import annotations

import functools
import json
from typing import Any

import numpy as np

from porenet.io.checkpoint import CheckpointSchedule
from porenet.simulation import Simulation


class Killed(Exception):
    """Stands for the process dying right after a checkpoint was written."""


class KilledAfterCheckpoint(CheckpointSchedule):
    """A :class:`~porenet.io.checkpoint.CheckpointSchedule` (same arguments) whose first
    checkpoint is written whole and then :class:`Killed` is raised, as if the process had
    died there: the run leaves its checkpoint and nothing else."""

    def write(self, simulation: Any) -> Any:
        super().write(simulation)
        raise Killed


def simulate(scene: Any, **kwargs: Any) -> tuple[Simulation, Any]:
    """``(simulation, result)`` of a scene; ``kwargs`` go to :meth:`Simulation.from_scene`."""
    sim = Simulation.from_scene(scene, **kwargs)
    return sim, sim.run()


@functools.cache
def _cached(key: str) -> tuple[Simulation, Any]:
    return simulate(json.loads(key))


def cached_run(scene: dict) -> tuple[Simulation, Any]:
    """:func:`simulate` a JSON-serialisable scene dict once per process (read-only results)."""
    return _cached(json.dumps(scene, sort_keys=True))


def pattern_overlap(a: np.ndarray, b: np.ndarray) -> float:
    """Jaccard overlap ``|A & B| / |A | B|`` of two boolean masks (1 when both are empty)."""
    union = int(np.sum(a | b))
    return float(np.sum(a & b) / union) if union else 1.0


def assert_viscous_run_sane(sim: Simulation, result: Any, max_steps: int | None = None) -> None:
    """A viscous run kept its invariants: finite pressures (state and run data) and invading
    pressure, no meniscus below length 0, a drained volume that is never negative and never
    decreases, and (given ``max_steps``) a step count that did not run away."""
    assert np.all(np.isfinite(sim.state.pressure))
    assert np.all(np.isfinite(result.data.pressure))
    assert np.isfinite(sim.state.invading_pressure)
    assert np.all(sim.state.meniscus_length >= 0.0)
    drained = sim.fluid.timeseries()["drained"]
    assert sim.fluid.volumes()["drained"] >= 0 and np.all(drained >= 0)
    assert np.all(np.diff(drained) >= 0)
    if max_steps is not None:
        assert 0 < result.summary["time_steps"] < max_steps


def tiny_lattice_cases(
    scene: Any, capillary_number: float, injection_pressure: float
) -> dict[str, tuple[dict, str]]:
    """The 3 x 3 hard cases, ``name -> (scene, expected stop reason)``: rate control to
    breakthrough and to completion at ``capillary_number``, and pressure control at
    ``injection_pressure`` (Pa) to completion. ``scene(**kw)`` is the test file's scene
    builder (it sets the integrator)."""
    return {
        "3x3": (scene(n=3, capillary_number=capillary_number), "breakthrough"),
        "3x3-complete": (
            scene(n=3, at="complete", capillary_number=capillary_number),
            "complete",
        ),
        "3x3-pressure": (
            scene(n=3, at="complete", control="pressure", injection_pressure=injection_pressure),
            "complete",
        ),
    }


def assert_tiny_lattice_outcome(result: Any, reason: str) -> None:
    """What a 3 x 3 run must end with: all 8 non-centre pores are outlet pores, so
    breakthrough comes at the second drained pore and "complete" drains everything (no
    cluster can be cut off)."""
    assert result.summary["n_drained"] == (2 if reason == "breakthrough" else 9)
    assert not result.data.trapped.any()


def frontier_menisci(
    data: Any, p_inv: float, pressure_scale: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The menisci of a run's final state (``result.data``, SI) at invading pressure ``p_inv``
    (Pa): the undrained pore each one enters, its scaled entry pressure ``2 / r`` (``r`` in
    units of the pore size ``a``) and the excess ``(p_inv - p_i) / pressure_scale - 2 / r``
    of its pressure difference over it (``pressure_scale = gamma / a`` in Pa)."""
    tp, drained = data.throat_pores, data.drained
    frontier = drained[tp[:, 0]] != drained[tp[:, 1]]
    pore = np.where(drained[tp[:, 0]], tp[:, 1], tp[:, 0])[frontier]
    entry = 2.0 / (data.apertures[frontier] / data.pore_size)
    return pore, entry, (p_inv - data.pressure[pore]) / pressure_scale - entry
