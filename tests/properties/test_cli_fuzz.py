"""Fuzzing the command line (docs/reliability.md, "Fuzzing"): any field of the scene schema,
set through ``--set`` to any value (strings, huge, tiny, negative, nan and inf numbers, lists,
kinds, nothing), gives exit status 0 or 2 (or 1 from a valid run that fails for a stated
reason), never a traceback, never "internal error"; a run that is valid (and cheap by the
plan's estimate) writes a run file whose numbers are finite, except those documented to be
nan (:data:`MAY_BE_NAN`).

The command runs in this process (``porenet.cli.main.main``), from one of four scenes (each model
on an 8 x 8 lattice, :data:`BASES`) with keys mostly among their own kinds' fields, so that
many examples are valid and an example costs milliseconds; a scene the fuzzer makes larger
or slower than :data:`RUN_SECONDS` by the plan's estimate is validated and planned, not run.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import signal
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

import h5py
import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from porenet.cli.main import main

#: The scenes the fuzzer starts from: each model on an 8 x 8 lattice.
BASES = {
    "ip": {"lattice": {"kind": "square"}, "fluid": {"kind": "invasion-percolation"}},
    "viscous": {
        "lattice": {"kind": "square"},
        "fluid": {"kind": "viscous", "capillary_number": 0.01},
    },
    "ip+hertz": {
        "lattice": {"kind": "square"},
        "fluid": {"kind": "invasion-percolation"},
        "solid": {"kind": "hertz", "fracturing_number": 1.0},
    },
    "viscous+hertz": {
        "lattice": {"kind": "square"},
        "fluid": {"kind": "viscous", "capillary_number": 0.01},
        "solid": {"kind": "hertz", "fracturing_number": 1.0},
    },
}

#: A valid scene is run only if the plan expects it to take less than this (s) on at most
#: ``MAX_N`` pores a side.
RUN_SECONDS = 0.5
MAX_N = 12
#: A run still going after this (s of wall time) is stopped as by Ctrl-C and not judged: the
#: cost model does not cover absurd physics, where a tiny run can take minutes (throats 3e6
#: times wider than the pores, ``lattice.mean_aperture = 0.3`` m beside ``pore_size = 1e-7``
#: m; or a pressure area factor of 4e16, which ended after 35 s with "made no progress").
RUN_LIMIT = 3

#: Float values of a run file that may be nan, and why: the fractal dimension and its error
#: when the pattern is too small to measure (``fractal_dimension_note`` says so;
#: docs/run-file.md). Nothing may be infinite.
MAY_BE_NAN = frozenset({"/summary/fractal_dimension", "/summary/fractal_dimension_error"})


def _keys(kinds: dict[str, str] | None = None) -> list[str]:
    """Every dotted field of the scene schema: of the given kind of each family (``kinds``),
    or of every registered kind."""
    from porenet.config.scene import InjectionConfig, SceneBase, StopConfig
    from porenet.hooks import get_registry

    keys = [k for k in SceneBase.model_fields if k not in ("injection", "stop")]
    keys += [f"injection.{k}" for k in InjectionConfig.model_fields]
    keys += [f"stop.{k}" for k in StopConfig.model_fields]
    keys += ["lattice", "fluid", "solid", "classifier", "observers"]  # whole sections
    defaults = get_registry().defaults()
    wanted = None if kinds is None else {**defaults, "solid": "rigid", **kinds}
    for entry in get_registry():
        if entry.config is None or entry.family in ("coupler", "observer"):
            continue
        if wanted is None or wanted.get(entry.family) == entry.kind:
            keys += [f"{entry.family}.{field}" for field in entry.config.model_fields]
    return sorted(set(keys))


def _defaults() -> dict[str, object]:
    """Numeric defaults of the registered kinds' fields, by dotted key."""
    from porenet.hooks import get_registry

    found: dict[str, object] = {}
    for entry in get_registry():
        if entry.config is None:
            continue
        for name, info in entry.config.model_fields.items():
            if isinstance(info.default, int | float) and not isinstance(info.default, bool):
                found[f"{entry.family}.{name}"] = info.default
    return found


def _kinds() -> list[str]:
    from porenet.hooks import get_registry

    return sorted({entry.kind for entry in get_registry()})


KEYS = _keys()
DEFAULTS = _defaults()
#: The fields of each base scene's kinds.
BASE_KEYS = {
    name: _keys({family: table["kind"] for family, table in base.items()})
    for name, base in BASES.items()
}
NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from(
        [0, -1, 1, 2, 3, 8, 0.5, 0.3, 1e-3, 1e-7, 1e300, -1e300, 1e-300, 2**63, -(2**70), 10**30]
    ),
    st.integers(),
    st.floats(1e-3, 10.0),  # values many fields accept
    st.integers(1, 12),
)


