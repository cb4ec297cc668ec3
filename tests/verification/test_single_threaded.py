"""On a lattice too small for threads, the viscous model runs the single-threaded variants of
its kernels (porenet.kernels.jit.single_threaded), which a first run compiles without any
parallel loop: the results are those of the full kernels, to the bit."""

from __future__ import annotations

import numpy as np
import pytest

from porenet.builtin.fluids.viscous import ViscousDrainage
from porenet.kernels.jit import PARALLEL_MIN, single_threaded
from porenet.kernels.viscous.explicit import explicit_advance
from porenet.kernels.viscous.rkc import rkc_advance
from porenet.simulation import Simulation


def scene(n, integrator):
    return {
        "seed": 3,
        "lattice": {"n": n, "disorder": 0.3, "pore_size": 1e-7},
        "fluid": {"kind": "viscous", "capillary_number": 1e-4, "integrator": integrator,
                  "local_steps": "off"},
        "stop": {"at": "breakthrough"},
        "classifier": {"kind": "none"},
    }  # fmt: skip


def test_small_lattices_take_the_variant_large_ones_the_full_kernel():
    small = Simulation.from_scene(scene(20, "rkc"))
    small.run()
    assert small.fluid.sized(rkc_advance) is single_threaded(rkc_advance) is not rkc_advance
    side = int(np.ceil(np.sqrt(PARALLEL_MIN)))
    large = Simulation.from_scene(
        {**scene(side, "rkc"), "stop": {"at": "breakthrough", "max_drained": 2}}
    )
    large.run()
    assert large.fluid.sized(rkc_advance) is rkc_advance
    assert large.fluid.sized(explicit_advance) is explicit_advance


@pytest.mark.parametrize("integrator", ["explicit", "rkc"])
def test_the_variant_gives_the_full_kernels_bits(integrator, monkeypatch):
    variant = Simulation.from_scene(scene(20, integrator)).run().state
    monkeypatch.setattr(ViscousDrainage, "full_kernels", True)
    full = Simulation.from_scene(scene(20, integrator)).run().state
    for name in ("order", "throat", "pressure", "time"):
        assert np.array_equal(getattr(variant.record, name), getattr(full.record, name)), name
    assert np.array_equal(variant.pressure, full.pressure)
    assert variant.time == full.time and variant.invading_pressure == full.invading_pressure
