"""The lock of a sweep's output directory: one sweep at a time writes into it.

A sweep holds ``DIR/.lock`` for its whole life: an operating-system lock on the file
(``fcntl.flock``), which the kernel releases when the process ends in any way, ``kill -9``
included, plus a small JSON body naming the holder (pid, host, start time, command) for the
message that a second sweep on the same directory gets (docs/sweeps.md, "The lock").

- Another process holds the OS lock: :class:`SweepLocked`, naming the holder.
- The OS lock is free but the body names a process: that sweep ended without releasing it
  (killed); if that process is no longer running on this host the lock is stale and is taken
  over with a one-line warning.
- A file system without locks (``flock`` fails with ``ENOLCK``, ...) and platforms without
  ``fcntl``: only the body is checked (its process must be gone on this host).

A clean end empties the body and closes the file (the file stays: removing a lock file that
another process may be opening is a race).
"""

from __future__ import annotations

import contextlib
import errno
import json
import logging
import os
import shlex
import socket
import sys
from dataclasses import asdict, dataclass
from datetime import datetime
from pathlib import Path
from typing import Any, Literal

from porenet._version import __version__
from porenet.core.errors import PorenetError
from porenet.sweep.files import io_error

log = logging.getLogger(__name__)

LOCK_FILE = ".lock"


class SweepLocked(PorenetError):
    """Another sweep is writing into the output directory (exit status 1: the command is
    valid and will work once that sweep has ended; docs/sweeps.md, "The lock")."""

    exit_status = 1


def process_start(pid: int) -> int | None:
    """When process ``pid`` started, in clock ticks since boot (Linux ``/proc/PID/stat``
    field 22), or None where that cannot be read. With the pid it names one process: a pid
    reused by a later process has another start time."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii", errors="replace") as fh:
            fields = fh.read().rsplit(")", 1)[1].split()
        return int(fields[19])
    except (OSError, IndexError, ValueError):
        return None


def _zombie(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii", errors="replace") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] in ("Z", "X")
    except (OSError, IndexError):
        return False


def _command() -> str:
    argv = list(sys.argv)
    if argv and Path(argv[0]).name in ("porenet", "__main__.py", "porenet.exe"):
        return shlex.join(["porenet", *argv[1:]])
    return shlex.join(getattr(sys, "orig_argv", None) or argv)


@dataclass(frozen=True)
class LockHolder:
    """The process that holds (or held) a directory's lock, as written in the lock file."""

    pid: int
    host: str
    started: str  # local time, ISO 8601
    command: str
    process_start: int | None = None  # see process_start(); tells a reused pid
    porenet_version: str = ""

    @classmethod
    def this_process(cls) -> LockHolder:
        """This process, now."""
        return cls(
            pid=os.getpid(),
            host=socket.gethostname(),
            started=datetime.now().astimezone().isoformat(timespec="seconds"),
            command=_command(),
            process_start=process_start(os.getpid()),
            porenet_version=__version__,
        )

    @classmethod
    def from_text(cls, text: str) -> LockHolder | None:
        """The holder written in ``text``; None for an empty or unreadable body."""
        try:
            data: Any = json.loads(text)
            return cls(
                pid=int(data["pid"]),
                host=str(data["host"]),
                started=str(data.get("started", "?")),
                command=str(data.get("command", "?")),
                process_start=(
                    int(data["process_start"]) if data.get("process_start") is not None else None
                ),
                porenet_version=str(data.get("porenet_version", "")),
            )
        except (ValueError, TypeError, KeyError):
            return None

    def to_text(self) -> str:
        """The lock file's body."""
        return json.dumps(asdict(self)) + "\n"

    def describe(self) -> str:
        """``pid 1234 on host vm, started 2026-01-02T10:00:00+01:00, command: porenet ...``."""
        return (
            f"pid {self.pid} on host {self.host}, started {self.started}, command: {self.command}"
        )

    def on_this_host(self) -> bool:
        """Whether the holder ran on this machine (its pid means something here)."""
        return self.host == socket.gethostname()

    def is_running(self) -> bool | None:
        """Whether the holder still runs: True or False on this host, None on another host
        (its pid cannot be checked from here)."""
        if not self.on_this_host():
            return None
        if os.name != "posix":  # no signal 0 to probe with: assume it may run
            return True
        try:
            os.kill(self.pid, 0)
        except ProcessLookupError:
            return False
        except PermissionError:
            pass  # it exists, under another user
        except OSError:
            return True
        if _zombie(self.pid):
            return False
        now = process_start(self.pid)
        return not (
            self.process_start is not None and now is not None and now != self.process_start
        )