def _toml(value: object) -> str:
    """``value`` as the VALUE of ``--set KEY=VALUE`` (a TOML literal)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return json.dumps(value)  # a TOML basic string


VALUES = st.one_of(
    NUMBERS.map(_toml),
    st.booleans().map(_toml),
    st.text(max_size=6).map(_toml),  # quoted strings
    st.text(max_size=6),  # raw text: a string, or a TOML literal, or garbage
    st.sampled_from(_kinds()).map(_toml),
    st.lists(NUMBERS, max_size=3).map(_toml),
    st.just(""),  # removes the key
    st.sampled_from(['[{kind = "progress"}]', "[{}]", "{}", "[", "=", '{kind = "square"}']),
)


def _base_text(name: str) -> str:
    lines = []
    for family, table in BASES[name].items():
        lines.append(f"[{family}]")
        lines += [f"{key} = {_toml(value)}" for key, value in table.items()]
        if family == "lattice":
            lines += ["n = 8", "disorder = 0.3"]
    return "\n".join(lines) + "\n"


@st.composite
def scenes_and_sets(draw: st.DrawFn) -> tuple[str, list[str]]:
    """A base scene and 1-3 ``KEY=VALUE`` overrides, the keys mostly among its own kinds'
    fields (so that many examples are valid and run)."""
    base = draw(st.sampled_from(sorted(BASES)))
    key = st.one_of(
        st.sampled_from(BASE_KEYS[base]),
        st.sampled_from(BASE_KEYS[base]),
        st.sampled_from(BASE_KEYS[base]),
        st.sampled_from(KEYS),
        st.text(min_size=1, max_size=8),
    )
    overrides = []
    for _ in range(draw(st.integers(1, 3))):
        name = draw(key)
        near = DEFAULTS.get(name)
        values = VALUES
        if near is not None:  # a value near the default, often valid: the run goes ahead
            factor = st.sampled_from([0.5, 1, 2, 3] if isinstance(near, int) else [0.3, 1, 3])
            values = st.one_of(VALUES, factor.map(lambda f, d=near: _toml(type(d)(d * f))))
        overrides.append(f"{name}={draw(values)}")
    return _base_text(base), overrides


def _cli(argv: list[str]) -> tuple[int, str]:
    """``porenet ARGV`` in this process: its exit status and stderr (argparse exits, with 2,
    on bad usage, e.g. a ``--set`` value that starts with ``-``)."""
    out, err = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                status = main(argv)
            except SystemExit as exc:
                status = exc.code if isinstance(exc.code, int) else 2
    except KeyboardInterrupt:  # _stop_after's, just after main returned
        status = 130
    return status, err.getvalue()


def _check_quiet_failure(status: int, err: str, argv: list[str], run: bool = False) -> None:
    """Exit 0 or 2, or, for a run, 1 with a stated reason (a valid scene whose run cannot
    finish: e.g. ``fluid.max_steps = 1``, which the viscous model refuses at its start with a
    NumericalError naming the field); never a traceback or an internal error."""
    allowed = (0, 1, 2) if run else (0, 2)
    assert status in allowed, f"{argv}: exit {status}\n{err}"
    assert "Traceback" not in err and "internal error" not in err, f"{argv}\n{err}"
    if status == 1:
        assert err.count(": error: ") == 1, f"{argv}\n{err}"


def non_finite(path: Path) -> list[str]:
    """Every float dataset or attribute of the run file with a non-finite value, as
    ``/group/name``, except :data:`MAY_BE_NAN` (which may be nan, never inf)."""
    found: list[str] = []

    def check(name: str, value: object) -> None:
        array = np.asarray(value)
        if array.dtype.kind != "f":
            return
        if name in MAY_BE_NAN:
            if np.isinf(array).any():
                found.append(name)
        elif not np.isfinite(array).all():
            found.append(name)

    with h5py.File(path, "r") as f:
        for key, value in f.attrs.items():
            check(f"/{key}", value)

        def visit(name: str, obj: object) -> None:
            for key, value in obj.attrs.items():  # type: ignore[attr-defined]
                check(f"/{name}/{key}", value)
            if isinstance(obj, h5py.Dataset):
                check(f"/{name}", obj[()])

        f.visititems(visit)
    return found


@contextlib.contextmanager
def _stop_after(seconds: int) -> Iterator[Callable[[], bool]]:
    """Interrupt the block (KeyboardInterrupt, as Ctrl-C, which ``porenet`` turns into exit
    130) after ``seconds`` of wall time; yields whether it did.

    The interrupt waits for a numba compilation in progress to end (one more second at a
    time): on a fresh machine a run's first tens of seconds are numba compiling, and an
    interrupt inside the compiler can leave numba's half-built function behind, so that the
    next call in this process fails with numba's "no compiled object yet" (found by CI on a
    clean checkout). ``porenet`` itself reports an error that follows a real Ctrl-C as the
    interruption, but these examples are interrupted in-process by a timer, and the
    half-built function would stay in this process: not what this property probes."""
    from porenet.jit.compilation import watch

    compiler = watch()
    fired = []

    def interrupt(signum: int, frame: object) -> None:
        if compiler.compiling:
            signal.alarm(1)
            return
        fired.append(signum)
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGALRM, interrupt)
    signal.alarm(seconds)
    try:
        yield lambda: bool(fired)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def _cheap(scene_path: Path, overrides: list[str]) -> bool:
    from porenet.config.loading import load_scene
    from porenet.core.plan import make_plan
    from porenet.hooks import get_registry

    registry = get_registry()
    scene = load_scene(scene_path, overrides, registry=registry)
    cost = make_plan(scene, registry).cost
    n = getattr(scene.lattice, "n", MAX_N + 1)
    return bool(
        cost is not None and cost.wall_seconds is not None and cost.wall_seconds < RUN_SECONDS
        and n <= MAX_N
    )  # fmt: skip


@settings(
    max_examples=60,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)
@given(scenes_and_sets())
def test_any_set_gives_0_or_2_and_finite_run_files(example):
    text, overrides = example
    sets = [arg for item in overrides for arg in ("--set", item)]
    with tempfile.TemporaryDirectory() as tmp:
        scene = Path(tmp) / "scene.toml"
        scene.write_text(text)
        status, err = _cli(["validate", str(scene), *sets])
        _check_quiet_failure(status, err, sets)
        if status != 0:
            assert ": error: " in err  # said why
            return
        status, err = _cli(["plan", str(scene), *sets])
        _check_quiet_failure(status, err, sets)
        if not _cheap(scene, overrides):
            return
        out = Path(tmp) / "run.h5"
        with _stop_after(RUN_LIMIT) as stopped:
            status, err = _cli(["run", str(scene), *sets, "-o", str(out), "-q", "--threads", "1"])
        if stopped():
            assert status == 130 and not out.exists(), err
            return
        _check_quiet_failure(status, err, sets, run=True)
        if status == 0:
            assert non_finite(out) == [], sets


def test_the_run_file_check_finds_what_it_should(tmp_path):
    """:func:`non_finite` sees an infinite attribute and a nan dataset, and lets a nan D_f
    pass."""
    path = tmp_path / "x.h5"
    with h5py.File(path, "w") as f:
        f.create_group("summary").attrs["fractal_dimension"] = np.nan
        f["summary"].attrs["wall_time_s"] = np.inf
        f["final/pressure"] = np.array([1.0, np.nan])
        f["final/drained"] = np.array([True, False])
    assert non_finite(path) == ["/final/pressure", "/summary/wall_time_s"]


def explore(examples: int) -> dict[str, int]:
    """Run the property on ``examples`` examples (the same ones every time) and count the
    exit statuses of each command, with the messages of exit 1 and 130:
    ``python tests/properties/test_cli_fuzz.py --examples 3000``."""
    import collections

    counts: collections.Counter[str] = collections.Counter()
    cli = globals()["_cli"]

    def counting(argv: list[str]) -> tuple[int, str]:
        status, err = cli(argv)
        counts[f"{argv[0]} exit {status}"] += 1
        if status in (1, 130):
            counts[f"  {' '.join(argv[2:-5])}: {err.strip()[:100]}"] += 1
        return status, err

    globals()["_cli"] = counting
    try:
        inner = test_any_set_gives_0_or_2_and_finite_run_files.hypothesis.inner_test
        settings(
            max_examples=examples,
            deadline=None,
            database=None,
            derandomize=True,  # the same examples every time
            suppress_health_check=list(HealthCheck),
        )(given(scenes_and_sets())(inner))()
    finally:
        globals()["_cli"] = cli
    return dict(sorted(counts.items()))


if __name__ == "__main__":
    import sys

    count = int(sys.argv[sys.argv.index("--examples") + 1]) if "--examples" in sys.argv else 1000
    for key, value in explore(count).items():
        print(f"{key}: {value}")
