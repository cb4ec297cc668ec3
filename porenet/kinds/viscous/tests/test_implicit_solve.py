"""The complementarity conditions of one implicit step (porenet.kinds.viscous.implicit_solve):
which meniscus states :func:`switch` changes, checked case by case against the conditions of
docs/model.md section 4 (OFF needs D' <= pe; SLIDE needs 0 <= q <= G pe; ON needs D' >= pe; a
latched meniscus is ON while D' > 0), and the rule of one sliding meniscus per pore."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from porenet.kinds.viscous.implicit_solve import OFF, ON, SLIDE, one_slide_per_pore, switch

TOL = 1e-10


def _one(state, delta, q, *, pe=1.0, g=2.0, latch=False, free=True):
    """switch() on a single meniscus into pore 0: (new state, violation, index)."""
    arrays = (
        np.array([state], dtype=np.int8),
        np.array([free]),
        np.array([latch]),
        np.array([delta], dtype=float),
        np.array([q], dtype=float),
        np.array([g], dtype=float),
        np.array([pe], dtype=float),
        np.array([0]),
    )
    new, viol, arg = switch(*arrays, TOL)
    return int(new[0]), viol, arg


@pytest.mark.parametrize(
    ("state", "delta", "q", "expected", "violation"),
    [
        (ON, 1.5, 1.0, ON, 0.0),  # D' >= pe: stays ON
        (ON, 0.7, 0.0, SLIDE, 0.3),  # D' < pe: ON fails by pe - D'
        (OFF, 0.9, 0.0, OFF, 0.0),  # D' <= pe: stays OFF
        (OFF, 1.25, 0.0, SLIDE, 0.25),  # D' > pe: OFF fails by D' - pe
        (SLIDE, 1.0, 1.0, SLIDE, 0.0),  # 0 <= q <= G pe = 2
        (SLIDE, 1.0, 3.0, ON, 0.5),  # q > G pe: fails by (q - G pe)/G
        (SLIDE, 1.0, -0.5, OFF, 0.25),  # q < 0: fails by -q/G
    ],
)
def test_threshold_meniscus_conditions(state, delta, q, expected, violation):
    new, viol, arg = _one(state, delta, q)
    assert new == expected
    assert viol == pytest.approx(violation)
    assert arg == (-1 if violation == 0.0 else 0)


@pytest.mark.parametrize(
    ("state", "delta", "expected"),
    [(ON, 0.5, ON), (ON, -0.5, OFF), (OFF, -0.5, OFF), (OFF, 0.5, ON)],
)
def test_latched_meniscus_is_on_while_the_pressure_difference_is_positive(state, delta, expected):
    new, _, _ = _one(state, delta, 0.0, latch=True)
    assert new == expected  # never SLIDE, whatever its entry pressure


def test_a_meniscus_held_off_is_never_switched():
    assert _one(OFF, 5.0, 0.0, free=False) == (OFF, 0.0, -1)


def test_the_largest_violation_is_reported():
    state = np.array([ON, OFF, SLIDE], dtype=np.int8)
    delta = np.array([0.9, 1.6, 1.0])  # ON fails by 0.1, OFF by 0.6
    q = np.array([0.0, 0.0, 2.2])  # SLIDE fails by (2.2 - 2)/2 = 0.1
    args = (np.ones(3, bool), np.zeros(3, bool), delta, q, np.full(3, 2.0), np.ones(3))
    new, viol, arg = switch(state, *args, np.arange(3), TOL)
    assert new.tolist() == [SLIDE, SLIDE, ON] and arg == 1 and viol == pytest.approx(0.6)


@settings(max_examples=200, deadline=None)
@given(
    st.lists(
        st.tuples(st.integers(0, 3), st.sampled_from([OFF, SLIDE, ON]), st.floats(0.1, 10.0)),
        min_size=1,
        max_size=12,
    )
)
def test_one_sliding_meniscus_per_pore_the_one_of_largest_entry_pressure(menisci):
    pore = np.array([m[0] for m in menisci])
    state = np.array([m[1] for m in menisci], dtype=np.int8)
    pe = np.array([m[2] for m in menisci])
    before = state.copy()
    one_slide_per_pore(state, np.ones(len(state), bool), pe, pore)
    for p in np.unique(pore):
        here = pore == p
        sliding = np.flatnonzero(here & (before == SLIDE))
        after = np.flatnonzero(here & (state == SLIDE))
        assert len(after) == min(len(sliding), 1)
        if len(sliding) > 1:  # the kept one has the largest entry pressure; the rest are ON
            assert pe[after[0]] == pe[sliding].max()
            assert set(state[sliding].tolist()) == {SLIDE, ON}
    assert np.array_equal(state[before != SLIDE], before[before != SLIDE])
