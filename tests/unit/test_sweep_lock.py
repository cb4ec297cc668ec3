"""The lock of a sweep's output directory (docs/sweeps.md, "The lock"), in this process: held
and released, a second holder refused with the first one's details, stale locks taken over,
file systems without locks. tests/unit/test_sweep_processes.py has two real sweeps."""

from __future__ import annotations

import errno
import json
import logging
import os
import socket
import subprocess
import sys

import pytest

from porenet.cli.main import main
from porenet.sweep import lock as sweep_lock
from porenet.sweep.lock import LOCK_FILE, DirectoryLock, LockHolder, SweepLocked

IP_SWEEP = """
name = "ip"
replicates = 2
[base]
lattice = { n = 16, disorder = 0.3 }
fluid = { kind = "invasion-percolation" }
"""

LINUX = sys.platform.startswith("linux")


def _ended_pid() -> int:
    """The pid of a process that has ended (and been reaped)."""
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def _write_holder(directory, **fields) -> LockHolder:
    holder = LockHolder(
        **{
            "pid": _ended_pid(),
            "host": socket.gethostname(),
            "started": "2026-01-02T03:04:05+00:00",
            "command": "porenet sweep old.toml -o out",
            **fields,
        }
    )
    directory.mkdir(exist_ok=True)
    (directory / LOCK_FILE).write_text(holder.to_text())
    return holder


def test_a_held_lock_refuses_a_second_holder_naming_the_first(tmp_path):
    with DirectoryLock(tmp_path) as held:
        body = json.loads((tmp_path / LOCK_FILE).read_text())
        assert body["pid"] == os.getpid() and body["host"] == socket.gethostname()
        assert body["command"] and body["started"] == held.holder.started
        with pytest.raises(SweepLocked) as info:
            DirectoryLock(tmp_path).acquire()  # another open file: the OS lock refuses it
        message = str(info.value)
        assert message.startswith(f"{tmp_path} is in use by another porenet sweep: pid ")
        assert (
            f"pid {os.getpid()} on host {socket.gethostname()}, started {held.holder.started}, "
            f"command: {held.holder.command} (lock file"
        ) in message
        assert f"(lock file {tmp_path / LOCK_FILE}); wait for it to finish or stop it " in message
        assert f"(kill {os.getpid()}), then re-run this command; or write to another" in message
        assert info.value.exit_status == 1
    assert (tmp_path / LOCK_FILE).read_text() == ""  # released: emptied, left in place
    with DirectoryLock(tmp_path) as again:
        assert again.taken_over is None


def test_a_stale_lock_is_taken_over_with_a_one_line_notice(tmp_path, caplog, capsys):
    """A sweep killed with -9 leaves its details in the lock file; its pid no longer runs."""
    sweep = tmp_path / "ip.toml"
    sweep.write_text(IP_SWEEP)
    out = tmp_path / "out"
    stale = _write_holder(out)
    with caplog.at_level(logging.WARNING, logger="porenet.sweep.lock"):
        assert main(["sweep", str(sweep), "-o", str(out), "-q", "--workers", "1"]) == 0
    notices = [r.getMessage() for r in caplog.records if r.name == "porenet.sweep.lock"]
    assert notices == [
        f"{out}: taking over the lock of a sweep that is no longer running ({stale.describe()})"
    ]
    assert "\n" not in notices[0]
    assert (out / LOCK_FILE).read_text() == "" and len(list((out / "runs").iterdir())) == 2


@pytest.mark.skipif(not LINUX, reason="process start times are read from /proc")
def test_a_reused_pid_is_not_mistaken_for_the_holder(tmp_path):
    """The lock names pid P started at time T; P now runs another process (another start)."""
    ppid = os.getppid()
    stale = _write_holder(tmp_path, pid=ppid, process_start=sweep_lock.process_start(ppid) + 1)
    assert stale.is_running() is False
    with DirectoryLock(tmp_path) as held:
        assert held.taken_over == stale


