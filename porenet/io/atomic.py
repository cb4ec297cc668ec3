"""Output files that are complete or absent: write under a temporary name, rename at the end.

Every file porenet writes (run files, pictures; checkpoints may use it too) goes through
:func:`atomic_output` or :func:`atomic_write_bytes`:

* the data go to a temporary file in the same directory as the target
  (``.NAME.XXXXXXXX.partial``), are flushed to the device, and the temporary is renamed onto
  the target only when complete, so the target is never a half-written file: it is the old
  file or the new one;
* on any failure the temporary is removed and the target left as it was;
* an ``OSError`` (disk full ``ENOSPC``, quota ``EDQUOT``, I/O error ``EIO``, read-only file
  system ``EROFS``, permission ``EACCES``, ...) becomes a
  :class:`~porenet.core.errors.OutputError` naming the path and the reason ("cannot write
  run file out/run.h5: no space left on device (ENOSPC); free some space or write
  elsewhere"), exit status 1 from the command; other exceptions pass through unchanged.

Writers that use a C library with its own file handling (HDF5) should build the file in
memory and hand the bytes to :func:`atomic_write_bytes`: then the library never sees a full
disk (h5py crashed the process after ``ENOSPC`` when it wrote to the disk itself,
docs/reliability.md, "Disk full and I/O errors").

Examples
--------
>>> with atomic_output("table.md", what="table") as tmp:  # doctest: +SKIP
...     tmp.write_text(text)
>>> atomic_write_bytes("run.h5", buffer.getbuffer(), what="run file")  # doctest: +SKIP

This module imports only the standard library.
"""

from __future__ import annotations

import contextlib
import errno
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

from porenet.core.errors import OutputError, PorenetError

#: Bytes handed to one ``write`` call by :func:`atomic_write_bytes`.
CHUNK = 1 << 24

#: Suffix of the temporary files (``.NAME.XXXXXXXX.partial``): a file with this name in an
#: output directory is the remains of a process that was killed while writing.
PARTIAL_SUFFIX = ".partial"


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _fsync_directory(directory: Path) -> None:
    """Make the rename durable (best effort: not every system can open a directory)."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


@contextlib.contextmanager
def atomic_output(
    path: str | os.PathLike[str],
    *,
    what: str = "file",
    mode: int | None = None,
    durable: bool = True,
) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it onto ``path`` when the block ends.

    Parameters
    ----------
    path : str or path-like
        The file to write. Its directory must exist. An existing file is replaced only when
        the block succeeds.
    what : str
        What the file is, for messages ("run file", "picture", "checkpoint").
    mode : int, optional
        Permission bits of the new file; default ``0o666`` less the umask (as ``open``
        would give).
    durable : bool
        Flush the file's data to the device before the rename, and the directory after it,
        so that a crash of the machine leaves the old file or the complete new one (default).

    Yields
    ------
    Path
        The temporary file, created empty: open it for writing (``"wb"`` or ``"w"``).

    Raises
    ------
    OutputError
        If the temporary cannot be created, written, flushed or renamed (any ``OSError``,
        also one raised inside the block); the temporary is removed.

    Notes
    -----
    Any other exception raised inside the block (including ``KeyboardInterrupt``) removes
    the temporary and propagates unchanged; so does a :class:`PorenetError`.
    """
    target = Path(path)
    directory = target.parent
    try:
        fd, name = tempfile.mkstemp(
            prefix=f".{target.name}.", suffix=PARTIAL_SUFFIX, dir=directory or "."
        )
    except OSError as exc:
        raise OutputError.from_os_error(target, exc, what) from None
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        os.chmod(tmp, (0o666 & ~_umask()) if mode is None else mode)
        if durable:
            with open(tmp, "rb+") as fh:
                os.fsync(fh.fileno())
        os.replace(tmp, target)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        if isinstance(exc, OSError) and not isinstance(exc, PorenetError):
            raise OutputError.from_os_error(target, exc, what) from exc
        raise
    if durable:
        _fsync_directory(tmp.parent)


def atomic_write_bytes(
    path: str | os.PathLike[str],
    data: bytes | bytearray | memoryview,
    *,
    what: str = "file",
    mode: int | None = None,
    durable: bool = True,
) -> Path:
    """Write ``data`` to ``path`` through :func:`atomic_output` and return the path.

    The bytes are written in chunks of :data:`CHUNK` with an unbuffered file, so a full disk
    is reported by the write that meets it, and nothing is written after it.

    Raises
    ------
    OutputError
        As :func:`atomic_output`.
    """
    with (
        memoryview(data) as whole,
        whole.cast("B") as view,
        atomic_output(path, what=what, mode=mode, durable=durable) as tmp,
        open(tmp, "wb", buffering=0) as fh,
    ):
        offset = 0
        while offset < len(view):
            with view[offset : offset + CHUNK] as chunk:
                written = fh.write(chunk)
            if not written:  # a device that accepts nothing and raises nothing
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            offset += written
    return Path(path)
