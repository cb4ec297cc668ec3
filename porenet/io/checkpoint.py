"""Checkpoints: a running simulation saved between two calls of its fluid model, to be resumed.

A checkpoint is written beside the run file (``OUT.h5`` -> ``OUT.h5.checkpoint``) while a run
goes on (``porenet run ... --checkpoint-every 10m``; docs/run-file.md, "Checkpoints") and
``porenet resume OUT.h5.checkpoint`` finishes the run with exactly the result an
uninterrupted run gives: the same drained pores in the same order, times and pressures to the
bit. That holds because a run's result never depends on where the fluid model's calls end
(``tests/verification/test_chunking.py``) and a checkpoint holds the whole state of the run
at such an end.

Format (version :data:`FORMAT`)::

    b"PORENET-CHECKPOINT\\n"
    8 bytes, little-endian: length H of the header
    H bytes: the header, UTF-8 JSON (see :class:`CheckpointHeader`)
    the payload: the pickled :class:`~porenet.simulation.Simulation`

The header says what the checkpoint holds (scene, progress, porenet version, a fingerprint of
the code that wrote it) and the SHA-256 of the payload, so a damaged or truncated file and a
checkpoint written by other code are refused before anything is unpickled. Like any pickle,
a checkpoint can run code when it is loaded: resume only checkpoints you wrote yourself.

Checkpoints are written atomically (:func:`porenet.io.atomic.atomic_output`: a temporary file
in the same directory, flushed to disk, then renamed), so a run killed while writing one
leaves the previous checkpoint intact, and a full disk is an ``OutputError`` naming the file.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import pickle
import struct
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from porenet._version import __version__
from porenet.core.errors import ConfigError, PorenetError

MAGIC = b"PORENET-CHECKPOINT\n"
#: Version of the layout above and of the header's fields.
FORMAT = 1
#: A checkpoint's file name is the run file's with this appended.
SUFFIX = ".checkpoint"


class CheckpointError(ConfigError):
    """A file given as a checkpoint is not one, is damaged, or was written by other code or
    for another scene (bad input: exit status 2)."""


def checkpoint_path(output: str | Path) -> Path:
    """Where the run writing ``output`` keeps its checkpoint: ``output`` + :data:`SUFFIX`."""
    output = Path(output)
    return output.with_name(output.name + SUFFIX)


@dataclass(frozen=True)
class CheckpointHeader:
    """What a checkpoint holds, readable without unpickling it.

    Attributes
    ----------
    format : int
        :data:`FORMAT` of the writer.
    porenet_version : str
        ``porenet.__version__`` of the writer.
    code_fingerprint : str
        SHA-256 over porenet's source (:func:`code_fingerprint`).
    plugin_sources : dict
        The run's models that come from plugins, with the SHA-256 of their source files
        (:func:`plugin_sources`).
    scene_digest : str
        SHA-256 of the resolved scene (:func:`scene_digest`).
    scene_name : str
        The scene's name.
    output : str or None
        The run file the run writes at its end.
    n_drained : int
        Drained pores when the checkpoint was written.
    step : int
        The fluid model's time steps (or invasion steps) so far.
    model_time : float
        Model time so far (scaled units; 0 for invasion percolation).
    wall_time_s : float
        Wall time the run had spent so far (building included).
    written : str
        When the checkpoint was written (local time, ISO 8601).
    payload_bytes : int
        Length of the pickled simulation.
    payload_sha256 : str
        Its SHA-256.
    """

    format: int
    porenet_version: str
    code_fingerprint: str
    plugin_sources: dict[str, str]
    scene_digest: str
    scene_name: str
    output: str | None
    n_drained: int
    step: int
    model_time: float
    wall_time_s: float
    written: str
    payload_bytes: int
    payload_sha256: str

    def describe(self) -> str:
        """One line: the scene, how far the run got, when."""
        return (
            f"scene {self.scene_name!r} at {self.n_drained:,} drained pores "
            f"({self.wall_time_s:.0f} s of wall time), written {self.written}"
        )


def scene_digest(scene: dict[str, Any]) -> str:
    """SHA-256 of a scene's JSON form (keys sorted): equal for equal resolved scenes."""
    text = json.dumps(scene, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def code_fingerprint() -> str:
    """SHA-256 over every ``.py`` file of the porenet package that a run can execute (relative
    path and bytes, in path order; the kinds' ``tests`` folders, which a source checkout holds
    and an installed package does not, are left out): a checkpoint resumes only under the code
    that wrote it."""
    import porenet

    root = Path(porenet.__file__).resolve().parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        relative = path.relative_to(root)
        if "tests" in relative.parts:
            continue
        digest.update(str(relative).encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


def plugin_sources(classes: tuple[type, ...]) -> dict[str, str]:
    """``{"module:Class": SHA-256 of its source file}`` for the classes of ``classes`` that
    do not come from porenet (a plugin's models): checked like porenet's own code."""
    import inspect

    out: dict[str, str] = {}
    for cls in classes:
        if cls.__module__.split(".")[0] == "porenet":
            continue
        try:
            source = inspect.getsourcefile(cls)
        except TypeError:  # no source file (a built-in or compiled class)
            source = None
        digest = hashlib.sha256(Path(source).read_bytes()).hexdigest() if source else ""
        out[f"{cls.__module__}:{cls.__qualname__}"] = digest
    return out


def _current_plugin_sources(names: dict[str, str]) -> dict[str, str]:
    """The digests of :func:`plugin_sources` for the classes named in ``names``, as the
    installed code has them now ("" for a class that cannot be imported)."""
    import importlib

    classes = []
    for name in names:
        module, _, qualname = name.partition(":")
        try:
            classes.append(getattr(importlib.import_module(module), qualname))
        except (ImportError, AttributeError):
            continue
    found = plugin_sources(tuple(classes))
    return {name: found.get(name, "") for name in names}


def write_checkpoint(path: str | Path, simulation: Any, header: dict[str, Any]) -> Path:
    """Pickle ``simulation`` to ``path`` behind a header built from ``header`` (the fields of
    :class:`CheckpointHeader` except the payload's length and hash), atomically.

    Raises
    ------
    OutputError
        The file could not be written (disk full, no permission, ...): the message names the
        path and the reason (exit status 1); the previous checkpoint, if any, is left as it
        was (:func:`porenet.io.atomic.atomic_output`).
    """
    path = Path(path)
    try:
        payload = pickle.dumps(simulation, protocol=pickle.HIGHEST_PROTOCOL)
    except (pickle.PicklingError, TypeError, AttributeError) as exc:
        raise PorenetError(
            f"cannot write checkpoint {path}: a part of the run cannot be saved ({exc}); an "
            "observer or plugin model that holds an open file or stream must drop it in "
            '__getstate__ (docs/plugins.md, "Checkpoints")'
        ) from None
    fields = dict(
        header,
        format=FORMAT,
        payload_bytes=len(payload),
        payload_sha256=hashlib.sha256(payload).hexdigest(),
    )
    head = json.dumps(dataclasses.asdict(CheckpointHeader(**fields))).encode()
    from porenet.io.atomic import atomic_output

    with atomic_output(path, what="checkpoint") as temporary, open(temporary, "wb") as out:
        out.write(MAGIC)
        out.write(struct.pack("<Q", len(head)))
        out.write(head)
        out.write(payload)
    return path


def _open_checkpoint(path: Path) -> tuple[CheckpointHeader, int]:
    """The header of the checkpoint at ``path`` and the offset of its payload."""
    if path.is_dir():
        raise CheckpointError(f"{path} is a directory; give a checkpoint file (*.checkpoint)")
    try:
        with open(path, "rb") as src:
            magic = src.read(len(MAGIC))
            if magic != MAGIC:
                raise CheckpointError(
                    f"{path} is not a porenet checkpoint (checkpoints are the files "
                    f"'OUT.h5{SUFFIX}' that `porenet run --checkpoint-every` writes)"
                )
            size_bytes = src.read(8)
            size = struct.unpack("<Q", size_bytes)[0] if len(size_bytes) == 8 else -1
            head = src.read(size) if 0 < size < 1 << 20 else b""
    except FileNotFoundError:
        raise CheckpointError(f"no such checkpoint: {path}") from None
    except OSError as exc:
        raise CheckpointError(f"cannot read checkpoint {path}: {exc.strerror or exc}") from None
    try:
        fields = json.loads(head.decode())
        if fields.get("format") != FORMAT:
            raise CheckpointError(
                f"{path}: checkpoint format {fields.get('format')} written by porenet "
                f"{fields.get('porenet_version')}; this porenet reads format {FORMAT} only"
            )
        header = CheckpointHeader(**fields)
    except (ValueError, TypeError) as exc:
        raise CheckpointError(f"{path}: damaged checkpoint (unreadable header: {exc})") from None
    return header, len(MAGIC) + 8 + len(head)


def read_header(path: str | Path) -> CheckpointHeader:
    """The header of a checkpoint, without reading its payload.

    Raises
    ------
    CheckpointError
        ``path`` is missing, not a checkpoint, or its header is damaged.
    """
    return _open_checkpoint(Path(path))[0]


def load_checkpoint(path: str | Path) -> tuple[Any, CheckpointHeader]:
    """Unpickle the simulation of the checkpoint at ``path``; return it with its header.

    Raises
    ------
    CheckpointError
        The file is not a checkpoint, is damaged or truncated (the payload's SHA-256 does not
        match), or was written by another version or other code of porenet or of a plugin
        the run uses (checked before anything is unpickled; the message says which).
    """
    path = Path(path)
    header, offset = _open_checkpoint(path)
    if header.porenet_version != __version__:
        raise CheckpointError(
            f"{path} was written by porenet {header.porenet_version}; this is porenet "
            f"{__version__}: resume it with the version that wrote it, or rerun the scene"
        )
    if header.code_fingerprint != code_fingerprint():
        raise CheckpointError(
            f"{path} was written by other porenet code (same version {__version__}, different "
            "source files): a run resumes only under the code that started it; rerun the scene"
        )
    changed = [
        name
        for name, digest in _current_plugin_sources(header.plugin_sources).items()
        if digest != header.plugin_sources[name]
    ]
    if changed:
        raise CheckpointError(
            f"{path}: the plugin code of {', '.join(changed)} is missing or changed since the "
            "checkpoint was written; install the plugin version that wrote it, or rerun the scene"
        )
    with open(path, "rb") as src:
        src.seek(offset)
        payload = src.read()
    if len(payload) != header.payload_bytes or (
        hashlib.sha256(payload).hexdigest() != header.payload_sha256
    ):
        raise CheckpointError(
            f"{path}: damaged checkpoint (expected {header.payload_bytes} bytes of state with "
            f"SHA-256 {header.payload_sha256[:12]}..., found {len(payload)} bytes that do not "
            "match); resume from another checkpoint or rerun the scene"
        )
    try:
        simulation = pickle.loads(payload)
    except Exception as exc:  # a class renamed or removed since, a plugin not installed
        raise CheckpointError(
            f"{path}: cannot restore the run ({type(exc).__name__}: {exc}); is every plugin "
            "the scene uses installed?"
        ) from None
    return simulation, header


def now_text() -> str:
    """The local time, ISO 8601 to the second."""
    return time.strftime("%Y-%m-%dT%H:%M:%S")


#: Units of ``--checkpoint-every`` durations, in seconds.
_UNITS = {"s": 1.0, "m": 60.0, "h": 3600.0}


class CheckpointSchedule:
    """When a run writes its checkpoint, and where (:meth:`porenet.simulation.Simulation.run`).

    Parameters
    ----------
    path : Path
        The checkpoint file (:func:`checkpoint_path` of the run file).
    every_seconds : float, optional
        Write one when this much wall time passed since the last (or since the start).
    every_drained : int, optional
        Write one when this many more pores drained since the last (or since the start).
    """

    def __init__(
        self, path: str | Path, every_seconds: float | None = None, every_drained: int | None = None
    ) -> None:
        self.path = Path(path)
        self.every_seconds = every_seconds
        self.every_drained = every_drained
        #: Checkpoints written so far by this schedule.
        self.written = 0
        self._last_time = time.perf_counter()
        self._last_drained: int | None = None

    @classmethod
    def parse(
        cls, text: str, path: str | Path, flag: str = "--checkpoint-every"
    ) -> CheckpointSchedule:
        """From ``flag``'s value: a duration (``90s``, ``10m``, ``2h``) or a number of drained
        pores (``5000``). Raises :class:`~porenet.core.errors.ConfigError` naming ``flag``."""
        text = text.strip().lower()
        try:
            if text and text[-1] in _UNITS:
                seconds = float(text[:-1]) * _UNITS[text[-1]]
                if not (seconds > 0 and seconds < float("inf")):
                    raise ValueError
                return cls(path, every_seconds=seconds)
            count = int(text)
            if count < 1:
                raise ValueError
            return cls(path, every_drained=count)
        except ValueError:
            raise ConfigError(
                f"{flag} {text!r}: give a duration such as 90s, 10m or 2h, or a number of "
                "drained pores such as 5000"
            ) from None

    def due(self, state: Any) -> bool:
        """Whether a checkpoint is due now (called between two calls of the fluid model)."""
        if self._last_drained is None:
            self._last_drained = int(state.n_drained)
        if self.every_drained is not None:
            return state.n_drained - self._last_drained >= self.every_drained
        if self.every_seconds is not None:
            return time.perf_counter() - self._last_time >= self.every_seconds
        return False

    def write(self, simulation: Any) -> Path:
        """Write the checkpoint of ``simulation`` (atomically) and restart the count."""
        write_checkpoint(self.path, simulation, simulation.checkpoint_header())
        self.written += 1
        self._last_time = time.perf_counter()
        self._last_drained = int(simulation.state.n_drained)
        return self.path

    def remove(self) -> None:
        """Remove the checkpoint (the run file is complete, so it is no longer needed)."""
        self.path.unlink(missing_ok=True)
