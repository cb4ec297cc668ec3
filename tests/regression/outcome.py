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


#: Floats agree to this fraction of the array's largest magnitude (see :func:`differences`).
RELATIVE = 1e-10
#: Values that measure round-off: they only have to stay at most :data:`ROUND_OFF_GROWTH`
#: times the largest stored value.
ROUND_OFF_MEASURES = frozenset({"summary/volume_balance_error", "mechanics/balance_residual"})
ROUND_OFF_GROWTH = 10.0


def differences(
    stored: dict[str, np.ndarray], now: dict[str, np.ndarray], exact: bool = False
) -> list[str]:
    """What differs between a stored outcome and a new one: integer, boolean and text arrays
    exactly, floats to round-off, or to the bit with ``exact``.

    Round-off: relative :data:`RELATIVE` of the array's largest magnitude. The refactorings
    this suite guards against change no arithmetic, and a change of the summation order shows
    as ~1e-16 in a sum; but sums that the kernels let the compiler reorder for SIMD
    (``reassociate``) come out differently on CPUs of different vector widths, and the
    implicit integrator's solves amplify that by their condition number: on a Zen 4 machine
    the ``viscous-implicit`` scene's released volumes differed from outcomes stored on
    another CPU by 1.6e-12 of their largest value. The measures of round-off themselves
    (:data:`ROUND_OFF_MEASURES`: the volume balance's relative error, ~1e-15 to 4e-12, and
    the mechanics' force residual, ~1e-23 N) only have to stay round-off: at most
    :data:`ROUND_OFF_GROWTH` times the largest stored value (on that machine they differed by
    up to 18 % and 16 %)."""
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
            if key in ROUND_OFF_MEASURES and not exact:
                close = np.abs(b) <= ROUND_OFF_GROWTH * scale
            else:
                tolerance = 0.0 if exact else RELATIVE * scale
                close = np.isclose(a, b, rtol=0.0, atol=tolerance, equal_nan=True)
            if not np.all(close):
                worst = float(np.nanmax(np.abs(a - b))) / scale
                problems.append(f"{key}: {int(np.sum(~close))} values differ (worst {worst:.2e})")
        elif not np.array_equal(a, b):
            problems.append(f"{key}: differs")
    return problems
