"""A full disk (or any I/O error) during a sweep: one message naming the path and the reason,
exit status 1, no traceback, and never a summary.csv cut short (docs/sweeps.md, "Disk full and
other I/O errors"). Errors are injected, and once on a real, small tmpfs where one can be
mounted."""

from __future__ import annotations

import csv
import errno
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import porenet
from porenet.cli.main import main
from porenet.core.errors import RunFileError
from porenet.io.runfile import read_run
from porenet.sweep import run_sweep
from porenet.sweep.files import SweepIOError, atomic_write_text, storage_error

ENOSPC = os.strerror(errno.ENOSPC)  # "No space left on device"
ADVICE = (
    "free some space on that file system (or use another output directory, -o) and re-run "
    "the same command: it resumes"
)

IP_SWEEP = """
name = "ip"
replicates = 4
[base]
lattice = { n = 16, disorder = 0.3 }
fluid = { kind = "invasion-percolation" }
[[axes]]
key = "lattice.n"
values = [16, 18]
"""

#: The first point fails at once (NumericalError: more steps needed than max_steps).
FAILING_SWEEP = """
name = "fails"
[base]
lattice = { n = 16, disorder = 0.3 }
fluid = { kind = "viscous", capillary_number = 1e-2 }
[[axes]]
key = "fluid.max_steps"
values = [1, 1000000]
"""


def _sweep(tmp_path: Path, text: str = IP_SWEEP) -> Path:
    path = tmp_path / "sweep.toml"
    path.write_text(text)
    return path


def _rows(out: Path) -> list[dict[str, str]]:
    with (out / "summary.csv").open(newline="") as f:
        return list(csv.DictReader(f))


def _partials(out: Path) -> list[Path]:
    return [*out.glob(".*.partial"), *(out / "runs").glob(".*.partial")]


def _disk_full_on(monkeypatch, matches, after: int = 0) -> None:
    """``os.replace`` onto a file whose name ``matches`` fails with ENOSPC after ``after``
    successful ones (what a full disk does to the last step of an atomic write)."""
    real = os.replace
    seen = [0]

    def replace(src, dst, *args, **kwargs):
        if matches(Path(dst).name):
            seen[0] += 1
            if seen[0] > after:
                raise OSError(errno.ENOSPC, ENOSPC)
        return real(src, dst, *args, **kwargs)

    monkeypatch.setattr(os, "replace", replace)


@pytest.mark.parametrize("step", ["fsync", "replace"])
def test_an_atomic_write_that_fails_keeps_the_old_file_and_no_temporary(
    tmp_path, monkeypatch, step
):
    path = tmp_path / "summary.csv"
    path.write_text("old\n")

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, ENOSPC)

    monkeypatch.setattr(os, step, full)
    with pytest.raises(SweepIOError) as info:
        atomic_write_text(path, "new\n" * 1000)
    assert str(info.value) == f"cannot write {path}: {ENOSPC}; {ADVICE}"
    assert info.value.errno == errno.ENOSPC and info.value.path == path
    assert path.read_text() == "old\n"
    assert list(tmp_path.iterdir()) == [path]  # the temporary file is gone


def test_a_full_disk_mid_sweep_stops_with_one_message_and_a_whole_summary(
    tmp_path, monkeypatch, capsys
):
    """The 4th write of summary.csv (the header, then after each run) fails: exit 1, one
    message, summary.csv is the last whole table (2 rows), the run files stay, a re-run
    completes."""
    out = tmp_path / "out"
    _disk_full_on(monkeypatch, lambda name: name == "summary.csv", after=3)
    assert main(["sweep", str(_sweep(tmp_path)), "-o", str(out), "--workers", "1"]) == 1
    err = capsys.readouterr().err
    assert err.count("porenet sweep: error: ") == 1
    assert (
        f"porenet sweep: error: cannot write {out / 'summary.csv'}: {ENOSPC}; the sweep "
        f"stopped with 3 of 8 runs finished, which are kept; {ADVICE}"
    ) in err
    assert "Traceback" not in err and "internal error" not in err
    rows = _rows(out)
    assert [r["run_id"] for r in rows] == ["p0000-r00", "p0000-r01"]
    assert all(read_run(out / r["run_file"]).summary["seed"] == int(r["seed"]) for r in rows)
    assert sorted(p.name for p in (out / "runs").iterdir()) == [
        "p0000-r00.h5",
        "p0000-r01.h5",
        "p0000-r02.h5",
    ]
    assert _partials(out) == [] and (out / ".lock").read_text() == ""  # released
    monkeypatch.undo()  # space is back
    assert main(["sweep", str(_sweep(tmp_path)), "-o", str(out), "-q", "--workers", "1"]) == 0
    rows = _rows(out)
    assert len(rows) == 8 and {r["status"] for r in rows} == {"done"}


def test_a_sweep_json_that_cannot_be_written_leaves_no_summary(tmp_path, monkeypatch, capsys):
    out = tmp_path / "out"
    _disk_full_on(monkeypatch, lambda name: name == "sweep.json")
    assert main(["sweep", str(_sweep(tmp_path)), "-o", str(out), "--workers", "1"]) == 1
    err = capsys.readouterr().err
    assert f"cannot write {out / 'sweep.json'}: {ENOSPC}; the sweep stopped with 0 of 8" in err
    assert "Traceback" not in err
    assert sorted(p.name for p in out.iterdir()) == [".lock", "runs"]  # no summary.csv
    assert list((out / "runs").iterdir()) == []


