"""How many threads the parallel kernels use, decided while a run goes on.

The viscous model's sweeps over large boxes run on several threads (docs/architecture.md).
Each sweep is one short parallel region (~0.1 ms at 400 x 400 pores) that ends when the
slowest thread is done: on a quiet machine two threads make a run 1.2-1.3x faster, but when
another program keeps a core busy, the operating system deschedules one of porenet's threads
for milliseconds at a time, every region waits for it, and a run on two threads took 2.5-3.7x
as long as on one (docs/performance.md, "Threads on a busy machine").

So by default (``porenet run`` without ``--threads``, :func:`configure_threads` ``"auto"``)
the run measures its own speed on one thread and on all of them and uses the faster: a
:class:`ThreadGovernor` times each call of the fluid model, per unit of work it reports
(:meth:`porenet.core.interfaces.FluidModel.parallel_work`: pore sweeps), and now and then
runs a short stretch on the other count (a *probe*) and compares it with the calls just
before and just after it. Results do not depend on the count (sums are taken per row, in
order), so changing it between calls changes no result, to the bit.

``--threads N`` (:func:`configure_threads` with an int) fixes the count: nothing is measured.
A sweep gives each run ``cores // workers`` threads at most and lets it choose below that.
"""

from __future__ import annotations

import logging
import math
import os
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass

log = logging.getLogger(__name__)

#: Seconds of wall time a call of the fluid model aims at (the Simulation regains control
#: this often: progress, observers, this governor) ...
CALL_SECONDS = 0.25
#: ... and a probe, a stretch on the other thread count (and the first sample of a run).
PROBE_SECONDS = 0.05


@dataclass(frozen=True)
class ThreadSetting:
    """The process's choice: at most ``most`` threads, chosen by measurement (``adaptive``)
    or always ``most``."""

    most: int
    adaptive: bool

    def describe(self) -> str:
        if self.most == 1:
            return "1 thread"
        return f"1 or {self.most} threads, measured" if self.adaptive else f"{self.most} threads"


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity, else ``os.cpu_count()``)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


_SETTING: ThreadSetting | None = None


def configure_threads(threads: int | str | None = "auto", most: int | None = None) -> ThreadSetting:
    """Set how the parallel kernels of the runs in this process choose their threads.

    Parameters
    ----------
    threads : int, "auto" or None
        An int fixes the count (at least 1); ``"auto"`` or None lets each run choose between
        1 and ``most`` by measuring (the default).
    most : int, optional
        The most threads a run may use under ``"auto"`` (default: the cores available).

    Returns
    -------
    ThreadSetting
    """
    global _SETTING
    if threads is None or threads == "auto":
        limit = available_cores() if most is None else int(most)
        _SETTING = ThreadSetting(max(1, min(limit, _numba_limit())), adaptive=True)
    else:
        count = int(threads)
        if count < 1:
            raise ValueError(f"threads must be at least 1 (got {count})")
        _SETTING = ThreadSetting(min(count, _numba_limit()), adaptive=False)
    return _SETTING


def thread_setting() -> ThreadSetting:
    """The process's setting (``"auto"`` over the available cores until configured)."""
    return _SETTING if _SETTING is not None else configure_threads("auto")


def _numba_limit() -> int:
    from porenet.jit.jit import thread_limit

    return thread_limit()


@dataclass
class _Sample:
    """Wall time and work accumulated on one thread count until long enough to compare."""

    threads: int
    seconds: float = 0.0
    work: float = 0.0


