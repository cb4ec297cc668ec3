"""Output files are complete or absent: porenet.io.atomic, and the run files and pictures
written through it, on a full disk (injected, and on a real small tmpfs where root may mount
one). docs/reliability.md, "Disk full and I/O errors"."""

from __future__ import annotations

import errno
import io
import os
from pathlib import Path

import h5py
import pytest

import porenet
from porenet.core.errors import OutputError
from porenet.io import atomic
from porenet.io.atomic import atomic_output, atomic_write_bytes
from porenet.io.runfile import read_run, update_summary, write_run

TINY = {"seed": 1, "lattice": {"n": 10, "disorder": 0.3}, "fluid": {}}


@pytest.fixture(scope="module")
def tiny_run():
    return porenet.run(TINY)


def _leftovers(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir() if p.name.endswith(".partial"))


class _FullDisk(io.RawIOBase):
    """A file whose writes fail with ENOSPC once ``room`` bytes are written."""

    def __init__(self, path: Path, room: int) -> None:
        self._fh = io.FileIO(path, "w")
        self.room = room

    def writable(self) -> bool:
        return True

    def write(self, data) -> int:  # type: ignore[override]
        if len(data) > self.room:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        self.room -= len(data)
        return self._fh.write(data)

    def close(self) -> None:
        self._fh.close()
        super().close()


@pytest.fixture
def full_disk(monkeypatch):
    """Every file porenet.io.atomic opens for writing takes 100 bytes, then fails (ENOSPC)."""

    def fake_open(path, mode="r", *args, **kwargs):
        if "w" in mode:
            return _FullDisk(Path(path), room=100)
        return open(path, mode, *args, **kwargs)

    monkeypatch.setattr(atomic, "open", fake_open, raising=False)


def test_atomic_output_renames_on_success_with_the_usual_permissions(tmp_path):
    target = tmp_path / "a.txt"
    with atomic_output(target, what="note") as tmp:
        assert tmp.parent == tmp_path and tmp.name.startswith(".a.txt.")
        tmp.write_text("hello")
        assert not target.exists()  # nothing under the final name before the end
    assert target.read_text() == "hello" and _leftovers(tmp_path) == []
    umask = os.umask(0)
    os.umask(umask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~umask


def test_a_failure_leaves_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "a.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError, match="boom"), atomic_output(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("boom")
    assert target.read_text() == "old" and _leftovers(tmp_path) == []
    with pytest.raises(KeyboardInterrupt), atomic_output(target) as tmp:
        raise KeyboardInterrupt
    assert target.read_text() == "old" and _leftovers(tmp_path) == []


def test_an_os_error_becomes_an_output_error_naming_path_and_reason(tmp_path):
    target = tmp_path / "run.h5"
    with pytest.raises(OutputError) as info, atomic_output(target, what="run file"):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    err = info.value
    assert err.path == target and err.errno == errno.ENOSPC and err.exit_status == 1
    assert str(err) == (
        f"cannot write run file {target}: no space left on device (ENOSPC); "
        "free some space or write elsewhere"
    )
    assert _leftovers(tmp_path) == []
    with pytest.raises(OutputError, match=r"directory does not exist.*\(ENOENT\)|\(ENOENT\)"):
        atomic_write_bytes(tmp_path / "absent" / "x.bin", b"x")


def test_atomic_write_bytes_on_a_full_disk(tmp_path, full_disk):
    target = tmp_path / "x.bin"
    with pytest.raises(OutputError, match="no space left on device"):
        atomic_write_bytes(target, b"x" * 1000, what="picture")
    assert not target.exists() and _leftovers(tmp_path) == []
    atomic_write_bytes(target, b"x" * 50)  # what fits is written
    assert target.read_bytes() == b"x" * 50


def test_a_run_file_on_a_full_disk_is_one_error_and_no_file(tmp_path, tiny_run, full_disk):
    """The h5py crash of issue 20: HDF5 builds the file in memory, so it never meets the
    full disk; the error names the path, nothing is left (the PytestUnraisableException
    filter turns any h5py noise at deallocation into a failure)."""
    target = tmp_path / "run.h5"
    with pytest.raises(OutputError, match=f"cannot write run file {target}: no space left"):
        write_run(target, tiny_run.data)
    assert list(tmp_path.iterdir()) == []


def test_a_picture_on_a_full_disk(tmp_path, tiny_run, full_disk):
    from porenet.viz.pattern import plot_pattern, save_figure

    target = tmp_path / "p.png"
    with pytest.raises(OutputError, match=f"cannot write picture {target}: no space left"):
        save_figure(plot_pattern(tiny_run.data), target)
    assert list(tmp_path.iterdir()) == []


def test_classify_on_a_full_disk_leaves_the_run_file_as_it_was(tmp_path, tiny_run, monkeypatch):
    target = write_run(tmp_path / "run.h5", tiny_run.data)
    before = target.read_bytes()

    def no_room(*args, **kwargs):
        raise OSError(errno.EDQUOT, os.strerror(errno.EDQUOT))

    monkeypatch.setattr(atomic.tempfile, "mkstemp", no_room)
    with pytest.raises(OutputError, match=r"\(EDQUOT\); free some space within your quota"):
        update_summary(target, {"regime": "VF"})
    assert target.read_bytes() == before and _leftovers(tmp_path) == []


def test_the_file_built_in_memory_reads_back(tmp_path, tiny_run):
    target = write_run(tmp_path / "run.h5", tiny_run.data)
    data = read_run(target)
    assert data.summary["n_drained"] == tiny_run.summary["n_drained"]
    update_summary(target, {"regime": "VF"})
    assert read_run(target).summary["regime"] == "VF"
    with h5py.File(target) as f:
        assert f.attrs["format_version"] == 2


def test_a_real_full_disk(tmp_path, tiny_run, tmpfs):
    """A 64 kB tmpfs filled to ~2 kB free (root only): the run file does not fit."""
    full = tmpfs(tmp_path / "full", full=True)
    target = full / "run.h5"
    with pytest.raises(OutputError, match="no space left on device"):
        write_run(target, tiny_run.data)
    assert sorted(p.name for p in full.iterdir()) == ["filler"]


def test_a_read_only_file_system(tmp_path, tiny_run, tmpfs):
    ro = tmpfs(tmp_path / "ro", readonly=True)
    with pytest.raises(OutputError, match=r"read-only file system \(EROFS\)"):
        write_run(ro / "run.h5", tiny_run.data)


def test_a_checkpoint_on_a_full_disk_keeps_the_previous_one(tmp_path, monkeypatch):
    """write_checkpoint goes through atomic_output: an OutputError (exit 1, not the exit 2
    of a bad checkpoint given to read), the previous checkpoint untouched."""
    from porenet.io.checkpoint import read_header, write_checkpoint

    header = dict(porenet_version="0", code_fingerprint="x", plugin_sources={},
                  scene_digest="y", scene_name="s", output=None, n_drained=1, step=1,
                  model_time=0.0, wall_time_s=0.0, written="now")  # fmt: skip
    path = write_checkpoint(tmp_path / "run.h5.checkpoint", {"state": 1}, header)
    before = path.read_bytes()
    monkeypatch.setattr(atomic.tempfile, "mkstemp", _no_space)
    with pytest.raises(OutputError, match=r"cannot write checkpoint .*: no space left") as info:
        write_checkpoint(path, {"state": 2}, header | {"n_drained": 2})
    assert info.value.exit_status == 1
    assert path.read_bytes() == before and read_header(path).n_drained == 1
    assert _leftovers(tmp_path) == []


def _no_space(*args, **kwargs):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
