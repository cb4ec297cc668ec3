"""The ``front.interface`` observer in real runs, registered through a hand-built registry:
its records are the front of the drained set at each scheduled count and at the end, they
reach the run file with their units, and the same seed gives the same records."""

from __future__ import annotations

import math
import os
import pickle
import subprocess
import sys

import h5py
import numpy as np
import porenet_front.plugin
import pytest
from porenet_front.config import KIND, FrontConfig
from porenet_front.front import front_geometry, measure
from porenet_front.observer import FrontObserver

import porenet.hooks
from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.io.runfile import read_run
from porenet.simulation import Simulation

N, PORE_SIZE = 24, 1e-4


@pytest.fixture(scope="module")
def reg():
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("PORENET_PLUGINS", "")  # an installed copy must not clash with ours
        return porenet.hooks.build_registry(
            strict=True, extra_plugins={"front": porenet_front.plugin}
        )


def scene(seed: int = 7, at: str = "left-edge", **observer) -> dict:
    return {
        "seed": seed,
        "lattice": {"kind": "square", "n": N, "disorder": 0.3, "pore_size": PORE_SIZE},
        "injection": {"at": at},
        "fluid": {"kind": "invasion-percolation"},
        "observers": [{"kind": KIND, "every": 0.04, **observer}],
        "stop": {"at": "breakthrough"},
        "classifier": {"kind": "none"},
    }


@pytest.fixture(scope="module")
def run(reg, tmp_path_factory):
    path = tmp_path_factory.mktemp("front") / "run.h5"
    sim = Simulation.from_scene(scene(), registry=reg, output=path)
    return sim, sim.run(), path


def test_registered_lazily_under_the_plugins_name(reg):
    entry = reg.get("observer", KIND)
    assert entry.config is FrontConfig
    assert entry.implementation == "porenet_front.observer:FrontObserver"
    assert entry.plugin == "front"
    assert entry.load() is FrontObserver


def test_plugin_import_does_not_import_the_observer():
    code = (
        "import sys, porenet_front.plugin; "
        "assert 'porenet_front.observer' not in sys.modules; "
        "assert 'porenet.kinds.invasion.kernels.ip' not in sys.modules; "
        "assert 'numba' not in sys.modules"
    )
    src = str(porenet_front.plugin.__file__).rsplit("porenet_front", 1)[0]
    env = {**os.environ, "PYTHONPATH": src}
    subprocess.run([sys.executable, "-c", code], check=True, env=env, cwd=src)


@pytest.mark.parametrize(
    ("value", "message"),
    [(0, "greater than 0"), (1.5, "less than or equal to 1"), ("nan", "finite"), ("x", "")],
)
def test_bad_every_is_a_config_error_naming_the_field(reg, value, message):
    with pytest.raises(ConfigError, match=rf"observers\[0\]\.every = .*{message}"):
        load_scene(scene(every=value), registry=reg)


def test_unknown_field_is_a_config_error_naming_it(reg):
    with pytest.raises(ConfigError, match=r"observers\[0\]\.evry: unknown field"):
        load_scene(scene(evry=0.1), registry=reg)


def test_records_are_the_front_of_the_drained_set_at_each_count(run):
    """Rebuild the drained set at each recorded count from the run's drainage order and
    measure it again: the observer saw exactly those states."""
    sim, result, _ = run
    records = result.data.observers[KIND]
    geometry = front_geometry(sim.lattice, "left-edge")
    order = result.data.order
    assert len(records["n_drained"]) >= 5
    for k, count in enumerate(records["n_drained"]):
        drained = np.zeros(sim.lattice.n_pores, dtype=bool)
        drained[order[:count]] = True
        front = measure(geometry, drained)
        assert records["menisci"][k] == front.menisci
        assert records["front_menisci"][k] == front.front_menisci
        assert records["front_position"][k] == front.position * PORE_SIZE
        assert records["front_width"][k] == front.width * PORE_SIZE
        assert records["extent"][k] == front.extent * PORE_SIZE
        # IP: the pressure at count k is the threshold of the step that drained pore k
        assert records["invading_pressure"][k] == result.data.invasion_pressure[count - 1]


