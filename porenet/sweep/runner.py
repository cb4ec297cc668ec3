"""Running a sweep: output directory, resume, failures, ``summary.csv`` and progress.

Layout of ``DIR`` (docs/sweeps.md; the names are :mod:`porenet.sweep.layout`'s)::

    DIR/sweep.json              the resolved sweep: spec, columns and every run's scene
    DIR/summary.csv             one row per finished run (rewritten atomically after each)
    DIR/runs/<run_id>.h5        run files (written atomically by porenet)
    DIR/runs/<run_id>.error.txt the message and traceback of a failed run
    DIR/runs/<run_id>.h5.checkpoint  a run in progress (``--checkpoint-every``)

Re-running the same sweep into the same ``DIR`` resumes: runs whose run file reads back with
the intended scene are not run again, failed runs are not retried unless asked. A run file (or
error record) whose scene differs from the sweep's is an error: a directory never mixes the
runs of two different sweeps. One sweep at a time writes into ``DIR``: it holds ``DIR/.lock``
(:mod:`porenet.sweep.lock`); its files are written atomically and an I/O error stops it with
a message (:mod:`porenet.sweep.files`). A run that left a checkpoint (``porenet sweep
--checkpoint-every``) goes on from it instead of from the start, to the same result
(docs/sweeps.md, "Checkpoints").
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import signal
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from porenet._version import __version__
from porenet.core.errors import ConfigError, PorenetError, RunFileError
from porenet.sweep.executors import (
    DaskExecutor,
    Executor,
    LocalExecutor,
    SerialExecutor,
    default_workers,
)
from porenet.sweep.files import (
    SweepIOError,
    atomic_write_text,
    clean_partials,
    io_error,
    remove,
)
from porenet.sweep.layout import ERROR_SUFFIX, RUNS_DIR, SUMMARY_CSV, SWEEP_JSON
from porenet.sweep.lock import DirectoryLock, SweepLocked
from porenet.sweep.progress import Progress, clock, format_progress
from porenet.sweep.records import (
    SUMMARY_FIELDS,
    SummaryWriter,
    error_text,
    read_error,
    scene_difference,
)
from porenet.sweep.spec import RunSpec, Sweep, columns, expand, load_sweep
from porenet.sweep.worker import RunTask, execute_run, one_line

log = logging.getLogger(__name__)


class SweepInterrupted(PorenetError):
    """Ctrl-C (exit status 130) or SIGTERM (143) during a sweep; the message says how many
    runs finished."""

    exit_status = 130


class _Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread so that the sweep stops as on Ctrl-C."""


@contextlib.contextmanager
def _sigterm_stops() -> Iterator[None]:
    """Turn SIGTERM into :class:`_Terminated` while the sweep runs (main thread only, and only
    if nobody else handles SIGTERM), so that its workers are terminated and its temporaries
    removed before it exits."""
    if threading.current_thread() is not threading.main_thread() or (
        signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL
    ):
        yield
        return

    def stop(signum: int, frame: object) -> None:
        raise _Terminated

    signal.signal(signal.SIGTERM, stop)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


# --------------------------------------------------------------------------- the sweep


@dataclass
class SweepReport:
    """What a sweep did."""

    out_dir: Path
    total: int
    done: int
    failed: int
    skipped: int  # finished before this session (done or failed), not run again
    ran: int  # run this session
    elapsed_s: float
    executor: str
    rows: list[dict[str, str]] = field(repr=False, default_factory=list)
    resumed: int = 0  # of those run this session, how many went on from a checkpoint

    @property
    def summary_path(self) -> Path:
        return self.out_dir / SUMMARY_CSV

    def describe(self) -> str:
        """The final line the CLI prints."""
        resumed = f", {self.resumed} of them from a checkpoint" if self.resumed else ""
        return (
            f"{self.total} runs: {self.done} done, {self.failed} failed"
            f" ({self.ran} run now{resumed}, {self.skipped} finished before); "
            f"{clock(self.elapsed_s)}; summary {self.summary_path}"
        )


def _clean_partials(out_dir: Path) -> None:
    """Remove the temporaries of interrupted writes (only while holding the lock)."""
    removed = clean_partials(out_dir, out_dir / RUNS_DIR)
    if removed:
        log.info("removed %d temporary file(s) of an interrupted sweep", len(removed))


