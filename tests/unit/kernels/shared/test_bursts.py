"""Burst statistics (porenet.kernels.bursts) against a slow, literal reference: a burst
opens at every step whose pressure exceeds all earlier ones and runs until the next such step
(docs/model.md section 3)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from porenet.kernels.bursts import burst_sizes


def reference(pressure: list[float]) -> tuple[list[int], list[int]]:
    starts = [i for i, p in enumerate(pressure) if all(p > q for q in pressure[:i])]
    ends = [*starts[1:], len(pressure)] if starts else []
    sizes = [b - a for a, b in zip(starts, ends, strict=True)]
    return starts, sizes


def test_a_hand_made_signal():
    start, size = burst_sizes(np.array([1.0, 0.5, 0.7, 2.0, 2.0, 1.0, 3.0]))
    assert start.tolist() == [0, 3, 6]  # 2.0 repeated is not a new record
    assert size.tolist() == [3, 3, 1]


def test_empty_signal_has_no_burst():
    start, size = burst_sizes(np.array([]))
    assert start.size == 0 and size.size == 0


@settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(-10, 10, allow_nan=False), max_size=60))
def test_matches_the_literal_definition_and_partitions_the_steps(pressure):
    start, size = burst_sizes(np.array(pressure, dtype=float))
    ref_start, ref_size = reference(pressure)
    assert start.tolist() == ref_start and size.tolist() == ref_size
    assert int(size.sum()) == len(pressure)


def test_nan_never_opens_a_burst():
    start, _ = burst_sizes(np.array([1.0, np.nan, 2.0]))
    assert start.tolist() == [0, 2]