@pytest.mark.skipif(not LINUX, reason="process start times are read from /proc")
def test_a_running_holder_that_does_not_hold_the_os_lock_is_refused(tmp_path):
    """The lock file names a process that runs (same pid, same start time) although the OS
    lock is free: the file system's locks cannot be trusted, so the pid decides."""
    ppid = os.getppid()
    _write_holder(tmp_path, pid=ppid, process_start=sweep_lock.process_start(ppid))
    with pytest.raises(SweepLocked) as info:
        DirectoryLock(tmp_path).acquire()
    message = str(info.value)
    assert "may be in use by another porenet sweep: the lock file names a process that is " \
           "still running although it does not hold the lock" in message  # fmt: skip
    assert f"if pid {ppid} is not a porenet sweep writing here, delete {tmp_path / LOCK_FILE}" \
           in message  # fmt: skip


def test_without_os_locks_the_pid_in_the_file_decides(tmp_path, monkeypatch, caplog):
    """On a file system that does not lock files (flock fails with ENOLCK)."""
    import fcntl

    def no_locks(fd, operation):
        raise OSError(errno.ENOLCK, os.strerror(errno.ENOLCK))

    monkeypatch.setattr(fcntl, "flock", no_locks)
    with caplog.at_level(logging.WARNING, logger="porenet.sweep.lock"), DirectoryLock(tmp_path):
        pass
    assert "does not lock files" in caplog.text
    # a holder on another host cannot be checked from here: refused, with what to do
    _write_holder(tmp_path, host="elsewhere.example", pid=4242)
    with pytest.raises(SweepLocked) as info:
        DirectoryLock(tmp_path).acquire()
    assert "a process on another host (elsewhere.example), which cannot be checked" in str(
        info.value
    )
    assert f"if that sweep is no longer running on elsewhere.example, delete {tmp_path}" in str(
        info.value
    )
    # a holder that has ended on this host: stale
    stale = _write_holder(tmp_path)
    with DirectoryLock(tmp_path) as held:
        assert held.taken_over == stale


def test_a_lock_file_that_cannot_be_opened_is_an_io_error(tmp_path, monkeypatch, capsys):
    real_open = os.open

    def read_only(path, flags, *args):
        if str(path).endswith(LOCK_FILE):
            raise OSError(errno.EROFS, os.strerror(errno.EROFS))
        return real_open(path, flags, *args)

    monkeypatch.setattr(os, "open", read_only)
    sweep = tmp_path / "ip.toml"
    sweep.write_text(IP_SWEEP)
    out = tmp_path / "out"
    assert main(["sweep", str(sweep), "-o", str(out), "--workers", "1"]) == 1
    err = capsys.readouterr().err
    assert err == (
        f"porenet sweep: error: cannot open {out / LOCK_FILE}: {os.strerror(errno.EROFS)}; "
        "make the directory writable (or use another output directory, -o) and re-run the "
        "same command: it resumes\n"
    )


def test_the_sweep_process_holds_the_lock_whatever_the_executor(tmp_path):
    """As with a dask cluster, the runs execute elsewhere: the lock is the sweep process's."""
    from porenet.sweep import Executor, run_sweep

    out = tmp_path / "out"
    holders = []

    class Elsewhere(Executor):
        workers = 1

        def run(self, tasks, fn):
            for task in tasks:
                holders.append(LockHolder.from_text((out / LOCK_FILE).read_text()))
                with pytest.raises(SweepLocked):
                    DirectoryLock(out).acquire()
                yield task, fn(task)

    sweep = tmp_path / "ip.toml"
    sweep.write_text(IP_SWEEP)
    assert run_sweep(sweep, out, executor=Elsewhere()).done == 2
    assert [h.pid for h in holders] == [os.getpid()] * 2
    assert (out / LOCK_FILE).read_text() == ""
