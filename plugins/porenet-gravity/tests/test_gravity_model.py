"""The model against its thresholds, porenet's own invasion percolation and the slow literal
reference (``porenet.testing.reference``); porenet's FluidModel contract is
test_gravity_contract.py's."""

from __future__ import annotations

import numpy as np
import pytest
from porenet_gravity.config import KIND
from porenet_gravity.front import front_statistics
from porenet_gravity.model import GravityInvasionPercolation

from porenet.core.state import State
from porenet.io.runfile import read_run
from porenet.simulation import Simulation
from porenet.testing.reference import reference_invasion
from porenet.viz import make_figure


def scene(n: int = 31, seed: int = 5, stop: str = "breakthrough", **fluid) -> dict:
    return {
        "seed": seed,
        "lattice": {"kind": "square", "n": n, "disorder": 0.3, "pore_size": 1e-4},
        "injection": {"at": "left-edge"},
        "fluid": {"kind": KIND, "bond_number": 0.02, **fluid},
        "stop": {"at": stop},
        "classifier": {"kind": "none"},
    }


def run(reg, data: dict, **kwargs) -> tuple[Simulation, object]:
    sim = Simulation.from_scene(data, registry=reg, **kwargs)
    return sim, sim.run()


def test_thresholds_are_entry_pressure_plus_bond_number_times_height(reg):
    """p_t = 2 / r_t + Bo z_t / a, z_t measured in units of a from the inlet column: on the
    square lattice a horizontal throat (i, j)-(i, j+1) sits at z = 2j + 1, a vertical throat
    of column j at z = 2j (pores at x = 2j + 1)."""
    n, bo = 7, 0.125
    sim, _ = run(reg, scene(n=n, bond_number=bo))
    r = sim.lattice.initial_apertures
    _, j = np.divmod(np.arange(n * (n - 1)), n - 1)
    z_horizontal = 2.0 * j + 1.0
    _, j = np.divmod(np.arange(n * (n - 1)), n)
    z_vertical = 2.0 * j
    z = np.concatenate([z_horizontal, z_vertical])
    np.testing.assert_allclose(sim.fluid.thresholds, 2.0 / r + bo * z, rtol=1e-15)
    down, _ = run(reg, scene(n=n, bond_number=bo, gravity="destabilising"))
    np.testing.assert_allclose(down.fluid.thresholds, 2.0 / r - bo * z, rtol=1e-15, atol=1e-15)


@pytest.mark.parametrize("trapping", [True, False])
@pytest.mark.parametrize("stop", ["breakthrough", "complete"])
@pytest.mark.parametrize("gravity", ["stabilising", "destabilising"])
def test_zero_bond_number_is_porenets_invasion_percolation(reg, trapping, stop, gravity):
    data = scene(n=41, stop=stop, bond_number=0.0, trapping=trapping, gravity=gravity)
    _, mine = run(reg, data)
    builtin = dict(data, fluid={"kind": "invasion-percolation", "trapping": trapping})
    _, theirs = run(reg, builtin)
    for name in ("order", "throat", "invasion_pressure", "drained", "trapped"):
        np.testing.assert_array_equal(getattr(mine.data, name), getattr(theirs.data, name), name)
    assert mine.summary["max_entry_pressure"] == theirs.summary["max_entry_pressure"]
    assert mine.summary["n_drained"] == theirs.summary["n_drained"]


@pytest.mark.parametrize("trapping", [True, False])
@pytest.mark.parametrize(
    ("gravity", "bond_number"), [("stabilising", 0.05), ("destabilising", 0.03)]
)
def test_same_order_as_the_literal_reference_on_the_shifted_thresholds(
    reg, trapping, gravity, bond_number
):
    data = scene(n=13, stop="complete", bond_number=bond_number, trapping=trapping, gravity=gravity)
    sim, result = run(reg, data)
    lat = sim.lattice
    order, trapped = reference_invasion(
        lat.throat_pores,
        sim.fluid.thresholds,
        lat.inlet_pores("left-edge"),
        lat.outlet_mask("left-edge"),
        trapping=trapping,
        stop_at_outlet=False,
    )
    assert result.data.order.tolist() == order
    if trapping:
        assert set(np.flatnonzero(result.data.trapped).tolist()) == trapped


