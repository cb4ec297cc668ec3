"""Benchmark: size of a checkpoint and the time to write and load it, for the paper's scenes.

    python tests/benchmarks/bench_checkpoint.py            # Fig. 1b and Fig. 5 at n = 400
    python tests/benchmarks/bench_checkpoint.py --n 200 --repeat 5

Each scene runs until a checkpoint after ``--drained`` pores is written (the schedule stops
the run there); then the checkpoint is written ``--repeat`` more times and loaded as often,
and the medians are printed. docs/run-file.md ("Checkpoints") quotes it. Not a test.
"""

from __future__ import annotations

import argparse
import contextlib
import statistics
import tempfile
import time
from pathlib import Path

from porenet.io.checkpoint import CheckpointSchedule, load_checkpoint
from porenet.simulation import Simulation
from porenet.testing.runs import Killed, KilledAfterCheckpoint

ROOT = Path(__file__).resolve().parents[2]
SCENES = {"fig1b": ROOT / "examples/scenes/fig1b.toml", "fig5": ROOT / "examples/scenes/fig5.toml"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=400)
    parser.add_argument("--drained", type=int, default=2000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--only", nargs="+", choices=list(SCENES), default=list(SCENES))
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="porenet-ckpt-"))
    print("| scene | n | drained | checkpoint (MB) | write (s) | load (s) |")
    print("|---|---|---|---|---|---|")
    for name in args.only:
        path = folder / f"{name}.h5.checkpoint"
        sim = Simulation.from_scene(SCENES[name], [f"lattice.n={args.n}"])
        with contextlib.suppress(Killed):
            sim.run(KilledAfterCheckpoint(path, every_drained=args.drained))
        writes, loads = [], []
        schedule = CheckpointSchedule(path)
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            schedule.write(sim)
            writes.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            load_checkpoint(path)
            loads.append(time.perf_counter() - t0)
        size = path.stat().st_size / 1e6
        print(f"| {name} | {args.n} | {sim.state.n_drained} | {size:.1f} | "
              f"{statistics.median(writes):.2f} | {statistics.median(loads):.2f} |")  # fmt: skip


if __name__ == "__main__":
    main()
