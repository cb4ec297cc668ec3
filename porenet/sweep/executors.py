"""Where a sweep's runs execute: in this process, in local worker processes, or on dask.

An :class:`Executor` takes tasks and a module-level function and yields ``(task, outcome)`` as
the tasks complete, ``outcome`` being the function's return value or the exception that
prevented one (a dead worker, a task that could not be sent). Results do not depend on the
executor: every run is determined by its scene, which carries its seed.

If the consumer stops iterating early (an exception, Ctrl-C, ``close()``), tasks not yet started
are cancelled and local worker processes are terminated; a run killed this way leaves no file
behind under its final name (run files are written atomically).

Local worker processes die with the process that started them, however it ends (``kill -9``
included): on Linux each worker asks the kernel for ``SIGKILL`` when its parent dies
(``prctl(PR_SET_PDEATHSIG)``); elsewhere a thread in each worker watches its parent's pid
(docs/sweeps.md, "When a sweep is stopped or killed"). Workers ignore ``SIGINT``: a Ctrl-C
reaches the sweep, which terminates them.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import logging
import os
import signal
import sys
import threading
import time
import uuid
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterable, Iterator
from typing import Any, TypeVar

from porenet.core.errors import ConfigError

log = logging.getLogger(__name__)

T = TypeVar("T")
R = TypeVar("R")


def default_workers(n_tasks: int) -> int:
    """``os.cpu_count()`` capped at the number of tasks (at least 1)."""
    return max(1, min(os.cpu_count() or 1, n_tasks))


class Executor(ABC):
    """Runs tasks; subclasses say where. Use as a context manager to release resources."""

    #: Number of runs that execute at once (for the ETA), if known.
    workers: int | None = None

    @abstractmethod
    def run(
        self, tasks: Iterable[T], fn: Callable[[T], R]
    ) -> Iterator[tuple[T, R | BaseException]]:
        """Yield ``(task, fn(task))``, or ``(task, exception)``, in order of completion."""

    def describe(self) -> str:
        """One line for logs and the final report."""
        return type(self).__name__

    def close(self) -> None:  # noqa: B027 (optional: nothing to release by default)
        """Release workers, clients and clusters."""

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class SerialExecutor(Executor):
    """Runs every task in this process, one after the other (``--workers 1``)."""

    workers = 1

    def run(
        self, tasks: Iterable[T], fn: Callable[[T], R]
    ) -> Iterator[tuple[T, R | BaseException]]:
        for task in tasks:
            try:
                outcome: R | BaseException = fn(task)
            except Exception as exc:
                outcome = exc
            yield task, outcome

    def describe(self) -> str:
        return "this process (1 worker)"


class LocalExecutor(Executor):
    """Local worker processes (``concurrent.futures.ProcessPoolExecutor``, spawn context).

    ``workers = 1`` runs in this process, without a pool. The spawn start method gives every
    worker a fresh interpreter (no state inherited from the parent, the same on every OS).
    """

    def __init__(self, workers: int) -> None:
        if workers < 1:
            raise ConfigError(f"--workers {workers}: must be at least 1")
        self.workers = workers

    def describe(self) -> str:
        if self.workers == 1:
            return "this process (1 worker)"
        return f"{self.workers} local worker processes"

    def run(
        self, tasks: Iterable[T], fn: Callable[[T], R]
    ) -> Iterator[tuple[T, R | BaseException]]:
        if self.workers == 1:
            yield from SerialExecutor().run(tasks, fn)
            return
        import multiprocessing

        pool = cf.ProcessPoolExecutor(
            max_workers=self.workers,
            mp_context=multiprocessing.get_context("spawn"),
            initializer=die_with_parent,
            initargs=(os.getpid(),),
        )
        finished = False
        try:
            futures = {pool.submit(fn, task): task for task in tasks}
            for future in cf.as_completed(futures):
                exc = future.exception()
                yield futures[future], (exc if exc is not None else future.result())
            finished = True
        finally:
            if not finished:  # interrupted: start nothing more, stop what runs
                _terminate(pool)
            pool.shutdown(wait=True, cancel_futures=True)


#: ``prctl`` option: the signal a process gets when its parent dies (linux/prctl.h).
PR_SET_PDEATHSIG = 1


def parent_death_signal(sig: int) -> bool:
    """Ask Linux to send ``sig`` to this process when its parent dies; False if not done."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return int(libc.prctl(PR_SET_PDEATHSIG, int(sig), 0, 0, 0)) == 0
    except (OSError, AttributeError):
        return False


def _watch_parent(parent_pid: int, interval_s: float = 0.5) -> None:
    while True:
        time.sleep(interval_s)
        if os.getppid() != parent_pid:
            os._exit(1)