class ThreadGovernor:
    """Chooses, call by call, 1 thread or ``most`` for the parallel kernels, by measuring.

    Use::

        threads = governor.before_call()        # sets the kernels' thread count
        ...  # one call of the fluid model, aiming at governor.call_seconds() of wall time
        governor.after_call(seconds, work)      # work done in that call, 0: none threaded

    A *sample* is at least :attr:`min_sample` seconds of calls on one count; its cost is
    seconds per unit of work. The governor starts on ``most`` threads, probes one thread
    right after its first sample, and then runs on :attr:`current` and, every
    :attr:`interval` seconds of threaded work (doubling, from :attr:`first_interval` up to
    :attr:`longest_interval` while probes keep losing), takes one sample on the other count
    (a probe) and compares it with the mean of the samples just before and just after it
    (work per second drifts as the box grows). It switches when the probe is cheaper by more
    than :attr:`margin`; a probe that lost by more than 2x quadruples the interval. On
    several threads, two samples in a row costing :attr:`jump` times their predecessors'
    median (the machine got busier) bring the next probe forward, at most once per
    :attr:`first_interval`.
    Calls whose work is 0 (boxes too small for threads) and calls during which kernels were
    compiled are not measured.
    """

    first_interval = 1.0
    longest_interval = 30.0
    min_sample = 0.04
    margin = 0.05
    jump = 1.3

    def __init__(self, setting: ThreadSetting, apply: Callable[[int], int] | None = None) -> None:
        self.setting = setting
        self.most = setting.most
        self.adaptive = setting.adaptive and setting.most > 1
        self.current = setting.most
        self._apply = apply if apply is not None else _set_kernel_threads
        self._history: deque[float] = deque(maxlen=5)  # costs of the current count's samples
        self._sample: _Sample | None = None
        self._probe: float | None = None  # the probe's cost, waiting for the next sample
        self._before: float | None = None  # the current count's cost just before the probe
        self._probing = False
        self.interval = self.first_interval
        self._threaded = 0.0  # seconds of measured (threaded) calls so far
        self._next_probe = 0.0  # the first probe follows the first sample
        self._last_probe = -math.inf  # when the last probe started (threaded seconds)
        self._changed = 0  # samples in a row whose cost left the usual range
        #: Counters for the run's summary.
        self.probes = 0
        self.switches = 0
        self.seconds_on: dict[int, float] = {1: 0.0, setting.most: 0.0}
        self._applied = 0

    # -- the two calls -----------------------------------------------------------------------
    def before_call(self) -> int:
        """Set the kernels' threads for the next call and return the count."""
        count = self.current
        if self.adaptive and self._probing:
            count = self._other()
        if count != self._applied:
            self._applied = self._apply(count)
        return count

    def call_seconds(self) -> float:
        """The wall time the next call should aim at (shorter for a probe and for the
        samples before the first decision)."""
        short = self._probing or (self.adaptive and self.probes == 0)
        return PROBE_SECONDS if short else CALL_SECONDS

    def after_call(self, seconds: float, work: float, compiled: bool = False) -> None:
        """Account one call: its wall ``seconds`` and its ``work`` (0 when nothing ran on
        threads); ``compiled``: kernels were compiled during it (not measured)."""
        count = self._applied or self.current
        if work <= 0 or seconds <= 0 or not math.isfinite(seconds):
            return
        self.seconds_on[count] = self.seconds_on.get(count, 0.0) + seconds
        if not self.adaptive:
            return
        if compiled:
            self._sample = None
            return
        sample = self._sample
        if sample is None or sample.threads != count:
            sample = self._sample = _Sample(count)
        sample.seconds += seconds
        sample.work += work
        self._threaded += seconds
        if sample.seconds < self.min_sample:
            return
        self._sample = None
        self._account(count, sample.seconds / sample.work)

    # -- decisions -------------------------------------------------------------------------
    def _other(self) -> int:
        return 1 if self.current != 1 else self.most

    def _account(self, count: int, cost: float) -> None:
        log.debug(
            "threads: sample on %d: %.3g s per unit (probing %s, probe %s, before %s)",
            count, cost, self._probing, self._probe, self._before,
        )  # fmt: skip
        if self._probing:  # the probe's sample
            self._probing = False
            self._probe = cost
            self.probes += 1
            return
        if self._probe is not None:  # the sample after a probe: decide
            before = self._before if self._before is not None else cost
            reference = 0.5 * (before + cost)
            if self._probe < (1.0 - self.margin) * reference:
                self.current = self._other()
                self.switches += 1
                self._history.clear()
                self._history.append(self._probe)
                self.interval = self.first_interval
            else:
                self._history.append(cost)
                # a probe that lost by far costs more: wait longer before the next one
                growth = 4.0 if self._probe > 2.0 * reference else 2.0
                self.interval = min(growth * self.interval, self.longest_interval)
            self._probe = self._before = None
            self._next_probe = self._threaded + self.interval
            return
        if self._history and self._threaded >= self._last_probe + self.first_interval:
            # on several threads a jump in cost means the machine got busier: look again now
            # (the interval itself keeps growing: costs also drift as the box grows). On one
            # thread a quieter machine hardly shows (the other cores were busy, not this
            # one): the periodic probes find it.
            changed = self.current > 1 and cost > self.jump * _median(self._history)
            self._changed = self._changed + 1 if changed else 0
            if self._changed >= 2:  # two samples in a row: not the scatter of one call
                self._next_probe = self._threaded
                self._changed = 0
        self._history.append(cost)
        if self._threaded >= self._next_probe:
            self._before = cost
            self._probing = True
            self._last_probe = self._threaded

    def summary(self) -> dict[str, object]:
        """What the run's summary records of the threads."""
        return {
            "threads_setting": self.setting.describe(),
            "threads_final": self.current,
            "thread_probes": self.probes,
            "thread_switches": self.switches,
            # wall time of the calls that ran on threads, on one and on the most
            "threaded_seconds_one": self.seconds_on.get(1, 0.0),
            "threaded_seconds_most": self.seconds_on.get(self.most, 0.0) if self.most > 1 else 0.0,
        }


class CallPace:
    """Time steps per call of a fluid model's kernel, so that a call lasts about the wall
    time asked for (:attr:`porenet.core.interfaces.FluidModel.call_seconds`).

    From the seconds per step of the last call: ``steps = seconds / (seconds per step)``,
    between :attr:`least` and ``most`` and at most :attr:`growth` times the last call's
    steps asked for (the first call, which may compile kernels, takes :attr:`first`).
    """

    first = 64
    least = 8
    growth = 4.0

    def __init__(self, most: int) -> None:
        self.most = most
        self._per_step: dict[int, float] = {}  # by thread count
        self._last = self.first

    def steps(self, seconds: float, threads: int = 1) -> int:
        """Steps for a call of ``seconds`` on ``threads`` threads."""
        per_step = self._per_step.get(threads) or next(iter(self._per_step.values()), None)
        if per_step is None or per_step <= 0:
            return min(self.first, self.most)
        want = min(seconds / per_step, self.growth * self._last, float(self.most))
        self._last = max(self.least, int(want))
        return self._last

    def record(self, steps: int, seconds: float, threads: int = 1) -> None:
        """What the last call, on ``threads`` threads, took."""
        if steps > 0 and seconds > 0:
            self._per_step[threads] = seconds / steps


def _median(values: deque[float]) -> float:
    ordered = sorted(values)
    mid = len(ordered) // 2
    return ordered[mid] if len(ordered) % 2 else 0.5 * (ordered[mid - 1] + ordered[mid])


def _set_kernel_threads(count: int) -> int:
    from porenet.jit.jit import set_threads

    return set_threads(count)
