"""Compiling kernels is announced on stderr, with what, that it happens once, and how long."""

from __future__ import annotations

import io

import numba

from porenet.config.loading import load_scene
from porenet.jit.compilation import CompileNotice
from porenet.jit.warmup import kind_warm_ups


def _fresh_kernel():
    @numba.njit  # not cached: compiles on every first call in a process
    def double(x):
        return 2 * x

    return double


def test_a_phase_that_compiles_says_so_and_how_long():
    stream = io.StringIO()
    notice = CompileNotice(stream=stream)
    with notice.phase("the 'test' fluid model"):
        assert _fresh_kernel()(21) == 42
    lines = stream.getvalue().splitlines()
    assert len(lines) == 2
    assert lines[0].startswith("porenet: compiling the kernels of the 'test' fluid model")
    assert "once per machine" in lines[0] and "porenet compile" in lines[0]
    assert lines[1].startswith("porenet: compiled the kernels of the 'test' fluid model in ")
    assert notice.compiled_seconds > 0


def test_a_phase_that_compiles_several_kernels_says_so_once():
    """Several outermost compilations in one phase (a model's setup calls several kernels):
    one announcement and one total, not a line per kernel."""
    stream = io.StringIO()
    notice = CompileNotice(stream=stream)
    with notice.phase("the 'test' fluid model"):
        for value in (1, 2, 3):
            assert _fresh_kernel()(value) == 2 * value
    lines = stream.getvalue().splitlines()
    assert len(lines) == 2, lines
    assert lines[0].startswith("porenet: compiling") and lines[1].startswith("porenet: compiled")


def test_a_phase_that_compiles_nothing_says_nothing():
    stream = io.StringIO()
    kernel = _fresh_kernel()
    kernel(1)
    notice = CompileNotice(stream=stream)
    with notice.phase("x"):
        kernel(2)
    assert stream.getvalue() == "" and notice.compiled_seconds == 0


def test_disabled_notices_write_nothing_but_count(caplog):
    stream = io.StringIO()
    notice = CompileNotice(stream=stream, enabled=False)
    counter = notice.counter()
    with caplog.at_level("INFO", logger="porenet"), notice.phase("y"):
        _fresh_kernel()(3)
    assert stream.getvalue() == "" and notice.counter() == counter + 1
    assert any("compiled the kernels of y" in r.getMessage() for r in caplog.records)


def test_the_warm_up_scenes_are_valid():
    """Every registered kind's warm-ups (porenet compile) are valid scenes, with unique names
    (the command reports them by name)."""
    warm_ups = kind_warm_ups()
    assert len({w.name for w in warm_ups}) == len(warm_ups) >= 14
    for warm in warm_ups:
        load_scene(warm.scene)
