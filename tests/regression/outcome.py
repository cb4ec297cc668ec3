"""What the regression suite stores of a run and how two runs are compared."""

from __future__ import annotations

from typing import Any

import numpy as np

#: Arrays of a run's data stored and compared (None when the run has none).
FIELDS = ("order", "throat", "drained", "trapped", "invasion_pressure", "invasion_time",
          "pressure", "final_apertures")  # fmt: skip
#: Summary values stored and compared (when the run has them).
SUMMARY = ("n_drained", "n_trapped", "stop_reason", "time_steps", "capillary_number_measured",
           "volume_balance_error", "mechanical_updates", "springs_removed")  # fmt: skip


def outcome(data: Any) -> dict[str, np.ndarray]:
    """The arrays of a run's :class:`~porenet.result.RunData` the suite keeps, flat."""
    out: dict[str, np.ndarray] = {}
    for name in FIELDS:
        value = getattr(data, name)
        if value is not None:
            out[name] = np.asarray(value)
    for key, series in (data.timeseries or {}).items():
        out[f"timeseries/{key}"] = np.asarray(series)
    for i, snap in enumerate(data.snapshots or []):
        out[f"snapshot{i}/pressure"] = np.asarray(snap.pressure)
        out[f"snapshot{i}/drained"] = np.asarray(snap.drained)
        out[f"snapshot{i}/time"] = np.asarray(snap.time)
    for key, series in (data.mechanics_series or {}).items():
        out[f"mechanics/{key}"] = np.asarray(series)
    for key in SUMMARY:
        if key in data.summary and data.summary[key] is not None:
            out[f"summary/{key}"] = np.asarray(data.summary[key])
    return out


def differences(
    stored: dict[str, np.ndarray], now: dict[str, np.ndarray], exact: bool = False
) -> list[str]:
    """What differs between a stored outcome and a new one: integer, boolean and text arrays
    exactly, floats to round-off (relative 1e-12 of the array's largest magnitude; the
    refactorings this suite guards against change no arithmetic, and a change of the
    summation order would show as ~1e-16), or to the bit with ``exact``."""
    problems = []
    for key in sorted(set(stored) | set(now)):
        if key not in now or key not in stored:
            where = "the stored outcome" if key in stored else "this run"
            problems.append(f"{key}: only in {where}")
            continue
        a, b = stored[key], now[key]
        if a.shape != b.shape:
            problems.append(f"{key}: shape {a.shape} stored, {b.shape} now")
        elif a.dtype.kind == "f":
            scale = float(np.max(np.abs(a[np.isfinite(a)]), initial=0.0)) or 1.0
            tolerance = 0.0 if exact else 1e-12 * scale
            close = np.isclose(a, b, rtol=0.0, atol=tolerance, equal_nan=True)
            if not np.all(close):
                worst = float(np.nanmax(np.abs(a - b))) / scale
                problems.append(f"{key}: {int(np.sum(~close))} values differ (worst {worst:.2e})")
        elif not np.array_equal(a, b):
            problems.append(f"{key}: differs")
    return problems
