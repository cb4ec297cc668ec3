"""Every way we know to get porenet wrong, through the real command line: the exit status, the
message and what is left on disk (docs/reliability.md).

Each :class:`Case` runs ``python -m porenet ARGS`` in a directory of its own that holds a
tiny scene (``scene.toml``, 10 x 10, invasion percolation) and a run file of it (``run.h5``);
``setup`` adds what the case needs. Every case must end with its exit status, a stderr that
contains its message, no traceback, no "internal error" and no ``*.partial`` file left
behind; ``after`` checks the rest of what is on disk. Errors found before a run starts run
nothing (a second or less each, mostly Python's start-up; :data:`WORKERS` cases run at a
time, all before the first test looks at its result). Cases that need root (a small tmpfs
to fill, a read-only one) or that root defeats (``chmod 000``) are skipped with the reason.

``python tests/unit/test_reliability.py --markdown`` prints the table of docs/reliability.md
("Every case"); ``--write`` puts it there. A test checks the page is current.
"""

from __future__ import annotations

import dataclasses
import os
import shutil
import signal
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "reliability.md"
BEGIN = "<!-- begin: python tests/unit/test_reliability.py --write -->"
END = "<!-- end of the generated table -->"

TINY = """\
seed = 1
[lattice]
n = 10
disorder = 0.3
[fluid]
kind = "invasion-percolation"
"""

SLOW = """\
seed = 1
[lattice]
n = 400
disorder = 0.3
[fluid]
kind = "viscous"
capillary_number = 9e-4
"""

#: Throats of the tiny scene's lattice, 2 n (n-1).
THROATS = 180


@dataclass(frozen=True)
class Case:
    """One way to get porenet wrong.

    Attributes
    ----------
    section : str
        Heading of the case in docs/reliability.md.
    name : str
        What is wrong, in words.
    argv : tuple of str
        Arguments of ``porenet``, relative to the case's directory.
    exit : int
        Expected exit status.
    message : str or tuple of str
        Fragments the stderr must contain.
    setup : callable, optional
        ``setup(directory, tmpfs)`` makes the files the case needs (``tmpfs`` is the fixture
        of tests/unit/conftest.py).
    after : callable, optional
        ``after(directory)`` asserts what is left on disk.
    needs : str
        ``"non-root"`` for permission cases, which root bypasses.
    memory_limit : int, optional
        Address-space limit (bytes, ``ulimit -v``) of the process.
    interrupt : str, optional
        Send SIGINT once stderr shows this.
    in_process : bool
        Call ``porenet.cli.main.main`` with the same arguments in the case's directory instead of
        starting ``python -m porenet`` (set from :data:`IN_PROCESS`).
    """

    section: str
    name: str
    argv: tuple[str, ...]
    exit: int
    message: str | tuple[str, ...]
    setup: Callable[[Path, Callable[..., Path]], None] | None = None
    after: Callable[[Path], None] | None = None
    needs: str = ""
    memory_limit: int | None = None
    interrupt: str | None = None
    in_process: bool = False


# ------------------------------------------------------------------------------ set-ups


def _write(name: str, content: str | bytes) -> Callable[[Path, object], None]:
    def setup(d: Path, _: object) -> None:
        if isinstance(content, bytes):
            (d / name).write_bytes(content)
        else:
            (d / name).write_text(content)

    return setup


def _mkdir(name: str) -> Callable[[Path, object], None]:
    return lambda d, _: (d / name).mkdir()


def _chmod(name: str, mode: int, content: str | None = None) -> Callable[[Path, object], None]:
    def setup(d: Path, _: object) -> None:
        path = d / name
        if content is not None:
            path.write_text(content)
        elif not path.exists():
            path.mkdir()
        path.chmod(mode)

    return setup


def _npy(name: str, array: np.ndarray, allow_pickle: bool = False) -> Callable:
    return lambda d, _: np.save(d / name, array, allow_pickle=allow_pickle)


def _pickle(name: str) -> Callable:
    import pickle

    return _write(name, pickle.dumps(np.full(THROATS, 1e-7)))


