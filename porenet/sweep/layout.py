"""The files of a sweep's output directory, named once (docs/sweeps.md, "The output directory").

::

    DIR/sweep.json              SWEEP_JSON: the resolved sweep, every run with its scene
    DIR/summary.csv             SUMMARY_CSV: one row per finished run
    DIR/runs/<run_id>.h5        RUNS_DIR: the run files
    DIR/runs/<run_id>.error.txt ERROR_SUFFIX: the record of a failed run

The runner (:mod:`porenet.sweep.runner`) writes them; the summary's writer and reader
(:mod:`porenet.sweep.records`), the run list (:class:`porenet.sweep.spec.RunSpec`) and the
phase diagram (:mod:`porenet.viz.phase`) take the names from here. This module imports
nothing.
"""

from __future__ import annotations

#: The summary table, one row per finished run (``porenet.sweep.records``).
SUMMARY_CSV = "summary.csv"

#: The resolved sweep: spec, summary columns and every run with its scene.
SWEEP_JSON = "sweep.json"

#: The folder of the run files and of the error records of failed runs.
RUNS_DIR = "runs"

#: Ending of a failed run's error record, ``RUNS_DIR/<run_id>.error.txt``.
ERROR_SUFFIX = ".error.txt"

__all__ = ["ERROR_SUFFIX", "RUNS_DIR", "SUMMARY_CSV", "SWEEP_JSON"]