def _edited(path: Path, run: RunSpec, sweep: Sweep, recorded: dict[str, Any]) -> ConfigError:
    return ConfigError(
        f"{path}: run {run.run_id} was made with a different scene than {sweep.source} now "
        f"gives it ({scene_difference(recorded, run.scene)}): the sweep file was edited; use a "
        f"new output directory (-o): a sweep directory never mixes runs of different sweeps"
    )


def _scan(
    out_dir: Path, runs: list[RunSpec], sweep: Sweep, table: SummaryWriter, retry_failed: bool
) -> list[RunSpec]:
    """Record finished runs in ``table``; return the runs to do. Refuses foreign files."""
    from porenet.io.checkpoint import SUFFIX as CHECKPOINT
    from porenet.io.runfile import read_run

    runs_dir = out_dir / RUNS_DIR
    known = {run.run_id for run in runs}
    patterns = ("*.h5", f"*{ERROR_SUFFIX}", f"*{CHECKPOINT}")
    for path in sorted(p for pattern in patterns for p in runs_dir.glob(pattern)):
        stem = path.name.split(".")[0]
        if stem not in known:
            raise ConfigError(
                f"{path}: not a run of {sweep.source} as it now stands ({len(runs)} runs, "
                f"{runs[0].run_id} to {runs[-1].run_id}): the sweep file was edited; use a new "
                f"output directory (-o): a sweep directory never mixes runs of different sweeps"
            )
    todo: list[RunSpec] = []
    for run in runs:
        run_path = out_dir / run.run_file
        error_path = runs_dir / f"{run.run_id}{ERROR_SUFFIX}"
        if run_path.is_file():
            try:
                data = read_run(run_path)
            except RunFileError as exc:
                log.warning("%s: unreadable (%s); running it again", run_path, exc)
            else:
                if data.scene != run.scene:
                    raise _edited(run_path, run, sweep, data.scene)
                table.record(run, "done", data.summary)
                # a run killed between writing its run file and removing its checkpoint
                remove(run_path.with_name(run_path.name + CHECKPOINT))
                continue
        if error_path.is_file():
            message, wall, scene = read_error(error_path)
            if scene is not None and scene != run.scene:
                raise _edited(error_path, run, sweep, scene)
            if not retry_failed:
                table.record(run, "failed", {"wall_time_s": wall}, message)
                continue
        todo.append(run)
    return todo


