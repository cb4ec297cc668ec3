"""Benchmark: what a first run on a fresh machine spends compiling numba's kernels.

    python tests/benchmarks/bench_compile.py               # every case, one run each
    python tests/benchmarks/bench_compile.py --repeat 3 --only quickstart viscous-50

Each case runs as a new process with an empty ``NUMBA_CACHE_DIR`` (a fresh machine's cache),
then once more with the cache it left (a later run). From the first run's stderr (the
``porenet: compiled the kernels of ... in X s`` lines, docs/architecture.md) it takes the
compile time of each phase; "before stepping" is what the lattice and the models' setup and
steps compile (all of it before or in their first call), "after" what the end of the run
compiles (the final trapped set, the classifier). It prints the
wall time of both runs and the compile times. ``porenet compile`` is a case too: all the
kernels at once. Not a test: no assertions. docs/performance.md ("First run") quotes it.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FIG1B = str(ROOT / "examples" / "scenes" / "fig1b.toml")
FIG5 = str(ROOT / "examples" / "scenes" / "fig5.toml")

#: name -> porenet command-line arguments
CASES: dict[str, list[str]] = {
    "quickstart": ["run", "--example", "quickstart"],
    "viscous-50": ["run", FIG1B, "--set", "lattice.n=50"],
    "viscous-50 explicit": ["run", FIG1B, "--set", "lattice.n=50", "--set",
                            "fluid.integrator=explicit"],
    "fig1b capped": ["run", FIG1B, "--set", "stop.max_drained=300"],
    "fig5 n=50": ["run", FIG5, "--set", "lattice.n=50"],
    "porenet compile": ["compile"],
    "porenet compile --jobs 2": ["compile", "--jobs", "2"],
}  # fmt: skip

COMPILED = re.compile(r"porenet: compiled the kernels of (.+) in ([0-9.]+) s")


def one(args: list[str], cache: Path, out: Path) -> tuple[float, list[tuple[str, float]]]:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    extra = ["-o", str(out)] if args[0] == "run" else []
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "porenet", *args, *extra], env=env,
                          capture_output=True, text=True, check=True)  # fmt: skip
    wall = time.perf_counter() - t0
    phases = [(m.group(1), float(m.group(2))) for m in COMPILED.finditer(proc.stderr)]
    return wall, phases


def split(phases: list[tuple[str, float]]) -> tuple[float, float]:
    """Seconds compiled before the run's end (the lattice, the models' setup and steps) and
    at its end (the final trapped set, the classifier)."""
    late = [s for what, s in phases if what == "the end of the run" or "classifier" in what]
    return sum(s for _, s in phases) - sum(late), sum(late)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--only", nargs="+", choices=list(CASES), default=list(CASES))
    args = parser.parse_args()
    print(f"{os.cpu_count()} CPUs; load average before: {os.getloadavg()[0]:.2f}", flush=True)
    rows = []
    for name in args.only:
        firsts, laters, befores, afters = [], [], [], []
        for _ in range(args.repeat):
            cache = Path(tempfile.mkdtemp(prefix="numba-cache-"))
            try:
                out = cache / "run.h5"
                first, phases = one(CASES[name], cache, out)
                if out.exists():
                    out.unlink()
                later, _ = one(CASES[name], cache, out)
            finally:
                shutil.rmtree(cache, ignore_errors=True)
            before, after = split(phases)
            if name.startswith("porenet compile"):
                before, after = first, 0.0  # the whole command compiles
            firsts.append(first)
            laters.append(later)
            befores.append(before)
            afters.append(after)
            print(f"  {name}: first run {first:.1f} s (compiling {before:.1f} s before stepping, "
                  f"{after:.1f} s after), later run {later:.1f} s; phases {phases}",
                  flush=True)  # fmt: skip
        rows.append((name, *(statistics.median(v) for v in (firsts, befores, afters, laters))))
    print()
    print("| case | first run (s) | compiling before stepping (s) | compiling after (s) |"
          " later run (s) |")  # fmt: skip
    print("|---|---|---|---|---|")
    for name, first, before, after, later in rows:
        print(f"| {name} | {first:.1f} | {before:.1f} | {after:.1f} | {later:.1f} |")


if __name__ == "__main__":
    main()
