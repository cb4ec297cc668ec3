"""``porenet run --checkpoint-every`` and ``porenet resume`` on the real command line: a run
killed with SIGKILL and resumed writes the uninterrupted run's file, to the bit; checkpoints
that are damaged, foreign or from other code are refused with exit 2 and a message that says
what to do (docs/run-file.md, "Checkpoints")."""

from __future__ import annotations

import json
import os
import signal
import struct
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from porenet.io.checkpoint import MAGIC, checkpoint_path, read_header
from porenet.io.runfile import read_run

ROOT = Path(__file__).resolve().parents[2]
FIG1B = str(ROOT / "examples" / "scenes" / "fig1b.toml")
#: Fig. 1b's scene, small and explicit: ~1 s to breakthrough, ~470 drained pores.
SETS = ["--set", "lattice.n=70", "--set", "fluid.integrator=explicit", "--set",
        "classifier.kind=none"]  # fmt: skip


def porenet(*args: str, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    """The real command line, in a new process."""
    return subprocess.run(
        [sys.executable, "-m", "porenet", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def porenet_here(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str]:
    """The command line in this process (for the many cases that end before any run): exit
    status and stderr."""
    from porenet.cli.main import main

    status = main(list(args))
    return status, capsys.readouterr().err


def test_killed_run_resumes_to_the_uninterrupted_result(tmp_path: Path) -> None:
    reference = tmp_path / "reference.h5"
    assert porenet("run", FIG1B, *SETS, "-o", str(reference), "-q").returncode == 0
    out = tmp_path / "run.h5"
    ckpt = checkpoint_path(out)
    proc = subprocess.Popen(
        [sys.executable, "-m", "porenet", "run", FIG1B, *SETS, "-o", str(out), "-q",
         "--checkpoint-every", "100"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )  # fmt: skip
    deadline = time.monotonic() + 120
    while not ckpt.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    assert ckpt.exists(), "no checkpoint appeared before the run ended"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    assert proc.returncode == -signal.SIGKILL
    assert not out.exists()  # the run file is written only at the end
    header = read_header(ckpt)
    assert header.n_drained >= 100 and header.output == str(out)

    again = porenet("run", FIG1B, *SETS, "-o", str(out))
    assert again.returncode == 2
    assert "porenet resume" in again.stderr and "--overwrite" in again.stderr

    done = porenet("resume", str(ckpt))
    assert done.returncode == 0, done.stderr
    assert "resuming" in done.stderr and not ckpt.exists()
    a, b = read_run(reference), read_run(out)
    for name in ("order", "throat", "invasion_pressure", "invasion_time", "pressure", "trapped"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    for key, series in a.timeseries.items():
        assert np.array_equal(series, b.timeseries[key]), key


@pytest.fixture(scope="module")
def checkpoint(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A checkpoint of a small run (written in-process: the API the CLI uses)."""
    from porenet.simulation import Simulation
    from porenet.testing.runs import Killed, KilledAfterCheckpoint

    folder = tmp_path_factory.mktemp("ckpt")
    path = folder / "small.h5.checkpoint"

    sim = Simulation.from_scene(FIG1B, ["lattice.n=30", "fluid.integrator=explicit"],
                                output=folder / "small.h5")  # fmt: skip
    with pytest.raises(Killed):
        sim.run(KilledAfterCheckpoint(path, every_drained=20))
    return path


def _rewrite_header(source: Path, target: Path, **changes: object) -> None:
    data = source.read_bytes()
    (size,) = struct.unpack("<Q", data[len(MAGIC) : len(MAGIC) + 8])
    head = json.loads(data[len(MAGIC) + 8 : len(MAGIC) + 8 + size])
    head.update(changes)
    new = json.dumps(head).encode()
    target.write_bytes(MAGIC + struct.pack("<Q", len(new)) + new + data[len(MAGIC) + 8 + size :])


def test_resume_writes_where_asked(checkpoint: Path, tmp_path: Path) -> None:
    copy = tmp_path / checkpoint.name
    copy.write_bytes(checkpoint.read_bytes())
    out = tmp_path / "elsewhere.h5"
    done = porenet("resume", str(copy), "-o", str(out), "-q")
    assert done.returncode == 0, done.stderr
    assert read_run(out).summary["n_drained"] > 20 and not copy.exists()


@pytest.mark.parametrize(
    ("damage", "message"),
    [
        ("text", "is not a porenet checkpoint"),
        ("truncated", "damaged checkpoint"),
        ("flipped", "damaged checkpoint"),
        ("version", "was written by porenet 0.0.0"),
        ("code", "other porenet code"),
        ("plugin", "plugin code of"),
        ("directory", "is a directory"),
        ("missing", "no such checkpoint"),
    ],
)
def test_bad_checkpoints_are_refused(
    checkpoint: Path, tmp_path: Path, damage: str, message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "bad.checkpoint"
    data = checkpoint.read_bytes()
    if damage == "text":
        bad.write_text("not a checkpoint\n")
    elif damage == "truncated":
        bad.write_bytes(data[: len(data) // 2])
    elif damage == "flipped":
        bad.write_bytes(data[:-100] + bytes([data[-100] ^ 0xFF]) + data[-99:])
    elif damage == "version":
        _rewrite_header(checkpoint, bad, porenet_version="0.0.0")
    elif damage == "code":
        _rewrite_header(checkpoint, bad, code_fingerprint="0" * 64)
    elif damage == "plugin":
        _rewrite_header(checkpoint, bad, plugin_sources={"no_such_plugin.models:Fluid": "ab"})
    elif damage == "directory":
        bad.mkdir()
    status, err = porenet_here(capsys, "resume", str(bad), "-o", str(tmp_path / "out.h5"))
    assert status == 2, err
    assert message in err and "Traceback" not in err
    assert not (tmp_path / "out.h5").exists()


def test_a_damaged_checkpoint_on_the_real_command_line(checkpoint: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad.checkpoint"
    bad.write_bytes(checkpoint.read_bytes()[:-10])
    result = porenet("resume", str(bad))
    assert result.returncode == 2 and "damaged checkpoint" in result.stderr
    assert "Traceback" not in result.stderr


@pytest.mark.parametrize("value", ["0", "-5", "10x", "", "nanm", "infs", "1.5"])
def test_bad_checkpoint_period_names_the_flag(
    value: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    status, err = porenet_here(capsys, "run", "--example", "quickstart", "-o",
                               str(tmp_path / "q.h5"), "--checkpoint-every", value)  # fmt: skip
    assert status == 2
    assert "--checkpoint-every" in err and not (tmp_path / "q.h5").exists()


def test_overwrite_starts_afresh_and_drops_the_old_checkpoint(
    checkpoint: Path, tmp_path: Path
) -> None:
    out = tmp_path / "q.h5"
    stale = checkpoint_path(out)
    stale.write_bytes(checkpoint.read_bytes())
    refused = porenet("run", "--example", "quickstart", "-o", str(out))
    assert refused.returncode == 2 and "holds a checkpoint of scene" in refused.stderr
    done = porenet("run", "--example", "quickstart", "-o", str(out), "--overwrite", "-q")
    assert done.returncode == 0 and out.exists() and not stale.exists()
