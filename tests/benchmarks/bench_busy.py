"""Benchmark: a run's default threads against ``--threads 1``, on a quiet and a busy machine.

    python tests/benchmarks/bench_busy.py                    # Fig. 1b to breakthrough
    python tests/benchmarks/bench_busy.py --max-drained 3000 --repeat 5   # a capped Fig. 1b
    python tests/benchmarks/bench_busy.py --threads auto 1 2 # also a fixed 2 threads
    python tests/benchmarks/bench_busy.py --threads 2 1 --env OMP_WAIT_POLICY=passive
                                                             # an OpenMP wait policy instead

Each run is ``porenet run examples/scenes/fig1b.toml -q --threads T`` as a new process (the
numba cache warm: one small run first), under three loads that the script starts and stops
itself: nothing else (``quiet``), one and two CPU-bound processes (``busy1``, ``busy2``: a
plain Python busy loop each). Within a load the thread settings alternate, ``--repeat``
times; the script prints the median wall time of each setting, the ratio of each to
``--threads 1`` measured in the same load, and what the governor did (its final count,
switches and probes, from the run file's summary). Not a test: no assertions.
docs/performance.md ("Threads on a busy machine") quotes it.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "examples" / "scenes" / "fig1b.toml"
BUSY = "while True: pass"


def run_once(threads: str, extra: list[str], out: Path, env: dict[str, str]) -> tuple[float, dict]:
    cmd = [sys.executable, "-m", "porenet", "run", str(SCENE), "-q", "-o", str(out),
           "--threads", threads, *extra]  # fmt: skip
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, env=dict(os.environ, **env))
    wall = time.perf_counter() - t0
    import h5py

    with h5py.File(out) as f:
        attrs = dict(f["summary"].attrs)
    out.unlink()
    return wall, attrs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs of each setting per load")
    parser.add_argument("--threads", nargs="+", default=["auto", "1"], help="settings to time")
    parser.add_argument("--loads", nargs="+", type=int, default=[0, 1, 2],
                        help="numbers of busy processes beside the runs")  # fmt: skip
    parser.add_argument("--max-drained", type=int, default=None, help="cap the run")
    parser.add_argument("--env", action="append", default=[], metavar="KEY=VALUE",
                        help="environment of the runs, e.g. OMP_WAIT_POLICY=passive or "
                        "NUMBA_THREADING_LAYER=workqueue (repeatable)")  # fmt: skip
    args = parser.parse_args()
    env = dict(item.split("=", 1) for item in args.env)
    if args.repeat < 1:
        parser.error("--repeat must be at least 1")
    extra = ["--set", "classifier.kind=none"]
    if args.max_drained is not None:
        extra += ["--set", f"stop.max_drained={args.max_drained}"]
    settings = list(dict.fromkeys(args.threads))
    if "1" not in settings:
        settings.append("1")
    print(f"scene {SCENE.name} {' '.join(extra)}; env {env}; {os.cpu_count()} CPUs; load "
          f"average before: {os.getloadavg()[0]:.2f}", flush=True)  # fmt: skip
    tmp = Path(tempfile.mkdtemp())
    subprocess.run([sys.executable, "-m", "porenet", "run", str(SCENE), "-q", "-o",
                    str(tmp / "warm.h5"), "--set", "lattice.n=64"], check=True)  # fmt: skip
    rows = []
    for load in args.loads:
        busy = [subprocess.Popen([sys.executable, "-c", BUSY]) for _ in range(load)]
        try:
            time.sleep(1.0)
            walls: dict[str, list[float]] = {s: [] for s in settings}
            last: dict[str, dict] = {}
            for r in range(args.repeat):
                order = settings if r % 2 == 0 else settings[::-1]
                for s in order:
                    wall, attrs = run_once(s, extra, tmp / f"run-{s}.h5", env)
                    walls[s].append(wall)
                    last[s] = attrs
                    print(f"  busy {load}, --threads {s}: {wall:.1f} s "
                          f"(final {attrs.get('threads_final')}, switches "
                          f"{attrs.get('thread_switches')}, probes {attrs.get('thread_probes')}, "
                          f"steps {attrs.get('time_steps')}, drained {attrs.get('n_drained')}, "
                          f"threaded s on 1/most {attrs.get('threaded_seconds_one', 0):.1f}/"
                          f"{attrs.get('threaded_seconds_most', 0):.1f})",
                          flush=True)  # fmt: skip
        finally:
            for p in busy:
                p.kill()
                p.wait()
        one = statistics.median(walls["1"])
        for s in settings:
            med = statistics.median(walls[s])
            rows.append((load, s, med, walls[s], med / one, last[s]))
    print()
    print("| busy processes | --threads | median wall (s) | runs (s) | / --threads 1 |"
          " final threads, switches, probes (last run) |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    for load, s, med, runs, ratio, attrs in rows:
        runs_text = ", ".join(f"{w:.1f}" for w in runs)
        gov = (f"{attrs.get('threads_final')}, {attrs.get('thread_switches')}, "
               f"{attrs.get('thread_probes')}")  # fmt: skip
        print(f"| {load} | {s} | {med:.1f} | {runs_text} | {ratio:.2f} | {gov} |")


if __name__ == "__main__":
    main()
