"""One run of a sweep, as a worker process (or dask worker) executes it.

:func:`execute_run` takes a picklable :class:`RunTask` and returns a plain dict: the run's
summary values or its failure, never an exception, with the porenet warnings it logged. A run
that left a checkpoint goes on from it (:func:`start_or_resume`; docs/sweeps.md,
"Checkpoints: runs that go on where they stopped"). The sweep's side (the directory, the
summary, the executors) is :mod:`porenet.sweep.runner`.
"""

from __future__ import annotations

import contextlib
import logging
import time
import traceback
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from porenet.sweep.files import storage_error
from porenet.sweep.records import SUMMARY_FIELDS, plain

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class RunTask:
    """What a worker needs for one run (picklable)."""

    run_id: str
    scene: dict[str, Any]
    output: str  # absolute path of the run file
    threads: int = 1  # threads of the parallel kernels (the cores a worker may use)
    #: ``--checkpoint-every`` (``"10m"``, ``"5000"``), None for no checkpoints; a checkpoint
    #: left beside the run file is resumed either way
    checkpoint_every: str | None = None


class _Capture(logging.Handler):
    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        with contextlib.suppress(Exception):
            self.messages.append(f"{record.levelname.lower()}: {record.getMessage()}")


def one_line(exc: BaseException) -> str:
    """``Type: message`` on one line."""
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def execute_run(task: RunTask) -> dict[str, Any]:
    """Run one scene and write its run file; never raises for a failing run.

    Returns ``{"status": "done", <SUMMARY_FIELDS>, "task_time_s", "warnings", "resumed_at"}``
    or ``{"status": "failed", "error", "traceback", "wall_time_s", "task_time_s",
    "warnings", "resumed_at"}``; ``resumed_at`` is the number of drained pores of the
    checkpoint the run went on from (:func:`start_or_resume`), None if it started afresh.
    The porenet log records of WARNING and above emitted during the run are returned in
    ``warnings`` instead of being printed by the worker. A failure caused by a full disk, a
    quota or a read-only file system (:func:`porenet.sweep.files.storage_error`) also has
    ``storage_errno`` and ``storage_error`` (the system's reason): the sweep stops on it
    instead of recording the run as failed, and the run's checkpoint is kept; after any other
    failure it is removed (a retry starts afresh).
    """
    t0 = time.perf_counter()
    logger = logging.getLogger("porenet")
    capture, propagate = _Capture(), logger.propagate
    logger.addHandler(capture)
    logger.propagate = False
    resumed_at: int | None = None
    try:
        from porenet.jit.threads import configure_threads

        configure_threads("auto", most=task.threads)
        simulation, schedule, resumed_at = start_or_resume(task)
        result = simulation.run(schedule)
        out: dict[str, Any] = {k: plain(result.summary.get(k)) for k in SUMMARY_FIELDS}
        out["status"] = "done"
    except Exception as exc:
        out = {
            "status": "failed",
            "error": one_line(exc),
            "traceback": traceback.format_exc(),
            "wall_time_s": time.perf_counter() - t0,
        }
        storage = storage_error(exc)  # a full disk is not the run's failure: it stops the sweep
        if storage is not None:
            out["storage_errno"], out["storage_error"] = storage
        else:
            with contextlib.suppress(OSError):
                _checkpoint_of(task).unlink(missing_ok=True)
    finally:
        logger.removeHandler(capture)
        logger.propagate = propagate
    out["task_time_s"] = time.perf_counter() - t0
    out["warnings"] = capture.messages
    out["resumed_at"] = resumed_at
    return out


def _checkpoint_of(task: RunTask) -> Path:
    from porenet.io.checkpoint import checkpoint_path

    return checkpoint_path(task.output)


def start_or_resume(task: RunTask) -> tuple[Any, Any, int | None]:
    """The simulation of ``task``, its checkpoint schedule (or None), and where it resumed.

    A checkpoint beside the run file (``<run file>.checkpoint``) of this very scene, written
    by this porenet, is loaded and the run goes on from it: the result is the one an
    uninterrupted run gives, to the bit (docs/run-file.md, "Checkpoints"); the third value is
    its number of drained pores. A checkpoint that cannot be resumed (another scene, another
    porenet version or code, damaged) is logged as a warning and the run starts afresh (None);
    the next checkpoint replaces it. The schedule writes checkpoints every
    ``task.checkpoint_every``; without one, a checkpoint resumed from is removed at the end.
    """
    from porenet.config.loading import load_scene
    from porenet.hooks import get_registry
    from porenet.io.checkpoint import CheckpointError, CheckpointSchedule, read_header, scene_digest
    from porenet.simulation import Simulation

    path = _checkpoint_of(task)
    registry = get_registry()
    scene = load_scene(task.scene, registry=registry)
    if task.checkpoint_every is not None:
        schedule = CheckpointSchedule.parse(task.checkpoint_every, path)
    else:
        schedule = CheckpointSchedule(path) if path.exists() else None
    if path.exists():
        try:
            header = read_header(path)
            if header.scene_digest != scene_digest(scene.model_dump(mode="json")):
                raise CheckpointError(f"{path} holds a checkpoint of another scene")
            simulation = Simulation.resume(path, output=task.output)
        except CheckpointError as exc:
            log.warning("%s; the run starts afresh", exc)
        else:
            log.info("%s: resumed at %d drained pores", task.run_id, header.n_drained)
            return simulation, schedule, header.n_drained
    simulation = Simulation.from_scene(scene, output=task.output, registry=registry)
    return simulation, schedule, None
