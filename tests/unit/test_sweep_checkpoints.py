"""Sweeps go on with an interrupted run from its checkpoint (docs/sweeps.md, "Checkpoints"):
the run file is the uninterrupted run's, to the bit; a checkpoint that cannot be resumed is
said and the run starts afresh; a checkpoint of a run the sweep does not have is refused; a
failed run's checkpoint is removed. The real-process case (``kill -9`` of ``porenet sweep``
mid-run, then the same command again) is in ``test_sweep_processes.py``."""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import pytest

from porenet.core.errors import ConfigError
from porenet.io.checkpoint import checkpoint_path
from porenet.io.runfile import read_run
from porenet.simulation import Simulation
from porenet.sweep.runner import run_sweep
from porenet.sweep.spec import expand, load_sweep
from porenet.sweep.worker import RunTask, execute_run
from porenet.testing.runs import Killed, KilledAfterCheckpoint

#: Fig. 1b's scene, small and explicit (~250 drained pores, < 1 s), two disorders.
SWEEP = """
name = "resume"
[base]
seed = 1
lattice = { n = 50, disorder = 0.3, pore_size = 1e-7 }
fluid = { kind = "viscous", capillary_number = 9e-4, integrator = "explicit" }
classifier = { kind = "none" }
[[axes]]
key = "lattice.disorder"
values = [0.3, 0.5]
"""

#: The arrays of a run file that must agree to the bit with the uninterrupted run's.
OUTCOME = ("order", "throat", "invasion_pressure", "invasion_time", "pressure", "trapped")


def interrupted(scene: dict, output: Path) -> Path:
    """The checkpoint a run of ``scene`` writing ``output`` leaves when killed mid-way."""
    path = checkpoint_path(output)
    path.parent.mkdir(parents=True, exist_ok=True)
    with pytest.raises(Killed):
        Simulation.from_scene(scene, output=output).run(
            KilledAfterCheckpoint(path, every_drained=60)
        )
    return path


def assert_same_run(a: Path, b: Path) -> None:
    x, y = read_run(a), read_run(b)
    for name in OUTCOME:
        assert np.array_equal(getattr(x, name), getattr(y, name)), name
    for key, series in x.timeseries.items():
        assert np.array_equal(series, y.timeseries[key]), key


@pytest.fixture(scope="module")
def sweep_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("sweep") / "resume.toml"
    path.write_text(SWEEP)
    return path


@pytest.fixture(scope="module")
def reference(sweep_file: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The sweep run without interruption."""
    out = tmp_path_factory.mktemp("reference")
    report = run_sweep(sweep_file, out, workers=1)
    assert report.done == 2 and report.resumed == 0
    return out


def test_a_sweep_goes_on_from_a_checkpoint_to_the_uninterrupted_result(
    sweep_file: Path, reference: Path, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    runs = expand(load_sweep(sweep_file))
    ckpt = interrupted(runs[1].scene, tmp_path / runs[1].run_file)
    caplog.set_level(logging.INFO, logger="porenet")
    report = run_sweep(sweep_file, tmp_path, workers=1, checkpoint_every="50")
    assert (report.done, report.ran, report.resumed) == (2, 2, 1)
    assert "(2 run now, 1 of them from a checkpoint, 0 finished before)" in report.describe()
    assert f"{runs[1].run_id} went on from its checkpoint at " in caplog.text
    assert not ckpt.exists()  # removed with the run file complete
    assert list((tmp_path / "runs").glob("*.checkpoint")) == []
    for run in runs:
        assert_same_run(reference / run.run_file, tmp_path / run.run_file)


def test_without_the_flag_a_left_checkpoint_is_still_resumed(
    sweep_file: Path, reference: Path, tmp_path: Path
) -> None:
    runs = expand(load_sweep(sweep_file))
    ckpt = interrupted(runs[0].scene, tmp_path / runs[0].run_file)
    report = run_sweep(sweep_file, tmp_path, workers=1)
    assert report.resumed == 1 and not ckpt.exists()
    assert_same_run(reference / runs[0].run_file, tmp_path / runs[0].run_file)


def test_a_checkpoint_of_another_scene_is_said_and_the_run_starts_afresh(
    sweep_file: Path, reference: Path, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    runs = expand(load_sweep(sweep_file))
    # run 1's checkpoint where run 0's belongs (an edited sweep file would do the same)
    interrupted(runs[1].scene, tmp_path / "runs" / "elsewhere.h5").rename(
        checkpoint_path(tmp_path / runs[0].run_file)
    )
    caplog.set_level(logging.INFO, logger="porenet")
    report = run_sweep(sweep_file, tmp_path, workers=1)
    assert report.resumed == 0 and report.done == 2
    assert "holds a checkpoint of another scene; the run starts afresh" in caplog.text
    assert_same_run(reference / runs[0].run_file, tmp_path / runs[0].run_file)
    assert not checkpoint_path(tmp_path / runs[0].run_file).exists()


def test_a_damaged_checkpoint_is_said_and_the_run_starts_afresh(
    sweep_file: Path, reference: Path, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    runs = expand(load_sweep(sweep_file))
    (tmp_path / "runs").mkdir()
    checkpoint_path(tmp_path / runs[0].run_file).write_bytes(b"PORENET-CHECKPOINT\nhalf")
    caplog.set_level(logging.INFO, logger="porenet")
    report = run_sweep(sweep_file, tmp_path, workers=1)
    assert report.resumed == 0 and report.done == 2
    assert "the run starts afresh" in caplog.text
    assert_same_run(reference / runs[0].run_file, tmp_path / runs[0].run_file)


def test_a_checkpoint_of_a_run_the_sweep_does_not_have_is_refused(
    sweep_file: Path, tmp_path: Path
) -> None:
    (tmp_path / "runs").mkdir()
    (tmp_path / "runs" / "p0007-r00.h5.checkpoint").write_bytes(b"")
    with pytest.raises(ConfigError, match=r"p0007-r00\.h5\.checkpoint: not a run of"):
        run_sweep(sweep_file, tmp_path, workers=1)


def test_a_checkpoint_beside_a_finished_run_is_removed(
    sweep_file: Path, reference: Path, tmp_path: Path
) -> None:
    """A run killed between writing its run file and removing its checkpoint."""
    import shutil

    shutil.copytree(reference, tmp_path / "out")
    runs = expand(load_sweep(sweep_file))
    stale = checkpoint_path(tmp_path / "out" / runs[0].run_file)
    stale.write_bytes(b"stale")
    report = run_sweep(sweep_file, tmp_path / "out", workers=1)
    assert (report.ran, report.skipped) == (0, 2) and not stale.exists()


def test_a_failed_run_leaves_no_checkpoint(tmp_path: Path) -> None:
    output = tmp_path / "r.h5"
    ckpt = checkpoint_path(output)
    ckpt.write_bytes(b"from a run that will fail")
    scene = {"lattice": {"n": 8}, "fluid": {"kind": "no-such-model"}}
    outcome = execute_run(RunTask("r", scene, str(output)))
    assert outcome["status"] == "failed" and outcome["resumed_at"] is None
    assert "no-such-model" in outcome["error"] and not ckpt.exists()


def test_a_bad_period_is_refused_before_anything_runs(sweep_file: Path, tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="--checkpoint-every '10 minutes': give a duration"):
        run_sweep(sweep_file, tmp_path / "out", checkpoint_every="10 minutes")
    assert not (tmp_path / "out").exists()