def test_state_and_record_follow_the_thresholds(reg):
    """Beyond the FluidModel contract (test_gravity_contract.py): no pressure field and no
    time, each step's pressure is the threshold of its throat, and breakthrough comes with
    the first outlet pore."""
    sim, result = run(reg, scene(n=41, bond_number=0.03))
    state, lat, fluid = sim.state, sim.lattice, sim.fluid
    size = state.record.size
    order = state.record.order[:size]
    throat = state.record.throat[:size]
    pressure = state.record.pressure[:size]
    assert state.pressure is None and state.time == 0.0 and state.meniscus_length is None
    inlets = len(lat.inlet_pores("left-edge"))
    np.testing.assert_array_equal(pressure[inlets:], fluid.thresholds[throat[inlets:]])
    assert state.invading_pressure == pressure[-1]
    outlet = lat.outlet_mask("left-edge")
    assert state.breakthrough and outlet[order[-1]] and not outlet[order[:-1]].any()
    assert fluid.exhausted and fluid.advance(state, 10) == 0
    assert result.summary["stop_reason"] == "breakthrough"


def test_chunked_advance_replays_the_same_invasion(reg):
    sim, result = run(reg, scene(n=31, stop="complete", bond_number=0.01))
    model = GravityInvasionPercolation(sim.fluid.config, sim.lattice, sim.context)
    state = State.initial(sim.lattice.n_pores, sim.lattice.initial_apertures)
    model.setup(state)
    rng = np.random.default_rng(0)
    calls = 0
    while not model.exhausted:
        model.advance(state, int(rng.integers(0, 40)))
        calls += 1
    model.finalize(state)
    assert calls > 10 and state.step <= calls
    np.testing.assert_array_equal(state.record.order[: state.record.size], result.data.order)
    np.testing.assert_array_equal(state.trapped, sim.state.trapped)
    assert state.invading_pressure == sim.state.invading_pressure


def test_summary_reports_gravity_and_the_front_in_si(reg):
    sim, result = run(reg, scene(n=41, bond_number=0.02, interfacial_tension=0.05))
    a, gamma = 1e-4, 0.05
    s = result.summary
    assert s["bond_number"] == 0.02
    assert s["hydrostatic_gradient"] == pytest.approx(0.02 * gamma / a**2, rel=1e-12)
    steps = sim.state.record.throat[: sim.state.record.size] >= 0
    p_max = sim.state.record.pressure[: sim.state.record.size][steps].max()
    assert s["max_entry_pressure"] == pytest.approx(p_max * gamma / a, rel=1e-12)
    position, width, count = front_statistics(sim.lattice, sim.state.drained)
    assert s["front_pores"] == count > 0
    assert s["front_width"] == pytest.approx(width * a, rel=1e-12)
    assert s["front_position"] == pytest.approx(position * a, rel=1e-12)


def test_run_file_plots_and_classifies(reg, tmp_path):
    path = tmp_path / "gravity.h5"
    data = scene(n=31, bond_number=0.01)
    data["classifier"] = {"kind": "rules"}
    run(reg, data, output=path)
    back = read_run(path)
    assert back.summary["bond_number"] == 0.01 and back.summary["front_width"] > 0
    assert "regime" in back.summary
    for kind in ("pattern", "timeseries"):
        assert make_figure(back, kind) is not None


def test_stabilising_gravity_flattens_the_front_and_destabilising_fingers(reg):
    """At breakthrough: the stabilising field invades more of the lattice than plain IP, with
    a narrower front; the destabilising one invades less (gravity fingering, Wilkinson
    1984). Summed over seeds on one lattice size, so a single odd pattern cannot decide."""
    drained = {}
    width = {}
    for gravity, bo in (("stabilising", 0.02), ("none", 0.0), ("destabilising", 0.02)):
        drained[gravity] = width[gravity] = 0.0
        for seed in range(3):
            g = "stabilising" if gravity == "none" else gravity
            _, result = run(reg, scene(n=61, seed=seed, bond_number=bo, gravity=g))
            drained[gravity] += result.summary["n_drained"]
            width[gravity] += result.summary["front_width"]
    assert drained["stabilising"] > drained["none"] > drained["destabilising"]
    assert width["stabilising"] < width["none"]