def threads_per_run(ex: Executor | None, scheduler: str | None) -> int:
    """Threads for each run's parallel kernels: the cores divided among the runs that execute
    at once on this machine (``os.cpu_count() // workers``, at least 1); 1 on a remote dask
    cluster, whose workers' cores are not known here. The results do not depend on it."""
    if ex is None or scheduler is not None or not ex.workers:
        return 1
    return max(1, (os.cpu_count() or 1) // ex.workers)


def _make_executor(
    n_todo: int, workers: int | None, scheduler: str | None, dask_local: bool
) -> Executor:
    if scheduler is not None and dask_local:
        raise ConfigError("give either --scheduler ADDRESS or --dask-local, not both")
    if workers is not None and workers < 1:
        raise ConfigError(f"--workers {workers}: must be at least 1")
    if scheduler is not None:
        if workers is not None:
            log.warning("--workers is ignored with --scheduler (the cluster has its workers)")
        return DaskExecutor(scheduler)
    n = workers if workers is not None else default_workers(n_todo)
    if dask_local:
        return DaskExecutor(local=True, workers=n)
    return LocalExecutor(n)


def run_sweep(
    sweep_file: str | Path | Sweep,
    out_dir: str | Path,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    dask_local: bool = False,
    executor: Executor | None = None,
    retry_failed: bool = False,
    on_progress: Callable[[Progress], None] | None = None,
    checkpoint_every: str | None = None,
) -> SweepReport:
    """Run (or resume) a sweep into ``out_dir``.

    Parameters
    ----------
    sweep_file : str, Path or Sweep
        The sweep file (or one loaded with :func:`~porenet.sweep.spec.load_sweep`).
    out_dir : str or Path
        Output directory, created if needed. The sweep holds its lock (``out_dir/.lock``)
        while it runs.
    workers : int, optional
        Local worker processes (default ``os.cpu_count()`` capped at the runs to do), or the
        LocalCluster's workers with ``dask_local``.
    scheduler : str, optional
        Address of a dask scheduler to submit the runs to.
    dask_local : bool
        Start a dask ``LocalCluster`` of ``workers`` workers.
    executor : Executor, optional
        Use this executor instead (not closed here).
    retry_failed : bool
        Run again the runs that failed before.
    on_progress : callable, optional
        Called with a :class:`Progress` when the runs start and after each finished run.
    checkpoint_every : str, optional
        Each run writes a checkpoint beside its run file this often (``porenet run
        --checkpoint-every``: ``"10m"``, ``"5000"`` drained pores). Whether or not it is
        given, a run that left a checkpoint goes on from it (docs/sweeps.md, "Checkpoints").

    Raises
    ------
    ConfigError
        Invalid sweep or point (nothing runs), or ``out_dir`` holds runs of another sweep.
    SweepLocked
        Another sweep is running in ``out_dir`` (nothing runs); the message names it.
    SweepIOError
        A file of ``out_dir`` cannot be written (a full disk, ...), or a run file cannot be
        written for lack of space: the sweep stops, finished runs are kept.
    SweepInterrupted
        On Ctrl-C or SIGTERM, after stopping the workers; finished runs are kept.
    """
    sweep = sweep_file if isinstance(sweep_file, Sweep) else load_sweep(sweep_file)
    runs = expand(sweep)
    if checkpoint_every is not None:  # a bad period is refused before anything runs
        from porenet.io.checkpoint import CheckpointSchedule

        CheckpointSchedule.parse(checkpoint_every, "unused")
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ConfigError(f"-o {out}: exists and is not a directory")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise io_error(out, exc, "create") from exc
    with DirectoryLock(out), _sigterm_stops():
        return _run_locked(
            sweep, runs, out, SweepOptions(workers, scheduler, dask_local, executor, retry_failed,
                                           on_progress, checkpoint_every)
        )  # fmt: skip


@dataclass(frozen=True)
class SweepOptions:
    """How :func:`run_sweep` runs the runs: its keyword arguments, documented there."""

    workers: int | None = None
    scheduler: str | None = None
    dask_local: bool = False
    executor: Executor | None = None
    retry_failed: bool = False
    on_progress: Callable[[Progress], None] | None = None
    checkpoint_every: str | None = None


def _run_locked(sweep: Sweep, runs: list[RunSpec], out: Path, options: SweepOptions) -> SweepReport:
    """:func:`run_sweep` once it holds the directory's lock."""
    swept = columns(sweep.spec)
    table = SummaryWriter(out, runs, swept)
    todo: list[RunSpec] = []
    ex: Executor | None = None
    own = False
    t0 = time.perf_counter()
    finished_now = resumed = 0

    def progress(last: str | None) -> None:
        if options.on_progress is not None:
            done, failed = table.counts()
            elapsed = time.perf_counter() - t0
            n_workers = ex.workers if ex else None
            options.on_progress(
                Progress(len(runs), done, failed, len(todo), finished_now, elapsed, n_workers, last)
            )

    try:
        try:
            (out / RUNS_DIR).mkdir(exist_ok=True)
        except OSError as exc:
            raise io_error(out / RUNS_DIR, exc, "create") from exc
        _clean_partials(out)  # left by a sweep that was killed: we hold the lock
        todo = _scan(out, runs, sweep, table, options.retry_failed)
        # the executor first: an unreachable scheduler fails before anything is written
        ex = options.executor
        if ex is None and todo:
            ex = _make_executor(len(todo), options.workers, options.scheduler, options.dask_local)
        own = options.executor is None and ex is not None
        _write_resolved(out, sweep, runs, swept)
        table.write()
        log.info("sweep %r: %d runs, %d finished before, %d to run", sweep.spec.name,
                 len(runs), len(runs) - len(todo), len(todo))  # fmt: skip
        by_id = {run.run_id: run for run in todo}
        threads = threads_per_run(ex, options.scheduler)
        tasks = [RunTask(r.run_id, r.scene, str((out / r.run_file).resolve()), threads,
                         options.checkpoint_every) for r in todo]  # fmt: skip
        t0 = time.perf_counter()
        progress(None)
        if ex is not None and todo:
            log.info("running %d runs on %s", len(todo), ex.describe())
            with contextlib.closing(ex.run(tasks, execute_run)) as outcomes:  # type: ignore[type-var]
                for task, outcome in outcomes:
                    _finish(out, by_id[task.run_id], outcome, table)
                    finished_now += 1
                    resumed += isinstance(outcome, dict) and outcome.get("resumed_at") is not None
                    table.write()
                    progress(task.run_id)
    except KeyboardInterrupt as exc:
        _clean_after_stop(out, ex)
        done, failed = table.counts()
        what = "terminated (SIGTERM)" if isinstance(exc, _Terminated) else "interrupted"
        stopped = SweepInterrupted(
            f"{what}: {done + failed} of {len(runs)} runs finished ({failed} failed; "
            f"{finished_now} since this command started); re-running the same command resumes"
        )
        if isinstance(exc, _Terminated):
            stopped.exit_status = 128 + signal.SIGTERM
        raise stopped from None
    except SweepIOError as exc:
        _clean_after_stop(out, ex)
        done, failed = table.counts()
        raise exc.with_note(
            f"the sweep stopped with {done + failed} of {len(runs)} runs finished, which are kept"
        ) from exc
    finally:
        if own and ex is not None:
            ex.close()
    done, failed = table.counts()
    return SweepReport(out, len(runs), done, failed, len(runs) - len(todo), finished_now,
                       time.perf_counter() - t0, ex.describe() if ex else "nothing to run",
                       table.sorted_rows(), resumed)  # fmt: skip


def _clean_after_stop(out: Path, ex: Executor | None) -> None:
    """Remove the temporaries of the runs just stopped: local workers are dead by now. A dask
    cluster's runs go on and write their files: their temporaries are theirs."""
    if ex is None or isinstance(ex, LocalExecutor | SerialExecutor):
        _clean_partials(out)


def _write_resolved(out: Path, sweep: Sweep, runs: list[RunSpec], swept: list[str]) -> None:
    """``DIR/sweep.json``: the spec, the summary's columns and every run with its scene."""
    resolved = {
        "porenet_version": __version__,
        "sweep_file": str(Path(sweep.source).resolve()) if sweep.source.exists() else None,
        "base_scene_file": None if isinstance(sweep.spec.base, dict) else sweep.base_source,
        "spec": sweep.spec.model_dump(mode="json"),
        "columns": swept,
        "runs": [
            {"run_id": r.run_id, "point": r.point, "replicate": r.replicate, "seed": r.seed,
             "params": r.params, "run_file": r.run_file, "scene": r.scene}
            for r in runs
        ],
    }  # fmt: skip
    atomic_write_text(out / SWEEP_JSON, json.dumps(resolved, indent=1) + "\n")


def _finish(out: Path, run: RunSpec, outcome: Any, table: SummaryWriter) -> None:
    """Record one outcome: a result dict of :func:`execute_run`, or an exception."""
    error_path = out / RUNS_DIR / f"{run.run_id}{ERROR_SUFFIX}"
    if isinstance(outcome, BaseException) and not isinstance(outcome, Exception):
        raise KeyboardInterrupt  # a worker was interrupted: so are we
    if isinstance(outcome, Exception):
        # not the run's failure but the executor's (a dead worker, ...): recorded in the
        # summary, with no error record, so that re-running tries again
        message = one_line(outcome)
        log.error("%s: could not run: %s", run.run_id, message)
        table.record(run, "failed", {}, f"executor: {message}")
        return
    for message in outcome.get("warnings", ()):
        log.info("%s: %s", run.run_id, message)
    if outcome.get("resumed_at") is not None:
        log.info("%s went on from its checkpoint at %d drained pores", run.run_id,
                 outcome["resumed_at"])  # fmt: skip
    if outcome["status"] == "done":
        remove(error_path)
        table.record(run, "done", outcome)
        return
    if outcome.get("storage_error"):  # the run file could not be written: stop the sweep
        raise SweepIOError(
            out / run.run_file, outcome["storage_error"], outcome.get("storage_errno")
        )
    log.info("%s failed: %s", run.run_id, outcome["error"])
    atomic_write_text(error_path, error_text(run, outcome))
    table.record(run, "failed", outcome, outcome["error"])


__all__ = [
    "SUMMARY_FIELDS",
    "Progress",
    "SweepIOError",
    "SweepInterrupted",
    "SweepLocked",
    "SweepReport",
    "format_progress",
    "run_sweep",
]
