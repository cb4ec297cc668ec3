"""Benchmark: whole runs of this checkout against an older revision, side by side in one run.

    python tests/benchmarks/bench_side_by_side.py --baseline e2ab4d1
    python tests/benchmarks/bench_side_by_side.py --baseline e2ab4d1 --only ip-400 --repeat 9

The baseline revision is checked out into a temporary git worktree. Each case runs in a new
process per repetition, alternating baseline and current (B, C, B, C, ...), after one
untimed run of each that fills numba's cache (a separate cache directory per tree, so that
neither compiles while timed). The time of a run is its ``Simulation.run`` wall time minus
the time it spent compiling (0 with a warm cache); a case shorter than 2 s is run five more
times in the same process (the first run of a process loads the kernels from the cache,
~0.7 s) and the median of those is its time. It prints the medians, the ratio
current / baseline, the median and quartiles of the ratios of each pair of runs made one
after the other (less sensitive to a machine whose speed drifts during the benchmark) and
the spread, and checks that both trees drained the same pores in the
same order. For refactorings that must not change speed (issue 21: within 3 %). Not a test.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FIG1B = str(ROOT / "examples/scenes/fig1b.toml")
FIG5 = str(ROOT / "examples/scenes/fig5.toml")
QUICK = str(ROOT / "porenet/examples/quickstart.toml")

#: name -> (scene file, overrides): every fluid model and integrator, and the solid.
CASES: dict[str, tuple[str, list[str]]] = {
    "ip-400": (QUICK, ["lattice.n=400"]),
    "ip-1000": (QUICK, ["lattice.n=1000"]),
    "explicit-fig1b-3000": (FIG1B, ["stop.max_drained=3000", "fluid.integrator=explicit"]),
    "rkc-n200-ca1e-4": (FIG1B, ["lattice.n=200", "fluid.capillary_number=1e-4",
                                "fluid.integrator=rkc", "fluid.local_steps=off"]),
    "rkc-local-n400-ca1e-5": (FIG1B, ["fluid.capillary_number=1e-5", "fluid.integrator=rkc",
                                      "fluid.local_steps=on", "stop.max_drained=1500"]),
    "implicit-n40-ca1e-6": (FIG1B, ["lattice.n=40", "fluid.capillary_number=1e-6",
                                    "fluid.integrator=implicit"]),
    "hertz-fig5-n100": (FIG5, ["lattice.n=100"]),
    "ip-hertz-n100": (FIG5, ["lattice.n=100", "fluid.kind=invasion-percolation",
                             "fluid.capillary_number=", "fluid.viscosity="]),
}  # fmt: skip

PROGRAM = """
import json, statistics, sys
from porenet.simulation import Simulation
try:
    from porenet.jit.threads import configure_threads
except ImportError:  # a baseline from before the jit/ package
    from porenet.threads import configure_threads
configure_threads(int(sys.argv[3]))
scene, overrides = sys.argv[1], json.loads(sys.argv[2]) + ["classifier.kind=none"]

def once():
    sim = Simulation.from_scene(scene, overrides)
    result = sim.run()
    s = result.summary
    return s["wall_time_s"] - sim.build_time - s["compile_time_s"], result

first, result = once()
times = [first]
if first < 2.0:  # short runs: the first pays the kernels' loading; time five more
    times = [once()[0] for _ in range(5)]
print(json.dumps({"run": statistics.median(times), "drained": result.summary["n_drained"],
                  "order_hash": hash(result.data.order.tobytes())}))
"""


def one(tree: Path, cache: Path, case: tuple[str, list[str]], threads: int) -> dict[str, float]:
    env = dict(os.environ, PYTHONPATH=str(tree), NUMBA_CACHE_DIR=str(cache), PYTHONHASHSEED="0")
    scene, overrides = case
    out = subprocess.run(
        [sys.executable, "-c", PROGRAM, scene, json.dumps(overrides), str(threads)],
        env=env, capture_output=True, text=True, check=True,
    )  # fmt: skip
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--baseline", required=True, help="git revision to compare with")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--only", nargs="+", choices=list(CASES), default=list(CASES))
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="porenet-side-by-side-"))
    base = work / "baseline"
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(base),
                    args.baseline], check=True, capture_output=True)  # fmt: skip
    rev = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                         capture_output=True, text=True).stdout.strip()  # fmt: skip
    print(
        f"{os.cpu_count()} CPUs, load {os.getloadavg()[0]:.2f}; baseline {args.baseline}, "
        f"current {rev} (+ working tree), {args.threads} thread(s), {args.repeat} runs each"
    )
    print("| case | baseline (s) | current (s) | current / baseline | paired ratio | spread "
          "| same order |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    try:
        for name in args.only:
            case = CASES[name]
            trees = {"baseline": base, "current": ROOT}
            caches = {k: work / f"cache-{k}" for k in trees}
            first = {k: one(trees[k], caches[k], case, args.threads) for k in trees}  # warm up
            times: dict[str, list[float]] = {k: [] for k in trees}
            for _ in range(args.repeat):
                for k in trees:
                    times[k].append(one(trees[k], caches[k], case, args.threads)["run"])
            b, c = statistics.median(times["baseline"]), statistics.median(times["current"])
            spread = max(
                (max(v) - min(v)) / statistics.median(v) for v in times.values() if min(v) > 0
            )
            runs = zip(times["baseline"], times["current"], strict=True)
            pairs = sorted(cur / bas for bas, cur in runs)
            low, high = pairs[(len(pairs) - 1) // 4], pairs[-1 - (len(pairs) - 1) // 4]
            same = first["baseline"]["order_hash"] == first["current"]["order_hash"]
            print(f"| {name} | {b:.3f} | {c:.3f} | {c / b:.3f} | "
                  f"{statistics.median(pairs):.3f} ({low:.3f}-{high:.3f}) | "
                  f"±{50 * spread:.0f} % | {'yes' if same else 'NO'} |", flush=True)  # fmt: skip
    finally:
        subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(base)],
                       check=False, capture_output=True)  # fmt: skip
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