def test_an_error_record_that_cannot_be_written_stops_the_sweep(tmp_path, monkeypatch, capsys):
    out = tmp_path / "out"
    _disk_full_on(monkeypatch, lambda name: name.endswith(".error.txt"))
    path = _sweep(tmp_path, FAILING_SWEEP)
    assert main(["sweep", str(path), "-o", str(out), "--workers", "1"]) == 1
    err = capsys.readouterr().err
    record = out / "runs" / "p0000-r00.error.txt"
    assert f"porenet sweep: error: cannot write {record}: {ENOSPC}" in err
    assert "Traceback" not in err and not record.exists() and _partials(out) == []
    monkeypatch.undo()
    report = run_sweep(path, out, workers=1)  # the failed run is run again
    assert (report.ran, report.done, report.failed) == (2, 1, 1) and record.exists()


def test_a_run_file_that_cannot_be_written_for_lack_of_space_stops_the_sweep(
    tmp_path, monkeypatch, capsys
):
    """Not recorded as the run's failure (no error record): a re-run runs it."""
    out = tmp_path / "out"
    _disk_full_on(monkeypatch, lambda name: name.endswith(".h5"), after=1)
    assert main(["sweep", str(_sweep(tmp_path)), "-o", str(out), "--workers", "1"]) == 1
    err = capsys.readouterr().err
    run_file = out / "runs" / "p0000-r01.h5"
    assert (
        f"porenet sweep: error: cannot write {run_file}: {ENOSPC}; the sweep stopped with 1 "
        f"of 8 runs finished, which are kept; {ADVICE}"
    ) in err
    assert sorted(p.name for p in (out / "runs").iterdir()) == ["p0000-r00.h5"]
    assert [r["run_id"] for r in _rows(out)] == ["p0000-r00"]
    monkeypatch.undo()
    report = run_sweep(_sweep(tmp_path), out, workers=1)
    assert (report.ran, report.done, report.failed) == (7, 8, 0)


def test_storage_errors_are_told_from_the_runs_own_failures():
    assert storage_error(OSError(errno.ENOSPC, ENOSPC)) == (errno.ENOSPC, ENOSPC)
    try:
        try:
            raise OSError(errno.EDQUOT, "quota")
        except OSError as exc:
            raise RunFileError("r.h5: cannot write run file") from exc
    except RunFileError as wrapped:
        assert storage_error(wrapped) == (errno.EDQUOT, os.strerror(errno.EDQUOT))
    hdf5 = RuntimeError(
        "Can't decrement id ref count (file write failed: time = ..., filename = 'x.partial', "
        "file descriptor = 10, errno = 28, error message = 'No space left on device')"
    )
    assert storage_error(hdf5) == (errno.ENOSPC, ENOSPC)
    assert storage_error(OSError(errno.ENOENT, "No such file")) is None
    assert storage_error(ValueError("a bad scene")) is None


# ------------------------------------------------------------------ a real, small file system

REAL_DISK = r"""
set -u
mount -t tmpfs -o size=512k porenet-test "$DISK" || exit 97
sweep() { "$PY" -m porenet sweep "$SWEEP" -o "$DISK/out" --workers 1 -q; }
sweep > "$LOG/1.out" 2> "$LOG/1.err"; echo $? > "$LOG/1.rc"
cp "$DISK/out/summary.csv" "$LOG/summary.before"
head -c 4096 /dev/zero > "$DISK/reserve"
dd if=/dev/zero of="$DISK/filler" bs=4096 2> /dev/null
rm "$DISK/reserve"   # one page left: the lock's details fit in it, sweep.json does not
sweep > "$LOG/2.out" 2> "$LOG/2.err"; echo $? > "$LOG/2.rc"
cp "$DISK/out/summary.csv" "$LOG/summary.after"
ls -A "$DISK/out" "$DISK/out/runs" > "$LOG/2.ls"
rm "$DISK/filler"
sweep > "$LOG/3.out" 2> "$LOG/3.err"; echo $? > "$LOG/3.rc"
"""


def test_on_a_full_tmpfs_the_summary_stays_whole(tmp_path):
    """A real full disk (a 512 KiB tmpfs in a private mount namespace): a re-run of a finished
    sweep cannot write sweep.json; exit 1, one message naming it, summary.csv unchanged, no
    temporary file left; with space again the same command succeeds."""
    unshare = shutil.which("unshare")
    if not sys.platform.startswith("linux") or unshare is None or os.geteuid() != 0:
        pytest.skip("needs Linux, unshare(1) and root to mount a small tmpfs")
    disk, log = tmp_path / "disk", tmp_path / "log"
    disk.mkdir()
    log.mkdir()
    sweep = tmp_path / "ip.toml"
    sweep.write_text(IP_SWEEP.replace("replicates = 4", "replicates = 2"))
    env = dict(
        os.environ,
        DISK=str(disk),
        LOG=str(log),
        SWEEP=str(sweep),
        PY=sys.executable,
        PYTHONPATH=str(Path(porenet.__file__).parents[1]),
    )
    done = subprocess.run(
        [unshare, "--mount", "--propagation", "private", "sh", "-c", REAL_DISK],
        env=env, cwd=tmp_path, capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    if done.returncode == 97 or (done.returncode != 0 and not (log / "1.rc").exists()):
        pytest.skip(f"cannot mount a tmpfs here: {done.stderr.strip()[:200]}")

    def step(name: str) -> tuple[int, str]:
        return int((log / f"{name}.rc").read_text()), (log / f"{name}.err").read_text()

    assert step("1") == (0, "")
    rc, err = step("2")
    assert rc == 1, err
    assert err == (
        f"porenet sweep: error: cannot write {disk / 'out' / 'sweep.json'}: {ENOSPC}; the sweep "
        f"stopped with 4 of 4 runs finished, which are kept; {ADVICE}\n"
    )
    assert (log / "summary.after").read_bytes() == (log / "summary.before").read_bytes()
    assert ".partial" not in (log / "2.ls").read_text()
    assert step("3") == (0, "")
