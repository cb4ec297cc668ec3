"""The sweep directory's own files, written so that a failure never leaves a misleading one.

``summary.csv``, ``sweep.json`` and the error records of failed runs are written to a temporary
name in the same directory (``.NAME.XXXXXXXX.partial``), flushed to the disk (``fsync``) and
renamed over the old file, so a reader sees the old file or the new one, never a truncated one.
An I/O error (a full disk, a read-only file system, ...) becomes a :class:`SweepIOError` naming
the path and the operating system's reason, and the temporary file is removed
(docs/sweeps.md, "Disk full and other I/O errors").
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
from pathlib import Path

from porenet.core.errors import OutputError, PorenetError
from porenet.io import atomic

#: errno values that mean "this file system cannot take the sweep's files now": they stop a
#: sweep instead of being recorded as a failed run (a full disk fails every later run too).
STORAGE_ERRNOS = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EROFS})

#: Suffix of the temporary files (every atomic write of porenet uses it).
PARTIAL_SUFFIX = atomic.PARTIAL_SUFFIX


class SweepIOError(PorenetError):
    """A file of the sweep directory cannot be written or read (exit status 1).

    The message names the path, the operating system's reason (``No space left on device``)
    and what to do next.
    """

    exit_status = 1

    def __init__(
        self,
        path: str | Path,
        reason: str,
        errno_: int | None = None,
        *,
        doing: str = "write",
        note: str = "",
    ) -> None:
        self.path = Path(path)
        self.reason = reason
        self.errno = errno_
        self.doing = doing
        self.note = note
        super().__init__(self._message())

    def _message(self) -> str:
        if self.errno in (errno.ENOSPC, errno.EDQUOT):
            fix = "free some space on that file system (or use another output directory, -o)"
        elif self.errno in (errno.EROFS, errno.EACCES, errno.EPERM):
            fix = "make the directory writable (or use another output directory, -o)"
        else:
            fix = "fix the cause"
        note = f"; {self.note}" if self.note else ""
        return (
            f"cannot {self.doing} {self.path}: {self.reason}{note}; {fix} and re-run the same "
            f"command: it resumes"
        )

    def with_note(self, note: str) -> SweepIOError:
        """The same error with ``note`` (e.g. how many runs are finished) in its message."""
        return SweepIOError(self.path, self.reason, self.errno, doing=self.doing, note=note)


def io_error(path: str | Path, exc: OSError, doing: str = "write") -> SweepIOError:
    """A :class:`SweepIOError` for ``exc`` raised while doing ``doing`` on ``path``."""
    reason = exc.strerror or (os.strerror(exc.errno) if exc.errno else "") or str(exc)
    return SweepIOError(path, reason, exc.errno, doing=doing)


def atomic_write_text(path: Path, text: str) -> None:
    """Replace ``path`` by a file holding ``text`` (UTF-8), atomically
    (:func:`porenet.io.atomic.atomic_write_bytes`: a temporary file in the same directory,
    synced, then renamed over ``path``): ``path`` is the old file or the new one, never a part
    of either. On failure the temporary file is removed.

    Raises
    ------
    SweepIOError
        If anything fails (``No space left on device``, ...); ``path`` is left as it was.
    """
    try:
        atomic.atomic_write_bytes(path, text.encode("utf-8"), what="sweep file")
    except OutputError as exc:  # the system's wording, as io_error gives it
        reason = exc.reason[:1].upper() + exc.reason[1:]
        raise SweepIOError(path, reason, exc.errno) from exc


def remove(path: Path) -> None:
    """Remove ``path`` if it exists.

    Raises
    ------
    SweepIOError
        If it exists and cannot be removed.
    """
    try:
        path.unlink()
    except FileNotFoundError:
        pass
    except OSError as exc:
        raise io_error(path, exc, "remove") from exc


def read_text(path: Path) -> str:
    """The text of ``path``; a :class:`SweepIOError` if it cannot be read."""
    try:
        return path.read_text(encoding="utf-8")
    except OSError as exc:
        raise io_error(path, exc, "read") from exc


def clean_partials(*directories: Path) -> list[Path]:
    """Remove the temporary files (``.*.partial``) that an interrupted or killed sweep left.

    Only the process that holds the directory's lock may call this (docs/sweeps.md,
    "The lock"): another sweep's temporaries are files in the making. Returns the files
    removed.
    """
    removed = []
    for directory in directories:
        for tmp in directory.glob(f".*{PARTIAL_SUFFIX}"):
            with contextlib.suppress(OSError):
                tmp.unlink()
                removed.append(tmp)
    return removed


_ERRNO_IN_TEXT = re.compile(r"errno\s*=\s*(\d+)")


def storage_error(exc: BaseException) -> tuple[int, str] | None:
    """``(errno, reason)`` if ``exc`` (or an exception it was raised from) is a full disk, a
    quota or a read-only file system (:data:`STORAGE_ERRNOS`), else None.

    HDF5 reports its write errors as text (``errno = 28, error message = 'No space left on
    device'``) in exceptions that carry no ``errno``: that text is read too.
    """
    seen: set[int] = set()
    current: BaseException | None = exc
    while current is not None and id(current) not in seen:
        seen.add(id(current))
        code = current.errno if isinstance(current, OSError) else None
        if code not in STORAGE_ERRNOS:
            match = _ERRNO_IN_TEXT.search(str(current))
            code = int(match.group(1)) if match else None
        if code in STORAGE_ERRNOS:
            return code, os.strerror(code)
        current = current.__cause__ or current.__context__
    return None


__all__ = [
    "PARTIAL_SUFFIX",
    "STORAGE_ERRNOS",
    "SweepIOError",
    "atomic_write_text",
    "clean_partials",
    "io_error",
    "read_text",
    "remove",
    "storage_error",
]