def _damaged(name: str, how: str) -> Callable[[Path, object], None]:
    def setup(d: Path, _: object) -> None:
        data = bytearray((d / "run.h5").read_bytes())
        size = len(data)
        if how == "truncated":
            data = data[: size // 2]
        elif how == "zeroed":  # the middle half zeroed: datasets and their metadata
            data[size // 4 : 3 * size // 4] = bytes(size // 2)
        (d / name).write_bytes(bytes(data))

    return setup


def _foreign_hdf5(d: Path, _: object) -> None:
    import h5py

    with h5py.File(d / "other.h5", "w") as f:
        f["x"] = np.arange(3)


def _full(d: Path, tmpfs: Callable[..., Path]) -> None:
    tmpfs(d / "full", full=True)


def _full_with_run(d: Path, tmpfs: Callable[..., Path]) -> None:
    tmpfs(d / "full", files=(d / "run.h5",), full=True)


def _read_only(d: Path, tmpfs: Callable[..., Path]) -> None:
    tmpfs(d / "ro", readonly=True)


# ------------------------------------------------------------------------------- checks


def _absent(*names: str) -> Callable[[Path], None]:
    def after(d: Path) -> None:
        for name in names:
            assert not (d / name).exists(), f"{name} was left on disk"

    return after


def _unchanged_run(where: str) -> Callable[[Path], None]:
    def after(d: Path) -> None:
        assert (d / where).read_bytes() == (d / "run.h5.orig").read_bytes()

    return after


def _readable_run(name: str, *absent: str) -> Callable[[Path], None]:
    def after(d: Path) -> None:
        from porenet.io.runfile import read_run

        assert read_run(d / name).summary["n_pores"] == 100
        _absent(*absent)(d)

    return after


def _untouched(name: str, text: str) -> Callable[[Path], None]:
    def after(d: Path) -> None:
        assert (d / name).read_text() == text, f"{name} was changed"

    return after


GB = 1 << 30

CASES: list[Case] = [
    # -------------------------------------------------------------------- usage
    Case("Usage", "no command", (), 2, "the following arguments are required: COMMAND"),
    Case("Usage", "an unknown command", ("frobnicate",), 2, "invalid choice: 'frobnicate'"),
    Case("Usage", "an unknown flag", ("run", "scene.toml", "--bogus"), 2,
         "unrecognized arguments: --bogus"),
    Case("Usage", "--dpi that is not a number", ("plot", "run.h5", "--dpi", "abc"), 2,
         "argument --dpi: invalid float value: 'abc'"),
    Case("Usage", "a scene file and --example", ("run", "scene.toml", "--example", "quickstart"),
         2, "give either a SCENE file or --example NAME, not both"),
    Case("Usage", "an unknown example", ("run", "--example", "nope"), 2,
         "unknown example 'nope'; available: quickstart"),
    Case("Usage", "--threads 0", ("run", "scene.toml", "--threads", "0"), 2,
         "--threads 0: must be at least 1"),
    Case("Usage", "--jobs 0", ("compile", "--jobs", "0"), 2, "--jobs 0: must be at least 1"),
    # -------------------------------------------------------------------- scene file
    Case("Scene", "a scene file that does not exist", ("run", "absent.toml"), 2,
         "absent.toml: no such file", after=_absent("absent.h5")),
    Case("Scene", "a directory given as the scene", ("validate", "dir"), 2,
         "dir: is a directory, not a scene file", setup=_mkdir("dir")),
    Case("Scene", "an unreadable scene file (chmod 000)", ("validate", "secret.toml"), 2,
         "secret.toml: permission denied; make the scene file readable",
         setup=_chmod("secret.toml", 0, TINY), needs="non-root"),
    Case("Scene", "not TOML", ("validate", "bad.toml"), 2, "bad.toml: not valid TOML",
         setup=_write("bad.toml", "[lattice\nn = 3\n")),
    Case("Scene", "a binary file", ("validate", "bin.toml"), 2, "bin.toml: not a text file",
         setup=_write("bin.toml", b"\xff\xfe\x00\x01")),
    Case("Scene", "an empty scene", ("validate", "empty.toml"), 2,
         "lattice: required field is missing", setup=_write("empty.toml", "")),
    Case("Scene", "a misspelt key", ("validate", "typo.toml"), 2,
         "lattice.dissorder: unknown field; did you mean 'disorder'?",
         setup=_write("typo.toml", TINY.replace("disorder", "dissorder"))),
    Case("Scene", "an unknown section", ("validate", "scene.toml", "--set", "bogus.x=1"), 2,
         "bogus: unknown field"),
    Case("Scene", "a word for a number", ("validate", "scene.toml", "--set", "lattice.n=abc"),
         2, "lattice.n = 'abc': Input should be a valid integer"),
    Case("Scene", "a number for a boolean",
         ("validate", "scene.toml", "--set", "fluid.trapping=3"), 2,
         "fluid.trapping = 3: Input should be a valid boolean"),
    Case("Scene", "disorder = nan in the file", ("validate", "nan.toml"), 2,
         "lattice.disorder = nan: must be a finite number",
         setup=_write("nan.toml", TINY.replace("0.3", "nan"))),
    Case("Scene", "inf in a float field",
         ("validate", "scene.toml", "--set", "lattice.pore_size=inf"), 2,
         "lattice.pore_size = inf: must be a finite number"),
    Case("Scene", "-inf in a list",
         ("validate", "scene.toml", "--set", "fluid.kind='viscous'", "--set",
          "fluid.capillary_number=1e-3", "--set", "fluid.snapshot_times=[1.0, -inf]"), 2,
         "fluid.snapshot_times[1] = -inf: must be a finite number"),
    Case("Scene", "a negative size", ("validate", "scene.toml", "--set", "lattice.n=-5"), 2,
         "lattice.n = -5: Input should be greater than or equal to 3"),
    Case("Scene", "a lattice larger than allowed",
         ("validate", "scene.toml", "--set", "lattice.n=20000"), 2,
         "lattice.n = 20000: Input should be less than or equal to 10000"),
    Case("Scene", "a huge float", ("validate", "scene.toml", "--set", "lattice.pore_size=1e300"),
         2, "lattice.pore_size = 1e+300: must be 0 or between 1e-30 and 1e+30 in magnitude"),
    Case("Scene", "an integer beyond 64 bits",
         ("validate", "scene.toml", "--set", "seed=99999999999999999999"), 2,
         "seed = 99999999999999999999: must be at most 9223372036854775807"),
    Case("Scene", "--set without =", ("validate", "scene.toml", "--set", "lattice.n"), 2,
         "--set 'lattice.n': expected KEY=VALUE with a dotted KEY"),
    Case("Scene", "--set into a value", ("validate", "scene.toml", "--set", "lattice.n.x=1"), 2,
         "'n' is not a table"),
    Case("Scene", "an unknown kind",
         ("validate", "scene.toml", "--set", "lattice.kind='sqaure'"), 2,
         "lattice.kind = 'sqaure'"),
    # -------------------------------------------------------------------- apertures file
    Case("Apertures file", "a text file",
         ("validate", "scene.toml", "--set", "lattice.apertures_file='ap.txt'"), 2,
         ("lattice.apertures_file = 'ap.txt'", "is not a NumPy file (it looks like a text "
          "file); expected an .npz file with an array named 'apertures'"),
         setup=_write("ap.txt", "1e-7\n" * THROATS)),
    Case("Apertures file", "a pickle",
         ("validate", "scene.toml", "--set", "lattice.apertures_file='ap.pkl'"), 2,
         "ap.pkl is not a NumPy file (it looks like a Python pickle)", setup=_pickle("ap.pkl")),
    Case("Apertures file", "an array of Python objects",
         ("validate", "scene.toml", "--set", "lattice.apertures_file='ap.npy'"), 2,
         "ap.npy holds Python objects, not numbers",
         setup=_npy("ap.npy", np.array([1e-7] * THROATS, dtype=object), allow_pickle=True)),
    Case("Apertures file", "integers",
         ("validate", "scene.toml", "--set", "lattice.apertures_file='ap.npy'"), 2,
         "ap.npy holds int64 values, not floats",
         setup=_npy("ap.npy", np.ones(THROATS, dtype=np.int64))),
    Case("Apertures file", "the wrong shape",
         ("validate", "scene.toml", "--set", "lattice.apertures_file='ap.npy'"), 2,
         "has shape (7,), expected (180,) = 2 n (n-1) throats for n = 10",
         setup=_npy("ap.npy", np.ones(7))),
    Case("Apertures file", "a non-finite aperture",
         ("validate", "scene.toml", "--set", "lattice.apertures_file='ap.npy'"), 2,
         "1 aperture(s) are not positive and finite (first: throat 179 = nan)",
         setup=_npy("ap.npy", np.r_[np.full(THROATS - 1, 1e-7), np.nan])),
    Case("Apertures file", "a directory",
         ("validate", "scene.toml", "--set", "lattice.apertures_file='ap'"), 2,
         "is a directory; give the .npz or .npy file of apertures", setup=_mkdir("ap")),
    Case("Apertures file", "a file that does not exist",
         ("validate", "scene.toml", "--set", "lattice.apertures_file='gone.npy'"), 2,
         "lattice.apertures_file = 'gone.npy': file not found"),
    # -------------------------------------------------------------------- memory
    Case("Memory", "n = 10 000 under a 3 GB memory limit (ulimit -v)",
         ("run", "scene.toml", "--set", "lattice.n=10000", "-o", "big.h5"), 2,
         ("lattice.n = 10000 needs ~24 GB of memory (the plan's estimate, docs/cost.md), more "
          "than the", "reduce lattice.n or pass --ignore-memory to try anyway"),
         memory_limit=3 * GB, after=_absent("big.h5")),
    # -------------------------------------------------------------------- output files
    Case("Output files", "-o in a directory that does not exist",
         ("run", "scene.toml", "-o", "nodir/out.h5"), 2,
         ("-o nodir/out.h5: directory does not exist (", "create it first"),
         after=_absent("nodir")),
    Case("Output files", "-o is a directory", ("run", "scene.toml", "-o", "dir"), 2,
         "-o dir: is a directory; give a file name", setup=_mkdir("dir")),
    Case("Output files", "-o names a file that is not a run file",
         ("run", "scene.toml", "-o", "notes.h5"), 2,
         "-o notes.h5: exists and is not a porenet run file; not replaced",
         setup=_write("notes.h5", "my notes"), after=_untouched("notes.h5", "my notes")),
    Case("Output files", "-o in a directory without write permission",
         ("run", "scene.toml", "-o", "locked/out.h5"), 2, "may not be written",
         setup=_chmod("locked", 0o555), needs="non-root"),
    Case("Output files", "-o on a read-only file system", ("run", "scene.toml", "-o", "ro/o.h5"),
         2, "is on a read-only file system; write somewhere else", setup=_read_only),
    Case("Output files", "--plot in a directory that does not exist",
         ("run", "scene.toml", "-o", "out.h5", "--plot", "nodir/p.png"), 2,
         "--plot nodir/p.png: directory", after=_absent("out.h5")),
    Case("Output files", "--plot with an unknown picture format",
         ("run", "scene.toml", "-o", "out.h5", "--plot", "p.xyz"), 2,
         "--plot p.xyz: unknown picture format; end the name with one of", after=_absent("out.h5")),
    Case("Output files", "the run file on a full disk (64 kB tmpfs)",
         ("run", "scene.toml", "-o", "full/run.h5", "-q"), 1,
         "cannot write run file full/run.h5: no space left on device (ENOSPC); free some space "
         "or write elsewhere", setup=_full, after=_absent("full/run.h5")),
    Case("Output files", "the picture on a full disk",
         ("run", "scene.toml", "-o", "out.h5", "-q", "--plot", "full/p.png"), 1,
         "cannot write picture full/p.png: no space left on device (ENOSPC)", setup=_full,
         after=_readable_run("out.h5", "full/p.png")),
    Case("Output files", "classify on a full disk", ("classify", "full/run.h5"), 1,
         "cannot write run file full/run.h5: no space left on device", setup=_full_with_run,
         after=_unchanged_run("full/run.h5")),
    # -------------------------------------------------------------------- pictures
    Case("Pictures", "--dpi 0", ("plot", "run.h5", "--dpi", "0"), 2,
         "--dpi 0: must be a positive number of dots per inch", after=_absent("run.png")),
    Case("Pictures", "--dpi -3", ("plot", "run.h5", "--dpi", "-3"), 2,
         "--dpi -3: must be a positive number"),
    Case("Pictures", "--dpi nan", ("plot", "run.h5", "--dpi", "nan"), 2,
         "--dpi nan: must be a positive number"),
    Case("Pictures", "--dpi inf", ("plot", "run.h5", "--dpi", "inf"), 2,
         "--dpi inf: must be a positive number"),
    Case("Pictures", "--dpi 100000", ("plot", "run.h5", "--dpi", "100000"), 2,
         "--dpi 100000: the picture would be 500,000 x 430,000 pixels (5 x 4.3 in), more than "
         "the 65,536 pixels a side matplotlib can draw; use --dpi 13107 or less",
         after=_absent("run.png")),
    Case("Pictures", "a figure the run cannot give", ("plot", "run.h5", "--kind", "pressure"), 2,
         "--kind pressure: run.h5"),
    Case("Pictures", "plot -o in a directory that does not exist",
         ("plot", "run.h5", "-o", "nodir/p.png"), 2, "-o nodir/p.png: directory"),
    # -------------------------------------------------------------------- run files given
    Case("Run files given to read", "a run file that does not exist", ("plot", "absent.h5"), 2,
         "absent.h5: no such run file"),
    Case("Run files given to read", "plot a directory", ("plot", "dir"), 2,
         "dir: is a directory; give a run file (.h5)", setup=_mkdir("dir")),
    Case("Run files given to read", "classify a directory", ("classify", "dir"), 2,
         "dir: is a directory; give a run file (.h5)", setup=_mkdir("dir")),
    Case("Run files given to read", "an empty file", ("plot", "empty.h5"), 2,
         "cannot read run file empty.h5: not an HDF5 file, or a damaged or truncated one",
         setup=_write("empty.h5", b"")),
    Case("Run files given to read", "a text file", ("classify", "notes.h5"), 2,
         "cannot read run file notes.h5: not an HDF5 file", setup=_write("notes.h5", "notes"),
         after=_untouched("notes.h5", "notes")),
    Case("Run files given to read", "a truncated run file", ("plot", "half.h5"), 2,
         "cannot read run file half.h5: not an HDF5 file, or a damaged or truncated one (h5py: "
         "Unable to synchronously open file (truncated file",
         setup=_damaged("half.h5", "truncated")),
    Case("Run files given to read", "a run file with bytes zeroed in the middle",
         ("plot", "zeroed.h5"), 2,
         "cannot read run file zeroed.h5: it is damaged or not a porenet run file (h5py: ",
         setup=_damaged("zeroed.h5", "zeroed"), after=_absent("zeroed.png")),
    Case("Run files given to read", "classify it", ("classify", "zeroed.h5"), 2,
         "cannot read run file zeroed.h5: it is damaged", setup=_damaged("zeroed.h5", "zeroed")),
    Case("Run files given to read", "an HDF5 file of another program", ("plot", "other.h5"), 2,
         "cannot read run file other.h5: an HDF5 file, but not a porenet run file",
         setup=_foreign_hdf5),
    Case("Run files given to read", "an unreadable run file (chmod 000)", ("plot", "locked.h5"),
         2, "cannot read run file locked.h5: permission denied",
         setup=_chmod("locked.h5", 0, "x"), needs="non-root"),
    Case("Run files given to read", "an unknown classifier",
         ("classify", "run.h5", "--classifier", "nope"), 2,
         "--classifier nope: unknown classifier kind", after=_unchanged_run("run.h5")),
    Case("Run files given to read", "phase-diagram of a directory that does not exist",
         ("phase-diagram", "nodir", "-o", "p.png"), 2,
         "nodir: does not exist; give the output directory of `porenet sweep`"),
    # -------------------------------------------------------------------- interrupted
    Case("Interrupted", "Ctrl-C during a run", ("run", "slow.toml", "-o", "slow.h5"), 130,
         "porenet run: interrupted; no run file was written", setup=_write("slow.toml", SLOW),
         interrupt="porenet: run", after=_absent("slow.h5")),
]  # fmt: skip

#: Cases checked in the test's own process, to keep the suite short: errors in the arguments
#: and the scene found before any run file is read or written. The issue's cases, and every
#: case that reads or writes files, runs or is interrupted, start ``python -m porenet``.
IN_PROCESS = {
    "Usage": {"an unknown command", "--dpi that is not a number", "a scene file and --example",
              "an unknown example", "--threads 0", "--jobs 0"},
    "Scene": {c.name for c in CASES if c.section == "Scene"}
    - {"a scene file that does not exist", "disorder = nan in the file",
       "an unreadable scene file (chmod 000)"},
    "Apertures file": {c.name for c in CASES if c.section == "Apertures file"} - {"a text file"},
    "Pictures": {"--dpi -3", "--dpi nan", "--dpi inf"},
    "Run files given to read": {"an unknown classifier",
                                "phase-diagram of a directory that does not exist"},
}  # fmt: skip
CASES = [dataclasses.replace(c, in_process=c.name in IN_PROCESS.get(c.section, ())) for c in CASES]


# ------------------------------------------------------------------------------ running

#: Cases run at once (the suite's machine has 2 cores; each case is mostly start-up).
WORKERS = 2


def command(case: Case) -> list[str]:
    """The command line of ``case``; a memory limit is set by the shell (``ulimit -v``), as
    a user would, and as is safe from threads (unlike ``preexec_fn``)."""
    cmd = [sys.executable, "-m", "porenet", *case.argv]
    if case.memory_limit is None:
        return cmd
    return ["sh", "-c", f'ulimit -v {case.memory_limit // 1024} && exec "$@"', "sh", *cmd]


def run_in_process(case: Case, directory: Path) -> subprocess.CompletedProcess[str]:
    """``porenet.cli.main.main(case.argv)`` in ``directory``, its output captured."""
    import contextlib
    import io

    from porenet.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    cwd = Path.cwd()
    os.chdir(directory)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                status = main(list(case.argv))
            except SystemExit as exc:  # argparse's usage errors
                status = exc.code if isinstance(exc.code, int) else 2
    finally:
        os.chdir(cwd)
    return subprocess.CompletedProcess(list(case.argv), status, out.getvalue(), err.getvalue())


def run_case(case: Case, directory: Path) -> subprocess.CompletedProcess[str]:
    """Run ``porenet`` as the case says, in ``directory``, in a process of its own."""
    cmd = command(case)
    if case.interrupt is None:
        return subprocess.run(
            cmd, cwd=directory, capture_output=True, text=True, timeout=300, check=False
        )
    proc = subprocess.Popen(
        cmd, cwd=directory, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert proc.stderr is not None
    seen = []
    for line in proc.stderr:  # the run has started: its start line is out
        seen.append(line)
        if case.interrupt in line:
            proc.send_signal(signal.SIGINT)
            break
    out, err = proc.communicate(timeout=300)
    return subprocess.CompletedProcess(cmd, proc.returncode, out, "".join(seen) + err)


# ------------------------------------------------------------------------------- the doc


def _fragments(case: Case) -> tuple[str, ...]:
    return (case.message,) if isinstance(case.message, str) else case.message


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def markdown() -> str:
    """The generated part of docs/reliability.md: one table per section."""
    lines = [BEGIN, ""]
    section = None
    for case in CASES:
        if case.section != section:
            if section is not None:
                lines.append("")
            section = case.section
            lines += [
                f"### {section}",
                "",
                "| input | command | exit | message contains | run |",
                "|---|---|---|---|---|",
            ]
        command = " ".join(["porenet", *case.argv])
        note = {"non-root": " (not as root)"}.get(case.needs, "")
        message = " ... ".join(f'"{_cell(m)}"' for m in _fragments(case))
        how = "in-process" if case.in_process else "process"
        lines.append(
            f"| {_cell(case.name)}{note} | `{_cell(command)}` | {case.exit} | {message} | {how} |"
        )
    lines += ["", END]
    return "\n".join(lines) + "\n"


def _write_doc() -> None:
    text = DOC.read_text(encoding="utf-8")
    head, _, rest = text.partition(BEGIN)
    _, _, tail = rest.partition(END + "\n")
    DOC.write_text(head + markdown() + tail, encoding="utf-8")


if __name__ == "__main__":
    if "--write" in sys.argv:
        _write_doc()
    else:
        sys.stdout.write(markdown())
    raise SystemExit(0)


# --------------------------------------------------------------------------------- tests

import pytest  # noqa: E402  (not needed to print the table)


@dataclass
class Outcome:
    """A case's directory and process, or why it was skipped."""

    directory: Path
    proc: subprocess.CompletedProcess[str] | None = None
    skipped: str = ""


@pytest.fixture(scope="module")
def outcomes(tmp_path_factory, module_tmpfs) -> dict[str, Outcome]:
    """Every case set up in a directory of its own and run, :data:`WORKERS` at a time (the
    tmpfs mounts stay until the module's tests have looked at them)."""
    from concurrent.futures import ThreadPoolExecutor

    from porenet.cli.main import main

    template = tmp_path_factory.mktemp("template")
    (template / "scene.toml").write_text(TINY)
    assert main(["run", str(template / "scene.toml"), "-o", str(template / "run.h5"), "-q"]) == 0
    found: dict[str, Outcome] = {}
    for case in CASES:
        directory = tmp_path_factory.mktemp("case")
        found[case_id(case)] = outcome = Outcome(directory)
        if case.needs == "non-root" and os.geteuid() == 0:
            outcome.skipped = "root bypasses file permissions"
            continue
        for name in ("scene.toml", "run.h5"):
            shutil.copy(template / name, directory / name)
        shutil.copy(template / "run.h5", directory / "run.h5.orig")
        try:
            if case.setup is not None:
                case.setup(directory, module_tmpfs)
        except pytest.skip.Exception as exc:
            outcome.skipped = str(exc)
    todo = [(case, found[case_id(case)]) for case in CASES if not found[case_id(case)].skipped]
    with ThreadPoolExecutor(WORKERS) as pool:
        started = [
            (outcome, pool.submit(run_case, case, outcome.directory))
            for case, outcome in todo
            if not case.in_process
        ]
        for case, outcome in todo:  # meanwhile, here (the processes were given absolute cwd)
            if case.in_process:
                outcome.proc = run_in_process(case, outcome.directory)
        for outcome, future in started:
            outcome.proc = future.result()
    return found


def case_id(case: Case) -> str:
    return f"{case.section}: {case.name}"


@pytest.mark.parametrize("case", CASES, ids=case_id)
def test_case(case: Case, outcomes: dict[str, Outcome]) -> None:
    outcome = outcomes[case_id(case)]
    if outcome.skipped:
        pytest.skip(outcome.skipped)
    proc, directory = outcome.proc, outcome.directory
    assert proc is not None
    err = proc.stderr
    assert proc.returncode == case.exit, err
    for fragment in _fragments(case):
        assert fragment in err
    assert "Traceback" not in err and "internal error" not in err, err
    if case.exit in (1, 2):
        assert err.count(": error: ") == 1, err  # one message
    partial = [str(p) for p in directory.rglob("*.partial")]
    assert partial == [], f"temporary files left: {partial}"
    if case.after is not None:
        case.after(directory)


def test_the_documented_table_is_current() -> None:
    text = DOC.read_text(encoding="utf-8")
    assert BEGIN in text and END in text
    assert markdown() in text, "run: python tests/unit/test_reliability.py --write"
