"""Exceptions raised by porenet.

Every error a user can cause derives from :class:`PorenetError`; the CLI turns these into a
one-paragraph message and an exit status (2 for configuration errors, 1 otherwise) instead of a
traceback.
"""

from __future__ import annotations


class PorenetError(Exception):
    """Base class of the errors porenet raises on purpose."""

    exit_status = 1


class ConfigError(PorenetError, ValueError):
    """A scene, sweep or option is invalid.

    The message names the file (when there is one), the dotted field and the offending value.
    """

    exit_status = 2


class PluginError(PorenetError):
    """A plugin failed to load, registered an invalid or duplicate kind, or misspelt a hook."""


class NumericalError(PorenetError, ArithmeticError):
    """Numerical trouble (NaN, non-convergence, singular system), with where and when it arose."""


class RunFileError(PorenetError, OSError):
    """A run file is missing, unreadable, or of an unknown format version."""
