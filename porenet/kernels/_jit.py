"""The JIT decorator used by porenet's kernels.

Numba compiles each kernel once per machine and caches the machine code on disk
(``cache=True``), so only the first run after installation pays the compilation (a few
seconds); later processes load the cache. If numba cannot be imported the kernels still run,
as plain (slow) Python, and a warning says so.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

log = logging.getLogger(__name__)

try:
    import numba

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - numba is a core dependency
    numba = None
    HAVE_NUMBA = False
    log.warning("numba is not importable: porenet's kernels run as plain Python (slow)")


def njit(func: Callable[..., Any]) -> Callable[..., Any]:
    """``numba.njit(cache=True, nogil=True)`` when numba is available, else identity."""
    if not HAVE_NUMBA:
        return func
    return numba.njit(cache=True, nogil=True)(func)  # type: ignore[no-any-return]
