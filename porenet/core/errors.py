"""Exceptions raised by porenet, and the exit status the command gives each.

Every error a user can cause derives from :class:`PorenetError`; the CLI turns these into a
one-line message and an exit status instead of a traceback (docs/reliability.md, "Exit
status"):

* 2, *bad usage or input*: what the user gave is wrong and the message names it (a scene
  field, a flag, a file): :class:`ConfigError`, :class:`RunFileError` (a run file given to
  read).
* 1, *the command failed*: the input was acceptable but the work could not be done
  (numerical trouble, a plugin, a disk that is full): every other :class:`PorenetError`.
"""

from __future__ import annotations

import errno as _errno
import os
from pathlib import Path


class PorenetError(Exception):
    """Base class of the errors porenet raises on purpose (exit status 1)."""

    exit_status = 1


class ConfigError(PorenetError, ValueError):
    """A scene, sweep, option or input file is invalid (exit status 2).

    The message names the file (when there is one), the dotted field or the flag, and the
    offending value.
    """

    exit_status = 2


class PluginError(PorenetError):
    """A plugin failed to load, registered an invalid or duplicate kind, or misspelt a hook."""


class NumericalError(PorenetError, ArithmeticError):
    """Numerical trouble (NaN, non-convergence, singular system), with where and when it arose."""


class RunFileError(PorenetError, OSError):
    """A run file given to read is missing, unreadable, damaged, not a porenet run file, or of
    a newer format version (exit status 2: the message names the file)."""

    exit_status = 2


class RunFileLayoutError(RunFileError):
    """A run's data do not fit the run-file layout (a model's time series or snapshots of the
    wrong shape); nothing was written (exit status 1: not the user's input)."""

    exit_status = 1


class OutputError(PorenetError, OSError):
    """An output file (run file, picture, table, checkpoint) could not be written.

    The message names the path and the operating system's reason (disk full, quota, read-only
    file system, permission, I/O error); :attr:`path` and :attr:`errno` hold them for code.
    Exit status 1. Raised by :func:`porenet.io.atomic.atomic_output`.

    Attributes
    ----------
    path : Path
        The file that was to be written.
    errno : int or None
        The OS error number (``errno.ENOSPC``, ...), None if there was none.
    reason : str
        The OS reason in words ("no space left on device").
    """

    path: Path
    reason: str

    @classmethod
    def from_os_error(cls, path: str | os.PathLike[str], exc: OSError, what: str) -> OutputError:
        """The error for ``exc``, raised while writing ``what`` (e.g. ``"run file"``) to
        ``path``: "cannot write run file PATH: no space left on device (ENOSPC); free some
        space or write elsewhere"."""
        number = exc.errno
        reason = (exc.strerror or str(exc) or type(exc).__name__).rstrip(".")
        reason = reason[:1].lower() + reason[1:]
        code = _errno.errorcode.get(number, "") if number is not None else ""
        hint = _HINTS.get(code, "")
        message = f"cannot write {what} {path}: {reason}" + (f" ({code})" if code else "")
        err = cls(message + (f"; {hint}" if hint else ""))
        err.errno = number
        err.path = Path(path)
        err.reason = reason
        return err


#: What to do about the common causes of a failed write (by errno name).
_HINTS = {
    "ENOSPC": "free some space or write elsewhere",
    "EDQUOT": "free some space within your quota or write elsewhere",
    "EROFS": "the file system is read-only: write elsewhere",
    "EACCES": "you may not write there: write elsewhere or change its permissions",
    "EPERM": "you may not write there: write elsewhere or change its permissions",
    "EIO": "the device reported an error: check it, or write elsewhere",
    "EFBIG": "the file is larger than this file system allows: write elsewhere",
    "ENAMETOOLONG": "choose a shorter name",
    "ENOENT": "the directory does not exist: create it or write elsewhere",
    "EISDIR": "it is a directory: give a file name",
}
