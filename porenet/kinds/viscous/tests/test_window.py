"""The helpers of a window of local time steps (porenet.kinds.viscous.kernels.window), each against
its definition written out by hand: box membership, pressures interpolated from the start of
the macro step, the volume booked on ring throats, the RKC shadow recursion, the open-edge
margin and the watch on menisci outside the window."""

from __future__ import annotations

import numpy as np
import pytest

from porenet.kinds.viscous.kernels.state import Status
from porenet.kinds.viscous.kernels.window import (
    Cut,
    Mode,
    Ring,
    WindowFloat,
    WindowInt,
    book_explicit,
    book_shadow,
    box_area,
    cut,
    far_meniscus,
    far_pressure,
    inside,
    n_entries,
    near_open_edge,
    no_window,
    ring_increment,
    set_ring,
    shadow_stage,
    window_arrays,
)

N = 6  # a 6 x 6 grid


def _window(mode=Mode.FINE, box=(1, 4, 2, 5), n_ring=3, n_outlet=0):
    win = window_arrays(mode, n_ring + n_outlet, N * N, 2 * N * (N - 1))
    win.box[:] = box
    win.ints[WindowInt.N_RING] = n_ring
    win.ints[WindowInt.N_OUTLET] = n_outlet
    rng = np.random.default_rng(0)
    # ring throat e: window pore w, ring pore r, throat t; outlet links: (w, -1, w)
    win.ring_index[:, :n_ring] = [[7, 8, 9][:n_ring], [1, 2, 3][:n_ring], [4, 5, 6][:n_ring]]
    for e in range(n_outlet):
        win.ring_index[:, n_ring + e] = (10 + e, -1, 10 + e)
    win.ring_value[Ring.P0] = rng.random(n_ring + n_outlet)
    win.ring_value[Ring.RATE] = rng.random(n_ring + n_outlet)
    win.floats[WindowFloat.T0] = 2.0
    win.p0[:] = rng.random(N * N)
    win.rate[:] = rng.random(N * N)
    return win


def test_box_membership_and_area():
    box = np.array([1, 4, 2, 5])
    members = [k for k in range(N * N) if inside(box, N, k)]
    assert members == [i * N + j for i in range(1, 4) for j in range(2, 5)]
    assert box_area(box) == len(members) == 9


def test_pressures_are_linear_in_time_from_the_macro_step_start():
    win = _window()
    for k in (0, 17, 35):
        assert far_pressure(win, k, 3.5) == pytest.approx(win.p0[k] + 1.5 * win.rate[k])
    p = np.zeros(N * N)
    set_ring(win, p, 2.5)
    d = np.zeros(N * N)
    ring_increment(win, d, 0.25)
    for e in range(3):
        r = win.ring_index[1, e]
        assert p[r] == pytest.approx(
            win.ring_value[Ring.P0, e] + 0.5 * win.ring_value[Ring.RATE, e]
        )
        assert d[r] == pytest.approx(0.25 * win.ring_value[Ring.RATE, e])
    untouched = np.setdiff1d(np.arange(N * N), win.ring_index[1, :3])
    assert not p[untouched].any() and not d[untouched].any()


def test_forward_euler_booking_is_the_flux_out_of_the_window():
    win = _window()
    rng = np.random.default_rng(1)
    p, g = rng.random(N * N), rng.random(2 * N * (N - 1))
    total = book_explicit(win, p, g, 0.1)
    total += book_explicit(win, p, g, 0.1)  # accumulates
    expected = [0.2 * g[t] * (p[w] - p[r]) for w, r, t in win.ring_index[:, :3].T]
    np.testing.assert_allclose(win.ring_value[Ring.FLUX, :3], expected)
    assert total == pytest.approx(sum(expected))