def test_records_follow_the_schedule_and_grow(run):
    _, result, _ = run
    records = result.data.observers[KIND]
    counts = records["n_drained"]
    step = math.ceil(0.04 * N * N)
    assert np.all(np.diff(counts) > 0)
    assert np.all(counts[:-1] % step == 0)  # scheduled records, then the final state
    assert step == N  # ceil(23.04): the N inlets reach the first count, recorded at the start
    assert counts[0] == step
    assert np.all(np.diff(records["extent"]) >= 0)  # the drained set only grows
    assert np.all(records["time"] == 0)  # quasi-static
    # the front is among the menisci, and lies between the inlet and the tip
    assert np.all(records["front_menisci"] <= records["menisci"])
    assert np.all(records["front_position"] <= records["extent"] + PORE_SIZE)


def test_final_record_is_the_final_state(run):
    sim, result, _ = run
    records, state = result.data.observers[KIND], sim.state
    front = measure(front_geometry(sim.lattice, "left-edge"), state.drained)
    assert records["n_drained"][-1] == state.n_drained == result.data.summary["n_drained"]
    assert records["invading_pressure"][-1] == state.invading_pressure * sim.scales.pressure
    assert records["menisci"][-1] == front.menisci
    assert records["front_menisci"][-1] == front.front_menisci
    assert records["front_position"][-1] == front.position * PORE_SIZE
    # breakthrough: the tip touches the outlet column, 2 (N - 1) pore sizes from the inlets
    assert result.data.summary["stop_reason"] == "breakthrough"
    assert records["extent"][-1] == pytest.approx(2 * (N - 1) * PORE_SIZE, rel=1e-15)


def test_records_and_units_are_stored_in_the_run_file(run):
    _, result, path = run
    back = read_run(path)
    assert back.observer_units[KIND] == FrontObserver.output_units
    assert list(back.observers[KIND]) == list(FrontObserver.output_units)
    for name, values in result.data.observers[KIND].items():
        np.testing.assert_array_equal(back.observers[KIND][name], values)
    with h5py.File(path) as f:
        assert f[f"observers/{KIND}/front_width"].attrs["units"] == "m"
        assert f[f"observers/{KIND}/invading_pressure"].attrs["units"] == "Pa"


def test_same_seed_same_records_other_seed_other_records(reg, run):
    _, first, _ = run
    again = Simulation.from_scene(scene(), registry=reg).run().data.observers[KIND]
    for name, values in first.data.observers[KIND].items():
        np.testing.assert_array_equal(again[name], values)
    other = Simulation.from_scene(scene(seed=8), registry=reg).run().data.observers[KIND]
    assert not np.array_equal(other["front_position"], first.data.observers[KIND]["front_position"])


def test_injection_at_the_centre_measures_radii(reg):
    sim = Simulation.from_scene(scene(at="centre", every=0.1), registry=reg)
    records = sim.run().data.observers[KIND]
    front = measure(front_geometry(sim.lattice, "centre"), sim.state.drained)
    assert records["front_position"][-1] == front.position * PORE_SIZE
    # breakthrough at the outer edge: the tip is at least half the lattice from the centre
    assert records["extent"][-1] >= (N - 1) * PORE_SIZE


def test_a_record_is_not_repeated_when_the_run_ends_on_a_scheduled_count(reg):
    data = scene(every=0.04)
    data["stop"] = {"at": "complete", "max_drained": 3 * math.ceil(0.04 * N * N)}
    records = Simulation.from_scene(data, registry=reg).run().data.observers[KIND]
    step = math.ceil(0.04 * N * N)
    np.testing.assert_array_equal(records["n_drained"], [step, 2 * step, 3 * step])


def test_observer_pickles_with_the_run(run):
    """``porenet run --checkpoint-every`` pickles observers: plain attributes only."""
    sim, _, _ = run
    (observer,) = [o for o in sim.observers if isinstance(o, FrontObserver)]
    copy = pickle.loads(pickle.dumps(observer))
    assert copy.records == observer.records
    assert copy.geometry is not None
