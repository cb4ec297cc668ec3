"""The viscous model runs the variants of its kernels that its run can use
(porenet.jit.jit.variant, ViscousDrainage.sized): without threads on a lattice too small
for them, without the list sweep on the square grid, without the windows of local time steps
where it cannot take them. A first run compiles less; the results are those of the full
kernels, to the bit."""

from __future__ import annotations

import numpy as np
import pytest

from porenet.jit.jit import PARALLEL_MIN, variant
from porenet.kinds.viscous.kernels.explicit import explicit_advance
from porenet.kinds.viscous.kernels.rkc import rkc_advance
from porenet.kinds.viscous.model import ViscousDrainage
from porenet.simulation import Simulation


def scene(n, integrator, **fluid):
    return {
        "seed": 3,
        "lattice": {"n": n, "disorder": 0.3, "pore_size": 1e-7},
        "fluid": {"kind": "viscous", "capillary_number": 1e-4, "integrator": integrator,
                  "local_steps": "off", **fluid},
        "stop": {"at": "breakthrough"},
        "classifier": {"kind": "none"},
    }  # fmt: skip


CUBIC = {
    "seed": 2,
    "lattice": {"kind": "cubic", "shape": [8, 8, 8], "disorder": 0.5},
    "fluid": {"kind": "viscous", "capillary_number": 1e-3},
    "stop": {"at": "breakthrough"},
    "classifier": {"kind": "none"},
}


def test_each_run_takes_the_variant_it_can_use():
    small = Simulation.from_scene(scene(20, "rkc"))
    small.run()
    assert small.fluid.sized(rkc_advance) is variant(
        rkc_advance, THREADS=False, LISTS=False, WINDOWS=False
    )
    side = int(np.ceil(np.sqrt(PARALLEL_MIN)))
    large = Simulation.from_scene(
        {**scene(side, "rkc"), "stop": {"at": "breakthrough", "max_drained": 2}}
    )
    large.run()
    assert large.fluid.sized(rkc_advance) is variant(rkc_advance, LISTS=False, WINDOWS=False)
    windows = Simulation.from_scene(scene(20, "rkc", local_steps="on"))
    windows.run()
    assert windows.fluid.sized(rkc_advance) is variant(rkc_advance, THREADS=False, LISTS=False)
    listed = Simulation.from_scene({**CUBIC, "stop": {"at": "breakthrough", "max_drained": 2}})
    listed.run()
    assert listed.fluid.sized(explicit_advance) is variant(
        explicit_advance, THREADS=False, WINDOWS=False
    )


CASES = {
    "explicit": scene(20, "explicit"),
    "rkc": scene(20, "rkc"),
    "rkc, local time steps": scene(20, "rkc", capillary_number=1e-5, local_steps="on"),
    "3-D, lists": CUBIC,
}


@pytest.mark.parametrize("name", list(CASES))
def test_the_variant_gives_the_full_kernels_bits(name, monkeypatch):
    sc = CASES[name]
    used = Simulation.from_scene(sc).run().state
    monkeypatch.setattr(ViscousDrainage, "switches", {})  # the full kernels
    full = Simulation.from_scene(sc).run().state
    for field in ("order", "throat", "pressure", "time"):
        assert np.array_equal(getattr(used.record, field), getattr(full.record, field)), field
    assert np.array_equal(used.pressure, full.pressure)
    assert used.time == full.time and used.invading_pressure == full.invading_pressure