@pytest.mark.parametrize("mode", [Mode.FINE, Mode.COARSE])
def test_shadow_recursion_and_booking(mode):
    """S_j = mu S_{j-1} + nu S_{j-2} + c_flux g (d_r - d_w) + c_f0 g (p_r - p_w), written out
    for five stages; outlet links (COARSE only) have the outlet at 0 with g = g_out."""
    win = _window(mode, n_outlet=2)
    assert n_entries(win.ints) == (5 if mode == Mode.COARSE else 3)
    rng = np.random.default_rng(2)
    p, g, g_out = rng.random(N * N), rng.random(2 * N * (N - 1)), rng.random(N * N)
    mus, nus, cfs, c0s = rng.random(6), rng.random(6), rng.random(6), rng.random(6)
    entries = n_entries(win.ints)
    s = {0: np.zeros(entries)}
    d_prev = np.zeros(N * N)
    for j in range(1, 6):
        shadow_stage(win, j, d_prev, g, g_out, p, mus[j], nus[j], cfs[j], c0s[j])
        expected = np.empty(entries)
        for e in range(entries):
            w, r, t = win.ring_index[:, e]
            gg, pr, dr = (g[t], p[r], d_prev[r]) if r >= 0 else (g_out[w], 0.0, 0.0)
            val = c0s[j] * gg * (pr - p[w])
            if j >= 2:
                val += cfs[j] * gg * (dr - d_prev[w]) + mus[j] * s[j - 1][e]
            if j >= 3:
                val += nus[j] * s[j - 2][e]
            expected[e] = val
        s[j] = expected
        np.testing.assert_allclose(win.ring_value[Ring.SHADOW + (j - 1) % 3, :entries], expected)
        d_prev = rng.random(N * N)  # the next stage's increments
    before = win.ring_value[Ring.COARSE, :entries].copy()
    left = book_shadow(win, 5, Ring.COARSE)
    np.testing.assert_allclose(win.ring_value[Ring.COARSE, :entries], before - s[5])
    assert left == pytest.approx(-s[5].sum())


def test_open_edges_are_those_inside_the_active_box():
    win = _window(box=(1, 5, 1, 5))
    win.ints[WindowInt.MARGIN] = 1
    nbox = np.array([0, 6, 1, 6])  # the active box: the window's left edge is also its edge
    for k in range(N * N):
        i, j = divmod(k, N)
        if not inside(win.box, N, k):
            continue
        expected = i == 1 or i == 4 or j == 4  # rows 1 and 4 and column 4 face a ring
        assert near_open_edge(win, nbox, N, k) == expected, (i, j)


def test_far_meniscus_is_watched_only_above_its_level():
    win = _window()
    tp = np.array([[0, 1], [2, 3]])  # throat 0: pores 0-1, throat 1: pores 2-3
    drained = np.zeros(N * N, dtype=np.bool_)
    drained[[0, 2]] = True  # both menisci enter pores 1 and 3
    win.far[:2] = [0, 1]
    win.ints[WindowInt.N_FAR] = 2
    win.p0[[1, 3]], win.rate[[1, 3]] = 0.0, 0.0
    entry = np.array([5.0, 3.0])
    win.floats[WindowFloat.FAR_LEVEL] = 10.0
    assert far_meniscus(win, 4.0, 0.0, 2.0, entry, tp, drained) == -1  # below the level
    win.floats[WindowFloat.FAR_LEVEL] = 0.0
    assert far_meniscus(win, 2.0, 0.0, 2.0, entry, tp, drained) == -1  # 2 < 3 and 2 < 5
    assert far_meniscus(win, 4.0, 0.0, 2.0, entry, tp, drained) == 3  # 4 > 3: pore 3
    assert far_meniscus(win, 2.0, 1.5, 2.0, entry, tp, drained) == 3  # within the margin


def test_cut_records_why_and_where():
    win = _window()
    assert cut(win, Cut.NEAR_EDGE, 17) == Status.CUT
    assert win.ints[WindowInt.CUT_REASON] == Cut.NEAR_EDGE and win.ints[WindowInt.CUT_PORE] == 17


def test_no_window_is_off_and_empty():
    win = no_window()
    assert win.ints[WindowInt.MODE] == Mode.OFF and n_entries(win.ints) == 0
