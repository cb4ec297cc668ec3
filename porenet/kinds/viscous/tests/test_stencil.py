"""The row stencil (porenet.kinds.viscous.kernels.stencil.interior_run) against the canonical grid
numbering written out pore by pore: pore (i, j) is i n + j, horizontal throat (i, j)-(i, j+1)
is i (n-1) + j, vertical throat (i, j)-(i+1, j) is n (n-1) + i n + j."""

from __future__ import annotations

import numpy as np
import pytest

from porenet.jit.jit import njit
from porenet.kinds.viscous.kernels.stencil import interior_run

FIELDS = ("centre", "west", "east", "up", "down", "g_west", "g_east", "g_up", "g_down", "g_out")


@njit(helper=True)
def _views(y, g, outlet, n, first, stop, has_up, has_down, out):
    """Copy the stencil's views into the rows of ``out`` (in the order of FIELDS), as the
    sweeps read them: from a compiled helper without reference counting, as the sweeps'
    row functions are (a caller with reference counting releases the views' parents, which
    corrupts the heap; Python gets the whole arrays back instead of the views)."""
    st = interior_run(y, g, outlet, n, first, stop, has_up, has_down)
    for j in range(stop - first):
        out[0, j] = st.centre[j]
        out[1, j] = st.west[j]
        out[2, j] = st.east[j]
        out[3, j] = st.up[j]
        out[4, j] = st.down[j]
        out[5, j] = st.g_west[j]
        out[6, j] = st.g_east[j]
        out[7, j] = st.g_up[j]
        out[8, j] = st.g_down[j]
        out[9, j] = st.g_outlet[j]
    return st.on_outlet


def _reference(y, g, outlet, n, first, stop):
    h = lambda i, j: i * (n - 1) + j  # noqa: E731
    v = lambda i, j: n * (n - 1) + i * n + j  # noqa: E731
    rows = {name: [] for name in FIELDS}
    for k in range(first, stop):
        i, j = divmod(k, n)
        rows["centre"].append(y[k])
        rows["west"].append(y[k - 1])
        rows["east"].append(y[k + 1])
        rows["up"].append(y[k - n] if i > 0 else np.nan)
        rows["down"].append(y[k + n] if i < n - 1 else np.nan)
        rows["g_west"].append(g[h(i, j - 1)])
        rows["g_east"].append(g[h(i, j)])
        rows["g_up"].append(g[v(i - 1, j)] if i > 0 else np.nan)
        rows["g_down"].append(g[v(i, j)] if i < n - 1 else np.nan)
        rows["g_out"].append(outlet[k])
    return rows


@pytest.mark.parametrize("n", [3, 4, 7])
def test_every_interior_run_of_every_row(n):
    rng = np.random.default_rng(n)
    y = rng.random(n * n)
    g = rng.random(2 * n * (n - 1))  # distinct values: a wrong index cannot match by chance
    outlet = rng.random(n * n)
    for i in range(n):
        for first in range(i * n + 1, i * n + n - 1):
            for stop in range(first + 1, i * n + n):
                has_up, has_down = i > 0, i < n - 1
                out = np.full((len(FIELDS), stop - first), np.nan)
                edge = _views(y, g, outlet, n, first, stop, has_up, has_down, out)
                ref = _reference(y, g, outlet, n, first, stop)
                for row, name in enumerate(FIELDS):
                    if name in ("up", "g_up") and not has_up:
                        continue  # "any valid view": not read
                    if name in ("down", "g_down") and not has_down:
                        continue
                    np.testing.assert_array_equal(out[row], ref[name], err_msg=name)
                assert edge == (i == 0 or i == n - 1)
