"""The parallel kernels: thread control, serial/parallel twins, and numba's on-disk cache."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np

from porenet.jit.jit import PARALLEL_MIN, set_threads, threads
from porenet.kinds.viscous.kernels.diffusion import copy_rows

# A kernel cached by a process that loaded its parallel callee from the cache does not start
# numba's threading layer when a third process loads it (numba issue #8578): its first call
# crashed the process before porenet started the layer itself on import.
OUTER = """
import numpy as np
from numba import njit
from porenet.kinds.viscous.kernels.diffusion import copy_rows

@njit(cache=True)
def outer(n, src, dst):
    copy_rows(n, np.array([0, n, 0, n], dtype=np.int64), src, dst)
"""

CALL = """
import sys
import numpy as np
n = 100
src = np.arange(n * n, dtype=float)
dst = np.zeros(n * n)
if sys.argv[1] == "inner":
    from porenet.kinds.viscous.kernels.diffusion import copy_rows
    copy_rows(n, np.array([0, n, 0, n], dtype=np.int64), src, dst)
else:
    from outer_kernel import outer
    outer(n, src, dst)
assert np.array_equal(src, dst)
print("ok")
"""


def test_a_cached_kernel_calling_a_parallel_one_runs_when_loaded_from_the_cache(tmp_path):
    (tmp_path / "outer_kernel.py").write_text(OUTER)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(tmp_path), env.get("PYTHONPATH")]))
    # 1: compiles and caches copy_rows; 2: loads it, compiles and caches outer; 3: loads outer
    for step, which in enumerate(("inner", "outer", "outer"), start=1):
        out = subprocess.run(
            [sys.executable, "-c", CALL, which], capture_output=True, text=True, env=env,
            cwd=tmp_path, timeout=300,
        )  # fmt: skip
        assert out.returncode == 0 and out.stdout.strip() == "ok", (step, out.returncode)


def test_set_threads_clamps_to_what_numba_allows():
    before = threads()
    try:
        assert set_threads(0) == 1 == threads()
        assert set_threads(10_000) == threads() >= 1
        assert set_threads(None) == threads()
    finally:
        set_threads(before)


def test_serial_and_parallel_paths_copy_the_same_box():
    n = 90  # 90 x 90 > PARALLEL_MIN: the parallel path; a 20 x 20 box: the serial one
    assert n * n >= PARALLEL_MIN > 20 * 20
    rng = np.random.default_rng(0)
    src = rng.random(n * n)
    for box in ([0, n, 0, n], [10, 30, 5, 25]):
        dst = np.zeros(n * n)
        b = np.array(box, dtype=np.int64)
        copy_rows(n, b, src, dst)
        inside = np.zeros((n, n), dtype=bool)
        inside[b[0] : b[1], b[2] : b[3]] = True
        assert np.array_equal(dst[inside.ravel()], src[inside.ravel()])
        assert not dst[~inside.ravel()].any()
