"""Real ``porenet sweep`` processes (docs/sweeps.md, "The lock"): a second sweep on the same
directory is refused at once, naming the first."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

import porenet
from porenet.sweep.lock import LOCK_FILE, LockHolder

#: 6 viscous runs of ~0.3-0.6 s each (n = 40): a few seconds on 2 workers.
SLOW_SWEEP = """
name = "slow"
replicates = 6
[base]
lattice = { n = 40, disorder = 0.3 }
fluid = { kind = "viscous", capillary_number = 1e-4 }
"""

STARTUP_S = 300  # a cold numba cache compiles the kernels first: patience, not a speed test


def _wait_for(condition, timeout: float, what: str, proc: subprocess.Popen | None = None):
    deadline = time.monotonic() + timeout
    while not (result := condition()):
        if proc is not None and proc.poll() is not None:
            pytest.fail(f"the sweep ended (status {proc.returncode}) before {what}")
        if time.monotonic() > deadline:
            pytest.fail(f"no {what} after {timeout} s")
        time.sleep(0.05)
    return result


class Sweep:
    """``python -m porenet sweep`` in a subprocess, with its output in files."""

    def __init__(self, tmp_path: Path, out: Path, name: str = "a") -> None:
        self.tmp_path, self.out, self.name = tmp_path, out, name
        self.sweep = tmp_path / "slow.toml"
        if not self.sweep.exists():
            self.sweep.write_text(SLOW_SWEEP)
        self.env = dict(os.environ, PYTHONPATH=str(Path(porenet.__file__).parents[1]))
        self.args = [sys.executable, "-m", "porenet", "sweep", str(self.sweep), "-o", str(out),
                     "--workers", "2"]  # fmt: skip
        self.proc: subprocess.Popen | None = None

    def start(self, **kwargs) -> subprocess.Popen:
        with (
            (self.tmp_path / f"{self.name}.out").open("w") as out,
            (self.tmp_path / f"{self.name}.err").open("w") as err,
        ):
            self.proc = subprocess.Popen(
                self.args, stdout=out, stderr=err, env=self.env, cwd=self.tmp_path, **kwargs
            )
        return self.proc

    def run(self) -> subprocess.CompletedProcess:
        return subprocess.run(
            self.args, capture_output=True, text=True, env=self.env, cwd=self.tmp_path,
            timeout=STARTUP_S, check=False,
        )  # fmt: skip

    @property
    def stderr(self) -> str:
        return (self.tmp_path / f"{self.name}.err").read_text()

    def kill(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


@pytest.fixture
def sweeps(tmp_path) -> Iterator[list[Sweep]]:
    """Started sweeps, killed at the end whatever happens."""
    started: list[Sweep] = []
    yield started
    for sweep in started:
        sweep.kill()


def test_a_second_sweep_on_the_same_directory_is_refused_at_once(tmp_path, sweeps):
    out = tmp_path / "out"
    first = Sweep(tmp_path, out)
    sweeps.append(first)
    proc = first.start()

    def holder() -> LockHolder | None:
        try:
            return LockHolder.from_text((out / LOCK_FILE).read_text())
        except OSError:
            return None

    held = _wait_for(holder, STARTUP_S, "lock file", proc)
    assert held.pid == proc.pid
    second = Sweep(tmp_path, out, "b").run()
    assert proc.poll() is None  # refused while the first one runs
    assert second.returncode == 1
    assert second.stderr == (
        f"porenet sweep: error: {out} is in use by another porenet sweep: pid {proc.pid} on "
        f"host {socket.gethostname()}, started {held.started}, command: porenet sweep "
        f"{first.sweep} -o {out} --workers 2 (lock file {out / LOCK_FILE}); wait for it to "
        f"finish or stop it (kill {proc.pid}), then re-run this command; or write to another "
        "output directory (-o)\n"
    )
    assert second.stdout == ""
