"""The benchmark scripts' own inputs: a bad scene override stops them before any run, with
the scene's message (exit 2), never a traceback or a half-made table."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks" / "bench_frictional.py"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["profile", "--set", "run.threads=1"], "run: unknown field"),
        (["tolerance", "--variants", "defaults", "solid.friction=-1"], "solid.friction = -1"),
        (["run", "--set", "solid.kind=nope"], "unknown solid kind 'nope'"),
        (["tolerance", "--variants", "solid.friction"], "--variants: 'solid.friction' is not"),
    ],
)
def test_bench_frictional_refuses_a_bad_override_before_running(args, message):
    out = subprocess.run([sys.executable, str(BENCH), *args], capture_output=True, text=True,
                         timeout=120)  # fmt: skip
    assert out.returncode == 2 and "Traceback" not in out.stderr, out.stderr
    assert message in out.stderr and out.stdout == ""


def test_bench_frictional_compares_run_files_made_apart(tmp_path):
    # `compare` gives the tolerance table of kept run files, the first the reference
    from porenet.simulation import Simulation

    scene = BENCH.parents[2] / "examples" / "scenes" / "fig5-mindlin.toml"
    files = []
    for tolerance in ("1e-4", "1e-2"):
        out = tmp_path / f"tol{tolerance}.h5"
        Simulation.from_scene(scene, ["lattice.n=16", f"solid.solver_tolerance={tolerance}"],
                              output=out).run()  # fmt: skip
        files.append(str(out))
    out = subprocess.run([sys.executable, str(BENCH), "compare", *files], capture_output=True,
                         text=True, timeout=120)  # fmt: skip
    assert out.returncode == 0, out.stderr
    rows = [line for line in out.stdout.splitlines() if line.startswith("| tol")]
    assert len(rows) == 2 and rows[0].endswith("| yes | yes | 0 | 0 |")
    bad = subprocess.run([sys.executable, str(BENCH), "compare", files[0], str(tmp_path / "x.h5")],
                         capture_output=True, text=True, timeout=120)  # fmt: skip
    assert bad.returncode == 1 and "Traceback" not in bad.stderr
    assert f"compare: no such run file: {tmp_path / 'x.h5'}" in bad.stderr


def test_bench_frictional_anatomy_splits_the_solver_work():
    # solves an update and V-cycles a solve, with the hierarchies kept and rebuilt before
    # every solve (two components: two builds a solve at least)
    out = subprocess.run([sys.executable, str(BENCH), "anatomy", "--set", "lattice.n=16",
                          "--max-drained", "5"], capture_output=True, text=True,
                         timeout=300)  # fmt: skip
    assert out.returncode == 0, out.stderr
    rows = [line.split(" | ") for line in out.stdout.splitlines()
            if "| kept" in line or "| rebuilt" in line]  # fmt: skip
    assert [(r[0], r[1]) for r in rows] == [
        ("| defaults", "kept (default)"),
        ("| defaults", "rebuilt every solve"),
        ("| solid.friction=0.3", "kept (default)"),
        ("| solid.friction=0.3", "rebuilt every solve"),
    ]
    for row in rows:
        updates, solves, builds = int(row[3]), int(row[4]), int(row[8])
        assert solves >= updates > 0
        if row[1] == "rebuilt every solve":
            assert builds >= 2 * solves


def test_bench_frictional_names_where_two_runs_differ():
    # the tolerance table says where the drained orders part and how many contacts differ
    sys.path.insert(0, str(BENCH.parent))
    from bench_frictional import contacts_column, order_column

    ref = np.arange(10)
    swapped = ref.copy()
    swapped[[3, 4]] = swapped[[4, 3]]
    assert order_column(ref, ref) == "yes"
    assert order_column(ref, swapped) == "no (at 4, 5)"
    assert order_column(ref, ref[::-1]) == "no (10 positions)"
    assert order_column(ref, ref[:8]) == "no (8 drained against 10)"
    open_ = np.array([True, False, True, False])
    assert contacts_column(open_, open_) == "yes"
    assert contacts_column(open_, np.array([True, True, False, False])) == "no (2 differ)"
