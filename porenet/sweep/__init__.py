"""Sweeps: many scenes from one file, run locally or on dask, resumable (docs/sweeps.md).

    from porenet.sweep import run_sweep
    report = run_sweep("examples/sweeps/demo.toml", "demo-out", workers=2)

Importing this package loads neither dask nor h5py.
"""

from __future__ import annotations

from porenet.sweep.executors import DaskExecutor, Executor, LocalExecutor, SerialExecutor
from porenet.sweep.files import SweepIOError
from porenet.sweep.lock import SweepLocked
from porenet.sweep.records import SweepSummary, read_summary
from porenet.sweep.runner import (
    SUMMARY_FIELDS,
    Progress,
    SweepInterrupted,
    SweepReport,
    format_progress,
    run_sweep,
)
from porenet.sweep.spec import DERIVED, RunSpec, Sweep, SweepSpec, expand, load_sweep
from porenet.sweep.worker import RunTask, execute_run

__all__ = [
    "DERIVED",
    "SUMMARY_FIELDS",
    "DaskExecutor",
    "Executor",
    "LocalExecutor",
    "Progress",
    "RunSpec",
    "RunTask",
    "SerialExecutor",
    "Sweep",
    "SweepIOError",
    "SweepInterrupted",
    "SweepLocked",
    "SweepReport",
    "SweepSpec",
    "SweepSummary",
    "execute_run",
    "expand",
    "format_progress",
    "load_sweep",
    "read_summary",
    "run_sweep",
]
