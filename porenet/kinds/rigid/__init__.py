"""The rigid medium (solid kind ``rigid``): builds nothing. See README.md beside this file."""
