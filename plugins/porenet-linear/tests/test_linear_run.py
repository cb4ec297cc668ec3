"""Real runs with the ``linear.springs`` solid coupled to porenet's invasion percolation
(quasi-static: the solid is updated after every drained pore): they complete, write a run file
with the solid's fields, and the stiff limit is the rigid medium."""

from __future__ import annotations

import numpy as np
import pytest
from porenet_linear.config import KIND

from porenet.io.runfile import read_run
from porenet.simulation import Simulation

PORE_SIZE, GAMMA = 1e-4, 0.07


def scene(nf: float, seed: int = 3) -> dict:
    return {
        "seed": seed,
        "lattice": {"kind": "square", "n": 16, "disorder": 0.3, "pore_size": PORE_SIZE},
        "fluid": {"kind": "invasion-percolation", "interfacial_tension": GAMMA},
        "solid": {"kind": KIND, "fracturing_number": nf, "coupling": "every-step"},
        "stop": {"at": "breakthrough"},
        "classifier": {"kind": "none"},
    }


@pytest.fixture(scope="module")
def soft(reg, tmp_path_factory):
    path = tmp_path_factory.mktemp("linear") / "run.h5"
    sim = Simulation.from_scene(scene(1.0), registry=reg, output=path)
    return sim, sim.run(), path


def test_run_completes_and_writes_the_solids_fields(soft):
    sim, _, path = soft
    back = read_run(path)
    summary = back.summary
    assert summary["stop_reason"] == "breakthrough"
    assert summary["fracturing_number"] == pytest.approx(1.0, rel=1e-14)
    k_si = 2 / (0.3 * 1.0) * GAMMA  # N/m
    assert summary["stiffness"] == pytest.approx(k_si, rel=1e-14)
    # every-step coupling: one update per drained pore after the inlet
    assert summary["mechanical_updates"] == summary["n_drained"] - 1
    assert summary["unsettled_updates"] == 0
    final = back.mechanics_final
    np.testing.assert_allclose(final["displacement"], sim.state.displacement * PORE_SIZE)
    np.testing.assert_allclose(final["spring_force"], sim.state.spring_force * GAMMA * PORE_SIZE)
    np.testing.assert_array_equal(final["removed_springs"], sim.state.spring_compression <= 0)
    np.testing.assert_allclose(back.final_apertures, sim.state.apertures * PORE_SIZE)
    assert len(back.mechanics_series["balance_residual"]) == summary["mechanical_updates"]


def test_forces_balance_throughout_the_run(soft):
    _, result, _ = soft
    prestress = 2 / (0.3 * 1.0) * 0.1 * GAMMA * PORE_SIZE  # k h_0 in N
    assert result.data.summary["largest_balance_residual"] < 1e-12 * prestress


def test_invader_pressure_pushes_the_drained_pores_open(soft):
    """The invader's pressure (the defender is at 0) pushes the particles around the drained
    pores apart: their throats widen on average, and contacts open (a soft solid)."""
    sim, result, _ = soft
    tp = np.asarray(sim.lattice.throat_pores)
    touching = sim.state.drained[tp[:, 0]] | sim.state.drained[tp[:, 1]]
    change = sim.state.apertures - sim.lattice.initial_apertures
    assert change[touching].mean() > 0
    assert result.data.summary["springs_removed"] > 0


def test_the_stiff_limit_is_the_rigid_medium(reg):
    """N_f = 1e-9: deformations of order 1e-9 a cannot reorder the entry pressures, so the
    drainage order is the rigid medium's; at N_f = 1 it is not (the solid matters)."""
    rigid_scene = {**scene(1.0), "solid": {"kind": "rigid"}}
    rigid = Simulation.from_scene(rigid_scene, registry=reg).run().data
    stiff = Simulation.from_scene(scene(1e-9), registry=reg).run().data
    np.testing.assert_array_equal(stiff.order, rigid.order)
    np.testing.assert_array_equal(stiff.throat, rigid.throat)
    assert np.abs(stiff.final_apertures - rigid.apertures).max() < 1e-6 * PORE_SIZE
    soft = Simulation.from_scene(scene(1.0), registry=reg).run().data
    assert not np.array_equal(soft.order, rigid.order[: len(soft.order)])
