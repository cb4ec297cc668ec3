"""Viscous drainage, the paper's dynamic model (kind ``viscous``). See README.md beside this
file."""
