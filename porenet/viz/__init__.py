"""Matplotlib figures. Imports matplotlib only when a figure is made."""

from porenet.viz.pattern import plot_pattern

__all__ = ["plot_pattern"]
