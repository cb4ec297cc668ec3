"""RunData and RunResult show themselves in a line per fact, as text and in a notebook's HTML,
whatever the size of their arrays."""

from __future__ import annotations

import numpy as np

import porenet
from porenet.io.runfile import read_run

SCENE = {"seed": 1, "lattice": {"n": 40, "disorder": 0.5}, "fluid": {}}


def test_the_repr_says_what_ran_and_what_came_out(tmp_path):
    result = porenet.run(SCENE, output=tmp_path / "run.h5")
    text = repr(result)
    drained = int(np.count_nonzero(result.data.drained))
    assert text.startswith("RunResult(") and len(text.splitlines()) < 15
    for fact in (
        "square (40 x 40)",
        "1600 pores",
        "invasion-percolation",
        "rigid",
        f"drained: {drained} pores",
        "stopped: breakthrough",
        str(tmp_path / "run.h5"),
    ):
        assert fact in text, fact  # fmt: skip
    assert "array(" not in text  # no array printed
    data = read_run(tmp_path / "run.h5")
    assert repr(data).startswith("RunData(") and f"drained: {drained} pores" in repr(data)


def test_the_html_is_a_table_with_its_text_escaped():
    result = porenet.run(SCENE)
    result.data.summary["regime"] = "<b>VF</b>"
    html = result._repr_html_()
    assert html.startswith("<table>") and "&lt;b&gt;VF&lt;/b&gt;" in html
    assert "run file</th><td style='text-align:left'>not written" in html


def test_a_lattice_with_no_grid_says_so():
    data = porenet.run(SCENE).data
    data.grid_shape = None  # as an imported network's data
    assert "(not a grid)" in repr(data)
