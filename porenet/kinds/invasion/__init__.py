"""Quasi-static invasion percolation (kind ``invasion-percolation``). See README.md beside this
file."""
