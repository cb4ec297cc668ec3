"""The progress display: a status line with an estimated ETA on a terminal, log lines elsewhere."""

from __future__ import annotations

import io
import itertools
import logging
import time
from types import SimpleNamespace

from porenet.config.loading import load_scene
from porenet.core.plan import make_plan
from porenet.hooks import get_registry
from porenet.io.progress import (
    ETA_MIN_ELAPSED,
    LOG_FRACTION,
    LOG_SECONDS,
    Progress,
    eta_text,
    format_duration,
)
from porenet.kinds.progress.config import ProgressConfig
from porenet.simulation import Simulation


class FakeTTY(io.StringIO):
    """A text stream that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def _run(scene_dict, stream, **kwargs):
    reg = get_registry()
    plan = make_plan(load_scene(scene_dict), reg, progress=True)
    progress = Progress(ProgressConfig(every_seconds=1e-9), stream=stream, **kwargs)
    Simulation(plan, reg, [progress]).run()
    return plan, progress


def test_log_lines_when_not_a_terminal(scene_dict):
    """Not a terminal (a batch job, nohup): whole lines, never rewritten in place, one each
    time another tenth of the expected pores drains (or every LOG_SECONDS)."""
    stream = io.StringIO()
    _plan, progress = _run(scene_dict, stream)
    lines = stream.getvalue().splitlines()
    assert lines and "\r" not in stream.getvalue()
    assert all(line.startswith("porenet: drained") for line in lines)
    assert len(lines) <= 1 + round(1 / LOG_FRACTION)
    assert not progress.terminal


def _attached(progress: Progress, n_pores: int, time_scale: float | None = None) -> None:
    """Attach ``progress`` to a stand-in for a run of ``n_pores`` pores (no plan: no ETA
    unless the progress was given an expected count)."""
    run = SimpleNamespace(lattice=SimpleNamespace(n_pores=n_pores),
                          scales=SimpleNamespace(time=time_scale),
                          expected_drained=None)  # fmt: skip
    progress.attach(run)


def test_a_log_line_at_least_every_log_seconds(monkeypatch):
    clock = [1000.0]
    monkeypatch.setattr(time, "perf_counter", lambda: clock[0])
    stream = io.StringIO()
    progress = Progress(stream=stream)  # no expected count: only the clock
    _attached(progress, 100)
    state = SimpleNamespace(n_drained=3, time=0.0, step=0)
    clock[0] += 1.0
    progress.observe(state)
    assert stream.getvalue() == ""
    clock[0] += LOG_SECONDS
    progress.observe(state)
    progress.observe(state)  # not again until another LOG_SECONDS
    assert stream.getvalue().count("\n") == 1 and "drained         3 / 100" in stream.getvalue()


def test_status_line_on_a_terminal(scene_dict):
    stream = FakeTTY()
    plan, progress = _run(scene_dict, stream)
    text = stream.getvalue()
    assert text.startswith("\r  drained") and text.endswith("\n")
    assert f"/ {31 * 31} pores" in text and "pores/s" in text
    # the expected drained count comes from the plan's cost estimate
    assert progress.expected_drained == plan.cost.drained


class NotebookStream(io.StringIO):
    """A text stream as ipykernel's: not a terminal, but a notebook honours its ``\\r``."""

    def isatty(self) -> bool:
        return False


NotebookStream.__module__ = "ipykernel.iostream"


def test_status_line_in_a_notebook(scene_dict):
    stream = NotebookStream()
    _run(scene_dict, stream)
    text = stream.getvalue()
    # one line rewritten in place, as on a terminal, with no escape code a notebook would print
    assert text.startswith("\r  drained") and text.endswith("\n") and text.count("\n") == 1
    assert "\x1b" not in text and text.count("\r") >= 2
    # a shorter line than the one before is padded over it
    lines = text.rstrip("\n").split("\r")[1:]
    assert all(len(b) >= len(a.rstrip()) for a, b in itertools.pairwise(lines))


def test_expected_count_is_max_drained_when_given(scene_dict):
    _, progress = _run(scene_dict | {"stop": {"max_drained": 50}}, FakeTTY())
    assert progress.expected_drained == 50
    _, progress = _run(scene_dict, FakeTTY(), expected_drained=10**9)
    assert progress.expected_drained == 31 * 31  # never more than the lattice


def test_eta_only_when_meaningful():
    late = ETA_MIN_ELAPSED + 8.0
    assert eta_text(100, None, late) == ""  # nothing expected
    assert eta_text(100, 1000, 0.5) == ""  # too early
    assert eta_text(1, 1000, late) == ""  # too few pores to tell a rate
    assert eta_text(1000, 1000, late) == "" and eta_text(1500, 1000, late) == ""  # past it
    assert eta_text(250, 1000, 10.0) == "ETA ~ 30 s (est.)"
    assert eta_text(100, 1000, 600.0) == "ETA ~ 1.5 h (est.)"
    assert format_duration(150) == "2.5 min"


def test_status_shows_model_time_and_eta():
    progress = Progress(stream=FakeTTY(), expected_drained=1000)
    _attached(progress, 10_000, time_scale=1e-3)
    state = SimpleNamespace(n_drained=500, time=2.0, step=77)
    line = progress.status(state, elapsed=20.0)
    assert "t = 2.000e-03 s, step 77" in line and "ETA ~ 20 s (est.)" in line


def test_library_logs_the_run_and_never_prints(scene_dict, caplog, capsys):
    with caplog.at_level(logging.INFO, logger="porenet"):
        Simulation.from_scene(scene_dict).run()
    messages = [r.getMessage() for r in caplog.records]
    assert any(m.startswith("run start:") for m in messages)
    assert any(m.startswith("estimate (docs/cost.md):") for m in messages)
    assert any(m.startswith("run finished:") for m in messages)
    out = capsys.readouterr()
    assert out.out == "" and out.err == ""


def test_no_print_calls_in_the_library():
    """Diagnostics go through ``logging``; only the command line (porenet/cli/main.py) prints."""
    import ast
    from pathlib import Path

    import porenet

    root = Path(porenet.__file__).parent
    offenders = []
    for path in root.rglob("*.py"):
        if path.name == "main.py" and path.parent == root / "cli":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "print":
                offenders.append(f"{path.relative_to(root)}:{node.lineno}")
    assert offenders == []
