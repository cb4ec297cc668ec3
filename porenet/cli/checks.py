"""Checks the ``porenet`` command makes before it starts work, and its messages
(docs/reliability.md).

Each check raises :class:`~porenet.core.errors.ConfigError` (exit status 2) naming the flag,
field or file and saying what to do, so that a command that cannot succeed stops before it
allocates, runs or draws anything: an output directory that does not exist or cannot be
written, a picture format matplotlib does not know, a ``--dpi`` that is not a positive
number or would draw a picture larger than the memory available, a scene whose estimated
memory (the plan's, docs/cost.md) exceeds the memory available.

Light: the standard library only at import (``porenet validate`` and ``plan`` stay free of
numerics); matplotlib is imported by the picture checks, which only drawing commands call.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

from porenet.core.errors import ConfigError
from porenet.core.extent import lattice_extent

#: The exit statuses of every ``porenet`` command (``porenet --help`` prints this).
EXIT_STATUS_HELP = """\
exit status:
  0    done
  1    the command failed although its input was acceptable (numerical trouble, a full
       disk, out of memory); the message says why and what to do
  2    bad usage or input: the message names the scene field, the file or the flag
  130  interrupted (Ctrl-C); a run file is never left half-written
errors are one line on stderr; --traceback shows the traceback (for a bug report);
docs/reliability.md lists the cases"""

#: matplotlib's Agg renderer draws at most this many pixels along each side.
MAX_PIXELS_PER_SIDE = 1 << 16
#: Bytes per pixel of a drawn picture (RGBA).
BYTES_PER_PIXEL = 4
#: Files read for the memory available (tests point them elsewhere).
MEMINFO = Path("/proc/meminfo")
CGROUP_ROOT = Path("/sys/fs/cgroup")
PROC_SELF_CGROUP = Path("/proc/self/cgroup")
PROC_SELF_STATUS = Path("/proc/self/status")
#: A cgroup v1 limit at or above this is "no limit" (the kernel writes ~2^63).
_NO_LIMIT = 1 << 60


def _size(value: float) -> str:
    """``24 GB``, ``3.1 GB``, ``512 MB``: two significant figures."""
    from porenet.core.cost import format_bytes

    return format_bytes(value).lstrip("~")


# ----------------------------------------------------------------------------- output files


def check_output_file(path: Path, flag: str) -> None:
    """``path``, an output of ``flag`` (``-o``, ``--plot``, ``--table``), can be created:
    its directory exists and may be written, and it is not a directory itself."""
    parent = path.resolve().parent
    if not parent.is_dir():
        raise ConfigError(f"{flag} {path}: directory does not exist ({parent}); create it first")
    if path.is_dir():
        raise ConfigError(f"{flag} {path}: is a directory; give a file name")
    if not os.access(parent, os.W_OK | os.X_OK):
        reason = "is on a read-only file system" if _read_only(parent) else "may not be written"
        raise ConfigError(
            f"{flag} {path}: directory {parent} {reason}; write somewhere else (another -o)"
        )


def _read_only(directory: Path) -> bool:
    try:
        return bool(os.statvfs(directory).f_flag & os.ST_RDONLY)
    except OSError:
        return False


def check_run_output(output: Path, overwrite: bool) -> None:
    """Before a run: the run file can be created (:func:`check_output_file`), and an
    existing file is replaced only if it is a porenet run file, or with ``--overwrite``
    (docs/run-file.md, "Overwriting")."""
    check_output_file(output, "-o")
    from porenet.io.runfile import is_run_file

    if output.exists() and not overwrite and not is_run_file(output):
        raise ConfigError(
            f"-o {output}: exists and is not a porenet run file; not replaced (choose another "
            "name, or --overwrite to replace it)"
        )


def check_export_output(output: Path, overwrite: bool) -> None:
    """Before ``porenet export``: the XDMF file can be created (:func:`check_output_file`),
    and an existing XDMF file or sidecar (``OUT.xdmf.h5``) is replaced only if ``porenet
    export`` wrote it, or with ``--overwrite`` (docs/run-file.md, "ParaView (XDMF export)")."""
    check_output_file(output, "-o")
    from porenet.io.xdmf import is_export, sidecar_path

    sidecar = sidecar_path(output)
    if sidecar.is_dir():
        raise ConfigError(f"-o {output}: its sidecar {sidecar} is a directory; give another name")
    for path in (output, sidecar):
        if path.exists() and not overwrite and not is_export(path):
            raise ConfigError(
                f"-o {output}: {path} exists and was not written by porenet export; not "
                "replaced (choose another name, or --overwrite to replace it)"
            )


def check_picture_output(path: Path, flag: str) -> None:
    """A picture to write: :func:`check_output_file`, and a format (suffix) matplotlib
    writes."""
    check_output_file(path, flag)
    from matplotlib.backend_bases import FigureCanvasBase

    formats = FigureCanvasBase.get_supported_filetypes()
    if path.suffix.lstrip(".").lower() not in formats:
        raise ConfigError(
            f"{flag} {path}: unknown picture format; end the name with one of "
            f"{', '.join('.' + f for f in formats)}"
        )


def apply_threads(value: str | None) -> None:
    """``--threads auto`` (the default) or ``--threads N`` (docs/performance.md, "Threads on a
    busy machine")."""
    from porenet.jit.threads import configure_threads

    if value is None or value == "auto":
        configure_threads("auto")
        return
    try:
        count = int(value)
    except ValueError:
        raise ConfigError(f"--threads {value}: give a number of threads or 'auto'") from None
    if count < 1:
        raise ConfigError(f"--threads {value}: must be at least 1")
    configure_threads(count)


# -------------------------------------------------------------------------------- pictures


def check_dpi(dpi: float | None, flag: str = "--dpi") -> None:
    """``--dpi`` is a positive, finite number (None: the default)."""
    if dpi is None:
        return
    if not math.isfinite(dpi) or dpi <= 0:
        raise ConfigError(
            f"{flag} {dpi:g}: must be a positive number of dots per inch (default 300)"
        )


def dpi_of(dpi: float | None) -> float:
    """The resolution to draw at: ``--dpi`` (checked by :func:`check_dpi`) or porenet's
    default (300)."""
    check_dpi(dpi)
    if dpi is not None:
        return float(dpi)
    from porenet.viz.style import rc

    return float(rc()["savefig.dpi"])


def check_picture_size(fig: Any, dpi: float, flag: str = "--dpi") -> None:
    """Refuse, before drawing, a picture matplotlib cannot draw (more than
    :data:`MAX_PIXELS_PER_SIDE` pixels a side) or whose pixels (4 bytes each) need more than
    the memory available; the message gives the largest ``--dpi`` that works."""
    width, height = (float(x) for x in fig.get_size_inches())
    pixels_w, pixels_h = width * dpi, height * dpi
    need = pixels_w * pixels_h * BYTES_PER_PIXEL
    side_dpi = (MAX_PIXELS_PER_SIDE - 1) / max(width, height)
    available = available_memory()
    memory_dpi = (
        math.inf
        if available is None
        else math.sqrt(available[0] / (BYTES_PER_PIXEL * width * height))
    )
    if dpi <= min(side_dpi, memory_dpi):
        return
    size = f"{pixels_w:,.0f} x {pixels_h:,.0f} pixels ({width:g} x {height:g} in)"
    if dpi > side_dpi:
        why = f"more than the {MAX_PIXELS_PER_SIDE:,} pixels a side matplotlib can draw"
    else:
        why = f"~{_size(need)} of memory, more than the {_size(available[0])} available"  # type: ignore[index]
    best = max(1, math.floor(min(side_dpi, memory_dpi)))
    raise ConfigError(
        f"{flag} {dpi:g}: the picture would be {size}, {why}; use --dpi {best} or less"
    )


# --------------------------------------------------------------------------------- memory


def _read_int(path: Path) -> int | None:
    try:
        text = path.read_text().strip()
    except OSError:
        return None
    try:
        return int(text)
    except ValueError:
        return None  # "max": no limit


def _meminfo(key: str) -> int | None:
    try:
        lines = MEMINFO.read_text().splitlines()
    except OSError:
        return None
    for line in lines:
        name, _, rest = line.partition(":")
        if name.strip() == key:
            parts = rest.split()
            if parts and parts[0].isdigit():
                return int(parts[0]) * (1024 if parts[1:2] == ["kB"] else 1)
    return None


def _cgroup_dirs() -> list[Path]:
    """This process's cgroup v2 directory (from /proc/self/cgroup), then the root."""
    dirs: list[Path] = []
    try:
        for line in PROC_SELF_CGROUP.read_text().splitlines():
            if line.startswith("0::"):
                dirs.append(CGROUP_ROOT / line[3:].lstrip("/"))
    except OSError:
        pass
    dirs.append(CGROUP_ROOT)
    return dirs


def _cgroup_available() -> int | None:
    """Limit less usage of the cgroup (v2 ``memory.max``, else v1 ``memory.limit_in_bytes``),
    None without a limit."""
    for directory in _cgroup_dirs():
        limit = _read_int(directory / "memory.max")
        if limit is not None:
            return max(0, limit - (_read_int(directory / "memory.current") or 0))
    v1 = CGROUP_ROOT / "memory"
    limit = _read_int(v1 / "memory.limit_in_bytes")
    if limit is not None and limit < _NO_LIMIT:
        return max(0, limit - (_read_int(v1 / "memory.usage_in_bytes") or 0))
    return None


def _address_space_available() -> int | None:
    """``RLIMIT_AS`` (``ulimit -v``) less this process's virtual size, None without a limit."""
    try:
        import resource
    except ImportError:  # not a Unix system
        return None
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft == resource.RLIM_INFINITY or soft < 0:
        return None
    used = 0
    try:
        for line in PROC_SELF_STATUS.read_text().splitlines():
            if line.startswith("VmSize:"):
                used = int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return max(0, soft - used)


def available_memory() -> tuple[int, str] | None:
    """The memory this process may still use, in bytes, and where the number comes from:
    the least of ``MemAvailable`` (/proc/meminfo), the cgroup's limit less its usage
    (/sys/fs/cgroup/memory.max) and ``RLIMIT_AS`` less the process's virtual size. None
    where none of them can be read (not Linux)."""
    found = [
        (value, source)
        for value, source in (
            (_meminfo("MemAvailable"), "MemAvailable in /proc/meminfo"),
            (_cgroup_available(), "the cgroup's memory.max"),
            (_address_space_available(), "the address-space limit, ulimit -v"),
        )
        if value is not None
    ]
    return min(found) if found else None


def check_memory(plan: Any, *, ignore: bool = False) -> str | None:
    """Refuse (exit 2) a scene whose estimated peak memory (``plan.cost``, docs/cost.md)
    exceeds the memory available, before anything is allocated.

    Returns the message instead of raising when ``ignore`` (``--ignore-memory``), None when
    the scene fits or either number is unknown.
    """
    cost = getattr(plan, "cost", None)
    need = getattr(cost, "memory_bytes", None)
    available = available_memory()
    if need is None or available is None or need <= available[0]:
        return None
    extent = lattice_extent(plan.scene.lattice)
    what = extent.size_field if extent is not None else "this scene"
    field = what.split(" = ")[0] if extent is not None else "the lattice's size"
    message = (
        f"{what} needs ~{_size(need)} of memory (the plan's estimate, docs/cost.md), more "
        f"than the {_size(available[0])} available ({available[1]}); reduce {field}"
    )
    if ignore:
        return message.split("; ")[0] + "; --ignore-memory: trying anyway"
    raise ConfigError(message + " or pass --ignore-memory to try anyway")


def report(exc: Exception, command: str) -> tuple[int, str | None]:
    """The exit status for ``exc``, raised by ``porenet COMMAND``, and the one-line message
    to print on stderr (None: nothing to say); docs/reliability.md, "Exit status"."""
    from porenet.core.errors import PorenetError

    prefix = f"porenet {command}"
    if isinstance(exc, PorenetError):
        return exc.exit_status, f"{prefix}: error: {exc}"
    if isinstance(exc, BrokenPipeError):  # the reader went away (``porenet plan | head``)
        # point stdout at /dev/null so that Python's flush at exit does not fail again
        import sys

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0, None
    if isinstance(exc, MemoryError):
        return 1, f"{prefix}: error: {out_of_memory(command)}"
    if isinstance(exc, OSError):  # an I/O failure no check foresaw: which file, and why
        where = f"{exc.filename}: " if exc.filename else ""
        return 1, f"{prefix}: error: {where}{exc.strerror or exc}"
    return 1, (  # a bug: say so briefly; --traceback shows it
        f"{prefix}: internal error: {type(exc).__name__}: {exc}\n"
        "  (rerun with --traceback and report it)"
    )


def out_of_memory(command: str) -> str:
    """What to say when memory ran out although the checks let ``command`` start."""
    if command == "run":
        return (
            "out of memory: the run needed more memory than is available; reduce lattice.n "
            "(porenet plan prints the estimate, docs/cost.md)"
        )
    if command in ("plot", "phase-diagram"):
        return "out of memory while drawing; lower --dpi"
    return "out of memory; free some memory or work on a smaller run"