def _os_lock(fd: int, path: Path) -> Literal["locked", "busy", "unsupported"]:
    try:
        import fcntl
    except ImportError:  # not a POSIX system
        return "unsupported"
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError as exc:
        if exc.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
            return "busy"
        log.warning(
            "%s: the file system does not lock files (%s); the lock relies on the process id "
            "written in it",
            path,
            exc.strerror or exc,
        )
        return "unsupported"
    return "locked"


def _read_body(fd: int) -> str:
    chunks = []
    try:
        os.lseek(fd, 0, os.SEEK_SET)
        while chunk := os.read(fd, 65536):
            chunks.append(chunk)
    except OSError:
        return ""  # unreadable: treated as no details
    return b"".join(chunks).decode("utf-8", errors="replace")


class DirectoryLock:
    """Holds ``directory/.lock`` while a sweep writes into ``directory``.

    Use as a context manager (or :meth:`acquire` and :meth:`release`). ``taken_over`` is the
    holder of a stale lock that :meth:`acquire` replaced, if any.

    Raises
    ------
    SweepLocked
        From :meth:`acquire`, if another running process holds the lock.
    SweepIOError
        From :meth:`acquire`, if the lock file cannot be created or written.
    """

    def __init__(self, directory: str | Path) -> None:
        self.directory = Path(directory)
        self.path = self.directory / LOCK_FILE
        self.holder = LockHolder.this_process()
        self.taken_over: LockHolder | None = None
        self._fd: int | None = None

    def acquire(self) -> DirectoryLock:
        """Take the lock, or raise :class:`SweepLocked` naming its holder."""
        if self._fd is not None:
            return self
        flags = os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0)
        try:
            fd = os.open(self.path, flags, 0o644)
        except OSError as exc:
            raise io_error(self.path, exc, "open") from exc
        try:
            state = _os_lock(fd, self.path)
            previous = LockHolder.from_text(_read_body(fd))
            if state == "busy":
                raise SweepLocked(self._busy(previous))
            if previous is not None and not self._mine(previous):
                running = previous.is_running()
                if running or (running is None and state == "unsupported"):
                    raise SweepLocked(self._not_released(previous, state))
                log.warning(
                    "%s: taking over the lock of a sweep that is no longer running (%s)",
                    self.directory,
                    previous.describe(),
                )
                self.taken_over = previous
            self._write(fd, self.holder.to_text())
        except BaseException:
            os.close(fd)
            raise
        self._fd = fd
        return self

    def release(self) -> None:
        """Empty the lock file and let go of it (a no-op if not held)."""
        fd, self._fd = self._fd, None
        if fd is None:
            return
        with contextlib.suppress(OSError):
            os.ftruncate(fd, 0)
        os.close(fd)  # the kernel releases the flock with the last descriptor

    def __enter__(self) -> DirectoryLock:
        return self.acquire()

    def __exit__(self, *exc: object) -> None:
        self.release()

    # ------------------------------------------------------------------ helpers

    def _mine(self, holder: LockHolder) -> bool:
        return (
            holder.on_this_host()
            and holder.pid == self.holder.pid
            and (holder.process_start == self.holder.process_start)
        )

    def _write(self, fd: int, text: str) -> None:
        data = text.encode("utf-8")
        try:
            os.ftruncate(fd, 0)
            os.lseek(fd, 0, os.SEEK_SET)
            while data:
                data = data[os.write(fd, data) :]
            os.fsync(fd)
        except OSError as exc:
            raise io_error(self.path, exc) from exc

    def _busy(self, holder: LockHolder | None) -> str:
        if holder is None:
            who = "another process (it has not written its details yet)"
            stop = "stop it"
        else:
            who = f"another porenet sweep: {holder.describe()}"
            where = "" if holder.on_this_host() else f" on {holder.host}"
            stop = f"stop it (kill {holder.pid}{where})"
        return (
            f"{self.directory} is in use by {who} (lock file {self.path}); wait for it to "
            f"finish or {stop}, then re-run this command; or write to another output directory "
            f"(-o)"
        )

    def _not_released(self, holder: LockHolder, state: str) -> str:
        if holder.is_running():
            why = "the lock file names a process that is still running" + (
                " although it does not hold the lock" if state == "locked" else ""
            )
            check = f"if pid {holder.pid} is not a porenet sweep writing here"
        else:
            why = f"the lock file names a process on another host ({holder.host}), which " \
                  "cannot be checked from here"  # fmt: skip
            check = f"if that sweep is no longer running on {holder.host}"
        return (
            f"{self.directory} may be in use by another porenet sweep: {why} "
            f"({holder.describe()}); {check}, delete {self.path} and re-run this command; or "
            f"write to another output directory (-o)"
        )


__all__ = ["LOCK_FILE", "DirectoryLock", "LockHolder", "SweepLocked", "process_start"]
