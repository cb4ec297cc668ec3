"""Real ``porenet sweep`` processes stopped from outside (docs/sweeps.md, "When a sweep is
stopped or killed", "The lock"): ``kill -9`` of the sweep takes its workers with it and the
sweep resumes; SIGTERM and Ctrl-C stop the workers too; a second sweep on the same directory
is refused at once, naming the first.

The workers are found in /proc (Linux): the children of the sweep process, recorded before it
is killed (a killed sweep's children are re-parented)."""

from __future__ import annotations

import csv
import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

import porenet
from porenet.io.runfile import read_run
from porenet.sweep.lock import LOCK_FILE, LockHolder

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="finds the worker processes in /proc"
)

#: 6 viscous runs of ~0.3-0.6 s each (n = 40): a few seconds on 2 workers.
SLOW_SWEEP = """
name = "slow"
replicates = 6
[base]
lattice = { n = 40, disorder = 0.3 }
fluid = { kind = "viscous", capillary_number = 1e-4 }
"""

STARTUP_S = 300  # a cold numba cache compiles the kernels first: patience, not a speed test
GONE_S = 10  # the workers must be gone within this (they go at once)


def _stat(pid: int) -> list[str] | None:
    """Fields 3... of /proc/PID/stat (state, ppid, ..., starttime at index 19)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii", errors="replace") as fh:
            return fh.read().rsplit(")", 1)[1].split()
    except OSError:
        return None


def _children(pid: int) -> dict[int, str]:
    """The live children of ``pid``: {pid: start time}."""
    found = {}
    for entry in os.listdir("/proc"):
        fields = _stat(int(entry)) if entry.isdigit() else None
        if fields is not None and int(fields[1]) == pid and fields[0] not in "ZX":
            found[int(entry)] = fields[19]
    return found


def _cmdline(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
    except OSError:
        return ""


def _alive(processes: dict[int, str]) -> list[int]:
    """Those of ``processes`` ({pid: start time}) still running (not zombies, not reused)."""
    return [
        pid
        for pid, start in processes.items()
        if (fields := _stat(pid)) is not None and fields[19] == start and fields[0] not in "ZX"
    ]


def _wait_for(condition, timeout: float, what: str, proc: subprocess.Popen | None = None):
    deadline = time.monotonic() + timeout
    while not (result := condition()):
        if proc is not None and proc.poll() is not None:
            pytest.fail(f"the sweep ended (status {proc.returncode}) before {what}")
        if time.monotonic() > deadline:
            pytest.fail(f"no {what} after {timeout} s")
        time.sleep(0.05)
    return result


def _run_files(out: Path) -> set[str]:
    return {p.name for p in (out / "runs").glob("*.h5")}


def _partials(out: Path) -> list[str]:
    return [p.name for p in (*out.glob(".*.partial"), *(out / "runs").glob(".*.partial"))]


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

    def first_run_finished(self) -> set[str]:
        assert self.proc is not None
        return _wait_for(lambda: _run_files(self.out), STARTUP_S, "run file", self.proc)

    def workers(self) -> dict[int, str]:
        """The sweep's worker processes (and multiprocessing's resource tracker)."""
        assert self.proc is not None
        kids = _children(self.proc.pid)
        spawned = [pid for pid in kids if "spawn_main" in _cmdline(pid)]
        assert len(spawned) == 2, {pid: _cmdline(pid) for pid in kids}
        return kids

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


def test_kill_9_takes_the_workers_with_the_sweep_and_a_rerun_resumes(tmp_path, sweeps):
    out = tmp_path / "out"
    sweep = Sweep(tmp_path, out)
    sweeps.append(sweep)
    proc = sweep.start()
    sweep.first_run_finished()
    workers = sweep.workers()
    proc.send_signal(signal.SIGKILL)
    assert proc.wait() == -signal.SIGKILL
    _wait_for(lambda: not _alive(workers), GONE_S, "end of the workers")
    written = _run_files(out)
    assert all(read_run(out / "runs" / name).scene["seed"] for name in written)  # all whole
    time.sleep(1.0)  # orphaned workers would have written another run by now
    assert _run_files(out) == written
    # a temporary left by a worker killed while writing, as the next sweep finds it
    (out / "runs" / ".p0000-r05.h5.k1ll3d.partial").write_bytes(b"\x89HDF half")

    rerun = sweep.run()
    assert rerun.returncode == 0, rerun.stderr
    assert (
        f"WARNING porenet.sweep.lock: {out}: taking over the lock of a sweep that is no longer "
        f"running (pid {proc.pid} on host {socket.gethostname()}, started "
    ) in rerun.stderr
    assert f"6 runs: 6 done, 0 failed ({6 - len(written)} run now, {len(written)} finished " \
           "before)" in rerun.stdout  # fmt: skip
    assert _partials(out) == [] and (out / LOCK_FILE).read_text() == ""
    with (out / "summary.csv").open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["run_id"] for r in rows] == [f"p0000-r{i:02d}" for i in range(6)]
    for row in rows:
        assert row["status"] == "done"
        assert read_run(out / row["run_file"]).summary["seed"] == int(row["seed"])


@pytest.mark.parametrize(
    ("signal_", "status", "message"),
    [
        (signal.SIGTERM, 128 + signal.SIGTERM, "porenet sweep: terminated (SIGTERM): "),
        (signal.SIGINT, 130, "porenet sweep: interrupted: "),
    ],
    ids=["SIGTERM", "ctrl-c"],
)
def test_sigterm_and_ctrl_c_stop_the_workers(tmp_path, sweeps, signal_, status, message):
    """SIGTERM to the sweep (``kill PID``); SIGINT to its whole process group, as Ctrl-C in a
    terminal sends it: the workers stop, nothing half-written is left, the lock is released."""
    out = tmp_path / "out"
    sweep = Sweep(tmp_path, out)
    sweeps.append(sweep)
    proc = sweep.start(start_new_session=True)
    sweep.first_run_finished()
    workers = sweep.workers()
    if signal_ == signal.SIGINT:
        os.killpg(proc.pid, signal.SIGINT)
    else:
        proc.send_signal(signal_)
    assert proc.wait(timeout=60) == status, sweep.stderr
    err = sweep.stderr
    assert message in err and "; re-running the same command resumes" in err
    assert "Traceback" not in err
    _wait_for(lambda: not _alive(workers), GONE_S, "end of the workers")
    written = _run_files(out)
    time.sleep(0.5)
    assert _run_files(out) == written
    assert _partials(out) == [] and (out / LOCK_FILE).read_text() == ""


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


#: A worker as on a system without prctl: only the watcher thread ties it to its parent.
WATCHED = """
import os, signal, sys, time
import porenet.sweep.executors as executors
executors.parent_death_signal = lambda sig: False
executors.die_with_parent(int(sys.argv[1]))
assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
print(os.getpid(), flush=True)
time.sleep(60)
"""

#: Its parent: starts it, then waits to be killed.
PARENT = """
import os, subprocess, sys, time
subprocess.Popen([sys.executable, "-c", sys.argv[1], str(os.getpid())])
time.sleep(60)
"""


def test_without_aparent_death_signal_a_watcher_thread_ends_the_worker(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(Path(porenet.__file__).parents[1]))
    parent = subprocess.Popen(
        [sys.executable, "-c", PARENT, WATCHED], stdout=subprocess.PIPE, text=True, env=env,
        cwd=tmp_path,
    )  # fmt: skip
    try:
        assert parent.stdout is not None
        worker = int(parent.stdout.readline())
        fields = _stat(worker)
        assert fields is not None and int(fields[1]) == parent.pid
        parent.kill()
        parent.wait()
        _wait_for(lambda: not _alive({worker: fields[19]}), GONE_S, "end of the worker")
    finally:
        parent.kill()
        parent.wait()


def test_a_worker_whose_parent_died_before_it_started_ends_at_once(tmp_path):
    """The worker's initializer is told its parent's pid; another parent means it is gone."""
    env = dict(os.environ, PYTHONPATH=str(Path(porenet.__file__).parents[1]))
    code = (
        "import os; import porenet.sweep.executors as e; e.die_with_parent(os.getppid() + 1); "
        "print('still here')"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path,
        timeout=60, check=False,
    )  # fmt: skip
    assert (done.returncode, done.stdout) == (1, "")


#: 2 runs of Fig. 1b's scene, small and explicit (~250 drained pores, < 1 s each).
CHECKPOINTED_SWEEP = """
name = "checkpointed"
replicates = 2
[base]
lattice = { n = 50, disorder = 0.3, pore_size = 1e-7 }
fluid = { kind = "viscous", capillary_number = 9e-4, integrator = "explicit" }
classifier = { kind = "none" }
"""


def test_after_kill_9_the_runs_go_on_from_their_checkpoints(tmp_path, sweeps):
    """docs/sweeps.md, "Checkpoints": the sweep is killed while its runs are mid-way, with a
    checkpoint each; the same command again finishes them from there, to the bit."""
    import numpy as np

    from porenet.simulation import run
    from porenet.sweep.spec import expand, load_sweep

    out = tmp_path / "out"
    sweep = Sweep(tmp_path, out)
    sweep.sweep = tmp_path / "checkpointed.toml"
    sweep.sweep.write_text(CHECKPOINTED_SWEEP)
    sweep.args = [sys.executable, "-m", "porenet", "sweep", str(sweep.sweep), "-o", str(out),
                  "--workers", "2", "--checkpoint-every", "60"]  # fmt: skip
    sweeps.append(sweep)
    proc = sweep.start()
    _wait_for(lambda: list((out / "runs").glob("*.checkpoint")), STARTUP_S, "checkpoint", proc)
    proc.send_signal(signal.SIGKILL)
    assert proc.wait() == -signal.SIGKILL
    time.sleep(0.5)  # the workers die with the sweep
    checkpoints = sorted((out / "runs").glob("*.checkpoint"))
    assert checkpoints and len(checkpoints) + len(_run_files(out)) <= 2

    rerun = sweep.run()
    assert rerun.returncode == 0, rerun.stderr
    assert f"{len(checkpoints)} of them from a checkpoint" in rerun.stdout, rerun.stdout
    assert list((out / "runs").glob("*.checkpoint")) == [] and _partials(out) == []
    for spec in expand(load_sweep(sweep.sweep)):
        reference = run(spec.scene, output=tmp_path / f"{spec.run_id}.h5").data
        resumed = read_run(out / spec.run_file)
        for name in ("order", "throat", "invasion_pressure", "invasion_time", "pressure"):
            assert np.array_equal(getattr(reference, name), getattr(resumed, name)), name
