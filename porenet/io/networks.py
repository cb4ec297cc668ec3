"""A pore network held in memory (an OpenPNM or PoreSpy network dict, or an OpenPNM
``Network``), saved as the ``.npz`` file a scene's ``lattice.file`` names.

``porenet.run(scene, network=net)`` saves ``net`` with :func:`save_network` and runs the
scene with ``lattice.file`` set to that file, so an in-memory network meets exactly the
checks of a file (docs/lattices.md, "Imported networks"), and the run file's scene names a
file that holds the network. The file's name is the SHA-256 of the network's arrays, so the
same network is saved once, and a changed one never overwrites another run's.

Where: ``PORENET_NETWORK_DIR`` if set, else ``$XDG_CACHE_HOME/porenet/networks`` (by default
``~/.cache/porenet/networks``).
"""

from __future__ import annotations

import hashlib
import io
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from porenet.core.errors import ConfigError

#: Environment variable naming the directory the networks are saved in.
NETWORK_DIR_ENV = "PORENET_NETWORK_DIR"


def network_dir() -> Path:
    """The directory in-memory networks are saved in (module docstring)."""
    given = os.environ.get(NETWORK_DIR_ENV)
    if given:
        return Path(given).expanduser()
    cache = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(cache).expanduser() / "porenet" / "networks"


def network_arrays(network: Any) -> dict[str, np.ndarray]:
    """The ``pore.*`` and ``throat.*`` arrays of a network dict (other keys, such as an
    OpenPNM object's settings, are not part of the network and are left out).

    Raises
    ------
    ConfigError
        ``network`` is not a mapping with such keys, or one of its arrays holds Python
        objects (the message names the key).
    """
    if not isinstance(network, Mapping):
        raise ConfigError(
            f"network=: an OpenPNM or PoreSpy network dict (keys 'pore.coords', "
            f"'throat.conns', ...) or an OpenPNM Network, not {type(network).__name__}"
        )
    arrays: dict[str, np.ndarray] = {}
    for key, value in network.items():
        if not (isinstance(key, str) and key.split(".")[0] in ("pore", "throat")):
            continue
        array = np.asarray(value)
        if array.dtype.hasobject or array.dtype.kind in "USV":
            raise ConfigError(
                f"network=: {key!r} holds {array.dtype} values; a network's arrays are numbers "
                "or booleans"
            )
        arrays[key] = np.ascontiguousarray(array)
    if not arrays:
        raise ConfigError(
            "network=: no 'pore.*' or 'throat.*' arrays (an OpenPNM or PoreSpy network dict has "
            "'pore.coords' and 'throat.conns' at least)"
        )
    return arrays


def network_digest(arrays: dict[str, np.ndarray]) -> str:
    """SHA-256 of the arrays' names, types, shapes and values, in key order."""
    digest = hashlib.sha256()
    for key in sorted(arrays):
        array = arrays[key]
        digest.update(f"{key}\0{array.dtype.str}\0{array.shape}\0".encode())
        digest.update(array.tobytes())
    return digest.hexdigest()


def save_network(network: Any, directory: Path | None = None) -> Path:
    """Save ``network``'s arrays as ``<sha256>.npz`` in ``directory`` (default
    :func:`network_dir`) unless that file is there already, and return its path.

    Raises
    ------
    ConfigError
        As :func:`network_arrays`.
    OutputError
        The directory cannot be made or written (the message names it).
    """
    from porenet.io.atomic import atomic_write_bytes

    arrays = network_arrays(network)
    folder = directory if directory is not None else network_dir()
    path = folder / f"{network_digest(arrays)}.npz"
    if path.is_file():
        return path
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)  # type: ignore[arg-type]
    folder.mkdir(parents=True, exist_ok=True)
    return atomic_write_bytes(path, buffer.getbuffer(), what="network file")
