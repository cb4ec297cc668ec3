"""The porenet command, as a user meets it: exit codes and messages, never tracebacks."""

from __future__ import annotations

import json

import h5py
import numpy as np
import pytest

from porenet.cli.main import main

SCENE = """
name = "cli"
seed = 2
[lattice]
n = 25
disorder = 0.4
[fluid]
kind = "invasion-percolation"
"""


def test_run_writes_file_and_plot(write_scene, tmp_path, capsys):
    path = write_scene(SCENE)
    out, png = tmp_path / "o.h5", tmp_path / "o.png"
    assert main(["run", str(path), "-o", str(out), "--plot", str(png)]) == 0
    assert out.is_file() and png.stat().st_size > 1000
    text = capsys.readouterr().out
    assert "breakthrough" in text and str(out) in text
    with h5py.File(out) as f:
        assert json.loads(f.attrs["scene"])["lattice"]["n"] == 25


def test_run_example_quickstart(tmp_path, capsys):
    out = tmp_path / "q.h5"
    assert main(["run", "--example", "quickstart", "-o", str(out), "--set", "lattice.n=40"]) == 0
    assert out.is_file()


def test_set_override_and_quiet(write_scene, tmp_path, capsys):
    out = tmp_path / "o.h5"
    assert (
        main(["run", str(write_scene(SCENE)), "-o", str(out), "-q", "--set", "stop.at='complete'"])
        == 0
    )
    assert capsys.readouterr().out == ""
    with h5py.File(out) as f:
        assert f["summary"].attrs["stop_reason"] == "complete"


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (["run", "absent.toml"], "no such file"),
        (["run"], "no scene given"),
        (["run", "--example", "nope"], "unknown example 'nope'"),
        (["validate", "SCENE", "--set", "lattice.disorder=-1"], "lattice.disorder = -1"),
        (["run", "SCENE", "-o", "/nonexistent-dir/x.h5"], "does not exist"),
        (["plot", "absent.h5"], "no such run file"),
        (["plot", "SCENE"], "not an HDF5 file"),
        (["run", "SCENE", "--threads", "0"], "--threads 0: must be at least 1"),
        (["run", "SCENE", "--threads", "many"], "--threads many: give a number of threads or"),
        (["compile", "--jobs", "0"], "--jobs 0: must be at least 1"),
    ],
)
def test_errors_exit_2_or_1_with_message(write_scene, capsys, args, expected):
    path = str(write_scene(SCENE))
    status = main([path if a == "SCENE" else a for a in args])
    err = capsys.readouterr().err
    assert status in (1, 2)
    assert expected in err and "Traceback" not in err


def test_config_error_exits_2(write_scene, capsys):
    assert main(["run", str(write_scene(SCENE.replace("disorder", "dissorder")))]) == 2


def test_no_partial_run_file_on_failure(write_scene, tmp_path):
    out = tmp_path / "bad.h5"
    assert main(["run", str(write_scene(SCENE)), "-o", str(out), "--set", "lattice.n=-1"]) == 2
    assert list(tmp_path.glob("bad.h5*")) == []


def test_validate_plan_plugins_schema(write_scene, capsys):
    path = str(write_scene(SCENE))
    assert main(["validate", path]) == 0
    assert "valid" in capsys.readouterr().out
    assert main(["validate", path, "--show"]) == 0
    assert json.loads(capsys.readouterr().out)["lattice"]["disorder"] == 0.4
    assert main(["plan", path]) == 0
    plan = capsys.readouterr().out
    assert "skip  solid" in plan and "no pressure solve" in plan
    assert main(["plugins"]) == 0
    listing = capsys.readouterr().out
    assert "square" in listing and "invasion-percolation" in listing and "porenet" in listing
    assert main(["schema"]) == 0
    schema = json.loads(capsys.readouterr().out)
    assert "lattice" in schema["properties"]


def test_plot_command(write_scene, tmp_path):
    out = tmp_path / "r.h5"
    assert main(["run", str(write_scene(SCENE)), "-o", str(out), "-q"]) == 0
    assert main(["plot", str(out)]) == 0
    assert (tmp_path / "r.png").stat().st_size > 1000


