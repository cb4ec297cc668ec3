"""The work-precision figure shared by the accuracy scripts."""

from __future__ import annotations

from porenet.viz.accuracy import error_vs_wall


def test_error_vs_wall_draws_zero_errors_below_the_smallest_one():
    rows_a = [{"wall": 1.0, "value": 0.1, "e": 0.2}, {"wall": 2.0, "value": 0.01, "e": 0.0}]
    rows_b = [{"wall": 1.5, "value": 8, "e": 0.03}]
    fig = error_vs_wall([("a", rows_a, "-"), ("b", rows_b, "--")], ["e"], "t", reference_wall=3)
    (ax,) = fig.axes
    ys = [y for line in ax.get_lines()[:2] for y in line.get_ydata()]
    assert min(ys) == 0.01  # the zero, a third of the smallest non-zero error 0.03
    zero_line, reference = ax.get_lines()[2:]
    assert list(zero_line.get_ydata()) == [0.01, 0.01]  # marked "exactly 0"
    assert any(t.get_text() == "exactly 0" for t in ax.texts)
    assert reference.get_xdata()[0] == 3  # the reference line
    fixed = error_vs_wall([("a", rows_a, "-")], ["e"], "t", zero_at=1e-16)
    assert min(fixed.axes[0].get_lines()[0].get_ydata()) == 1e-16
