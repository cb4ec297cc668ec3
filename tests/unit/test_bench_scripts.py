"""The benchmark scripts' own inputs: a bad scene override stops them before any run, with
the scene's message (exit 2), never a traceback or a half-made table."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

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
