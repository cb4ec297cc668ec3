"""Benchmark: numba's compile time per function for one run with an empty kernel cache.

    NUMBA_CACHE_DIR=$(mktemp -d) python tests/benchmarks/compile_profile.py
    NUMBA_CACHE_DIR=$(mktemp -d) python tests/benchmarks/compile_profile.py SCENE --set lattice.n=50

Runs ``SCENE`` (default: Fig. 1b's at n = 50, as ``bench_compile.py``'s ``viscous-50``) once,
with no classifier, and prints each compiled function's compile time as numba's
``numba:compile`` events report it (a function's time includes the callees compiled inside
it), the largest first. To compare two revisions, run it in each tree with
``PYTHONPATH=TREE`` and an empty cache each time (docs/performance.md, "Issue 21's
refactoring"). Not a test: no assertions.
"""

from __future__ import annotations

import argparse
import time
from collections import defaultdict
from pathlib import Path

from numba.core import event

ROOT = Path(__file__).resolve().parents[2]


class _Timer(event.Listener):
    """Seconds per compiled function (the outermost event of each dispatcher and signature)."""

    def __init__(self) -> None:
        self.started: dict[tuple[int, str], float] = {}
        self.seconds: dict[str, float] = defaultdict(float)

    def on_start(self, ev: event.Event) -> None:
        self.started[id(ev.data["dispatcher"]), str(ev.data["args"])] = time.perf_counter()

    def on_end(self, ev: event.Event) -> None:
        key = (id(ev.data["dispatcher"]), str(ev.data["args"]))
        start = self.started.pop(key, None)
        if start is not None:
            func = ev.data["dispatcher"].py_func
            self.seconds[f"{func.__module__}.{func.__qualname__}"] += time.perf_counter() - start


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
    rows = sorted(timer.seconds.items(), key=lambda kv: -kv[1])
    print(f"{len(rows)} functions compiled")
    print("| function | compile time with its callees (s) |\n|---|---|")
    for name, seconds in rows[: args.top]:
        print(f"| {name} | {seconds:.2f} |")


if __name__ == "__main__":
    main()
