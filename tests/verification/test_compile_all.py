"""``porenet compile`` compiles every kernel a run of the built-in models can call.

In a fresh numba cache (a new machine), ``porenet compile`` runs its tiny warm-up scenes;
then runs of other sizes, integrators, controls, solids and stops must not compile anything
(numba's compile events, counted by :class:`porenet.jit.compilation.CompileWatch`).

Both processes run with ``PORENET_LINK_ONLY=0``, so this is also the suite's one compilation of
every real kernel through numba's default path, the one link-only compilation falls back to
(porenet.jit.link_only); the rest of the suite compiles them link-only, as users' runs do.
Costs the compilation of everything once, the default way, which compiles more (every level
of a kernel tree, numba's wrappers and literal variants): ``porenet compile --jobs 2`` took
385 s of wall time against 210 s link-only, on 2 cores shared with other work.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

CHECK = r"""
import json, sys
from porenet.jit.compilation import watch
from porenet.simulation import Simulation
w = watch()
fig1b, fig5, ip, cubic, mindlin = sys.argv[1:6]
cases = [
    (fig1b, ["lattice.n=100"]),
    (fig1b, ["lattice.n=100", "fluid.capillary_number=1e-5"]),
    (fig1b, ["lattice.n=70", "fluid.integrator=explicit", "injection.at=left-edge"]),
    (fig1b, ["lattice.n=80", "fluid.capillary_number=1e-5", "fluid.local_steps=on"]),
    (fig1b, ["lattice.n=30", "fluid.integrator=implicit", "fluid.capillary_number=1e-5"]),
    (fig1b, ["lattice.n=40", "fluid.control=pressure", "fluid.capillary_number=",
             "fluid.injection_pressure=1.6e6", "fluid.max_time=1e-6"]),
    (fig5, ["lattice.n=40"]),
    (fig5, ["lattice.n=30", "solid.solver=sparse-direct", "fluid.kind=invasion-percolation",
            "fluid.capillary_number=", "fluid.viscosity="]),
    (ip, ["lattice.n=100", "stop.at=complete"]),
    (ip, ["lattice.n=100", "fluid.trapping=false"]),
    (cubic, ["lattice.shape=[10, 10, 10]"]),
    (cubic, ["lattice.shape=[10, 10, 10]", "fluid.integrator=rkc", "injection.at=z-"]),
    (mindlin, ["lattice.n=60"]),
    (mindlin, ["lattice.n=50", "solid.friction=0.2", "solid.fracturing_number=3"]),
    (mindlin, ["lattice.n=20", "solid.rotation=free", "solid.fracturing_number=0.1"]),
]
counts = []
for scene, sets in cases:
    Simulation.from_scene(scene, sets + ["stop.max_drained=300"]).run()
    counts.append(w.count)
print(json.dumps(counts))
"""


@pytest.mark.long
def test_after_porenet_compile_no_run_compiles(tmp_path):
    # numba's default compilation, no link-only twins (the module's docstring)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"), PORENET_LINK_ONLY="0")
    done = subprocess.run(
        [sys.executable, "-m", "porenet", "compile", "--jobs", "2"],
        env=env, capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "porenet compile:" in done.stdout
    scenes = [str(ROOT / "examples" / "scenes" / f) for f in ("fig1b.toml", "fig5.toml",
                                                                "ip-400.toml",
                                                                "cubic-viscous.toml",
                                                                "fig5-mindlin.toml")]  # fmt: skip
    check = subprocess.run(
        [sys.executable, "-c", CHECK, *scenes], env=env, capture_output=True, text=True,
        check=False,
    )  # fmt: skip
    assert check.returncode == 0, check.stderr
    assert json.loads(check.stdout.strip().splitlines()[-1]) == [0] * 15
