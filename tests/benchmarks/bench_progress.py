"""Benchmark: when a run first shows progress, on a terminal and in a log.

    python tests/benchmarks/bench_progress.py                # a 200 x 200 viscous scene
    python tests/benchmarks/bench_progress.py --set lattice.n=400 --set stop.max_drained=3000

Runs ``porenet run examples/scenes/fig1b.toml --set lattice.n=200`` twice as a new process:
once on a pseudo-terminal (as a user at a shell sees it) and once with stderr to a pipe (a
batch job, ``nohup``). For each, the wall time (from the start of the process) of every
piece of stderr: the start line, the compile notices, the first status line (terminal) or
the log lines (pipe). Prints, for the terminal, the time from the end of the last compile
notice (or the start line, if nothing compiled) to the first status line — "progress
within 2 s of the start of stepping" — and, for the pipe, the intervals between log lines.
Not a test: no assertions. docs/performance.md ("Progress") quotes it.
"""

from __future__ import annotations

import argparse
import os
import pty
import select
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENE = str(ROOT / "examples" / "scenes" / "fig1b.toml")


def _command(sets: list[str], out: Path) -> list[str]:
    extra = [a for s in sets for a in ("--set", s)]
    return [sys.executable, "-m", "porenet", "run", SCENE, "-o", str(out), *extra]


def on_terminal(cmd: list[str]) -> list[tuple[float, str]]:
    """(seconds, text) of each chunk the run wrote to its terminal."""
    leader, follower = pty.openpty()
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdin=follower, stdout=follower, stderr=follower)
    os.close(follower)
    chunks: list[tuple[float, str]] = []
    while True:
        ready, _, _ = select.select([leader], [], [], 0.2)
        if ready:
            try:
                data = os.read(leader, 65536)
            except OSError:
                break
            if not data:
                break
            chunks.append((time.perf_counter() - t0, data.decode(errors="replace")))
        elif proc.poll() is not None:
            break
    proc.wait()
    os.close(leader)
    return chunks


def in_a_log(cmd: list[str]) -> list[tuple[float, str]]:
    """(seconds, line) of each line the run wrote to its stderr, a pipe."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    lines = [(time.perf_counter() - t0, line.rstrip()) for line in proc.stderr]  # type: ignore[union-attr]
    proc.wait()
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--set", action="append", default=None, metavar="KEY=VALUE")
    args = parser.parse_args()
    sets = args.set or ["lattice.n=200"]
    tmp = Path(tempfile.mkdtemp())
    chunks = on_terminal(_command(sets, tmp / "tty.h5"))
    start = next((t for t, c in chunks if "porenet: run" in c), None)
    ready = max((t for t, c in chunks if "compiled the kernels" in c), default=start)
    first = next((t for t, c in chunks if "\r  drained" in c and ready is not None and t >= ready),
                 None)  # fmt: skip
    print(
        f"terminal: start line at {start:.2f} s, stepping from ~{ready:.2f} s, first status "
        f"line at {first:.2f} s: {first - ready:.2f} s after the start of stepping"
    )
    for t, c in chunks:
        if "porenet:" in c:
            for line in c.splitlines():
                if line.startswith("porenet:"):
                    print(f"  {t:7.2f} s  {line[:110]}")
    lines = in_a_log(_command(sets, tmp / "log.h5"))
    print("log (stderr a pipe):")
    last = None
    for t, line in lines:
        gap = "" if last is None else f" (+{t - last:.1f} s)"
        print(f"  {t:7.2f} s{gap}  {line[:110]}")
        last = t


if __name__ == "__main__":
    main()
