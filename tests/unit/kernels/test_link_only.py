"""Kernels that only kernels call: the ``_callee`` twins of porenet.jit.jit, compiled for
linking only (porenet.jit.link_only), on a small tree of kernels; switched off, and after a
failure at compile time, numba's default compilation. Each case runs in new processes that
share one numba cache directory, as a first run, a later run and a run with part of the cache
left, do. The same on porenet's real kernels: test_link_only_fallback.py."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from porenet.jit import link_only

# A small tree: root (allocates, so it uses numba's reference counting) -> rows, a serial and
# a parallel twin -> row (a helper); root also calls a kernel that raises with a message built
# at run time, and a reassociated sum.
KERNELS = """
import numpy as np
from porenet.jit.jit import THREADS, njit, prange, serial_and_parallel


@njit(helper=True)
def row(i, a, out):
    s = 0.0
    for j in range(a.shape[1]):
        s += a[i, j] * (j + 1)
    out[i] = s


def rows(a, out):
    for i in prange(a.shape[0]):
        row(i, a, out)


rows_serial, rows_parallel = serial_and_parallel(rows)


@njit(reassociate=True)
def total(x):
    s = 0.0
    for v in x:
        s += v
    return s


@njit
def check(x, limit):
    for i in range(len(x)):
        if x[i] > limit:
            raise ValueError(f"value at {i} exceeds the limit")


@njit
def root(a, limit, threaded):
    out = np.empty(a.shape[0])
    if THREADS and threaded:
        rows_parallel(a, out)
    else:
        rows_serial(a, out)
    check(out, limit)
    return out, total(out)
"""

PROGRAM = """
import json, sys
import numpy as np
from numba.core import event

compiled = []


class Listener(event.Listener):
    def on_start(self, ev):
        compiled.append(ev.data["dispatcher"].py_func.__qualname__)

    def on_end(self, ev):
        pass


event.register("numba:compile", Listener())
import tree_kernels as k

a = np.arange(60.0).reshape(12, 5) / 7.0
result = {}
for threaded in (False, True):
    out, s = k.root(a, 1e9, threaded)
    result[str(threaded)] = [out.tolist(), s]
direct = np.empty(12)
k.row(3, a, direct)  # a helper called from Python: the Python-side dispatcher
result["direct"] = float(direct[3])
try:
    k.root(a, 1.0, False)
    result["error"] = None
except ValueError as exc:
    result["error"] = str(exc)
