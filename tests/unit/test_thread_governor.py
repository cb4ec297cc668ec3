"""The thread governor on a simulated machine: it keeps the faster of 1 and N threads, follows a
machine whose load changes, and costs little where it is wrong for a while.

The machine is a cost per unit of work on each thread count (seconds), possibly changing with
time and with noise; the loop stands for the Simulation's calls of the fluid model. The real
runs are measured by ``tests/benchmarks/bench_busy.py`` (docs/performance.md).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from porenet.jit.threads import (
    CallPace,
    ThreadGovernor,
    ThreadSetting,
    configure_threads,
    thread_setting,
)


def drive(cost, seconds=60.0, most=2, noise=0.0, seed=0, adaptive=True):
    """Run the governor for ``seconds`` of simulated wall time on the machine ``cost(count,
    t)``; return (wall time per unit of work, time on each count, the governor)."""
    rng = np.random.default_rng(seed)
    gov = ThreadGovernor(ThreadSetting(most, adaptive), apply=lambda count: count)
    t, work = 0.0, 0.0
    spent = {1: 0.0, most: 0.0}
    while t < seconds:
        count = gov.before_call()
        dt = gov.call_seconds()
        c = cost(count, t) * (1.0 + noise * rng.standard_normal())
        w = dt / max(c, 1e-12)
        gov.after_call(dt, w)
        t += dt
        work += w
        spent[count] += dt
    return t / work, spent, gov


def quiet(count, t):
    return 1.0 if count == 1 else 1 / 1.3  # two threads 1.3x faster


def busy(count, t):
    return 1.0 if count == 1 else 2.5  # a descheduled thread stalls every region


def test_a_quiet_machine_keeps_the_threads():
    per_work, spent, gov = drive(quiet)
    assert gov.current == 2 and gov.switches == 0
    assert spent[1] < 0.02 * spent[2]  # the probes
    assert per_work < 1.01 / 1.3


def test_a_busy_machine_falls_back_to_one_thread_at_once():
    per_work, spent, gov = drive(busy)
    assert gov.current == 1 and gov.switches == 1
    assert per_work < 1.03  # within 3 % of one thread throughout
    assert spent[2] < 0.02 * spent[1]


@pytest.mark.parametrize("first, then", [(quiet, busy), (busy, quiet)])
def test_it_follows_a_machine_that_changes(first, then):
    def machine(count, t):
        return first(count, t) if t < 60 else then(count, t)

    per_work, _spent, gov = drive(machine, seconds=180.0)
    best = 1.0 if then is busy else 1 / 1.3
    assert gov.current == (1 if then is busy else 2)
    # the best fixed setting for each half, against what the governor did over both
    ideal = (60 * 1.0 / (1.0 if first is busy else 1 / 1.3) + 120 / best) / 180
    assert 1 / per_work > 0.93 * ideal


@settings(max_examples=60, deadline=None)
@given(
    ratio=st.floats(0.25, 4.0),
    noise=st.floats(0.0, 0.15),
    seed=st.integers(0, 1000),
)
def test_never_more_than_ten_percent_slower_than_the_better_count(ratio, noise, seed):
    """Whatever the ratio of the two counts' costs and ±15 % noise per call, a 40 s run is
    at most 10 % slower than the better fixed count (and at most 5 % with ratios beyond
    1.2, where the choice matters)."""

    def machine(count, t):
        return 1.0 if count == 1 else ratio

    per_work, _, _ = drive(machine, seconds=40.0, noise=noise, seed=seed)
    best = min(1.0, ratio)
    assert per_work <= 1.10 * best
    if ratio > 1.2 or ratio < 1 / 1.2:
        assert per_work <= 1.05 * best


def test_a_fixed_setting_never_probes():
    _, spent, gov = drive(busy, adaptive=False)
    assert gov.probes == 0 and spent[1] == 0.0 and gov.current == 2
    _, spent, gov = drive(busy, most=1)
    assert gov.probes == 0 and gov.current == 1


def test_calls_without_threaded_work_or_with_compilation_are_not_measured():
    gov = ThreadGovernor(ThreadSetting(2, True), apply=lambda count: count)
    for _ in range(100):
        gov.before_call()
        gov.after_call(0.25, 0.0)  # a box too small for threads
        gov.before_call()
        gov.after_call(30.0, 1.0, compiled=True)  # kernels compiled during the call
    assert gov.probes == 0 and gov.current == 2


def test_configure_threads():
    before = thread_setting()
    try:
        assert configure_threads(1) == ThreadSetting(1, adaptive=False)
        setting = configure_threads("auto", most=1)
        assert setting.most == 1 and setting.describe() == "1 thread"
        with pytest.raises(ValueError, match="at least 1"):
            configure_threads(0)
    finally:
        configure_threads("auto" if before.adaptive else before.most, most=before.most)


def test_call_pace_aims_at_the_wall_time():
    pace = CallPace(most=20_000)
    assert pace.steps(0.25) == CallPace.first  # nothing known yet
    pace.record(64, 6.4)  # a first call that compiled: 0.1 s per step
    assert pace.steps(0.25) == CallPace.least
    for _ in range(8):
        n = pace.steps(0.25)
        pace.record(n, n * 1e-4)  # 0.1 ms per step from now on
    assert pace.steps(0.25) == 2500
    pace.record(100, 100 * 1e-3, threads=2)  # two threads known separately
    assert pace.steps(0.25, threads=2) == 250 and pace.steps(0.25, threads=1) == 1000


def test_costs_that_drift_and_scatter_do_not_make_it_probe_all_the_time():
    """Cost per unit of work grows as the box outgrows the caches and scatters from call to
    call; on a busy machine the governor must still probe the slow count only now and then."""

    def machine(count, t):
        return (1.0 + t / 30.0) * (1.0 if count == 1 else 2.5)

    _, spent, gov = drive(machine, seconds=60.0, noise=0.15, seed=3)
    assert gov.current == 1 and gov.probes <= 12
    assert spent[2] < 0.03 * spent[1]
