"""Benchmark: numba's compile time per function for one run with an empty kernel cache.

    NUMBA_CACHE_DIR=$(mktemp -d) python tests/benchmarks/compile_profile.py
    NUMBA_CACHE_DIR=$(mktemp -d) python tests/benchmarks/compile_profile.py SCENE --set lattice.n=50

Runs ``SCENE`` (default: Fig. 1b's at n = 50, as ``bench_compile.py``'s ``viscous-50``) once,
with no classifier, and prints the total compile time and each compiled function's own
compile time (without the callees compiled inside it) as numba's ``numba:compile`` events
report it, the largest first, beside its time with those callees. To compare two revisions,
run it in each tree with ``PYTHONPATH=TREE`` and an empty cache each time
(docs/performance.md, "Issue 21's refactoring"). Not a test: no assertions.
"""

from __future__ import annotations

import argparse
import time
from collections import defaultdict
from pathlib import Path

from numba.core import event

ROOT = Path(__file__).resolve().parents[2]


class _Timer(event.Listener):
    """Seconds per compiled function: with its callees compiled inside it (``seconds``) and
    without them (``own``: what this function's own compilation costs). Compilations nest
    (a caller's type inference compiles its callees), so they are kept on a stack."""

    def __init__(self) -> None:
        self.stack: list[list[float]] = []  # [start, seconds of nested compilations]
        self.seconds: dict[str, float] = defaultdict(float)
        self.own: dict[str, float] = defaultdict(float)
        self.total = 0.0

    def on_start(self, ev: event.Event) -> None:
        self.stack.append([time.perf_counter(), 0.0])

    def on_end(self, ev: event.Event) -> None:
        start, nested = self.stack.pop()
        elapsed = time.perf_counter() - start
        func = ev.data["dispatcher"].py_func
        name = f"{func.__module__}.{func.__qualname__}"
        self.seconds[name] += elapsed
        self.own[name] += elapsed - nested
        if self.stack:
            self.stack[-1][1] += elapsed
        else:
            self.total += elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", nargs="?", default=str(ROOT / "examples/scenes/fig1b.toml"))
    parser.add_argument("--set", action="append", default=None, metavar="KEY=VALUE")
    parser.add_argument("--top", type=int, default=40)
    args = parser.parse_args()
    overrides = args.set if args.set is not None else ["lattice.n=50"]
    timer = _Timer()
    event.register("numba:compile", timer)
    from porenet.simulation import Simulation

    Simulation.from_scene(args.scene, [*overrides, "classifier.kind=none"]).run()
    rows = sorted(timer.own.items(), key=lambda kv: -kv[1])
    print(f"{len(rows)} functions compiled in {timer.total:.1f} s")
    print("| function | own compile time (s) | with its callees (s) |\n|---|---|---|")
    for name, own in rows[: args.top]:
        print(f"| {name} | {own:.2f} | {timer.seconds[name]:.2f} |")


if __name__ == "__main__":
    main()