def die_with_parent(parent_pid: int) -> None:
    """Worker initializer: end this process when the process ``parent_pid`` ends.

    On Linux the kernel sends ``SIGKILL`` to the worker when its parent dies (any death,
    ``kill -9`` included); elsewhere, or if that fails, a daemon thread checks every 0.5 s
    that the parent is still the one it was. A parent that died before this ran is noticed
    at once (the worker has been re-parented). ``SIGINT`` is ignored: the sweep handles
    Ctrl-C and terminates its workers.
    """
    with contextlib.suppress(ValueError, OSError):  # not the main thread / no SIGINT here
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    if not parent_death_signal(signal.SIGKILL):
        threading.Thread(target=_watch_parent, args=(parent_pid,), daemon=True).start()
    if os.getppid() != parent_pid:  # the parent died before the kernel was asked
        os._exit(1)


def _terminate(pool: cf.ProcessPoolExecutor) -> None:
    """Cancel queued tasks and terminate the pool's processes (runs in progress are lost;
    their run files are written atomically, so none appears half-written)."""
    stop = getattr(pool, "terminate_workers", None)  # Python >= 3.14
    if stop is not None:
        with contextlib.suppress(Exception):
            stop()
        return
    processes = list((getattr(pool, "_processes", None) or {}).values())  # before shutdown
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        with contextlib.suppress(Exception):
            process.terminate()
    for process in processes:
        with contextlib.suppress(Exception):
            process.join(5)


class DaskExecutor(Executor):
    """Runs tasks on dask.distributed: an existing scheduler (``address``) or a
    ``LocalCluster`` of ``workers`` single-threaded worker processes (``local=True``).

    The workers write the run files themselves, so on a remote cluster the output directory
    must be on a file system the workers share with this machine.

    Raises
    ------
    ConfigError
        If dask.distributed is not installed, or neither or both of ``address`` and ``local``
        are given.
    """

    def __init__(
        self, address: str | None = None, *, local: bool = False, workers: int = 2
    ) -> None:
        if (address is None) == (not local):
            raise ConfigError("give a dask scheduler address or local=True (--dask-local)")
        if workers < 1:
            raise ConfigError(f"--workers {workers}: must be at least 1")
        try:
            import distributed
        except ImportError:
            raise ConfigError(
                'dask.distributed is not installed: pip install "porenet[dask]"'
            ) from None
        self._cluster: Any = None
        self._log_level: int | None = None
        if local:
            # the scheduler runs in this process: keep its INFO chatter out of our log
            dask_log = logging.getLogger("distributed")
            self._log_level = dask_log.level
            dask_log.setLevel(max(logging.WARNING, dask_log.getEffectiveLevel()))
            self._cluster = distributed.LocalCluster(
                n_workers=workers,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
                silence_logs=logging.WARNING,
            )
            self.client = distributed.Client(self._cluster)
            self.workers = workers
        else:
            try:
                self.client = distributed.Client(address, timeout="20s")
            except OSError as exc:
                raise ConfigError(
                    f"--scheduler {address}: cannot reach the dask scheduler: {exc}"
                ) from None
            self.workers = len(self.client.scheduler_info().get("workers", {})) or None
        self.address = address

    def describe(self) -> str:
        if self.address is None:
            return f"dask LocalCluster of {self.workers} workers"
        return f"dask scheduler {self.address} ({self.workers or '?'} workers)"

    def run(
        self, tasks: Iterable[T], fn: Callable[[T], R]
    ) -> Iterator[tuple[T, R | BaseException]]:
        import distributed

        token = uuid.uuid4().hex[:8]
        futures = {}
        for i, task in enumerate(tasks):
            name = getattr(task, "run_id", str(i))
            future = self.client.submit(fn, task, key=f"porenet-{name}-{token}", pure=False)
            futures[future] = task
        finished = False
        try:
            for future in distributed.as_completed(list(futures)):
                if future.status == "finished":
                    outcome: Any = future.result()
                else:
                    outcome = future.exception()
                    if outcome is None:  # cancelled by someone else
                        outcome = RuntimeError(f"dask task {future.key} was {future.status}")
                yield futures[future], outcome
            finished = True
        finally:
            if not finished:
                with contextlib.suppress(Exception):
                    self.client.cancel(list(futures))

    def close(self) -> None:
        with contextlib.suppress(Exception):
            self.client.close()
        if self._cluster is not None:
            with contextlib.suppress(Exception):
                self._cluster.close()
            self._cluster = None
        if self._log_level is not None:
            logging.getLogger("distributed").setLevel(self._log_level)
            self._log_level = None