print(json.dumps({"result": result, "compiled": compiled}))
"""


def _run(tmp_path, env):
    out = subprocess.run(
        [sys.executable, "-c", PROGRAM], capture_output=True, text=True, env=env, cwd=tmp_path,
        timeout=300,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.fixture
def tree(tmp_path):
    (tmp_path / "tree_kernels.py").write_text(KERNELS)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(tmp_path), env.get("PYTHONPATH")]))
    return tmp_path, env


def _reference():
    a = np.arange(60.0).reshape(12, 5) / 7.0
    out = np.array([sum(a[i, j] * (j + 1) for j in range(5)) for i in range(12)])
    return out


def test_link_only_is_in_use_with_this_numba():
    assert link_only.available()


def test_a_tree_of_callees_runs_is_cached_and_loads_in_part(tree):
    tmp_path, env = tree
    first = _run(tmp_path, env)
    ref = _reference()
    for threaded in ("False", "True"):
        out, s = first["result"][threaded]
        assert np.allclose(out, ref, rtol=1e-15, atol=0)
        assert s == pytest.approx(ref.sum(), rel=1e-14)
    # the serial and the parallel sweep give the same bits
    assert first["result"]["False"] == first["result"]["True"]
    assert first["result"]["direct"] == pytest.approx(ref[3], rel=1e-15)
    # an error raised inside a callee reaches Python with its message
    assert first["result"]["error"] == "value at 0 exceeds the limit"
    # the kernels only root calls compiled as callee twins, never their Python side
    names = set(first["compiled"])
    assert {"root", "rows_callee", "rows_parallel_callee", "check_callee", "total_callee"} <= names
    assert "rows" not in names and "check" not in names
    # a later run loads everything from the cache: nothing compiles, the same bits
    later = _run(tmp_path, env)
    assert later["compiled"] == [] and later["result"] == first["result"]
    # the root's cache entry lost: it compiles again, linking the callees loaded from the cache
    lost = [p for p in (tmp_path / "cache").rglob("*") if ".root-" in p.name]
    assert lost
    for path in lost:
        path.unlink()
    again = _run(tmp_path, env)
    assert "root" in again["compiled"]
    assert not any(name.endswith("_callee") for name in again["compiled"])
    assert again["result"] == first["result"]


def test_switched_off_the_same_results(tree):
    tmp_path, env = tree
    on = _run(tmp_path, env)
    off_env = dict(env, PORENET_LINK_ONLY="0", NUMBA_CACHE_DIR=str(tmp_path / "cache-off"))
    off = _run(tmp_path, off_env)
    assert np.allclose(on["result"]["False"][0], off["result"]["False"][0], rtol=1e-15, atol=0)
    assert on["result"]["error"] == off["result"]["error"]
    # no twin: root calls the kernels' own dispatchers, as numba does by default
    assert not any(name.endswith("_callee") for name in off["compiled"])
    assert {"root", "rows", "rows_parallel", "check", "total"} <= set(off["compiled"])


# A numba internal the link-only machinery needs, made to fail at compile time: "mark", the
# object-cache hooks no longer read the mark on the environments' module (the failure comes
# after the callees were linked in and the environments entered numba's execution engine);
# "constructor", the library class takes other arguments (the failure is in the pass).
FAILURES = {
    "mark": 'link_only._MARK = "_Renamed__library"\n',
    "constructor": (
        "def init(self, codegen, name):\n"
        "    raise TypeError(\"__init__() missing 1 required positional argument: 'options'\")\n"
        "link_only.LinkOnlyLibrary.__init__ = init\n"
    ),
}


@pytest.mark.parametrize("failure", sorted(FAILURES))
def test_a_failure_at_compile_time_falls_back_to_numba_s_default(tree, failure):
    tmp_path, env = tree
    patch = "from porenet.jit import link_only\n" + FAILURES[failure]
    out = subprocess.run(
        [sys.executable, "-c", patch + PROGRAM], capture_output=True, text=True, env=env,
        cwd=tmp_path, timeout=300,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr[-2000:]
    notices = [line for line in out.stderr.splitlines() if "numba does by default" in line]
    assert len(notices) == 1, out.stderr[-2000:]
    assert ("_Renamed__library" if failure == "mark" else "TypeError") in notices[0]
    fell_back = json.loads(out.stdout.strip().splitlines()[-1])
    # the twins are still compiled (as numba does by default), the first one twice
    names = fell_back["compiled"]
    assert "root" in names and len(names) > len(set(names))
    assert "rows" not in names and "check" not in names
    ref = _reference()
    for threaded in ("False", "True"):
        out_, s = fell_back["result"][threaded]
        assert np.allclose(out_, ref, rtol=1e-15, atol=0)
        assert s == pytest.approx(ref.sum(), rel=1e-14)
    assert fell_back["result"]["error"] == "value at 0 exceeds the limit"
    # cached like any numba function: a later run (link-only on) loads it all, the same bits
    later = _run(tmp_path, env)
    assert later["compiled"] == [] and later["result"] == fell_back["result"]


SINGLE = """
import json
import numpy as np
from numba.core import event
from porenet.jit.jit import variant

compiled = []


class Listener(event.Listener):
    def on_start(self, ev):
        compiled.append(ev.data["dispatcher"].py_func.__qualname__)

    def on_end(self, ev):
        pass


event.register("numba:compile", Listener())
import tree_kernels as k

a = np.arange(60.0).reshape(12, 5) / 7.0
one = variant(k.root, THREADS=False)
out, s = one(a, 1e9, True)  # the threaded branch runs the serial twin
print(json.dumps({"out": out.tolist(), "total": s, "compiled": compiled,
                  "same": variant(k.root, THREADS=False) is one,
                  "leaf": variant(k.row, THREADS=False) is k.row}))
"""


@pytest.mark.parametrize("link_only_switch", ["1", "0"])
def test_the_variant_without_threads_runs_the_serial_loops_and_compiles_no_parallel_one(
    tree, link_only_switch
):
    tmp_path, env = tree
    env = dict(env, PORENET_LINK_ONLY=link_only_switch)
    out = subprocess.run(
        [sys.executable, "-c", SINGLE], capture_output=True, text=True, env=env, cwd=tmp_path,
        timeout=300,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr[-2000:]
    got = json.loads(out.stdout.strip().splitlines()[-1])
    full = _run(tmp_path, env)["result"]["True"]
    assert [got["out"], got["total"]] == full  # the same bits as the kernel with threads
    assert "root_without_threads" in got["compiled"]
    assert not any("parallel" in name for name in got["compiled"])
    assert got["same"] and got["leaf"]  # one variant per kernel; none for a kernel without
