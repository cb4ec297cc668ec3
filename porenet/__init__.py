"""porenet: pore-scale simulation of drainage in deformable, disordered media.

Implements Holtzman & Juanes, Phys. Rev. E 82, 046305 (2010). The public API is small::

    import porenet
    result = porenet.run("scene.toml", output="run.h5")
    data = porenet.read_run("run.h5")
    porenet.register(MyLatticeConfig, MyLattice)   # a kind defined in a script or notebook

Importing porenet loads no plugin, numba, h5py or matplotlib; they load on first use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from porenet._version import __version__

if TYPE_CHECKING:  # pragma: no cover
    from porenet.config.loading import load_scene
    from porenet.hooks import register
    from porenet.io.runfile import read_run
    from porenet.result import RunData, RunResult
    from porenet.simulation import Simulation, run
    from porenet.sweep.records import read_sweep

__all__ = [
    "RunData",
    "RunResult",
    "Simulation",
    "__version__",
    "load_scene",
    "read_run",
    "read_sweep",
    "register",
    "run",
]

_LAZY = {
    "load_scene": "porenet.config.loading",
    "read_run": "porenet.io.runfile",
    "read_sweep": "porenet.sweep.records",
    "register": "porenet.hooks",
    "RunData": "porenet.result",
    "RunResult": "porenet.result",
    "Simulation": "porenet.simulation",
    "run": "porenet.simulation",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'porenet' has no attribute {name!r}")
