"""Run files (HDF5), checkpoints and atomic output.

The names below load on first use, so that importing :mod:`porenet.io.atomic` (standard
library only) does not import numpy with the run-file reader; h5py loads only when a file is
written or read.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from porenet.io.runfile import FORMAT_VERSION, read_run, write_run

__all__ = ["FORMAT_VERSION", "read_run", "write_run"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        return getattr(importlib.import_module("porenet.io.runfile"), name)
    raise AttributeError(f"module 'porenet.io' has no attribute {name!r}")