def test_module_entry_point_runs(write_scene, tmp_path):
    import subprocess
    import sys

    out = tmp_path / "m.h5"
    proc = subprocess.run(
        [sys.executable, "-m", "porenet", "run", str(write_scene(SCENE)), "-o", str(out), "-q"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    assert np.asarray(h5py.File(out)["final/drained"]).shape == (25, 25)


def test_run_says_at_once_what_it_runs_and_quiet_silences_it(write_scene, tmp_path, capsys):
    """stderr is not a terminal here (a batch job): a start line with the plan's estimate,
    then progress lines; -q prints neither."""
    path = str(write_scene(SCENE))
    assert main(["run", path, "-o", str(tmp_path / "a.h5"), "--threads", "auto"]) == 0
    err = capsys.readouterr().err
    first = err.splitlines()[0]
    assert first.startswith("porenet: run 'cli': 'invasion-percolation' fluid model, rigid")
    assert "625 pores" in first and "expect ~" in first and "docs/cost.md" in first
    assert main(["run", path, "-o", str(tmp_path / "b.h5"), "-q", "--threads", "1"]) == 0
    assert capsys.readouterr().err == ""


def test_compile_command(capsys, monkeypatch):
    from porenet.jit import warmup

    tiny = tuple(w for w in warmup.kind_warm_ups() if w.name == "invasion percolation")
    monkeypatch.setattr(warmup.compile_all, "__defaults__", (None, tiny, 1))
    assert main(["compile"]) == 0
    out = capsys.readouterr().out
    assert "invasion percolation:" in out and "porenet compile:" in out


def test_a_reader_that_goes_away_is_not_an_error(tmp_path):
    """``porenet plan SCENE | head -1``: the pipe closes before porenet writes (it takes
    longer to start than the reader to close); exit 0 and no "internal error"."""
    import os
    import subprocess
    import sys

    read_end, write_end = os.pipe()
    os.close(read_end)  # the reader is gone before the first line
    proc = subprocess.run(
        [sys.executable, "-m", "porenet", "plan", "--example", "quickstart"],
        stdout=write_end,
        stderr=subprocess.PIPE,
        text=True,
        timeout=120,
    )
    os.close(write_end)
    assert proc.returncode == 0, proc.stderr
    assert "internal error" not in proc.stderr and "Traceback" not in proc.stderr


def test_output_never_destroys_a_file_that_is_not_a_run_file(write_scene, tmp_path, capsys):
    """-o over a non-run file: exit 2 before running, the file untouched; --overwrite replaces
    it; an existing run file is replaced (re-running a scene); a missing directory exits 2."""
    scene = str(write_scene(SCENE))
    notes = tmp_path / "notes.h5"
    notes.write_text("my notes")
    assert main(["run", scene, "-q", "-o", str(notes)]) == 2
    assert "exists and is not a porenet run file" in capsys.readouterr().err
    assert notes.read_text() == "my notes"
    assert main(["run", scene, "-q", "-o", str(notes), "--overwrite"]) == 0
    with h5py.File(notes) as f:
        assert "porenet_version" in f.attrs
    assert main(["run", scene, "-q", "-o", str(notes)]) == 0  # a run file: replaced
    assert main(["run", scene, "-q", "-o", str(tmp_path / "absent" / "x.h5")]) == 2
    assert main(["run", scene, "-q", "-o", str(tmp_path)]) == 2
    assert "is a directory" in capsys.readouterr().err


@pytest.fixture
def ctrl_c_reaches_python():
    """SIGINT raises KeyboardInterrupt during the test, even where pytest runs with SIGINT
    ignored (a job that a script started with &, which porenet leaves alone)."""
    import signal

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


@pytest.mark.usefixtures("ctrl_c_reaches_python")
def test_an_error_that_follows_ctrl_c_is_reported_as_the_interruption(monkeypatch, capsys):
    """Numba can drop a KeyboardInterrupt raised inside an LLVM callback and fail later with
    an unrelated error ("no compiled object yet"): after Ctrl-C, that is exit 130."""
    import contextlib
    import os
    import signal

    import porenet.cli.main as cli

    def swallowed_then_failed(args):
        with contextlib.suppress(KeyboardInterrupt):  # as ctypes drops it in a callback
            os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C
        raise RuntimeError("no compiled object yet for <Library 'kernel'>")

    monkeypatch.setitem(cli.COMMANDS, "validate", swallowed_then_failed)
    assert main(["validate", "scene.toml"]) == 130
    assert "porenet validate: interrupted" in capsys.readouterr().err
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored


@pytest.mark.usefixtures("ctrl_c_reaches_python")
def test_ctrl_c_that_a_ctypes_callback_dropped_still_interrupts(monkeypatch, capsys):
    """LLVM calls Python through ctypes while numba compiles; ctypes drops a KeyboardInterrupt
    raised there, and the run went on to its end (exit 0) as if Ctrl-C had not been pressed.
    It is raised again once the callback has returned."""
    import ctypes
    import ctypes.util
    import os
    import signal
    import sys
    import time

    import porenet.cli.main as cli

    libc = ctypes.CDLL(ctypes.util.find_library("c"))
    compare = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p)
    went_on = []

    def ctrl_c_in_a_callback(args):
        def callback(a, b):
            os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C, inside the ctypes callback
            time.sleep(0.01)  # the handler runs here and its KeyboardInterrupt is dropped
            return 0

        items = (ctypes.c_int * 2)(2, 1)
        libc.qsort(items, 2, ctypes.sizeof(ctypes.c_int), compare(callback))
        went_on.append(True)  # the interrupt must not let the command go on
        return 0

    hook, profile = sys.unraisablehook, sys.getprofile()
    monkeypatch.setitem(cli.COMMANDS, "validate", ctrl_c_in_a_callback)
    assert main(["validate", "scene.toml"]) == 130
    err = capsys.readouterr().err
    assert "porenet validate: interrupted" in err and "Exception ignored" not in err
    assert not went_on
    assert sys.unraisablehook is hook and sys.getprofile() is profile
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


@pytest.mark.usefixtures("ctrl_c_reaches_python")
def test_ctrl_c_that_a_library_swallowed_is_reported(monkeypatch, capsys):
    """numpy's C code calls a Python check while it makes some dtypes and clears any error it
    raises, a KeyboardInterrupt too: the command goes on to its end, and says so."""
    import os
    import signal
    import time

    import porenet.cli.main as cli

    def swallowed_then_done(args):
        try:  # as C code that calls Python and clears its error
            os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C
            time.sleep(0.01)
        except KeyboardInterrupt:
            pass
        return 0

    monkeypatch.setitem(cli.COMMANDS, "validate", swallowed_then_done)
    assert main(["validate", "scene.toml"]) == 0
    err = capsys.readouterr().err
    assert "porenet validate: Ctrl-C was lost inside a library" in err
    assert "its output is complete" in err


def test_an_interrupt_that_escaped_an_exec_string_still_exits_130(tmp_path):
    """``python -m porenet``: CPython kills itself with SIGINT at exit after a
    KeyboardInterrupt escaped an exec() of a string (numba and dataclasses build code that
    way), whatever status the program returned: the parent saw -2, not 130
    (docs/reliability.md, "Exit status"). Run as a module, as ``-m`` runs porenet; ``-c``
    and a script file take another exit path that does not look at the note."""
    import os
    import subprocess
    import sys

    (tmp_path / "interrupted_in_built_code.py").write_text(
        "import porenet.cli.main as cli\n"
        "def command(args):\n"
        "    exec('raise KeyboardInterrupt')\n"
        "cli.COMMANDS['validate'] = command\n"
        "raise SystemExit(cli.main(['validate', 'scene.toml']))\n"
    )
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(tmp_path), *filter(None, [os.environ.get("PYTHONPATH")])]))  # fmt: skip
    out = subprocess.run([sys.executable, "-m", "interrupted_in_built_code"], env=env,
                         capture_output=True, text=True, timeout=120)  # fmt: skip
    assert out.returncode == 130, (out.returncode, out.stderr[-800:])
    assert "porenet validate: interrupted" in out.stderr and "Traceback" not in out.stderr


def test_ctrl_c_during_a_first_compilation_exits_130(tmp_path):
    """Ctrl-C at several moments of a first viscous run (empty kernel cache, so numba is
    compiling): always exit 130 and "interrupted", never an internal error."""
    import os
    import signal
    import subprocess
    import sys
    import time
    from pathlib import Path

    scene = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "fig1b.toml"
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    for delay in (1.0, 2.5, 4.0):
        proc = subprocess.Popen(
            [sys.executable, "-m", "porenet", "run", str(scene), "--set", "lattice.n=30",
             "-o", str(tmp_path / "run.h5")],
            stderr=subprocess.PIPE, text=True, env=env,
            # as from a terminal, also where pytest runs with SIGINT ignored (started with &)
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        )  # fmt: skip
        time.sleep(delay)
        proc.send_signal(signal.SIGINT)
        err = proc.communicate(timeout=120)[1]
        if proc.returncode == 0:  # finished before the interrupt (a warm machine)
            continue
        assert proc.returncode == 130, (delay, err[-800:])
        assert "interrupted" in err and "internal error" not in err
        assert not (tmp_path / "run.h5").exists()
