"""Link-only compilation on porenet's real kernels: when a numba internal it relies on is
missing at compile time it falls back to numba's default compilation (one notice, the same
results, a cache that later runs load), and ``PORENET_LINK_ONLY=0`` patches nothing
(porenet.jit.link_only's docstring). Each case runs in a new process with its own numba
cache, as a first run on a new machine does."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np

NOTICE = "kernels compile as numba does by default"

SCENE = {
    "seed": 1,
    "lattice": {"kind": "square", "n": 12, "disorder": 0.3, "pore_size": 1e-7},
    "fluid": {"kind": "invasion-percolation"},
}

# Runs the tiny invasion-percolation scene; with "missing" as its argument, the link-only
# finalize finds an instance attribute it reads missing (as after numba renamed it).
RUN = """
import json, sys
from numba.core import event
from porenet.jit import link_only

if sys.argv[2] == "missing":
    finalize = link_only.LinkOnlyLibrary._finalize_link_only

    def without_reload_init(self):
        del self._reload_init
        return finalize(self)

    link_only.LinkOnlyLibrary._finalize_link_only = without_reload_init

compiled = []


class Listener(event.Listener):
    def on_start(self, ev):
        compiled.append(ev.data["dispatcher"].py_func.__qualname__)

    def on_end(self, ev):
        pass


event.register("numba:compile", Listener())
from porenet.simulation import Simulation

data = Simulation.from_scene(json.loads(sys.argv[1])).run().data
print(json.dumps({"order": data.order.tolist(), "pressure": data.invasion_pressure.tolist(),
                  "drained": data.drained.tolist(), "compiled": compiled,
                  "active": link_only.active()}))
"""


def _outcome(data):
    return {
        "order": data.order.tolist(),
        "pressure": data.invasion_pressure.tolist(),
        "drained": data.drained.tolist(),
    }


def _run(env, how):
    done = subprocess.run(
        [sys.executable, "-c", RUN, json.dumps(SCENE), how], env=env, capture_output=True,
        text=True, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1]), done.stderr


def test_a_missing_internal_at_compile_time_falls_back_with_the_same_result(tmp_path):
    from porenet.simulation import Simulation

    # this process's kernels (link-only on, as the suite runs) give the reference
    reference = _outcome(Simulation.from_scene(SCENE).run().data)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    env.pop("PORENET_LINK_ONLY", None)
    first, stderr = _run(env, "missing")
    # one notice, naming what was missing
    notices = [line for line in stderr.splitlines() if NOTICE in line]
    assert len(notices) == 1 and "_reload_init" in notices[0], stderr[-3000:]
    assert not first["active"]
    # the twin that failed is compiled again (numba's default), and so are the kernels after it
    twins = [name for name in first["compiled"] if name.endswith("_callee")]
    assert len(twins) > len(set(twins)) and len(set(twins)) > 5
    assert {k: first[k] for k in reference} == reference
    # a later run (link-only on) loads every kernel from that cache: nothing compiles
    later, stderr = _run(env, "as-is")
    assert NOTICE not in stderr
    assert later["active"] and later["compiled"] == []
    assert {k: later[k] for k in reference} == reference


# Imports the invasion-percolation kernels and reports, for every porenet kernel, whether numba's
# dispatcher methods were rebound, and how many ``_callee`` twins exist.
KERNELS = """
import gc, importlib, json, pkgutil
from numba.core.dispatcher import Dispatcher
import porenet.kinds.invasion.kernels as package
from porenet.jit import jit, link_only

for module in pkgutil.iter_modules(package.__path__):
    importlib.import_module(package.__name__ + "." + module.name)
kernels = [dispatcher for dispatcher, _ in jit._OPTIONS.values()]
rebound = [sorted({"get_call_template", "get_overload"} & set(vars(k))) for k in kernels]
twins = [o for o in gc.get_objects() if isinstance(o, Dispatcher)
         and o.py_func.__name__.endswith("_callee")]
print(json.dumps({"kernels": len(kernels), "rebound": sum(map(bool, rebound)),
                  "all_rebound": all(r == ["get_call_template", "get_overload"] for r in rebound),
                  "twins": len(twins), "pipeline": link_only.PIPELINE is not None}))
"""


def test_switched_off_a_kernel_is_a_plain_numba_dispatcher(tmp_path):
    report = {}
    for switch in ("1", "0"):
        env = dict(os.environ, PORENET_LINK_ONLY=switch, NUMBA_CACHE_DIR=str(tmp_path / switch))
        done = subprocess.run(
            [sys.executable, "-c", KERNELS], env=env, capture_output=True, text=True, timeout=300
        )
        assert done.returncode == 0, done.stderr[-3000:]
        assert NOTICE not in done.stderr
        report[switch] = json.loads(done.stdout.strip().splitlines()[-1])
    on, off = report["1"], report["0"]
    assert on["kernels"] == off["kernels"] > 10
    assert on["pipeline"] and on["all_rebound"] and on["twins"] == on["kernels"]
    assert not off["pipeline"] and off["rebound"] == 0 and off["twins"] == 0


def test_unavailable_is_switched_off_with_one_notice(monkeypatch, caplog):
    from numba.core import codegen

    from porenet.jit import jit, link_only

    # a numba without a class-level internal: no pipeline, and what is missing is named
    monkeypatch.delattr(codegen.CPUCodeLibrary, "_verify_declare_only_symbols")
    pipeline, library, missing = link_only._build()
    assert pipeline is None and library is None
    assert "_verify_declare_only_symbols" in missing
    monkeypatch.undo()
    # as switched off: the notice once, and kernels are plain dispatchers
    monkeypatch.setattr(link_only, "_build", lambda: (None, None, "missing X.y"))
    monkeypatch.setattr(link_only, "_noticed", False)
    monkeypatch.delenv("PORENET_LINK_ONLY", raising=False)
    with caplog.at_level("WARNING", logger="porenet.jit.link_only"):
        assert link_only._pipeline() == (None, None)
        assert link_only._pipeline() == (None, None)
    assert len(caplog.records) == 1
    assert NOTICE in caplog.text and "missing X.y" in caplog.text
    monkeypatch.setattr(link_only, "PIPELINE", None)
    monkeypatch.setattr(jit, "_OPTIONS", dict(jit._OPTIONS))

    def double(x):
        return 2 * x

    kernel = jit._kernel(double, {"cache": False})
    assert "get_call_template" not in vars(kernel) and "get_overload" not in vars(kernel)
    assert kernel(np.float64(2.0)) == 4.0
